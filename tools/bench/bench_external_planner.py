"""The external planner protocol's overhead: per control step and per 750-step episode
(issue 44's targets: at most 50 µs median per step, 40 ms per 750-step episode).

The C++ client's straight planner (clients/cpp, built here with CMake) is compared with
srfm's built-in ``straight`` planner, which computes the same command in Python. Both
see the same observations: those of the five paper scenarios' episodes of seeds
``0 .. --seeds − 1`` (recorded once with the built-in planner; the external one gives
the same record, tests/external/test_cpp.py).

- **per step**: each recorded observation is handed to ``act`` of both planners,
  alternately, ``--repeats`` times; every call is timed with ``time.perf_counter_ns``.
  The overhead is the median external call minus the median built-in call (the
  external call: encode the observation, send it over the Unix socket, the C++ planner
  decodes, computes and answers, srfm decodes and checks the command).
- **per 750-step episode**: the recorded observations are cut into blocks of 750 (a
  paper episode's horizon: the most ``act`` calls one episode can make) and each block
  is timed as a whole with each planner; the overhead is the median over blocks of the
  difference.
- **the Python client**: the same straight planner written as a function served by
  ``srfm.planners.external.serve``, timed per step beside the two others (its process
  decodes every message into NumPy arrays: the Python client is for convenience).
- **whole episodes**: ``srfm.run_episode`` of each recorded episode with each planner,
  median wall time over ``--repeats`` runs (the robot reaches its goal in 200-340
  steps, so these episodes make fewer than 750 calls).

Usage::

    .venv/bin/python tools/bench/bench_external_planner.py
    .venv/bin/python tools/bench/bench_external_planner.py --seeds 5 --repeats 10
    .venv/bin/python tools/bench/bench_external_planner.py \\
        --json docs/results/performance/external.json

``--json PATH`` also writes the figures of the tables (and the run's record,
``tools/results/record.py``) for docs/performance.md's generated blocks.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np

import srfm
from srfm.planners import Observation, PlannerContext, StraightPlanner
from srfm.planners.external import define_external
from srfm.scenarios import EVALUATION_SCENARIOS

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))
from tools.results.record import run_record
from tools.results.record import start as record_start

REPO = Path(__file__).resolve().parents[2]
EPISODE_STEPS = 750
# The Python client's straight planner (srfm.planners.external.serve), for its row.
PYTHON_PLANNER = """
import math
from srfm.planners.external import serve

def act(step, episode):
    error = math.remainder(
        math.atan2(step.goal[1] - step.y, step.goal[0] - step.x) - step.theta, 2.0 * math.pi
    )
    wmax = episode.max_angular_speed_radps
    return episode.max_speed_mps * max(math.cos(error), 0.0), max(-wmax, min(wmax, 2.0 * error))

serve(act, detection_range_m=0.0)
"""


class _Recorder(StraightPlanner):
    """The built-in straight planner, keeping its context and observations."""

    def __init__(self) -> None:
        super().__init__()
        self.context: PlannerContext | None = None
        self.observations: list[Observation] = []

    def reset(self, context: PlannerContext, rng: np.random.Generator) -> None:
        self.context = context
        super().reset(context, rng)

    def act(self, observation: Observation) -> Any:
        self.observations.append(observation)
        return super().act(observation)


def build(build_dir: Path) -> Path:
    """Build clients/cpp (Release); the straight planner's path."""
    subprocess.run(
        ["cmake", "-S", str(REPO / "clients" / "cpp"), "-B", str(build_dir)],
        check=True,
        stdout=subprocess.DEVNULL,
    )
    subprocess.run(
        ["cmake", "--build", str(build_dir), "-j", "2"], check=True, stdout=subprocess.DEVNULL
    )
    return build_dir / "straight_planner"


