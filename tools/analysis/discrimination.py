"""Where the benchmark can tell planners apart (issue 29): headroom, standard errors and
seeds needed per scenario; the selection of the `discriminative` suite; its report.

    # 1. measure (resumable: an interrupted run goes on where it stopped)
    nice -n 5 .venv/bin/python tools/analysis/discrimination.py run results/disc-select \
        --suite all --seeds 1000-1099
    # 2. select the suite on those seeds (writes docs/discrimination/selection.json)
    .venv/bin/python tools/analysis/discrimination.py select results/disc-select
    # 3. measure the chosen suite on other seeds and report it
    nice -n 5 .venv/bin/python tools/analysis/discrimination.py run results/disc-report \
        --suite discriminative --seeds 0-99
    .venv/bin/python tools/analysis/discrimination.py report results/disc-report \
        --json /tmp/report.json
    # the oracle's CPU time per episode (paper suite; --suite francis for another)
    .venv/bin/python tools/analysis/discrimination.py cost --seeds 0-19
    # any results folder with straight and oracle (e.g. a suite without td3-srfm)
    .venv/bin/python tools/analysis/discrimination.py report results/francis \
        --json /tmp/francis.json

`run` is `srfm benchmark -j 1 --no-logs --no-figures` with the planners below (`-j N`
for N workers: the same episodes); the other commands read its per-episode files and
print Markdown. The docs' tables (docs/results/discriminative.md) are generated from the
committed results sets by ``tools/results/generate.py`` with this file's functions.

SELECTION RULE (written down on 2026-11-27 before the selection was run, and not
changed after): the candidates are the 28 scenarios of suite `all` (paper, francis,
navwareset, flows; not `large`, whose 300-400 pedestrians make the oracle cost minutes
per episode, and not the training scenario `random`). On seeds 1000-1099, with every
planner of `PLANNERS`, a scenario qualifies when

  (a) it discriminates (srfm.metrics.headroom.discriminates): headroom = mean of
      straight - oracle >= 0.1 m and >= 3 standard errors (SD of straight / sqrt(n));
  (b) the oracle reaches its goal in >= 95 % of the seeds;
  (c) straight reaches its goal in >= 95 % of the seeds (so the headroom's upper end
      is a robot that does its task);
  (d) 100 seeds suffice to detect 0.05 m between two planners (seeds_needed <= 100,
      sigma_d the median SD of paired differences over the pairs of non-reference
      planners).

Qualifying scenarios are ranked by headroom / sigma_d (the headroom in units of the
noise of a paired comparison); the first `MAX_SUITE` (8) form the suite, listed in the
library's order. The report runs them on seeds 0-99, which the selection never saw.
"""

from __future__ import annotations

import argparse
import json
import math
import subprocess
import sys
import time
from collections import defaultdict
from pathlib import Path
from typing import Any

import numpy as np

from srfm.metrics.headroom import (
    DETECT_M,
    MIN_HEADROOM_M,
    MIN_STANDARD_ERRORS,
    scenario_references,
)
from srfm.scenarios.suites import SUITES

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path:  # run as a script from the repository's root
    sys.path.insert(0, str(ROOT))

from tools.results.record import source_commit  # noqa: E402

PLANNERS = (
    "straight",
    "oracle",
    "stay",
    "dwa",
    "orca",
    "social-force",
    "vo",
    "td3-base",
    "td3-srfm",
)
MIN_GOAL_RATE = 0.95
MAX_SEEDS = 100
MAX_SUITE = 8
SELECTION = ROOT / "docs" / "discrimination" / "selection.json"


Cells = dict[tuple[str, str], dict[int, dict[str, float]]]


