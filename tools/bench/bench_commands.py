"""Every row of docs/performance.md's "Commands" table, in one run: what a user waits for.

Times whole commands in fresh processes, as a user runs them (``python -m srfm.cli``
with the checkout first on the path): wall time of the command and CPU time of the
command and all its workers (the children's rusage), the median of ``--runs`` runs with
the minimum and maximum beside it, and the load average before and after each row.
Rows (``--rows``, default all but ``full`` and ``crowd``):

- ``help``: ``srfm --help``;
- ``simulate``: ``srfm simulate --scenario crosswalk --seed 0 --planner dwa`` (warm cache);
- ``quick``: ``srfm benchmark --quick`` (default logs and figures, warm cache);
- ``quick-bare``: the same with ``--no-logs --no-figures``;
- ``cold``: ``srfm benchmark --quick`` with ``NUMBA_CACHE_DIR`` on a new, empty folder
  for every run (a fresh clone's first run);
- ``cold-busy``: the same with a CPU-bound process (a Python busy loop) beside it, the
  other core taken;
- ``full``: ``srfm benchmark`` (seeds 0-99, every planner, default logs): minutes a run;
  also prints the MCAP bytes per episode;
- ``crowd``: ``tools/bench/bench_crowd_step.py`` at N = 1000 against JuPedSim by both
  protocols (its own and, ``--side-by-side``, the side-by-side one; needs the ``bench``
  extra), its own tables;
- ``shared-crowd``: the project's judging script ``../shared/tools/crowd_side_by_side.py
  --sizes 1000 10000`` (srfm's crowd step against JuPedSim's, one process, side by side),
  ``--runs`` times from ``--tree``; the ratio per run and size (needs the ``bench`` extra
  and the shared folder beside the checkout, or ``--shared``);
- ``stages``: where the quick benchmark's time goes, in this process (``--tree`` only):
  CPU ms per episode by planner and stage (set-up and simulation, metrics, MCAP, Rerun,
  the figure episode) over the 5 scenarios × seeds 0-2 after one untimed episode each,
  then the report phase (tables, figures, results page).

``--vs TREE`` runs every command also from another checkout (e.g. ``git worktree add
/tmp/before main``), alternating the two run by run, and prints the ratio of the medians:
a before/after comparison under the same load. Each checkout keeps its own numba cache
(``__pycache__`` beside its sources), so the warm rows are warm for both once a first,
untimed run of each row has filled it (``--warmup``, default 1).

``--json PATH`` also writes every run's figures (wall, CPU, simulation phase, MCAP bytes,
the crowd ratios), the date, the commits, the CPU model and the loads to PATH, with the
run's record (``tools/results/record.py``): the data that docs/performance.md's goal
and command tables are generated from (``make docs-tables``).

Usage::

    .venv/bin/python tools/bench/bench_commands.py
    .venv/bin/python tools/bench/bench_commands.py --vs /tmp/before --runs 3
    .venv/bin/python tools/bench/bench_commands.py --rows full --runs 1
    .venv/bin/python tools/bench/bench_commands.py --rows simulate full shared-crowd \\
        --json docs/results/performance/goals.json
    .venv/bin/python tools/bench/bench_commands.py --rows help simulate quick-bare quick \\
        cold cold-busy --json docs/results/performance/commands.json
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import re
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Sequence
from pathlib import Path

# the same folder: one definition of the commit line and of the busy core
from bench_crowd_step import busy_core, srfm_commit

ROOT = Path(__file__).resolve().parents[2]

ROWS: dict[str, tuple[str, list[str]]] = {
    "help": ("srfm --help", ["--help"]),
    "simulate": (
        "srfm simulate --scenario crosswalk --seed 0 --planner dwa",
        ["simulate", "--scenario", "crosswalk", "--seed", "0", "--planner", "dwa"],
    ),
    "quick": ("srfm benchmark --quick", ["benchmark", "--quick", "--out", "{out}"]),
    "quick-bare": (
        "srfm benchmark --quick --no-logs --no-figures",
        ["benchmark", "--quick", "--no-logs", "--no-figures", "--out", "{out}"],
    ),
    "cold": (
        "srfm benchmark --quick, empty numba cache",
        ["benchmark", "--quick", "--out", "{out}"],
    ),
    "cold-busy": (
        "srfm benchmark --quick, empty numba cache, the other core busy",
        ["benchmark", "--quick", "--out", "{out}"],
    ),
    "full": ("srfm benchmark (seeds 0-99, 7 planners)", ["benchmark", "--out", "{out}"]),
}
COLD_ROWS = ("cold", "cold-busy")
DEFAULT_ROWS = ("help", "simulate", "quick-bare", "quick", "cold")
SHARED_RATIO = re.compile(r"N=(\d+): srfm ([0-9,]+) +jupedsim ([0-9,]+) agent-steps/s +ratio")
SIMULATED = re.compile(r"simulated (\d+) of (\d+) episodes in ([0-9.]+) s")


def _load() -> str:
    return "/".join(f"{x:.1f}" for x in os.getloadavg())


class Run:
    """One timed command: wall s, CPU s (command + workers), simulation phase s (as the
    benchmark prints it, else None), MCAP bytes per episode (``full``, else None)."""

    def __init__(self, wall: float, cpu: float, sim: float | None, mcap: float | None) -> None:
        self.wall, self.cpu, self.sim, self.mcap = wall, cpu, sim, mcap


def run_once(tree: Path, row: str, scratch: Path) -> Run:
    """Run ``row``'s command from ``tree`` once in a fresh process and time it."""
    out = scratch / "out"
    shutil.rmtree(out, ignore_errors=True)
    args = [a.replace("{out}", str(out)) for a in ROWS[row][1]]
    env = dict(os.environ, PYTHONPATH=str(tree))
    # As a user runs it: Python writes its bytecode caches (__pycache__/*.pyc) at the
    # first import and reads them after. With PYTHONDONTWRITEBYTECODE set (some shells
    # and CI images set it) every command compiled srfm's ~60 modules from source,
    # 0.1-0.2 s of each command.
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    if row in COLD_ROWS:
        cache = scratch / "numba-cache"
        shutil.rmtree(cache, ignore_errors=True)
        cache.mkdir()
        env["NUMBA_CACHE_DIR"] = str(cache)
    cmd = [sys.executable, "-m", "srfm.cli", *args]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    proc = subprocess.run(cmd, env=env, cwd=scratch, capture_output=True, text=True)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if proc.returncode != 0:
        sys.exit(f"{' '.join(cmd)} (in {tree}) failed ({proc.returncode}):\n{proc.stderr[-2000:]}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    match = SIMULATED.search(proc.stdout + proc.stderr)
    sim = float(match.group(3)) if match else None
    mcap = None
    if row == "full":
        files = [p for p in (out / "logs").rglob("*.mcap") if "_counterfactual" not in p.parts]
        mcap = sum(p.stat().st_size for p in files) / max(1, len(files))
    return Run(wall, cpu, sim, mcap)


def _cpu_model() -> str:
    """The CPU's model name (``/proc/cpuinfo``), or the platform's processor string."""
    cpuinfo = Path("/proc/cpuinfo")
    if cpuinfo.is_file():
        for line in cpuinfo.read_text(encoding="utf-8").splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    import platform

    return platform.processor() or "unknown"


def shared_crowd(tree: Path, shared: Path) -> dict[int, tuple[float, float]]:
    """One run of the shared judging script from ``tree``: agent-steps/s of srfm and
    JuPedSim at N = 1000 and 10,000 (the script prints both; the ratio is theirs)."""
    script = shared / "tools" / "crowd_side_by_side.py"
    if not script.is_file():
        sys.exit(f"{script}: not found (the shared folder beside the checkout, or --shared)")
    proc = subprocess.run(
        [sys.executable, str(script), "--sizes", "1000", "10000"],
        env=dict(os.environ, PYTHONPATH=str(tree)),
        cwd=tree,
        capture_output=True,
        text=True,
    )
    if proc.returncode != 0:
        sys.exit(f"{script} failed ({proc.returncode}):\n{proc.stderr[-2000:]}")
    found = {
        int(m.group(1)): (float(m.group(2).replace(",", "")), float(m.group(3).replace(",", "")))
        for m in SHARED_RATIO.finditer(proc.stdout)
    }
    if set(found) != {1000, 10000}:
        sys.exit(f"{script}: no rates for N = 1000 and 10000 in its output:\n{proc.stdout}")
    return found


def _spread(values: Sequence[float]) -> str:
    return f"{statistics.median(values):.2f} ({min(values):.2f}–{max(values):.2f})"


def stages(tree: Path) -> None:
    """Print the CPU ms per episode by planner and stage, and the report phase's."""
    sys.path.insert(0, str(tree))
    from srfm.benchmark import BenchmarkRequest
    from srfm.benchmark._html import render_report
    from srfm.benchmark._request import MANIFEST, new_manifest
    from srfm.benchmark.figures import render_figures, save_figure_episode
    from srfm.logs import EpisodeLogger, LogOptions
    from srfm.logs._mcap import write_counterfactual_mcap, write_episode_mcap
    from srfm.logs._rerun import write_rrd
    from srfm.metrics import episode_metrics
    from srfm.metrics.report import render_tables
    from srfm.sim.episode import build_planner, run_episode

    request = BenchmarkRequest.create(quick=True)
    logger = EpisodeLogger.create(
        LogOptions.benchmark_default(),
        scenarios=request.scenarios,
        planners=request.planners,
        seeds=request.seeds,
        reference=request.reference,
    )
    clock = time.process_time
    print(
        f"\nper episode, CPU ms (mean over {len(request.scenarios)} scenarios × seeds "
        f"{list(request.seeds)}), load {_load()}:"
    )
    print(
        "| planner | set-up + simulation | metrics | MCAP (compact) | shared counterfactual"
        " MCAP | Rerun (.rrd) | figure episode |"
    )
    print("|---|---:|---:|---:|---:|---:|---:|")
    results = []
    with tempfile.TemporaryDirectory(prefix="srfm-stages-") as tmp:
        out = Path(tmp)
        for planner in request.planners:
            cost = dict.fromkeys(("sim", "metrics", "mcap", "cf", "rrd", "fig"), 0.0)
            n = 0
            for scenario in request.scenarios:
                run_episode(scenario, 0, build_planner(planner), request.params)  # untimed
                for seed in request.seeds:
                    t = clock()
                    record = run_episode(
                        scenario, seed, build_planner(planner), request.params, parallel=False
                    )
                    t1 = clock()
                    metrics = episode_metrics(record)
                    t2 = clock()
                    write_episode_mcap(
                        out / "e.mcap",
                        record,
                        scenario=scenario,
                        metrics=metrics,
                        profile="compact",
                        counterfactual_file="cf.mcap",
                        benchmark=logger.benchmark,
                    )
                    t3 = clock()
                    write_counterfactual_mcap(out / "cf.mcap", record, scenario=scenario)
                    t4 = clock()
                    write_rrd(out / "e.rrd", record, scenario=scenario, metrics=metrics)
                    t5 = clock()
                    save_figure_episode(out, record)
                    t6 = clock()
                    steps = (t1 - t, t2 - t1, t3 - t2, t4 - t3, t5 - t4, t6 - t5)
                    for key, dt in zip(cost, steps, strict=True):
                        cost[key] += dt
                    n += 1
                    results.append(metrics)
            cells = " | ".join(f"{1e3 * v / n:.1f}" for v in cost.values())
            print(f"| {planner} | {cells} |", flush=True)
        t = clock()
        files, tables = render_tables(
            results,
            scenarios=[s.name for s in request.scenarios],
            planners=request.planners,
            seeds=request.seeds,
            params=request.params,
            reference=request.reference,
        )
        t1 = clock()
        files.update(render_figures(out, request, tables.table, tables.extended))
        t2 = clock()
        (out / MANIFEST).write_text(json.dumps(new_manifest(request, None)))
        render_report(out, files)
        t3 = clock()
    print(
        f"report phase, CPU s: tables {t1 - t:.2f}, figures {t2 - t1:.2f}, "
        f"results page {t3 - t2:.2f}"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rows", nargs="+", default=list(DEFAULT_ROWS), metavar="ROW")
    parser.add_argument("--runs", type=int, default=3, help="timed runs per row and tree")
    parser.add_argument("--warmup", type=int, default=1, help="untimed runs first (warm rows)")
    parser.add_argument("--tree", type=Path, default=ROOT, help="the checkout to time")
    parser.add_argument("--vs", type=Path, default=None, help="a second checkout, alternated")
    parser.add_argument("--crowd-seconds", type=float, default=2.0)
    parser.add_argument("--json", type=Path, default=None, help="also write the figures here")
    parser.add_argument(
        "--shared", type=Path, default=ROOT.parent / "shared", help="the shared folder"
    )
    args = parser.parse_args()
    unknown = set(args.rows) - set(ROWS) - {"crowd", "stages", "shared-crowd"}
    if unknown:
        parser.error(
            f"unknown rows {sorted(unknown)}; known: {[*ROWS, 'crowd', 'shared-crowd', 'stages']}"
        )
    trees = [args.tree.resolve(), *([args.vs.resolve()] if args.vs else [])]
    begun = None
    if args.json is not None:  # imports srfm from ROOT: only when a record is written
        sys.path.insert(0, str(ROOT))
        from tools.results import record as run_record

        begun = run_record.start()
    started = datetime.datetime.now(datetime.UTC)
    record: dict[str, object] = {
        "date": f"{started:%Y-%m-%d %H:%M} UTC",
        "cpu": _cpu_model(),
        "cores": os.cpu_count(),
        "commits": {"AB"[k]: srfm_commit(tree) for k, tree in enumerate(trees)},
        "command": "python tools/bench/bench_commands.py " + " ".join(sys.argv[1:]),
        "rows": {},
    }
    rows_out: dict[str, object] = record["rows"]  # type: ignore[assignment]
    print(f"date: {started:%Y-%m-%d %H:%M} UTC, cores {os.cpu_count()}, CPU {record['cpu']}")
    for k, tree in enumerate(trees):
        print(f"tree {'AB'[k]}: {tree} (commit {srfm_commit(tree)})")
    print("figures: median (min–max) of the runs, seconds; CPU = the command and its workers")
    head = "| row | tree | wall | CPU | simulation phase | load before/after (1/5/15 min) |"
    print(head + ("" if args.vs is None else " A/B wall, CPU (medians) |"))
    print("|---|---|---:|---:|---:|---|" + ("" if args.vs is None else "---|"))
    with tempfile.TemporaryDirectory(prefix="srfm-bench-commands-") as tmp:
        scratch = Path(tmp)
        for row in args.rows:
            if row in ("crowd", "stages", "shared-crowd"):
                continue
            load_before = _load()
            if row not in COLD_ROWS:
                for _ in range(args.warmup):
                    for tree in trees:
                        run_once(tree, row, scratch)
            runs: dict[Path, list[Run]] = {tree: [] for tree in trees}
            with busy_core(row == "cold-busy"):
                for _ in range(args.runs):
                    for tree in trees:
                        runs[tree].append(run_once(tree, row, scratch))
            load_after = _load()
            rows_out[row] = {
                "label": ROWS[row][0],
                "load_before": load_before,
                "load_after": load_after,
                "runs": {
                    "AB"[k]: [
                        {"wall_s": r.wall, "cpu_s": r.cpu, "sim_s": r.sim, "mcap_bytes": r.mcap}
                        for r in runs[tree]
                    ]
                    for k, tree in enumerate(trees)
                },
            }
            for k, tree in enumerate(trees):
                rs = runs[tree]
                sims = [r.sim for r in rs if r.sim is not None]
                cells = [
                    ROWS[row][0],
                    "AB"[k],
                    _spread([r.wall for r in rs]),
                    _spread([r.cpu for r in rs]),
                    _spread(sims) if sims else "–",
                    f"{load_before} → {load_after}",
                ]
                if args.vs is not None:
                    if k == 0:
                        a, b = runs[trees[0]], runs[trees[1]]
                        wall = statistics.median(r.wall for r in a) / statistics.median(
                            r.wall for r in b
                        )
                        cpu = statistics.median(r.cpu for r in a) / statistics.median(
                            r.cpu for r in b
                        )
                        cells.append(f"{wall:.2f}, {cpu:.2f}")
                    else:
                        cells.append("")
                print("| " + " | ".join(cells) + " |", flush=True)
                mcaps = [r.mcap for r in rs if r.mcap is not None]
                if mcaps:
                    print(
                        f"  tree {'AB'[k]}: {statistics.median(mcaps) / 1e3:.1f} kB"
                        " of MCAP an episode"
                    )
    if "stages" in args.rows:
        stages(args.tree.resolve())
    if "crowd" in args.rows:
        print(f"\ncrowd step at N = 1000 (tools/bench/bench_crowd_step.py), load {_load()}:")
        for tree in trees:
            subprocess.run(
                [
                    sys.executable,
                    str(tree / "tools/bench/bench_crowd_step.py"),
                    "--cpu-time",
                    "--no-pysocialforce",
                    "--side-by-side",
                    "--sizes",
                    "1000",
                    "--seconds",
                    str(args.crowd_seconds),
                    "--repeats",
                    "3",
                    "--memory-n",
                    "0",
                ],
                env=dict(os.environ, PYTHONPATH=str(tree)),
                cwd=tree,
                check=True,
            )
    if "shared-crowd" in args.rows:
        load_before = _load()
        print(f"\ncrowd step, the shared script (--sizes 1000 10000), load {load_before}:")
        crowd: dict[str, list[dict[str, float]]] = {"AB"[k]: [] for k in range(len(trees))}
        for _ in range(args.runs):
            for k, tree in enumerate(trees):
                rates = shared_crowd(tree, args.shared.resolve())
                crowd["AB"[k]].append(
                    {
                        f"{kind}_{n}": rates[n][j]
                        for n in rates
                        for j, kind in enumerate(("srfm", "jupedsim"))
                    }
                )
                ratios = ", ".join(f"N={n}: {rates[n][0] / rates[n][1]:.2f}x" for n in rates)
                print(f"  tree {'AB'[k]}: {ratios}", flush=True)
        rows_out["shared-crowd"] = {
            "label": "crowd step against JuPedSim (../shared/tools/crowd_side_by_side.py)",
            "load_before": load_before,
            "load_after": _load(),
            "runs": crowd,
        }
    print(f"load average at end: {_load()}")
    if args.json is not None and begun is not None:
        run_record.write_json(args.json, record, begun)


if __name__ == "__main__":
    main()
