"""How large the deviation term r_div of the reward is under random actions (docs/rl.md,
"Reward"): the share of steps where it is non-zero, its mean and 99th percentile.

    python tools/rl/reward_stats.py [--steps 50000] [--seed 0] [--json docs/rl/reward_stats.json]

Runs ``SocialNavEnv("random")`` with the default ``EnvConfig`` and uniformly random
actions (the action space seeded with ``--seed``; episodes reset with ``--seed``, then
from the environment's own stream) for ``--steps`` steps, and collects ``info["r_div"]``
of every step. Deterministic for a seed. ``--json`` writes the figures with the command,
the commit and the date: the data of the generated sentence in docs/rl.md.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path:  # run as a script from the repository's root
    sys.path.insert(0, str(ROOT))

from tools.results.record import source_commit  # noqa: E402


def measure(steps: int, seed: int) -> dict[str, float]:
    """The share of the steps with r_div > 0, its mean and 99th percentile (m)."""
    from srfm.rl.env import SocialNavEnv

    env = SocialNavEnv("random")
    env.action_space.seed(seed)
    env.reset(seed=seed)
    values = np.empty(steps)
    for k in range(steps):
        _, _, terminated, truncated, info = env.step(env.action_space.sample())
        values[k] = info["r_div"]
        if terminated or truncated:
            env.reset()
    return {
        "steps": steps,
        "nonzero_share": float(np.mean(values > 0.0)),
        "mean_m": float(values.mean()),
        "p99_m": float(np.percentile(values, 99)),
    }


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--steps", type=int, default=50_000)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--json", type=Path)
    args = ap.parse_args(argv)
    started = time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())
    figures = measure(args.steps, args.seed)
    print(
        f"r_div > 0 in {100 * figures['nonzero_share']:.1f} % of {args.steps} steps; mean "
        f"{figures['mean_m']:.4f} m, 99th percentile {figures['p99_m']:.4f} m"
    )
    if args.json is not None:
        commit = source_commit()
        doc = {
            "command": "python tools/rl/reward_stats.py "
            + " ".join(sys.argv[1:] if argv is None else argv),
            "commit": commit,
            "started": started,
            "seed": args.seed,
            **figures,
        }
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(doc, indent=1) + "\n", encoding="utf-8")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
