"""Wall-clock time of full twin episodes, ``srfm.run_episode``, per built-in scenario.

Two planners are timed on every scenario, over the seeds ``0 .. --seeds-1``, each
episode running the scenario's full horizon (750 steps of 1/15 s by default) for both
twin crowds:

* ``straight``, the built-in baseline: ``srfm.run_episode(name, seed, "straight")``.
  The robot's episode may end early (goal reached, collision), after which the planner
  is no longer called but the crowds keep stepping to the horizon.
* ``stay``, defined here: commands zero velocity and observes every pedestrian, so the
  robot stays active (and is observed and commanded) for the whole horizon and times
  out: the worst case for the per-step Python overhead.

The first episode in the process, which compiles the numba kernels (or loads them from
numba's on-disk cache), is timed and reported separately; every scenario is then run
once untimed before its seeds are timed with ``time.perf_counter``.

With ``--walls`` it times instead what walls cost (issue 17): every built-in scenario
with walls or pillars, with the ``stay`` planner (the robot's route is followed and
updated at every step), once as it is and once with its obstacles removed (the same
people and robot, no wall forces, no routes), and prints the ratio.

Usage::

    .venv/bin/python tools/bench/bench_episode.py
    .venv/bin/python tools/bench/bench_episode.py --seeds 50 --scenarios footpath circle
    .venv/bin/python tools/bench/bench_episode.py --walls --seeds 10
    .venv/bin/python tools/bench/bench_episode.py --json docs/results/performance/episodes.json

``--json PATH`` also writes every episode's time, per scenario and planner, with the
run's record (``tools/results/record.py``): the data docs/performance.md's "Full
episodes" table is generated from (``make docs-tables``).
"""

from __future__ import annotations

import argparse
import collections
import importlib
import os
import statistics
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

if TYPE_CHECKING:
    from srfm.planners import Observation, Planner, PlannerContext
    from srfm.scenarios import Scenario


class StayPlanner:
    """Commands zero velocity at every step and observes every pedestrian."""

    name = "stay"
    detection_range_m: float | None = None

    def reset(self, context: PlannerContext, rng: np.random.Generator) -> None:
        """Nothing to prepare."""

    def act(self, observation: Observation) -> NDArray[np.float64]:
        """Zero velocity: (v, ω) = (0, 0) for a unicycle, (vx, vy) = (0, 0) otherwise."""
        return np.zeros(2)


@dataclass(frozen=True)
class Row:
    """Timings of one scenario and planner over the seeds."""

    scenario: str
    pedestrians: int
    horizon: int
    active_steps: float  # median number of steps with the robot active
    outcomes: str
    times_s: list[float]


def time_scenario(name: str | Scenario, planner: str | Planner, seeds: int) -> Row:
    """Run ``seeds`` episodes of ``name`` after one untimed warm-up episode."""
    import srfm

    label = name if isinstance(name, str) else name.name
    srfm.run_episode(name, 0, planner)
    times: list[float] = []
    active: list[int] = []
    outcomes: collections.Counter[str] = collections.Counter()
    n = horizon = 0
    for seed in range(seeds):
        t0 = time.perf_counter()
        record = srfm.run_episode(name, seed, planner)
        times.append(time.perf_counter() - t0)
        n = record.factual_pos.shape[1]
        horizon = record.horizon_steps
        active.append(int(np.count_nonzero(record.robot_active[:-1])))
        outcomes[record.outcome] += 1
    summary = ", ".join(f"{k} {v}" for k, v in sorted(outcomes.items()))
    return Row(label, n, horizon, statistics.median(active), summary, times)


def print_table(title: str, rows: list[Row]) -> None:
    """One Markdown table of episode times (ms) with per-step cost."""
    print(f"\n{title}\n")
    print(
        "| scenario | pedestrians | steps | robot active steps (median) | median (ms) | min (ms)"
        " | max (ms) | median per step (µs) | robot outcomes |"
    )
    print("|---|---:|---:|---:|---:|---:|---:|---:|---|")
    for r in rows:
        med = statistics.median(r.times_s)
        print(
            f"| {r.scenario} | {r.pedestrians} | {r.horizon} | {r.active_steps:g}"
            f" | {med * 1e3:.1f} | {min(r.times_s) * 1e3:.1f} | {max(r.times_s) * 1e3:.1f}"
            f" | {med / r.horizon * 1e6:.1f} | {r.outcomes} |"
        )