def _read(out: Path) -> tuple[list[str], list[str], Cells]:
    """Scenarios and planners of the run's request, in order, and per (scenario,
    planner) per seed its frechet_m and success, from the run's per-episode files (so a
    run still going can be read: a scenario counts once every planner of the request
    has all its seeds). The request must have ``straight`` and ``oracle``."""
    cells: Cells = defaultdict(dict)
    manifest = json.loads((out / "manifest.json").read_text(encoding="utf-8"))
    order = list(manifest["request"]["scenarios"])
    planners = [p for p in PLANNERS if p in manifest["request"]["planners"]]
    if not {"straight", "oracle"} <= set(planners):
        raise SystemExit(f"{out}: the run needs the planners straight and oracle")
    n_seeds = len(manifest["request"]["seeds"])
    for path in sorted((out / "episodes").glob("*/*/seed-*.json")):
        doc = json.loads(path.read_text(encoding="utf-8"))
        value = doc["metrics"]["frechet_m"]
        cells[doc["scenario"], doc["planner"]][int(doc["seed"])] = {
            "frechet_m": math.nan if value is None else float(value),
            "success": float(doc["outcome"] == "goal_reached"),
        }
    done = [s for s in order if all(len(cells.get((s, p), {})) == n_seeds for p in planners)]
    return done, planners, cells


def _measure(out: Path) -> list[dict[str, Any]]:
    """One entry per scenario of a run's folder: the reference points and every
    planner's mean (:func:`measure`)."""
    scenarios, planners, cells = _read(out)
    return measure(cells, scenarios, planners)


def measure(cells: Cells, scenarios: list[str], planners: list[str]) -> list[dict[str, Any]]:
    """One entry per scenario: the reference points and every planner's mean, SD and
    goal rate over the seeds every planner has."""
    rows = []
    for s in scenarios:
        seeds = sorted(set.intersection(*(set(cells[s, p]) for p in planners)))
        values = {p: np.array([cells[s, p][k]["frechet_m"] for k in seeds]) for p in planners}
        goal = {p: float(np.mean([cells[s, p][k]["success"] for k in seeds])) for p in planners}
        refs = scenario_references(values)
        rows.append(
            {
                "scenario": s,
                "n_seeds": len(seeds),
                "seeds": [seeds[0], seeds[-1]],
                "mean_m": {p: float(np.nanmean(v)) for p, v in values.items()},
                "sd_m": {p: float(np.nanstd(v, ddof=1)) for p, v in values.items()},
                "goal_rate": goal,
                "standard_error_m": refs.standard_error,
                "headroom_m": refs.headroom.estimate,
                "headroom_ci_m": [refs.headroom.low, refs.headroom.high],
                "headroom_in_se": refs.headroom.estimate / refs.standard_error,
                "scores": {p: [i.estimate, i.low, i.high] for p, i in refs.scores.items()},
                "sd_diff_m": refs.sd_diff,
                "seeds_needed": refs.seeds_needed,
                "discriminates": refs.discriminates,
            }
        )
    return rows


def select(rows: list[dict[str, Any]]) -> list[str]:
    """Apply the selection rule to measured rows (adds ``fails`` and ``rank`` to each);
    return the suite, in the rows' (the library's) order."""
    for r in rows:
        r["fails"] = _qualifies(r)
    qualified = [r for r in rows if not r["fails"]]
    qualified.sort(key=lambda r: -r["headroom_m"] / r["sd_diff_m"])
    for rank, r in enumerate(qualified, start=1):
        r["rank"] = rank
    chosen = {r["scenario"] for r in qualified[:MAX_SUITE]}
    return [r["scenario"] for r in rows if r["scenario"] in chosen]


def thresholds() -> dict[str, float]:
    """The rule's thresholds, as the selection file records them."""
    return {
        "min_headroom_m": MIN_HEADROOM_M,
        "min_standard_errors": MIN_STANDARD_ERRORS,
        "min_goal_rate": MIN_GOAL_RATE,
        "detect_m": DETECT_M,
        "max_seeds": MAX_SEEDS,
        "max_suite": MAX_SUITE,
    }


def _qualifies(row: dict[str, Any]) -> list[str]:
    """The conditions (a)-(d) a scenario fails (empty: it qualifies)."""
    failed = []
    if not row["discriminates"]:
        failed.append("a")
    if row["goal_rate"]["oracle"] < MIN_GOAL_RATE:
        failed.append("b")
    if row["goal_rate"]["straight"] < MIN_GOAL_RATE:
        failed.append("c")
    if row["seeds_needed"] is None or row["seeds_needed"] > MAX_SEEDS:
        failed.append("d")
    return failed


