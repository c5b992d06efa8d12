"""The issue-17 checks of the scenario library over 20 seeds (the tests run 3).

For every Francis and NavWareSet scenario: the counterfactual pedestrians reach their
goals (>= 95 %), never stand in a wall, nobody overlaps at the start, and a classical
planner (DWA, else the first of VO, ORCA, social-force that passes) reaches the robot
goal in >= 90 % of the seeds. Prints a Markdown table; exits 1 when a check fails.

    nice .venv/bin/python tools/scenarios/check_scenarios.py [--seeds 20] [NAME ...]
"""

from __future__ import annotations

import argparse
import sys
import time

from srfm.scenarios import FLOW_SCENARIOS, FRANCIS_SCENARIOS, NAVWARESET_SCENARIOS
from srfm.sim.checks import check_scenario

PLANNERS = ("dwa", "vo", "orca", "social-force")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--seeds", type=int, default=20)
    parser.add_argument("names", nargs="*")
    args = parser.parse_args()
    names = args.names or [*FRANCIS_SCENARIOS, *NAVWARESET_SCENARIOS, *FLOW_SCENARIOS]
    seeds = range(args.seeds)
    failed = []
    print("| scenario | pedestrians arrived | in a wall | overlaps | robot goal (planner) |")
    print("|---|---|---|---|---|")
    start = time.perf_counter()
    for name in names:
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
        print(
            f"| {name} | {check.ped_arrived}/{check.ped_total} | {check.in_wall_samples} | "
            f"{check.overlapping_starts} | {check.robot_goals}/{check.seeds} ({check.planner})"
            + ("" if ok else " **FAIL**")
            + " |",
            flush=True,
        )
    print(f"\n{len(names)} scenarios x {args.seeds} seeds in {time.perf_counter() - start:.0f} s")
    if failed:
        print(f"failed: {', '.join(failed)}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
