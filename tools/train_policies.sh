#!/usr/bin/env bash
# The recipe of the two shipped TD3 policies, srfm/policies/td3_srfm.zip (SRFM-aware,
# k2 = 2) and srfm/policies/td3_base.zip (RL_base, k2 = 0). docs/rl.md records the
# steps, the wall time and the machine of the shipped run.
#
# Both runs train in parallel with the paper's TD3 set-up (the srfm train defaults),
# seed 0, one torch thread each, niced, into $RUNS (default: runs/, outside the
# package). A run stopped at step N holds the same policy as one started with
# --steps N, so the shipped files are reproduced by training to the shipped steps and
# copying those checkpoints:
#
#     tools/train_policies.sh              # train both (hours), then copy the checkpoints
#     RUNS=/tmp/runs tools/train_policies.sh
#
# Run from the repository root with the rl extra installed.
set -euo pipefail

RUNS=${RUNS:-runs}
SRFM_STEPS=${SRFM_STEPS:-SRFM_STEPS_PLACEHOLDER}
BASE_STEPS=${BASE_STEPS:-BASE_STEPS_PLACEHOLDER}
SRFM=${SRFM:-.venv/bin/srfm}
export NUMBA_NUM_THREADS=1 OMP_NUM_THREADS=1
mkdir -p "$RUNS"

common=(--seed 0 --eval-every 25000 --eval-seeds 10 --checkpoint-every 25000 --no-progress)
nice -n 10 "$SRFM" train --run-dir "$RUNS/td3-srfm" --k-div 2.0 --steps "$SRFM_STEPS" \
    "${common[@]}" > "$RUNS/td3-srfm.log" 2>&1 &
nice -n 10 "$SRFM" train --run-dir "$RUNS/td3-base" --k-div 0 --steps "$BASE_STEPS" \
    "${common[@]}" > "$RUNS/td3-base.log" 2>&1 &
wait

printf -v srfm_ckpt 'step_%09d.zip' "$SRFM_STEPS"
printf -v base_ckpt 'step_%09d.zip' "$BASE_STEPS"
cp "$RUNS/td3-srfm/checkpoints/$srfm_ckpt" srfm/policies/td3_srfm.zip
cp "$RUNS/td3-base/checkpoints/$base_ckpt" srfm/policies/td3_base.zip
echo "shipped $RUNS/td3-srfm/checkpoints/$srfm_ckpt and $RUNS/td3-base/checkpoints/$base_ckpt"
