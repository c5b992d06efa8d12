"""What range beams cost the environment's training step: microseconds per step of
``SocialNavEnv`` in the training set-up (no full counterfactual twin) without and with
range beams, per scenario.

    PYTHONPATH=. python tools/bench/bench_range_beams.py --json docs/rl/range_beams.json

One environment in one process, random actions drawn up front (uniform in [-1, 1]²,
seed 0), episodes reset as they end (the resets are inside the timed loop). Per
scenario and beam count: one untimed warm-up block, then ``--repeats`` timed blocks of
``--steps`` steps; the figure is the best block (the least disturbed). ``--json`` writes
every block's time per step with the run's record (``tools/results/record.py``: command,
commit, date, wall time, load); run it with every other job paused
(``flock /tmp/measure.lock /work/wt/freeze_measure.sh ...``).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from tools.results.record import run_record, start  # noqa: E402

SCENARIOS = ("random", "entering_room", "corridor_flow")


def step_times(scenario: str, beams: int, steps: int, repeats: int) -> list[float]:
    """Microseconds per step of each timed block."""
    from srfm.rl import EnvConfig, SocialNavEnv

    config = EnvConfig(counterfactual_twin=False, range_beams=beams, range_max_m=4.0)
    env = SocialNavEnv(scenario, config)
    env.reset(seed=0)
    actions = np.random.default_rng(0).uniform(-1.0, 1.0, (steps, 2)).astype(np.float32)

    def block() -> float:
        t0 = time.perf_counter()
        for a in actions:
            _, _, terminated, truncated, _ = env.step(a)
            if terminated or truncated:
                env.reset()
        return (time.perf_counter() - t0) / steps * 1e6

    block()  # warm-up: kernels loaded, first episodes
    return [block() for _ in range(repeats)]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=(__doc__ or "").split("\n\n")[0])
    ap.add_argument("--scenarios", nargs="+", default=list(SCENARIOS))
    ap.add_argument("--beams", type=int, default=24, help="range beams, set beside 0")
    ap.add_argument("--steps", type=int, default=50_000, help="steps per timed block")
    ap.add_argument("--repeats", type=int, default=5, help="timed blocks per row")
    ap.add_argument("--json", type=Path, help="also write the figures here")
    args = ap.parse_args(argv)
    if args.beams < 1 or args.steps < 1 or args.repeats < 1:
        raise SystemExit(
            f"--beams, --steps and --repeats must be positive, got {args.beams}, "
            f"{args.steps}, {args.repeats}"
        )
    started, t0, load = start()
    rows = []
    print("| scenario | beams | µs per step (best) | median |")
    print("|---|---:|---:|---:|")
    for scenario in args.scenarios:
        for beams in (0, args.beams):
            times = step_times(scenario, beams, args.steps, args.repeats)
            rows.append({"scenario": scenario, "beams": beams, "us_per_step": times})
            print(f"| {scenario} | {beams} | {min(times):.1f} | {float(np.median(times)):.1f} |")
    if args.json is not None:
        doc = {
            "steps": args.steps,
            "repeats": args.repeats,
            "range_max_m": 4.0,
            "rows": rows,
            "run": run_record(started, t0, load),
        }
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(doc, indent=1) + "\n", encoding="utf-8")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