def wall_costs(names: list[str], seeds: int) -> None:
    """Median episode time of each walled scenario, with and without its obstacles."""
    import attrs

    from srfm.models.state import Obstacles
    from srfm.scenarios import load_scenario

    print("\nPlanner `stay`, full horizon; with walls (routes on) vs the same without obstacles:\n")
    print("| scenario | pedestrians | walls | pillars | with (ms) | without (ms) | ratio |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    ratios = []
    for name in names:
        scenario = load_scenario(name)
        if scenario.obstacles.empty:
            continue
        bare = attrs.evolve(scenario, obstacles=Obstacles())
        with_walls = statistics.median(time_scenario(scenario, StayPlanner(), seeds).times_s)
        without = statistics.median(time_scenario(bare, StayPlanner(), seeds).times_s)
        ratios.append(with_walls / without)
        print(
            f"| {name} | {scenario.n_pedestrians} | {scenario.obstacles.segments.shape[0]}"
            f" | {scenario.obstacles.circles.shape[0]} | {with_walls * 1e3:.1f}"
            f" | {without * 1e3:.1f} | {with_walls / without:.2f} |"
        )
    print(f"\n- ratio: median {statistics.median(ratios):.2f}, max {max(ratios):.2f}")


def parse_args(argv: list[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(
        description=__doc__.split("\n\n")[0] if __doc__ else None,
        formatter_class=argparse.ArgumentDefaultsHelpFormatter,
    )
    parser.add_argument("--seeds", type=int, default=20, help="episodes timed per scenario")
    parser.add_argument(
        "--scenarios", nargs="+", metavar="NAME", help="built-in scenarios to time (default: all)"
    )
    parser.add_argument(
        "--walls", action="store_true", help="time scenarios with walls against without"
    )
    parser.add_argument("--json", type=Path, default=None, help="also write the figures here")
    parser.add_argument(
        "--cold-cache",
        action="store_true",
        help="use an empty numba cache so the first episode includes a full JIT compile",
    )
    args = parser.parse_args(argv)
    if args.seeds < 1:
        parser.error("--seeds must be >= 1")
    return args


def main(argv: list[str] | None = None) -> int:
    args = parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="srfm-bench-") as tmp:
        if args.cold_cache:
            os.environ["NUMBA_CACHE_DIR"] = str(Path(tmp) / "numba-cache")  # before numba loads
        t0 = time.perf_counter()
        importlib.import_module("srfm")
        import_s = time.perf_counter() - t0

        # The machine description is shared with the crowd-step benchmark (same folder).
        from bench_crowd_step import OtherLoad, load_average, machine_info

        import srfm
        from srfm.scenarios import BUILTIN_SCENARIOS

        names: list[str] = args.scenarios or list(BUILTIN_SCENARIOS)
        unknown = sorted(set(names) - set(BUILTIN_SCENARIOS))
        if unknown:
            raise SystemExit(f"unknown scenario(s) {unknown}; built-in: {list(BUILTIN_SCENARIOS)}")

        sys.path.insert(0, str(Path(__file__).resolve().parents[2]))
        from tools.results import record

        begun = record.start()
        other = OtherLoad()
        t0 = time.perf_counter()
        srfm.run_episode(names[0], 0, "straight")
        first_s = time.perf_counter() - t0

        print("## Episode wall-clock time (one twin episode, lower is better)\n")
        print(*machine_info(), sep="\n")
        print(f"- {args.seeds} seeds per scenario (0 .. {args.seeds - 1}), default kernel choice")
        print(f"- import srfm: {import_s:.2f} s")
        print(
            f"- first episode in the process ({names[0]}, seed 0, straight; JIT compile or"
            f" numba cache load, cache {'cold' if args.cold_cache else 'as found'}):"
            f" {first_s:.2f} s"
        )

        if args.walls:
            wall_costs(names, args.seeds)
            print(
                f"\n- load average (1, 5, 15 min) at end: {load_average()}; other processes"
                f" used {other.percent():.1f} % of the machine's CPU time"
            )
            return 0
        straight = [time_scenario(name, "straight", args.seeds) for name in names]
        print_table("Planner `straight` (robot episode may end before the horizon):", straight)
        stay = [time_scenario(name, StayPlanner(), args.seeds) for name in names]
        print_table("Planner `stay` (zero velocity, observes everyone; active all steps):", stay)
        other_percent = other.percent()
        print(
            f"\n- load average (1, 5, 15 min) at end: {load_average()}; other processes used"
            f" {other_percent:.1f} % of the machine's CPU time during the measurements"
        )
        if args.json is not None:
            record.write_json(
                args.json,
                {
                    "seeds": args.seeds,
                    "numba_cache": "cold" if args.cold_cache else "as found",
                    "first_episode_s": first_s,
                    "other_cpu_percent": other_percent,
                    "planners": {
                        "straight": [_row_dict(r) for r in straight],
                        "stay": [_row_dict(r) for r in stay],
                    },
                },
                begun,
            )
    return 0


def _row_dict(row: Row) -> dict[str, object]:
    return {
        "scenario": row.scenario,
        "pedestrians": row.pedestrians,
        "horizon_steps": row.horizon,
        "active_steps_median": row.active_steps,
        "outcomes": row.outcomes,
        "times_s": row.times_s,
    }


if __name__ == "__main__":
    raise SystemExit(main())
