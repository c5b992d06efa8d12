"""Train a small TD3 policy for a few thousand steps and benchmark it as a planner.

    pip install -e '.[rl]' -c constraints.txt   # gymnasium, stable-baselines3, torch (CPU)
    python examples/04_train_policy.py          # 5,000 steps (a few minutes on 2 cores)
    python examples/04_train_policy.py --fast   # 300 steps: shows the steps, learns nothing

The environment is srfm/SocialNav-v0 (the paper's observation and reward: goal distance
plus k2 × the one-step deviation the robot causes, docs/rl.md) on the randomised
training scenario. The run writes checkpoints; the last one is exported to a NumPy
policy file, which runs as a planner with NumPy only (no torch), like the shipped
td3-srfm and td3-base. The paper trains 2 million steps: a policy of a few thousand
steps has not learned to reach its goal yet, so compare it with the shipped ones.
`srfm train --run-dir DIR --steps N` and `srfm export-policy` do the same from the shell.
"""

import os
import sys
from pathlib import Path

import srfm
from srfm.planners.td3 import TD3Planner
from srfm.rl.training import TrainConfig, evaluate_planner, export_policy, train

FAST = "--fast" in sys.argv or os.environ.get("SRFM_EXAMPLES_FAST") == "1"
OUT = Path(os.environ.get("SRFM_EXAMPLES_OUT", "out/examples")) / "04_train_policy"

config = TrainConfig(
    total_steps=300 if FAST else 5_000,  # environment steps (one step = 1/15 s)
    learning_starts=100 if FAST else 1_000,  # random actions first, to fill the buffer
    buffer_size=50_000,
    batch_size=64,
    net_arch=(64, 64),  # the paper: (256, 256)
    k_div=2.0,  # the deviation penalty k2 (1/m): 0 trains the RL_base variant
    eval_every=0,  # no periodic evaluation; we evaluate below
    checkpoint_every=0,  # only the final checkpoint
    seed=1,
)
result = train(config, OUT / "run", log=print)
print(f"trained {result.steps} steps in {result.wall_time_s:.0f} s -> {result.run_dir}")

# Export the final checkpoint (SB3 zip, unpickled: trusted files only) to a NumPy policy.
policy_json, _ = export_policy(OUT / "run" / "latest.zip", OUT / "my_policy")

# Evaluate it as a planner on the paper's scenarios, beside the shipped td3-srfm.
scenarios = ["crosswalk"] if FAST else list(srfm.EVALUATION_SCENARIOS)
seeds = [0] if FAST else [0, 1, 2]
for name, make in (
    ("my-td3", lambda: TD3Planner(policy_json, name="my-td3")),
    ("td3-srfm", lambda: "td3-srfm"),  # a planner name works too
):
    ev = evaluate_planner(make, scenarios, seeds)
    print(
        f"{name:>9}: success {ev.success_rate:.0%}, collisions {ev.collision_rate:.0%}, "
        f"mean deviation {ev.mean_deviation_m:.3f} m over {ev.episodes} episodes"
    )
# To benchmark it: srfm.planners.register_planner("my-td3", lambda: TD3Planner(path,
# "my-td3"), "my policy"), then run_benchmark as in 01_own_planner.py.
