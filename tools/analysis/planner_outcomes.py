"""Robot outcomes of every planner on every evaluation scenario, over many seeds.

For each scenario and planner, runs ``srfm.run_episode(scenario, seed, planner,
parallel=False)`` for the seeds ``--first-seed .. --first-seed + --seeds − 1`` and
prints a Markdown table per scenario: the share of episodes that reached the goal,
collided, left the world or timed out, the mean robot speed while its episode ran
(path length / active time), the mean time to the goal over the successful episodes,
and the mean closest approach (centre to centre) to a factual pedestrian.

Episodes are spread over ``--jobs`` worker processes, each with one numba thread
(``NUMBA_NUM_THREADS=1``, set before srfm is imported) and the serial force kernel.

Usage::

    .venv/bin/python tools/analysis/planner_outcomes.py                       # 100 seeds, 2 workers
    .venv/bin/python tools/analysis/planner_outcomes.py --seeds 10 --planners vo \\
        --set vo.detection_range_m=1.4 --kinematics holonomic

``--out DIR`` also writes the episodes as data, ``DIR/episodes.parquet`` (one row per
episode: the fields of :class:`Result`) and ``DIR/manifest.json`` (the command, the
commit, when it ran, its wall time and workers, the options), from which
``tools/results/generate.py`` writes the tables of docs/planners.md
(:func:`markdown_table`, :func:`read`).
"""

from __future__ import annotations

import os

os.environ["NUMBA_NUM_THREADS"] = "1"  # before numba is imported, here and in workers

import argparse
import ast
import collections
import json
import multiprocessing
import statistics
import subprocess
import sys
import time
from dataclasses import dataclass, fields
from pathlib import Path
from typing import Any

DEFAULT_PLANNERS = ("straight", "dwa", "vo", "orca", "social-force")


@dataclass(frozen=True)
class Result:
    """One episode's robot outcome."""

    scenario: str
    planner: str
    seed: int
    outcome: str
    end_step: int
    speed_mps: float
    time_to_goal_s: float
    min_distance_m: float


def _overrides(spec: list[str]) -> dict[str, dict[str, Any]]:
    out: dict[str, dict[str, Any]] = collections.defaultdict(dict)
    for item in spec:
        key, sep, value = item.partition("=")
        planner, dot, field = key.partition(".")
        if not sep or not dot:
            raise SystemExit(f"--set wants planner.field=value, got {item!r}")
        try:
            out[planner][field] = ast.literal_eval(value)
        except (ValueError, SyntaxError):
            out[planner][field] = value
    return dict(out)


def make_planner(name: str, overrides: dict[str, dict[str, Any]]) -> Any:
    """A registered planner, with its config fields replaced by ``overrides[name]``."""
    import attrs

    from srfm.planners import make_planner as registry_planner

    planner = registry_planner(name)
    fields = overrides.get(name)
    if fields:
        config = attrs.evolve(planner.config, **fields)  # type: ignore[attr-defined]
        planner = type(planner)(config)
    return planner


Task = tuple[str, str, int, str | None, dict[str, dict[str, Any]], dict[str, float]]


def run_one(task: Task) -> Result:
    """Run one episode and summarise it."""
    import attrs
    import numpy as np

    import srfm

    scenario_name, planner_name, seed, kinematics, overrides, model = task
    scenario = srfm.load_scenario(scenario_name)
    if kinematics is not None:
        scenario = attrs.evolve(scenario, robot=attrs.evolve(scenario.robot, kinematics=kinematics))
    planner = make_planner(planner_name, overrides)
    params = srfm.SRFMParams().replace(**model) if model else None
    record = srfm.run_episode(scenario, seed, planner, params, parallel=False)
    active_s = record.end_step * record.dt_s
    path = float(
        np.sum(
            np.linalg.norm(np.diff(record.robot_pose[: record.end_step + 1, :2], axis=0), axis=1)
        )
    )
    return Result(
        scenario=scenario_name,
        planner=planner_name,
        seed=seed,
        outcome=record.outcome,
        end_step=record.end_step,
        speed_mps=path / active_s if active_s > 0 else 0.0,
        time_to_goal_s=active_s if record.outcome == "goal_reached" else float("nan"),
        min_distance_m=record.min_robot_distance_m(),
    )


