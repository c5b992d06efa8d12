"""Planning cost per step: microseconds per ``Planner.act`` call, per planner and scenario.

For each planner and evaluation scenario, the script runs the episodes of seeds
``0 .. --seeds − 1`` once, recording every observation the planner was given (so the
workload is exactly what the benchmark sees: the pedestrians inside the planner's
detection range at every step while the robot is active). It then resets a fresh
planner with the same episode context and replays the recorded observations through
``act`` in a tight loop, ``--repeats`` times, timing each pass with
``time.perf_counter`` (``--clock cpu``: ``time.process_time``, the process's own CPU
time, steadier on a machine that other jobs load); the best pass is reported as µs
per act (mean over the calls of that pass). The planners keep no state between steps
that depends on the observations, so a replay does the same work as the live episode.

The calls with at least one pedestrian in range and those with none are also replayed
separately (each its own best pass), since the kernels skip most work when nobody is
in range. The script also reports the mean number of observed pedestrians per call,
the share of calls with someone in range, and the median wall time of a whole episode
(``srfm.run_episode(..., parallel=False)``), which includes both crowds' simulation.

``--detection-range`` overrides every planner's range (``none``: everyone observed, a
heavier load than the benchmark's).

Usage::

    NUMBA_NUM_THREADS=1 .venv/bin/python tools/bench/bench_planners.py
    .venv/bin/python tools/bench/bench_planners.py --seeds 5 --planners dwa orca
    .venv/bin/python tools/bench/bench_planners.py --detection-range none
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from srfm.planners import Observation

DEFAULT_PLANNERS = ("straight", "dwa", "vo", "orca", "social-force")


class Recorder:
    """Wraps a planner and keeps every observation it is given."""

    def __init__(self, planner: Any) -> None:
        self.inner = planner
        self.name = planner.name
        self.detection_range_m = planner.detection_range_m
        self.observations: list[Observation] = []
        self.context: Any = None

    def reset(self, context: Any, rng: np.random.Generator) -> None:
        """Reset the wrapped planner and remember the context."""
        self.context = context
        self.inner.reset(context, rng)

    def act(self, observation: Observation) -> Any:
        """Record, then delegate."""
        self.observations.append(observation)
        return self.inner.act(observation)


def _cpu_busy_other() -> tuple[int, int]:
    with open("/proc/stat", encoding="ascii") as f:
        fields = [int(x) for x in f.readline().split()[1:]]
    idle = fields[3] + fields[4]
    return sum(fields) - idle, sum(fields)


def _self_cpu_ticks() -> int:
    t = os.times()
    return round((t.user + t.system) * os.sysconf("SC_CLK_TCK"))


CLOCKS: dict[str, Callable[[], float]] = {"wall": time.perf_counter, "cpu": time.process_time}


def _replay(
    planners: list[Any], calls: list[list[Observation]], repeats: int, clock: Callable[[], float]
) -> tuple[float, int]:
    """Best of ``repeats`` timed passes over ``calls``: (µs per act, number of acts)."""
    n_calls = sum(len(obs) for obs in calls)
    if n_calls == 0:
        return float("nan"), 0
    best = float("inf")
    for _ in range(repeats):
        t0 = clock()
        for p, obs in zip(planners, calls, strict=True):
            act = p.act
            for o in obs:
                act(o)
        best = min(best, clock() - t0)
    return best / n_calls * 1e6, n_calls


def _planner(name: str, detection: str | None) -> Any:
    from srfm.planners import make_planner

    planner = make_planner(name)
    if detection is not None:
        planner.detection_range_m = None if detection == "none" else float(detection)
    return planner


def bench(
    planner_name: str,
    scenario: str,
    seeds: int,
    repeats: int,
    detection: str | None,
    clock: Callable[[], float] = time.perf_counter,
) -> dict[str, float]:
    """µs per act (all calls, calls with and without observed pedestrians), mean
    observed pedestrians, calls, median episode ms."""
    import srfm

    try:
        from srfm.sim.episode import planner_rng
    except ImportError:  # the layout before issue 11, for side-by-side runs
        from srfm.episode import planner_rng  # type: ignore[import-not-found,no-redef]

    calls: list[tuple[Any, list[Observation]]] = []
    episode_s: list[float] = []
    for seed in range(seeds):
        rec = Recorder(_planner(planner_name, detection))
        srfm.run_episode(scenario, seed, rec, parallel=False)
        calls.append((rec.context, rec.observations))
        t0 = time.perf_counter()
        srfm.run_episode(scenario, seed, _planner(planner_name, detection), parallel=False)
        episode_s.append(time.perf_counter() - t0)
    peds = sum(int(o.ped_ids.shape[0]) for _, obs in calls for o in obs)
    planners = [_planner(planner_name, detection) for _ in calls]
    for p, (context, _) in zip(planners, calls, strict=True):
        p.reset(context, planner_rng(context.seed))
    every = [obs for _, obs in calls]
    seen = [[o for o in obs if o.ped_ids.shape[0] > 0] for obs in every]
    empty = [[o for o in obs if o.ped_ids.shape[0] == 0] for obs in every]
    us_all, n_all = _replay(planners, every, repeats, clock)
    us_seen, n_seen = _replay(planners, seen, repeats, clock)
    us_empty, n_empty = _replay(planners, empty, repeats, clock)
    return {
        "us": us_all,
        "calls": n_all,
        "us_seen": us_seen,
        "calls_seen": n_seen,
        "us_empty": us_empty,
        "calls_empty": n_empty,
        "peds": peds / n_all,
        "episode_ms": statistics.median(episode_s) * 1e3,
    }


def _pooled(per: dict[str, dict[str, float]], key: str, calls: str) -> str:
    """Mean µs per act over the scenarios, weighted by their numbers of calls."""
    pairs = [(r[key], r[calls]) for r in per.values() if r[calls] > 0]
    if not pairs:
        return "–"
    return f"{sum(us * n for us, n in pairs) / sum(n for _, n in pairs):.1f}"


def _commit() -> str:
    root = Path(__file__).resolve().parents[2]
    try:
        out = subprocess.run(
            ["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True, check=True,
            cwd=root,
        )  # fmt: skip
        dirty = subprocess.run(
            ["git", "status", "--porcelain", "--", "srfm"], capture_output=True, text=True,
            check=True, cwd=root,
        )  # fmt: skip
    except (OSError, subprocess.CalledProcessError):
        return "unknown"
    return out.stdout.strip() + (" (srfm/ modified)" if dirty.stdout.strip() else "")


def parse_args(argv: list[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(
        description=__doc__.split("\n\n")[0] if __doc__ else None,
        formatter_class=argparse.ArgumentDefaultsHelpFormatter,
    )
    parser.add_argument("--seeds", type=int, default=10, help="episodes per scenario")
    parser.add_argument("--repeats", type=int, default=5, help="timed replays; the best counts")
    parser.add_argument(
        "--clock",
        choices=sorted(CLOCKS),
        default="wall",
        help="time the replays in wall or CPU time",
    )
    parser.add_argument("--planners", nargs="+", default=list(DEFAULT_PLANNERS), metavar="NAME")
    parser.add_argument(
        "--scenarios", nargs="+", metavar="NAME", help="default: the evaluation set"
    )
    parser.add_argument(
        "--detection-range",
        metavar="M|none",
        help="override every planner's detection range (m); none: observe everyone",
    )
    return parser.parse_args(argv)


def main(argv: list[str] | None = None) -> int:
    args = parse_args(argv)
    import numba

    import srfm

    scenarios = args.scenarios or list(srfm.EVALUATION_SCENARIOS)
    t0 = time.perf_counter()
    srfm.run_episode(scenarios[0], 0, args.planners[0], parallel=False)  # load the kernels
    for name in args.planners:
        srfm.run_episode(scenarios[0], 0, name, parallel=False)
    warm = time.perf_counter() - t0
    busy0, total0 = _cpu_busy_other()
    self0 = _self_cpu_ticks()
    load0 = os.getloadavg()[0]
    rows: dict[str, dict[str, dict[str, float]]] = {}
    for name in args.planners:
        rows[name] = {
            s: bench(name, s, args.seeds, args.repeats, args.detection_range, CLOCKS[args.clock])
            for s in scenarios
        }
    busy1, total1 = _cpu_busy_other()
    self1 = _self_cpu_ticks()
    other = max(0, (busy1 - busy0) - (self1 - self0)) / max(1, total1 - total0)
    print(
        f"srfm commit {_commit()}; Python {platform.python_version()}, numpy {np.__version__}, "
        f"numba {numba.__version__} ({numba.config.NUMBA_NUM_THREADS} threads); "
        f"{os.cpu_count()} CPUs; load average {load0:.2f} at the start; other processes "
        f"used {100 * other:.1f} % of the machine's CPU time during the run; seeds "
        f"0..{args.seeds - 1}, best of {args.repeats} replays ({args.clock} time); warm-up "
        f"{warm:.1f} s; detection "
        f"range {args.detection_range or 'as configured'}"
    )
    print("\nµs per act (mean over the recorded calls of the best replay):\n")
    print("| planner | " + " | ".join(scenarios) + " | all | with people in range | without |")
    print("|---|" + "---:|" * (len(scenarios) + 3))
    for name, per in rows.items():
        cells = " | ".join(f"{per[s]['us']:.1f}" for s in scenarios)
        print(
            f"| {name} | {cells} | {_pooled(per, 'us', 'calls')}"
            f" | {_pooled(per, 'us_seen', 'calls_seen')}"
            f" | {_pooled(per, 'us_empty', 'calls_empty')} |"
        )
    print(
        "\nMean observed pedestrians per call / share of calls with someone in range / "
        "calls per episode / median episode (ms):\n"
    )
    print("| planner | " + " | ".join(scenarios) + " |")
    print("|---|" + "---|" * len(scenarios))
    for name, per in rows.items():
        cells = " | ".join(
            f"{per[s]['peds']:.2f} / {100 * per[s]['calls_seen'] / per[s]['calls']:.0f} % / "
            f"{per[s]['calls'] / args.seeds:.0f} / {per[s]['episode_ms']:.1f}"
            for s in scenarios
        )
        print(f"| {name} | {cells} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
