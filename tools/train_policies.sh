#!/usr/bin/env bash
# The recipe of the two shipped TD3 policies; docs/rl.md records the runs, their wall
# times and how every choice was reached.
#
# Six runs, started together: RL_base (k2 = 0) and SRFM-aware (k2 = 2, reached by a
# curriculum: 0 until 25,000 steps, then a linear ramp over 75,000 steps), each with
# training seeds 1, 2 and 3. Every run trains SBX TD3 ([64, 64], 50 gradient steps every
# 50 steps, learning rate 3e-4) for 300,000 actions on the mixed training layouts
# (srfm.scenarios.training), each action held for 4 simulation steps (action repeat
# 4: 0.27 s), with the paper's reward plus the potential-based progress term
# (k_progress = 10). Training never sees the benchmark's seeds 0-99 nor the evaluation
# scenarios' layouts; it is evaluated every 25,000 steps on the five evaluation
# scenarios with seeds 10000-10009, and keeps its best checkpoint (best.zip).
#
# The shipped policy of each variant is the best.zip of the training seed whose best
# evaluation ranks first (higher success, then fewer collisions, then less deviation;
# tools/select_policy.py). The export step writes the NumPy policy files the planners
# run (no JAX, torch or pickle needed). To re-export the shipped checkpoints only:
#
#     EXPORT_ONLY=1 tools/train_policies.sh
#
# The evaluation (per-seed policies, 100-seed benchmark, the claim's tests, learning
# curves) runs at the end; alone with EVALUATE_ONLY=1. AFTER_TRAINING=1 does everything
# after the training runs (selection, export, evaluation).
#
# A killed run resumes from its latest checkpoint and replay buffer:
#
#     RESUME=1 tools/train_policies.sh
#
# Run from the repository root with the rl and sbx extras installed (make setup).
set -euo pipefail

RUNS=${RUNS:-runs}
EXPORT_ONLY=${EXPORT_ONLY:-0}
RESUME=${RESUME:-0}
STEPS=${STEPS:-300000}
SEEDS=${SEEDS:-"1 2 3"}
SRFM=${SRFM:-.venv/bin/srfm}
PYTHON=${PYTHON:-.venv/bin/python}
export NUMBA_NUM_THREADS=1 OMP_NUM_THREADS=1
mkdir -p "$RUNS"

export_policies() {
    # The NumPy policy files, from the checkpoints in srfm/policies/.
    for name in td3_base td3_srfm; do
        "$SRFM" export-policy "srfm/policies/$name.zip" "srfm/policies/$name" --eval-seeds 10 \
            --note "shipped ${name/_/-}; recipe and run: tools/train_policies.sh, docs/rl.md"
    done
}
evaluate() {
    # Every training seed's best checkpoint as a NumPy policy (tools/policies/), the
    # 100-seed benchmark of the shipped and per-seed policies beside the classical
    # planners, the claim's tests and the learning curves (docs/rl.md).
    for name in td3-base td3-srfm; do
        for seed in $SEEDS; do
            "$SRFM" export-policy "$RUNS/$name-seed$seed/best.zip" \
                "tools/policies/${name/-/_}_seed$seed" \
                --note "$name, training seed $seed: best.zip of tools/train_policies.sh"
        done
    done
    seeds=""
    for seed in $SEEDS; do
        seeds+=",tools.seed_planners:srfm_seed$seed,tools.seed_planners:base_seed$seed"
    done
    PYTHONPATH="$PWD${PYTHONPATH:+:$PYTHONPATH}" "$SRFM" benchmark -p "td3-srfm,td3-base,dwa,vo,orca,social-force,straight$seeds" \
        --seeds 0-99 --out "$RUNS/benchmark" --no-logs -j 2
    "$PYTHON" tools/rl_claim.py "$RUNS/benchmark" > "$RUNS/claim.md"
    "$PYTHON" tools/plot_learning_curves.py "$RUNS" docs/rl_learning_curves.png
}
ship() {
    # The shipped checkpoint of each variant: the best training seed (select_policy.py).
    for name in td3-base td3-srfm; do
        best=$("$PYTHON" tools/select_policy.py "$RUNS"/"$name"-seed*/)
        cp "$best" "srfm/policies/${name/-/_}.zip"
        echo "shipped $best as srfm/policies/${name/-/_}.zip"
    done
}
if [ "${AFTER_TRAINING:-0}" = 1 ]; then
    ship
    export_policies
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

common=(--scenario mixed --k-progress 10 --action-repeat 4 --backend sbx --net-arch 64,64
    --train-freq 50 --gradient-steps 50 --learning-rate 3e-4 --steps "$STEPS" --eval-every 25000
    --eval-seeds 10 --checkpoint-every 50000 --no-progress)
declare -A variant=([td3-base]="--k-div 0" [td3-srfm]="--k-div 2 --k-div-start 25000 --k-div-ramp 75000")

for name in td3-base td3-srfm; do
    for seed in $SEEDS; do
        run="$RUNS/$name-seed$seed"
        resume=()
        if [ "$RESUME" = 1 ] && [ -f "$run/latest.zip" ]; then
            resume=(--resume "$run/latest.zip")
        fi
        # shellcheck disable=SC2086  # the variant's options are words
        nice -n 10 "$SRFM" train --run-dir "$run" --seed "$seed" ${variant[$name]} \
            "${common[@]}" "${resume[@]}" >> "$run.log" 2>&1 &
    done
done
wait

ship
export_policies
evaluate
