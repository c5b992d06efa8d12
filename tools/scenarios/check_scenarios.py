"""The issue-17 checks of the scenario library over 20 seeds (the tests run 3).

For every Francis and NavWareSet scenario: the counterfactual pedestrians reach their
goals (>= 95 %), never stand in a wall, nobody overlaps at the start, and a classical
planner (DWA, else the first of VO, ORCA, social-force that passes) reaches the robot
goal in >= 90 % of the seeds. Prints a Markdown table; exits 1 when a check fails.

    nice .venv/bin/python tools/scenarios/check_scenarios.py [--seeds 20] [NAME ...] \\
        [--json docs/scenarios/checks.json]

``--json`` also writes every scenario's row (with the CPU seconds its checks took, this
process alone, ``time.process_time``) with the command, the commit, when it ran and its
wall time, and the run record of ``tools/results/record.py``: the data of the table in
docs/scenarios.md (``tools/results/generate.py``).
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from pathlib import Path

from srfm.scenarios import FLOW_SCENARIOS, FRANCIS_SCENARIOS, NAVWARESET_SCENARIOS
from srfm.sim.checks import check_scenario

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path:  # run as a script from the repository's root
    sys.path.insert(0, str(ROOT))

from tools.results.record import run_record, source_commit  # noqa: E402
from tools.results.record import start as record_start  # noqa: E402

PLANNERS = ("dwa", "vo", "orca", "social-force")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--seeds", type=int, default=20)
    parser.add_argument("names", nargs="*")
    parser.add_argument("--json", type=Path, help="also write the rows and provenance here")
    args = parser.parse_args()
    rows: dict[str, dict[str, object]] = {}
    record_started, t0, load0 = record_start()
    started = time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())
    names = args.names or [*FRANCIS_SCENARIOS, *NAVWARESET_SCENARIOS, *FLOW_SCENARIOS]
    seeds = range(args.seeds)
    failed = []
    print("| scenario | pedestrians arrived | in a wall | overlaps | robot goal (planner) |")
    print("|---|---|---|---|---|")
    start = time.perf_counter()
    cpu_start = time.process_time()
    for name in names:
        cpu0 = time.process_time()
        for planner in PLANNERS:
            check = check_scenario(name, seeds, planner)
            if check.robot_success_rate >= 0.9:
                break
        ok = (
            check.arrival_rate >= 0.95
            and check.in_wall_samples == 0
            and check.overlapping_starts == 0
            and check.robot_success_rate >= 0.9
        )
        if not ok:
            failed.append(name)
        rows[name] = {
            "ped_arrived": check.ped_arrived,
            "ped_total": check.ped_total,
            "in_wall_samples": check.in_wall_samples,
            "overlapping_starts": check.overlapping_starts,
            "robot_goals": check.robot_goals,
            "seeds": check.seeds,
            "planner": check.planner,
            "ok": ok,
            "cpu_s": round(time.process_time() - cpu0, 2),
        }
        print(
            f"| {name} | {check.ped_arrived}/{check.ped_total} | {check.in_wall_samples} | "
            f"{check.overlapping_starts} | {check.robot_goals}/{check.seeds} ({check.planner})"
            + ("" if ok else " **FAIL**")
            + " |",
            flush=True,
        )
    wall = time.perf_counter() - start
    cpu = time.process_time() - cpu_start
    print(f"\n{len(names)} scenarios x {args.seeds} seeds in {wall:.0f} s")
    if args.json is not None:
        commit = source_commit()
        doc = {
            "command": "python tools/scenarios/check_scenarios.py " + " ".join(sys.argv[1:]),
            "commit": commit,
            "started": started,
            "wall_s": wall,
            "cpus": os.cpu_count(),
            "load_average": round(os.getloadavg()[0], 2),
            "cpu_s": round(cpu, 1),
            "scenarios": rows,
            "run": run_record(record_started, t0, load0),
        }
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(doc, indent=1) + "\n", encoding="utf-8")
    if failed:
        print(f"failed: {', '.join(failed)}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
