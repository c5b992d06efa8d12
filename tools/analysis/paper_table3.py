"""The paper's Table 3 beside srfm's, cell by cell (docs/benchmark.md, issue 29).

Reads the ``summary.json`` of a paper-suite results folder (the five evaluation
scenarios with dwa, vo, td3-base and td3-srfm) and prints Markdown: per scenario and
planner, the paper's mean ± std and srfm's for the four Table 3 columns, then the
lowest Fréchet deviation per scenario in each, and how many of the table's marks the
multiple-comparison correction removed.

    .venv/bin/python tools/analysis/paper_table3.py results/paper100

The paper's numbers are those of Agrawal et al. 2024, Table 3 (mean ± std over "100
runs"; its ``*`` marks an independent t-test against its own policy at p = 0.05).
"""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import Any

SCENARIOS = {
    "footpath": "Scenario 1",
    "crosswalk": "Scenario 2",
    "cross_footpath": "Scenario 3",
    "circle": "Scenario 4",
    "concert": "Scenario 5",
}
PLANNERS = {"td3-srfm": "Ours", "td3-base": "RL_base", "dwa": "DWA", "vo": "VO"}
COLUMNS = ("frechet_m", "min_robot_distance_m", "path_length_m", "robot_duration_s")
HEADERS = ("Fréchet (m)", "Min. robot dist. (m)", "Traj. length (m)", "Time (s)")

# Agrawal et al. 2024, Table 3: (mean, std, marked with * in the paper) per column.
PAPER: dict[str, dict[str, tuple[tuple[float, float, bool], ...]]] = {
    "footpath": {
        "td3-srfm": (
            (0.69, 0.05, True),
            (1.42, 0.09, False),
            (8.94, 0.10, False),
            (18.71, 0.15, False),
        ),
        "td3-base": (
            (0.78, 0.04, False),
            (1.49, 0.18, False),
            (9.00, 0.13, False),
            (18.71, 0.20, False),
        ),
        "dwa": ((0.76, 0.05, False), (1.55, 0.15, False), (8.77, 0.14, True), (14.49, 1.20, True)),
        "vo": ((0.76, 0.04, False), (1.63, 0.20, True), (9.02, 0.10, False), (23.01, 1.27, False)),
    },
    "crosswalk": {
        "td3-srfm": (
            (1.25, 0.17, False),
            (1.42, 0.15, False),
            (14.63, 0.12, False),
            (19.57, 0.70, False),
        ),
        "td3-base": (
            (1.32, 0.14, False),
            (1.40, 0.19, False),
            (14.74, 0.23, False),
            (20.74, 0.54, False),
        ),
        "dwa": ((1.57, 0.17, False), (1.58, 0.05, False), (14.09, 0.38, True), (17.60, 1.71, True)),
        "vo": (
            (1.29, 0.15, False),
            (1.61, 0.05, False),
            (14.63, 0.17, False),
            (21.12, 2.53, False),
        ),
    },
    "cross_footpath": {
        "td3-srfm": (
            (0.68, 0.08, False),
            (1.76, 0.08, True),
            (8.68, 0.08, False),
            (19.11, 0.44, False),
        ),
        "td3-base": (
            (0.72, 0.09, False),
            (1.62, 0.17, False),
            (8.79, 0.11, False),
            (19.37, 0.41, False),
        ),
        "dwa": ((0.75, 0.08, False), (1.70, 0.13, False), (8.67, 0.14, False), (14.82, 1.28, True)),
        "vo": ((0.76, 0.11, False), (1.69, 0.07, False), (8.86, 0.15, False), (20.01, 0.81, False)),
    },
    "circle": {
        "td3-srfm": (
            (4.72, 0.36, False),
            (1.52, 0.04, False),
            (8.68, 0.35, False),
            (13.00, 0.02, False),
        ),
        "td3-base": (
            (4.43, 0.45, False),
            (1.53, 0.12, False),
            (9.06, 0.42, False),
            (14.19, 0.72, False),
        ),
        "dwa": ((5.67, 0.65, False), (1.69, 0.05, False), (7.38, 0.91, True), (11.65, 1.48, True)),
        "vo": ((4.38, 0.38, True), (1.72, 0.04, True), (9.09, 0.38, False), (14.60, 0.57, False)),
    },
    "concert": {
        "td3-srfm": (
            (0.70, 0.05, True),
            (1.56, 0.10, False),
            (2.18, 0.13, True),
            (22.02, 0.10, True),
        ),
        "td3-base": (
            (0.79, 0.10, False),
            (1.57, 0.10, False),
            (2.34, 0.20, False),
            (22.23, 0.21, False),
        ),
        "dwa": ((0.81, 0.06, False), (1.66, 0.06, True), (2.64, 0.27, False), (33.91, 7.21, False)),
        "vo": ((0.79, 0.07, False), (1.62, 0.08, False), (2.39, 0.17, False), (25.15, 2.74, False)),
    },
}


