"""Has the deviation converged in the time step? (issue 41; docs/metrics.md,
"Convergence in the time step").

The paper suite at the scenarios' step dt (1/15 s) and with the crowd stepped 2 and 4
times per control step (dt/2, dt/4; the planners' control rate unchanged,
``srfm benchmark --crowd-substeps N``), seeds 0-99, the default planners:

    for n in 1 2 4; do
      nice -n 5 .venv/bin/srfm benchmark --suite paper --seeds 0-99 --crowd-substeps $n \\
          --no-logs --no-figures -j 2 --out results/conv-sub$n
    done
    # every episode's deviation at the three steps (the committed data)
    .venv/bin/python tools/analysis/convergence.py collect results/conv-sub1 \\
        results/conv-sub2 results/conv-sub4 --csv docs/convergence/frechet.csv
    # the tables of docs/metrics.md from that file alone
    .venv/bin/python tools/analysis/convergence.py table docs/convergence/frechet.csv

or, the three runs timed and the data written in one command (each run's wall time,
CPU time of all its processes and the load, with the run record of
``tools/results/record.py``, into ``docs/convergence/runs.json``; resumable like the
benchmark):

    .venv/bin/python tools/analysis/convergence.py run results/conv \
        --csv docs/convergence/frechet.csv --json docs/convergence/runs.json

Relative change of a quantity q from dt to a finer step: (q(dt) − q(fine)) / |q(fine)|,
q the mean deviation of a (scenario, planner) or the difference of two planners' mean
deviations in a scenario. The default step has converged for q when the change from
dt to dt/4 is at most 5 % (``THRESHOLD``). A difference smaller than ``SMALL_M`` is
left out of the relative figures (a change of a near-zero difference says nothing):
its absolute change is printed instead.
"""

from __future__ import annotations

import argparse
import csv
import itertools
import json
import math
import os
import resource
import subprocess
import sys
import time
from collections import defaultdict
from pathlib import Path
from typing import Any

SUBSTEPS = (1, 2, 4)
THRESHOLD = 0.05
SMALL_M = 0.01
_COLUMNS = tuple(f"frechet_sub{n}" for n in SUBSTEPS)