def _f(x: float, digits: int = 2) -> str:
    return "–" if x is None or not math.isfinite(x) else f"{x:.{digits}f}"


def table(rows: list[dict[str, Any]], *, selection: bool) -> str:
    head = (
        "| scenario | straight (m) | oracle (m) | stay (m) | headroom (m) [95 % CI] "
        "| SE (m) | headroom / SE | σ_d (m) | seeds for 0.05 m | oracle goal | discriminates |"
    )
    if selection:
        head += " fails | rank |"
    lines = [head, "|---" * (head.count("|") - 1) + "|"]
    for r in rows:
        m = r["mean_m"]
        ci = r["headroom_ci_m"]
        cells = [
            r["scenario"],
            _f(m["straight"]),
            _f(m["oracle"]),
            _f(m.get("stay", math.nan)),
            f"{_f(r['headroom_m'])} [{_f(ci[0])}, {_f(ci[1])}]",
            _f(r["standard_error_m"], 3),
            _f(r["headroom_in_se"], 1),
            _f(r["sd_diff_m"], 3),
            str(r["seeds_needed"]),
            f"{100 * r['goal_rate']['oracle']:.0f} %",
            "yes" if r["discriminates"] else "**no**",
        ]
        if selection:
            cells += [",".join(r["fails"]) or "–", str(r.get("rank") or "–")]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def _planners(rows: list[dict[str, Any]]) -> list[str]:
    """The planners measured, in ``PLANNERS``' order."""
    measured = {p for r in rows for p in r["mean_m"]}
    return [p for p in PLANNERS if p in measured]


def scores_table(rows: list[dict[str, Any]]) -> str:
    planners = [p for p in _planners(rows) if p not in ("straight", "oracle")]
    head = "| scenario | " + " | ".join(planners) + " |"
    lines = [head, "|---" * (len(planners) + 1) + "|"]
    for r in rows:
        items = []
        for p in planners:
            est, low, high = r["scores"].get(p, [math.nan] * 3)
            items.append(f"{_f(est)} [{_f(low)}, {_f(high)}]")
        lines.append(f"| {r['scenario']} | " + " | ".join(items) + " |")
    return "\n".join(lines)


def means_table(rows: list[dict[str, Any]]) -> str:
    planners = _planners(rows)
    head = "| scenario | " + " | ".join(planners) + " |"
    lines = [head, "|---" * (len(planners) + 1) + "|"]
    for r in rows:
        items = [
            f"{_f(r['mean_m'][p])} ± {_f(r['sd_m'][p])} ({100 * r['goal_rate'][p]:.0f} %)"
            for p in planners
        ]
        lines.append(f"| {r['scenario']} | " + " | ".join(items) + " |")
    return "\n".join(lines)


def cmd_run(args: argparse.Namespace) -> None:
    command = [
        sys.executable,
        "-m",
        "srfm.cli",
        "benchmark",
        "--suite",
        args.suite,
        "-p",
        args.planners,
        "--seeds",
        args.seeds,
        "-j",
        str(args.jobs),
        "--no-logs",
        "--no-figures",
        "--reference",
        "straight",
        "--out",
        str(args.out),
    ]
    print(" ".join(command), flush=True)
    subprocess.run(command, check=True)


def cmd_select(args: argparse.Namespace) -> None:
    manifest = json.loads((args.out / "manifest.json").read_text(encoding="utf-8"))
    if manifest["request"]["planners"] != list(PLANNERS):
        raise SystemExit(f"{args.out}: the selection rule needs the planners {PLANNERS}")
    rows = _measure(args.out)
    suite = select(rows)
    qualified = [r for r in rows if not r["fails"]]
    measured = {r["scenario"] for r in rows}
    incomplete = [s for s in manifest["request"]["scenarios"] if s not in measured]
    doc = {
        "rule": __doc__.split("SELECTION RULE")[1].split('"""')[0].strip(),
        "thresholds": thresholds(),
        "planners": list(PLANNERS),
        "suite": suite,
        # candidates whose episodes were not all there: not selected from
        "incomplete": incomplete,
        "scenarios": rows,
    }
    args.json.parent.mkdir(parents=True, exist_ok=True)
    args.json.write_text(json.dumps(doc, indent=1, allow_nan=True) + "\n", encoding="utf-8")
    print(table(rows, selection=True))
    print(f"\nqualified: {len(qualified)}; suite: {suite}")
    if incomplete:
        print(f"not complete (left out): {incomplete}")