def _cell(entry: dict) -> str:
    marks = entry.get("marks", "").replace("*", "\\*")
    return f"{marks}{entry['mean']:.2f} ± {entry['std']:.2f}"


def main(folder: Path) -> None:
    summary = json.loads((folder / "summary.json").read_text(encoding="utf-8"))
    print("\n".join(lines(summary["table"])))


def lines(table: dict[str, Any]) -> list[str]:
    """The Markdown of the comparison, from the ``table`` entry of a summary.json."""
    out: list[str] = []
    add = out.append
    n = table["n_seeds"]
    add(f"| Scenario | Planner | {' | '.join(f'{h}: paper | srfm' for h in HEADERS)} |")
    add("|---|---|" + "--:|--:|" * len(HEADERS))
    for scenario, paper_name in SCENARIOS.items():
        for planner, label in PLANNERS.items():
            cells = table["scenarios"][scenario][planner]
            parts = []
            for k, column in enumerate(COLUMNS):
                mean, std, star = PAPER[scenario][planner][k]
                star_text = "\\*" if star else ""
                parts.append(f"{star_text}{mean:.2f} ± {std:.2f}")
                parts.append(_cell(cells[column]))
            add(f"| {scenario} ({paper_name}) | {planner} ({label}) | " + " | ".join(parts) + " |")
    add("")
    add("Lowest mean Fréchet deviation per scenario (paper's four planners):")
    add("")
    add(
        "| Scenario | paper | srfm (same four) "
        "| srfm: td3-srfm vs the lowest other, paired p (Holm) |"
    )
    add("|---|---|---|---|")
    for scenario in SCENARIOS:
        paper_best = min(PLANNERS, key=lambda p: PAPER[scenario][p][0][0])
        cells = table["scenarios"][scenario]
        ours = min(PLANNERS, key=lambda p: cells[p]["frechet_m"]["mean"])
        others = [p for p in PLANNERS if p != "td3-srfm"]
        rival = min(others, key=lambda p: cells[p]["frechet_m"]["mean"])
        entry = cells[rival]["frechet_m"]
        diff = cells["td3-srfm"]["frechet_m"]["mean"] - entry["mean"]
        add(
            f"| {scenario} | {paper_best} | {ours} | td3-srfm − {rival} = {diff:+.3f} m, "
            f"p = {entry['paired_p']:.2g} (adjusted {entry['paired_p_adjusted']:.2g}) |"
        )
    add("")
    raw = adjusted = 0
    for scenario in table["scenarios"].values():
        for cells in scenario.values():
            for name, entry in cells.items():
                if "|" in name or "paired_p" not in entry:
                    continue
                raw += entry["paired_p"] is not None and entry["paired_p"] < 0.05
                adjusted += (
                    entry["paired_p_adjusted"] is not None and entry["paired_p_adjusted"] < 0.05
                )
    add(
        f"Paired tests against {table['reference']} in the four unconditional columns "
        f"({n} seeds): {raw} with p < 0.05 before the correction, {adjusted} after Holm's "
        f"over the table's {table['family']['paired']} paired tests."
    )
    return out


if __name__ == "__main__":
    main(Path(sys.argv[1]))