def collect(folders: list[Path], out: Path) -> None:
    """One row per (scenario, planner, seed): the episode's frechet_m at each step."""
    from srfm.benchmark._results import EPISODES_DIR, read_episode

    if len(folders) != len(SUBSTEPS):
        raise SystemExit(f"give {len(SUBSTEPS)} folders, for crowd substeps {SUBSTEPS}")
    values: dict[tuple[str, str, int], list[float]] = defaultdict(lambda: [math.nan] * 3)
    for k, folder in enumerate(folders):
        for path in sorted((folder / EPISODES_DIR).glob("*/*/seed-*.json")):
            r = read_episode(path)
            values[(r.scenario, r.planner, r.seed)][k] = r["frechet_m"]
    out.parent.mkdir(parents=True, exist_ok=True)
    with out.open("w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(["scenario", "planner", "seed", *_COLUMNS])
        for key in sorted(values):
            w.writerow([*key, *(repr(v) for v in values[key])])
    print(f"{len(values)} episodes -> {out}")


def _benchmark_command(n: int, out: Path) -> list[str]:
    """The benchmark of crowd substep ``n`` (the module's command)."""
    srfm = str(Path(sys.executable).with_name("srfm"))
    return [
        *("nice", "-n", "10", srfm, "benchmark", "--suite", "paper", "--seeds", "0-99"),
        *("--crowd-substeps", str(n), "--no-logs", "--no-figures", "-j", "2"),
        *("--out", str(out)),
    ]


def run(root: Path, csv_out: Path, json_out: Path) -> None:
    """The three benchmarks into ``root-sub1``, ``root-sub2``, ``root-sub4``, each timed
    (wall and CPU seconds of all its processes, the 1-minute load before and after),
    then :func:`collect`; the times go to ``json_out`` with the run record."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[2]))
    from tools.results.record import run_record, start

    started, t0, load0 = start()
    runs = []
    folders = []
    for n in SUBSTEPS:
        folder = Path(f"{root}-sub{n}")
        folders.append(folder)
        cmd = _benchmark_command(n, folder)
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        load_before = os.getloadavg()
        wall0 = time.perf_counter()
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
        wall = time.perf_counter() - wall0
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
        runs.append(
            {
                "crowd_substeps": n,
                "command": " ".join(Path(a).name if a.endswith("/srfm") else a for a in cmd),
                "wall_s": round(wall, 1),
                "cpu_s": round(cpu, 1),
                "load_before": [round(x, 2) for x in load_before],
                "load_after": [round(x, 2) for x in os.getloadavg()],
            }
        )
        print(f"crowd substeps {n}: {wall:.0f} s wall, {cpu:.0f} s CPU")
    collect(folders, csv_out)
    doc = {"runs": runs, "run": run_record(started, t0, load0)}
    json_out.parent.mkdir(parents=True, exist_ok=True)
    json_out.write_text(json.dumps(doc, indent=1) + "\n", encoding="utf-8")
    print(f"-> {json_out}")


def _read(path: Path) -> dict[tuple[str, str], list[list[float]]]:
    """(scenario, planner) -> per step, the episodes' deviations (seed order)."""
    cells: dict[tuple[str, str], list[list[float]]] = defaultdict(lambda: [[], [], []])
    scenarios: list[str] = []
    with path.open() as f:
        for row in csv.DictReader(f):
            if row["scenario"] not in scenarios:
                scenarios.append(row["scenario"])
            for k, column in enumerate(_COLUMNS):
                cells[(row["scenario"], row["planner"])][k].append(float(row[column]))
    return cells


def _mean(x: list[float]) -> float:
    return sum(x) / len(x)


def _rel(coarse: float, fine: float) -> float:
    return (coarse - fine) / abs(fine) if fine != 0.0 else math.nan


def _pct(x: float) -> str:
    return "–" if math.isnan(x) else f"{100.0 * x:+.1f} %"


def _pair_stats(
    cells: dict[tuple[str, str], list[list[float]]], s: str, planners: list[str]
) -> dict[str, Any]:
    """A scenario's pairwise differences: how many are big, change > 5 %, the worst
    relative and absolute changes, the systematic ones and the sign flips."""
    n = len(cells[(s, planners[0])][0])
    means = {p: [_mean(x) for x in cells[(s, p)]] for p in planners}
    big = over = systematic = 0
    worst_rel = 0.0
    worst_abs = 0.0
    flips = []
    for a, b in itertools.combinations(planners, 2):
        d = [means[a][k] - means[b][k] for k in range(3)]
        worst_abs = max(worst_abs, abs(d[0] - d[2]))
        if d[0] * d[2] < 0.0:
            flips.append(f"{a}–{b}")
        if abs(d[2]) >= SMALL_M:
            big += 1
            rel = abs(_rel(d[0], d[2]))
            worst_rel = max(worst_rel, rel)
            over += rel > THRESHOLD
            if rel > THRESHOLD:
                ea, eb = cells[(s, a)], cells[(s, b)]
                change = [(ea[0][i] - eb[0][i]) - (ea[2][i] - eb[2][i]) for i in range(n)]
                mu = _mean(change)
                sd = math.sqrt(sum((c - mu) ** 2 for c in change) / (n - 1))
                systematic += abs(mu) > 2.0 * sd / math.sqrt(n)
    return {
        "big": big,
        "over": over,
        "systematic": systematic,
        "worst_rel": worst_rel,
        "worst_abs": worst_abs,
        "flips": flips,
    }


def table_lines(path: Path) -> list[str]:
    """The two Markdown tables and the verdict of each scenario."""
    cells = _read(path)
    scenarios = list(dict.fromkeys(s for s, _ in cells))
    planners = list(dict.fromkeys(p for _, p in cells))
    n = len(cells[(scenarios[0], planners[0])][0])
    out = [f"Mean deviation (m), {n} seeds, and its relative change from dt to dt/2, dt/4:", ""]
    out += ["| scenario | planner | dt | dt/2 | dt/4 | dt vs dt/2 | dt vs dt/4 |"]
    out += ["|---|---|--:|--:|--:|--:|--:|"]
    worst_mean: dict[str, float] = {}
    for s in scenarios:
        for p in planners:
            m = [_mean(x) for x in cells[(s, p)]]
            r2, r4 = _rel(m[0], m[1]), _rel(m[0], m[2])
            worst_mean[s] = max(worst_mean.get(s, 0.0), abs(r4))
            out.append(
                f"| {s} | {p} | {m[0]:.3f} | {m[1]:.3f} | {m[2]:.3f} | {_pct(r2)} | {_pct(r4)} |"
            )
    out += [
        "",
        "Pairwise differences of mean deviation (row planner − column planner), per "
        f"scenario: pairs, how many of those with |difference at dt/4| ≥ {SMALL_M} m "
        "change by more than 5 % from dt to dt/4, the largest such change, the largest "
        "absolute change (m), how many of the > 5 % changes exceed twice their standard "
        "error over the seeds (a systematic change, not the seeds' noise), and pairs "
        "whose sign flips:",
        "",
        "| scenario | pairs | ≥ 0.01 m | > 5 % | largest relative | largest absolute (m) "
        "| > 5 % and > 2 SE | sign flips dt→dt/4 |",
        "|---|--:|--:|--:|--:|--:|--:|---|",
    ]
    verdict = {}
    pairs = len(planners) * (len(planners) - 1) // 2
    for s in scenarios:
        st = _pair_stats(cells, s, planners)
        out.append(
            f"| {s} | {pairs} | {st['big']} | {st['over']} | {_pct(st['worst_rel'])} | "
            f"{st['worst_abs']:.3f} | {st['systematic']} | {', '.join(st['flips']) or 'none'} |"
        )
        verdict[s] = worst_mean[s] <= THRESHOLD and st["over"] == 0
    out.append("")
    for s in scenarios:
        state = "converged" if verdict[s] else "NOT converged"
        out.append(
            f"- {s}: {state} at dt (largest change of a mean deviation dt vs dt/4: "
            f"{_pct(worst_mean[s])})"
        )
    return out


def table(path: Path) -> None:
    """Print the two Markdown tables and the verdict."""
    print("\n".join(table_lines(path)))


def summary(path: Path) -> dict[str, Any]:
    """The figures the verdict of docs/metrics.md quotes: over the (scenario, planner)
    means, the largest |change| dt vs dt/4 overall and per scenario (with its planner and
    mean deviation) and every scenario's changes; over the pairs, the scenarios with a
    change above 5 %, the largest relative and absolute changes, the systematic ones and
    each scenario's sign flips."""
    cells = _read(path)
    scenarios = list(dict.fromkeys(s for s, _ in cells))
    planners = list(dict.fromkeys(p for _, p in cells))
    changes: dict[str, list[float]] = {}
    worst_planner: dict[str, str] = {}
    worst_value: dict[str, float] = {}
    for s in scenarios:
        changes[s] = []
        for p in planners:
            m = [_mean(x) for x in cells[(s, p)]]
            change = abs(_rel(m[0], m[2]))
            if not changes[s] or change > max(changes[s]):
                worst_planner[s], worst_value[s] = p, m[0]
            changes[s].append(change)
    stats = {s: _pair_stats(cells, s, planners) for s in scenarios}
    rel_scenario = max(scenarios, key=lambda s: stats[s]["worst_rel"])
    return {
        "n_means": len(scenarios) * len(planners),
        "pairs": len(planners) * (len(planners) - 1) // 2,
        "worst_mean": max(max(c) for c in changes.values()),
        "worst_mean_by_scenario": {s: max(c) for s, c in changes.items()},
        "worst_mean_planner": worst_planner,
        "worst_mean_value": worst_value,
        "mean_changes": changes,
        "over": [s for s in scenarios if stats[s]["over"]],
        "worst_rel": stats[rel_scenario]["worst_rel"],
        "worst_rel_scenario": rel_scenario,
        "worst_abs": max(st["worst_abs"] for st in stats.values()),
        "systematic": sum(st["systematic"] for st in stats.values()),
        "flips": {s: st["flips"] for s, st in stats.items()},
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = parser.add_subparsers(dest="command", required=True)
    c = sub.add_parser("collect", help="the episodes' deviations of three folders -> CSV")
    c.add_argument("folders", nargs=3, type=Path)
    c.add_argument("--csv", type=Path, required=True)
    t = sub.add_parser("table", help="the Markdown tables from the CSV")
    t.add_argument("csv", type=Path)
    r = sub.add_parser("run", help="the three benchmarks, timed, then collect")
    r.add_argument("root", type=Path, help="folders ROOT-sub1, ROOT-sub2, ROOT-sub4")
    r.add_argument("--csv", type=Path, required=True)
    r.add_argument("--json", type=Path, required=True)
    args = parser.parse_args()
    if args.command == "collect":
        collect(args.folders, args.csv)
    elif args.command == "run":
        run(args.root, args.csv, args.json)
    else:
        table(args.csv)


if __name__ == "__main__":
    sys.exit(main())
