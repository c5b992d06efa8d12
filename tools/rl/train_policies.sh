#!/usr/bin/env bash
# The recipe of the two shipped TD3 policies; docs/rl.md records the runs, their wall
# times and how every choice was reached.
#
# Every run trains SBX TD3 ([64, 64], 50 gradient steps every 50 actions, learning rate
# 3e-4) on the mixed training layouts (srfm.scenarios.training), each action held for
# 4 simulation steps (action repeat 4: 0.27 s), with the paper's reward plus the
# potential-based progress term (k_progress = 10 in stage 1, 5 in stage 2). Training
# never sees the benchmark's seeds 0-99 nor the evaluation scenarios' layouts; every
# run is evaluated on the five evaluation scenarios (stage 1: every 25,000 actions,
# seeds 10000-10009; stage 2: every 5,000 actions, seeds 10000-10019) and keeps its
# best checkpoint (best.zip; for the SRFM-aware runs only evaluations at the final k2).
#
# Stage 1, pre-training: three RL_base runs (k2 = 0, success and timeout 25, training
# seeds 1-3), 300,000 actions each. The best.zip of the seed whose best evaluation
# ranks first (higher success, then fewer collisions, then less deviation;
# tools/rl/select_policy.py) is the starting point of stage 2 ($RUNS/stage1_base.zip).
#
# Stage 2, the two variants: six runs continue from that checkpoint (an empty replay
# buffer) to 225,000 actions with success and timeout 100 (collision 100: a timeout
# costs as much as a collision) and the progress term at half its stage-1 weight
# (k_progress = 5: with 10 and gamma = 0.99 the term pays a robot that stands still
# exactly what k1 = 0.1 charges it, so waiting in front of a crowd costs nothing; with
# 5 it costs 0.05 d/d0 per step), evaluated every 5,000 actions on 20 seeds per
# scenario (10000-10019): RL_base (k2 = 0) and SRFM-aware (k2 = 0 until 125,000
# actions, then rising linearly to 2 by 150,000), each with training seeds 11-13. Both variants start from the same network
# and differ only in k2: the stage-2 RL_base runs are the SRFM-aware runs' control in
# the claim's tests (docs/rl.md). The shipped td3-base is the stage-1 checkpoint itself
# (it ranked above every stage-2 RL_base run in the evaluations); the shipped td3-srfm
# is the best.zip of the best stage-2 SRFM-aware seed (select_policy.py again). The
# export step writes the NumPy policy files the planners run (no JAX, torch or pickle
# needed) into srfm/policies/; the checkpoints they come from are kept in
# tools/rl/policies/ (not in the package). To re-export the shipped checkpoints only:
#
#     EXPORT_ONLY=1 tools/rl/train_policies.sh
#
# The evaluation (per-seed policies, 100-seed benchmark, the claim's tests, learning
# curves) runs at the end; alone with EVALUATE_ONLY=1. AFTER_TRAINING=1 does everything
# after the stage-2 runs (selection, export, evaluation). STAGE=2 skips stage 1 (it
# needs $RUNS/stage1_base.zip).
#
# A killed run resumes from its latest checkpoint and replay buffer:
#
#     RESUME=1 tools/rl/train_policies.sh
#
# Run from the repository root with the rl and sbx extras installed (make setup).
set -euo pipefail

RUNS=${RUNS:-runs}
EXPORT_ONLY=${EXPORT_ONLY:-0}
RESUME=${RESUME:-0}
STAGE=${STAGE:-1}
STEPS=${STEPS:-300000}
SEEDS=${SEEDS:-"1 2 3"}  # stage 1
STAGE2_SEEDS=${STAGE2_SEEDS:-"11 12 13"}
SRFM=${SRFM:-.venv/bin/srfm}
PYTHON=${PYTHON:-.venv/bin/python}
export NUMBA_NUM_THREADS=1 OMP_NUM_THREADS=1
mkdir -p "$RUNS"