def cmd_report(args: argparse.Namespace) -> None:
    rows = _measure(args.out)
    doc = {"planners": _planners(rows), "scenarios": rows}
    args.json.parent.mkdir(parents=True, exist_ok=True)
    args.json.write_text(json.dumps(doc, indent=1, allow_nan=True) + "\n", encoding="utf-8")
    print(table(rows, selection=False))
    print()
    print(means_table(rows))
    print()
    print(scores_table(rows))


def cmd_cost(args: argparse.Namespace) -> None:
    """The oracle's CPU time per episode (``time.process_time``, one process, after a
    warm-up episode) over a suite's scenarios, written with the command, the commit, the
    time and the load to ``--json`` (resumable: the scenarios measured stay)."""
    import os

    from srfm.scenarios import load_scenario
    from srfm.sim.episode import run_episode

    lo, hi = (int(x) for x in args.seeds.split("-"))
    commit = source_commit()
    doc: dict[str, Any] = {
        "command": f"python tools/analysis/discrimination.py cost --suite {args.suite} "
        f"--seeds {args.seeds}" + (f" --json {args.json}" if args.json else ""),
        "commit": commit,
        "started": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
        "cpus": os.cpu_count(),
        "load_average": [],
        "scenarios": {},
    }
    if args.json and args.json.exists():  # resume: the scenarios already measured stay
        old = json.loads(args.json.read_text(encoding="utf-8"))
        if "scenarios" in old:
            doc = old
    out: dict[str, Any] = doc["scenarios"]
    for name in SUITES[args.suite]:
        if name not in out:
            scenario = load_scenario(name)
            run_episode(scenario, hi + 1, "oracle")  # compile outside the clock
            times, goals = [], 0
            for seed in range(lo, hi + 1):
                t0 = time.process_time()
                record = run_episode(scenario, seed, "oracle")
                times.append(time.process_time() - t0)
                goals += record.outcome == "goal_reached"
            out[name] = {
                "mean_s": float(np.mean(times)),
                "max_s": float(np.max(times)),
                "seeds": [lo, hi],
                "goals": goals,
            }
            doc["load_average"].append(round(os.getloadavg()[0], 2))
            if args.json:
                args.json.write_text(json.dumps(doc, indent=1) + "\n", encoding="utf-8")
        row = out[name]
        print(f"| {name} | {row['mean_s']:.2f} | {row['max_s']:.2f} |", flush=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    sub = ap.add_subparsers(dest="command", required=True)
    run = sub.add_parser("run", help="srfm benchmark with the reference planners")
    run.add_argument("out", type=Path)
    run.add_argument("--suite", default="all")
    run.add_argument("--seeds", default="1000-1099")
    run.add_argument(
        "-p",
        "--planners",
        default=",".join(PLANNERS),
        help="comma-separated; default: every planner of the selection rule",
    )
    run.add_argument(
        "-j",
        "--jobs",
        type=int,
        default=1,
        help="worker processes (the results do not depend on it)",
    )
    run.set_defaults(func=cmd_run)
    sel = sub.add_parser("select", help="apply the selection rule to a run")
    sel.add_argument("out", type=Path)
    sel.add_argument("--json", type=Path, default=SELECTION)
    sel.set_defaults(func=cmd_select)
    rep = sub.add_parser("report", help="reference points of every scenario of a run")
    rep.add_argument("out", type=Path)
    rep.add_argument("--json", type=Path, required=True)
    rep.set_defaults(func=cmd_report)
    cost = sub.add_parser("cost", help="the oracle's CPU time per episode over a suite")
    cost.add_argument("--suite", default="paper", choices=sorted(SUITES))
    cost.add_argument("--seeds", default="0-19")
    cost.add_argument("--json", type=Path)
    cost.set_defaults(func=cmd_cost)
    args = ap.parse_args()
    args.func(args)


if __name__ == "__main__":
    main()