def _commit() -> str:
    try:
        out = subprocess.run(
            ["git", "rev-parse", "--short", "HEAD"],
            capture_output=True,
            text=True,
            check=True,
            cwd=Path(__file__).resolve().parents[2],
        )
        dirty = subprocess.run(
            ["git", "status", "--porcelain", "--", "srfm"],
            capture_output=True,
            text=True,
            check=True,
            cwd=Path(__file__).resolve().parents[2],
        )
    except (OSError, subprocess.CalledProcessError):
        return "unknown"
    return out.stdout.strip() + (" (srfm/ modified)" if dirty.stdout.strip() else "")


def _pct(n: int, total: int) -> str:
    return f"{100.0 * n / total:.0f}"


def markdown_table(results: list[Result], scenarios: list[str], planners: list[str]) -> list[str]:
    """One Markdown table, a row per (scenario, planner): the shares of the episodes
    that reached the goal, collided, left the world or timed out (%), the mean robot
    speed, the mean time to the goal over the successful episodes and the mean closest
    approach."""
    by_key: dict[tuple[str, str], list[Result]] = collections.defaultdict(list)
    for r in results:
        by_key[(r.scenario, r.planner)].append(r)
    lines = [
        "| scenario | planner | success % | collision % | out of bounds % | timeout % "
        "| mean speed (m/s) | time to goal (s) | closest approach (m) |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for scenario in scenarios:
        for planner in planners:
            rows = by_key[(scenario, planner)]
            if not rows:
                raise SystemExit(f"no episodes of {planner} in {scenario}")
            n = len(rows)
            count = collections.Counter(r.outcome for r in rows)
            ttg = [r.time_to_goal_s for r in rows if r.outcome == "goal_reached"]
            ttg_s = f"{statistics.fmean(ttg):.2f}" if ttg else "–"
            lines.append(
                f"| {scenario} | {planner} | {_pct(count['goal_reached'], n)} | "
                f"{_pct(count['collision'], n)} | {_pct(count['out_of_bounds'], n)} | "
                f"{_pct(count['timeout'], n)} | "
                f"{statistics.fmean(r.speed_mps for r in rows):.3f} | {ttg_s} | "
                f"{statistics.fmean(r.min_distance_m for r in rows):.2f} |"
            )
    return lines


def print_tables(results: list[Result], scenarios: list[str], planners: list[str]) -> None:
    """The table, and every episode that did not reach the goal."""
    print("\n" + "\n".join(markdown_table(results, scenarios, planners)))
    bad = [r for r in results if r.outcome != "goal_reached"]
    if bad:
        print("\nEpisodes that did not reach the goal:\n")
        for r in sorted(bad, key=lambda r: (r.planner, r.scenario, r.seed)):
            print(f"- {r.planner} / {r.scenario} / seed {r.seed}: {r.outcome} at step {r.end_step}")


def write(out: Path, results: list[Result], manifest: dict[str, Any]) -> None:
    """``out/episodes.parquet`` (one row per episode, in task order) and
    ``out/manifest.json``."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    out.mkdir(parents=True, exist_ok=True)
    columns = {f.name: [getattr(r, f.name) for r in results] for f in fields(Result)}
    pq.write_table(pa.table(columns), out / "episodes.parquet", compression="zstd")
    (out / "manifest.json").write_text(json.dumps(manifest, indent=1) + "\n", encoding="utf-8")


def read(folder: Path) -> tuple[list[Result], dict[str, Any]]:
    """The episodes and the manifest :func:`write` wrote."""
    import pyarrow.parquet as pq

    table = pq.read_table(folder / "episodes.parquet").to_pylist()
    manifest = json.loads((folder / "manifest.json").read_text(encoding="utf-8"))
    return [Result(**row) for row in table], manifest


def parse_args(argv: list[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(
        description=__doc__.split("\n\n")[0] if __doc__ else None,
        formatter_class=argparse.ArgumentDefaultsHelpFormatter,
    )
    parser.add_argument("--seeds", type=int, default=100, help="episodes per scenario and planner")
    parser.add_argument("--first-seed", type=int, default=0, help="the first seed")
    parser.add_argument("--planners", nargs="+", default=list(DEFAULT_PLANNERS), metavar="NAME")
    parser.add_argument(
        "--scenarios", nargs="+", metavar="NAME", help="default: the evaluation set"
    )
    parser.add_argument("--jobs", type=int, default=2, help="worker processes")
    parser.add_argument(
        "--kinematics", choices=("unicycle", "holonomic"), help="override the robot's kinematics"
    )
    parser.add_argument(
        "--set",
        action="append",
        default=[],
        metavar="PLANNER.FIELD=VALUE",
        help="override a planner config field, e.g. vo.detection_range_m=1.4 (repeatable)",
    )
    parser.add_argument(
        "--model",
        action="append",
        default=[],
        metavar="FIELD=VALUE",
        help="override an SRFM parameter of the agrawal2024 preset, e.g. a_robot=0 "
        "(pedestrians that ignore the robot; repeatable)",
    )
    parser.add_argument(
        "--out", type=Path, help="also write the episodes and a manifest into this folder"
    )
    return parser.parse_args(argv)


def main(argv: list[str] | None = None) -> int:
    args = parse_args(argv)
    import srfm

    scenarios = args.scenarios or list(srfm.EVALUATION_SCENARIOS)
    overrides = _overrides(args.set)
    for name in overrides:  # fail early on a bad override
        make_planner(name, overrides)
    model = {}
    for item in args.model:
        key, sep, value = item.partition("=")
        if not sep:
            raise SystemExit(f"--model wants field=value, got {item!r}")
        model[key] = float(value)
    srfm.SRFMParams().replace(**model)  # fail early on a bad field or value
    tasks: list[Task] = [
        (s, p, seed, args.kinematics, overrides, model)
        for s in scenarios
        for p in args.planners
        for seed in range(args.first_seed, args.first_seed + args.seeds)
    ]
    started = time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())
    t0 = time.perf_counter()
    if args.jobs > 1:
        with multiprocessing.get_context("spawn").Pool(args.jobs) as pool:
            results = pool.map(run_one, tasks, chunksize=max(1, len(tasks) // (8 * args.jobs)))
    else:
        results = [run_one(t) for t in tasks]
    wall = time.perf_counter() - t0
    print(
        f"srfm commit {_commit()}; seeds {args.first_seed}..{args.first_seed + args.seeds - 1}; "
        f"kinematics {args.kinematics or 'as in the scenario'}; overrides {args.set or 'none'}; "
        f"SRFM parameters agrawal2024{' with ' + ', '.join(args.model) if args.model else ''}; "
        f"{len(tasks)} episodes in {wall:.1f} s with {args.jobs} worker(s)"
    )
    print_tables(results, scenarios, args.planners)
    if args.out is not None:
        write(
            args.out,
            results,
            {
                "command": "python tools/analysis/planner_outcomes.py "
                + " ".join(sys.argv[1:] if argv is None else argv),
                "commit": _commit(),
                "started": started,
                "wall_s": wall,
                "jobs": args.jobs,
                "load_average": list(os.getloadavg()),
                "scenarios": scenarios,
                "planners": list(args.planners),
                "seeds": [args.first_seed, args.first_seed + args.seeds - 1],
                "kinematics": args.kinematics or "as in the scenario",
                "overrides": args.set,
                "model": args.model,
            },
        )
        print(f"-> {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