export_policies() {
    # The NumPy policy files (srfm/policies/), from the checkpoints in tools/rl/policies/.
    for name in td3_base td3_srfm; do
        "$SRFM" export-policy "tools/rl/policies/$name.zip" "srfm/policies/$name" --eval-seeds 10 \
            --note "shipped ${name/_/-}; recipe and run: tools/rl/train_policies.sh, docs/rl.md"
    done
}
evaluate() {
    # Every stage-2 seed's best checkpoint as a NumPy policy (tools/rl/policies/) with its
    # evaluations (tools/rl/policies/evals/), the 100-seed benchmark of the shipped and
    # per-seed policies beside the classical planners, the claim's tests and the
    # learning curves (docs/rl.md).
    mkdir -p tools/rl/policies/evals
    for name in td3-base td3-srfm; do
        for seed in $STAGE2_SEEDS; do
            "$SRFM" export-policy "$RUNS/$name-seed$seed/best.zip" \
                "tools/rl/policies/${name/-/_}_seed$seed" \
                --note "$name, training seed $seed: best.zip of stage 2 of tools/rl/train_policies.sh"
            cp "$RUNS/$name-seed$seed/eval.jsonl" "tools/rl/policies/evals/$name-seed$seed.jsonl"
        done
    done
    mkdir -p tools/rl/policies/stage1
    for seed in $SEEDS; do
        if [ ! -d "$RUNS/stage1-seed$seed" ]; then
            echo "no $RUNS/stage1-seed$seed: keeping tools/rl/policies/stage1/td3_base_seed$seed" >&2
            continue
        fi
        "$SRFM" export-policy "$RUNS/stage1-seed$seed/best.zip" \
            "tools/rl/policies/stage1/td3_base_seed$seed" \
            --note "RL_base, training seed $seed: best.zip of stage 1 of tools/rl/train_policies.sh"
        cp "$RUNS/stage1-seed$seed/eval.jsonl" "tools/rl/policies/evals/stage1-seed$seed.jsonl"
    done
    seeds=""
    for seed in $STAGE2_SEEDS; do
        seeds+=",tools.rl.seed_planners:srfm_seed$seed,tools.rl.seed_planners:base_seed$seed"
    done
    for seed in $SEEDS; do
        seeds+=",tools.rl.seed_planners:stage1_seed$seed"
    done
    PYTHONPATH="$PWD${PYTHONPATH:+:$PYTHONPATH}" "$SRFM" benchmark -p "td3-srfm,td3-base,dwa,vo,orca,social-force,straight$seeds" \
        --seeds 0-99 --out "$RUNS/benchmark" --no-logs -j 2
    "$PYTHON" tools/rl/rl_claim.py "$RUNS/benchmark" > "$RUNS/claim.md"
    "$PYTHON" tools/rl/plot_learning_curves.py "$RUNS" docs/rl_learning_curves.png
}
ship() {
    # The shipped checkpoints: td3-base is the stage-1 start of stage 2 (the best
    # stage-1 seed), td3-srfm the best stage-2 SRFM-aware seed (select_policy.py). Each
    # is exported from its run folder, so that its policy file records that run's
    # configuration, command and evaluations.
    local pairs=()
    if compgen -G "$RUNS/stage1-seed*/" > /dev/null; then
        pairs+=("td3_base:$("$PYTHON" tools/rl/select_policy.py "$RUNS"/stage1-seed*/)")
    else
        echo "no $RUNS/stage1-seed*: keeping the shipped td3_base" >&2
    fi
    pairs+=("td3_srfm:$("$PYTHON" tools/rl/select_policy.py "$RUNS"/td3-srfm-seed*/)")
    for pair in "${pairs[@]}"; do
        name=${pair%%:*}
        cp "${pair#*:}" "tools/rl/policies/$name.zip"
        "$SRFM" export-policy "${pair#*:}" "srfm/policies/$name" --eval-seeds 10 \
            --note "shipped ${name/_/-}; recipe and run: tools/rl/train_policies.sh, docs/rl.md"
    done
}
train() {
    # One run in the background: train RUN_DIR OPTIONS...; RESUME=1 continues it.
    local run=$1
    shift
    local start=()
    if [ "$RESUME" = 1 ] && [ -f "$run/latest.zip" ]; then
        start=(--resume "$run/latest.zip")
    fi
    nice -n 10 "$SRFM" train --run-dir "$run" "$@" "${start[@]}" >> "$run.log" 2>&1 &
}
if [ "${AFTER_TRAINING:-0}" = 1 ]; then
    ship
    evaluate
    exit 0
fi
if [ "$EXPORT_ONLY" = 1 ]; then
    export_policies
    exit 0
fi
if [ "${EVALUATE_ONLY:-0}" = 1 ]; then
    evaluate
    exit 0
fi

common=(--scenario mixed --action-repeat 4 --backend sbx --net-arch 64,64
    --train-freq 50 --gradient-steps 50 --learning-rate 3e-4 --steps "$STEPS" --eval-every 25000
    --eval-seeds 10 --no-progress)

if [ "$STAGE" = 1 ]; then
    for seed in $SEEDS; do
        train "$RUNS/stage1-seed$seed" --seed "$seed" --k-div 0 --checkpoint-every 50000 \
            --k-progress 10 "${common[@]}"
    done
    wait
    best=$("$PYTHON" tools/rl/select_policy.py "$RUNS"/stage1-seed*/)
    cp "$best" "$RUNS/stage1_base.zip"
    echo "stage 1: $best is the start of stage 2"
fi

stage2=(--success-reward 100 --timeout-penalty 100 --k-progress 5 --checkpoint-every 25000
    "${common[@]}" --steps 225000 --eval-every 5000 --eval-seeds 20)
for seed in $STAGE2_SEEDS; do
    # a fresh stage-2 run starts from stage 1; RESUME=1 continues a started one instead
    from=(--resume "$RUNS/stage1_base.zip")
    if [ "$RESUME" = 1 ] && [ -f "$RUNS/td3-base-seed$seed/latest.zip" ]; then from=(); fi
    train "$RUNS/td3-base-seed$seed" --seed "$seed" --k-div 0 "${stage2[@]}" "${from[@]}"
    from=(--resume "$RUNS/stage1_base.zip")
    if [ "$RESUME" = 1 ] && [ -f "$RUNS/td3-srfm-seed$seed/latest.zip" ]; then from=(); fi
    train "$RUNS/td3-srfm-seed$seed" --seed "$seed" --k-div 2 --k-div-start 125000 \
        --k-div-ramp 25000 "${stage2[@]}" "${from[@]}"
done
wait

ship
evaluate