def main() -> None:
    """Measure and print the tables."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seeds", type=int, default=3, help="seeds 0 .. N-1 per scenario")
    parser.add_argument("--repeats", type=int, default=5, help="passes over the observations")
    parser.add_argument(
        "--build-dir",
        type=Path,
        default=Path(tempfile.gettempdir()) / "srfm-cpp-client",
        help="where clients/cpp is built",
    )
    parser.add_argument("--json", type=Path, default=None, help="also write the figures here")
    args = parser.parse_args()
    started, t0_run, load0 = record_start()
    program = build(args.build_dir)
    name = define_external("bench-cpp", [str(program)])
    script = args.build_dir / "python_planner.py"
    script.write_text(PYTHON_PLANNER, encoding="utf-8")
    python = srfm.planners.make_planner(define_external("bench-py", [sys.executable, str(script)]))
    assert python.detection_range_m == 0.0

    episodes: list[tuple[str, int, _Recorder]] = []
    for scenario in EVALUATION_SCENARIOS:
        for seed in range(args.seeds):
            recorder = _Recorder()
            srfm.run_episode(scenario, seed, recorder)
            episodes.append((scenario, seed, recorder))

    builtin = StraightPlanner()
    external = srfm.planners.make_planner(name)
    assert external.detection_range_m == 0.0  # opens the connection (the handshake)
    rng = np.random.default_rng(0)
    clock = time.perf_counter_ns
    t_in: list[float] = []
    t_ex: list[float] = []
    t_py: list[float] = []
    block_in: list[float] = []
    block_ex: list[float] = []
    for _ in range(args.repeats):
        for _scenario, _seed, rec in episodes:
            assert rec.context is not None
            builtin.reset(rec.context, rng)
            external.reset(rec.context, rng)
            python.reset(rec.context, rng)
            for obs in rec.observations:
                t0 = clock()
                builtin.act(obs)
                t1 = clock()
                external.act(obs)
                t2 = clock()
                python.act(obs)
                t3 = clock()
                t_in.append((t1 - t0) / 1e3)
                t_ex.append((t2 - t1) / 1e3)
                t_py.append((t3 - t2) / 1e3)
        stream = [(rec, obs) for _s, _k, rec in episodes for obs in rec.observations]
        for start in range(0, len(stream) - EPISODE_STEPS + 1, EPISODE_STEPS):
            block = stream[start : start + EPISODE_STEPS]
            context = block[0][0].context
            assert context is not None
            builtin.reset(context, rng)
            external.reset(context, rng)
            t0 = clock()
            for _rec, obs in block:
                builtin.act(obs)
            t1 = clock()
            for _rec, obs in block:
                external.act(obs)
            t2 = clock()
            block_in.append((t1 - t0) / 1e6)
            block_ex.append((t2 - t1) / 1e6)

    print(
        f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, {platform.node()}, "
        f"{os.cpu_count()} CPUs, Python {platform.python_version()}, "
        f"load average {os.getloadavg()[0]:.2f}"
    )
    steps = sum(len(rec.observations) for _s, _k, rec in episodes)
    print(
        f"{len(episodes)} episodes ({len(EVALUATION_SCENARIOS)} paper scenarios x {args.seeds} "
        f"seeds), {steps} observations, {args.repeats} passes\n"
    )
    med_in = statistics.median(t_in)
    med_ex = statistics.median(t_ex)
    p90_ex = statistics.quantiles(t_ex, n=10)[-1]
    print("| per control step | median (µs) | 90th percentile (µs) |")
    print("|---|---:|---:|")
    print(
        f"| built-in straight, act() | {med_in:.1f} | {statistics.quantiles(t_in, n=10)[-1]:.1f} |"
    )
    print(f"| C++ straight over the protocol, act() | {med_ex:.1f} | {p90_ex:.1f} |")
    print(f"| **overhead** (difference of the medians) | **{med_ex - med_in:.1f}** | |")
    p90_py = statistics.quantiles(t_py, n=10)[-1]
    print(
        f"| Python client's straight over the protocol, act() | {statistics.median(t_py):.1f} "
        f"| {p90_py:.1f} |"
    )
    diffs = [e - i for e, i in zip(block_ex, block_in, strict=True)]
    print(f"\n| per {EPISODE_STEPS}-step episode ({len(diffs)} blocks) | median (ms) | max (ms) |")
    print("|---|---:|---:|")
    print(f"| built-in straight | {statistics.median(block_in):.1f} | {max(block_in):.1f} |")
    med_block = statistics.median(block_ex)
    print(f"| C++ straight over the protocol | {med_block:.1f} | {max(block_ex):.1f} |")
    print(f"| **overhead** | **{statistics.median(diffs):.1f}** | {max(diffs):.1f} |")

    print(
        "\n| whole episode, run_episode (median of runs) | built-in (ms) | external (ms) "
        "| planner steps |"
    )
    print("|---|---:|---:|---:|")
    whole = []
    for scenario in EVALUATION_SCENARIOS:
        walls: dict[str, list[float]] = {"straight": [], name: []}
        record = None
        for _ in range(args.repeats):
            for planner in walls:
                t0 = time.perf_counter()
                record = srfm.run_episode(scenario, 0, planner)
                walls[planner].append((time.perf_counter() - t0) * 1e3)
        assert record is not None
        print(
            f"| {scenario}, seed 0 | {statistics.median(walls['straight']):.1f} | "
            f"{statistics.median(walls[name]):.1f} | {record.end_step} |"
        )
        whole.append(
            {
                "scenario": scenario,
                "builtin_ms": round(statistics.median(walls["straight"]), 2),
                "external_ms": round(statistics.median(walls[name]), 2),
                "planner_steps": int(record.end_step),
            }
        )
    if args.json is not None:

        def q(values: list[float]) -> dict[str, float]:
            return {
                "median": round(statistics.median(values), 2),
                "p90": round(
                    statistics.quantiles(values, n=10)[-1] if len(values) > 1 else values[0], 2
                ),
                "max": round(max(values), 2),
            }

        doc = {
            "episodes": len(episodes),
            "scenarios": list(EVALUATION_SCENARIOS),
            "seeds": args.seeds,
            "observations": steps,
            "passes": args.repeats,
            "episode_steps": EPISODE_STEPS,
            "per_step_us": {"builtin": q(t_in), "cpp": q(t_ex), "python": q(t_py)},
            "per_episode_ms": {
                "blocks": len(diffs),
                "builtin": q(block_in),
                "cpp": q(block_ex),
                "overhead": q(diffs),
            },
            "whole_episodes_ms": whole,
            "run": run_record(started, t0_run, load0),
        }
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(doc, indent=1) + "\n", encoding="utf-8")
        print(f"-> {args.json}")


if __name__ == "__main__":
    main()
