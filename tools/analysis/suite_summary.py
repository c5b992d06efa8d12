"""One line per scenario of a benchmark results folder: every planner's mean Fréchet
deviation (m) and, in brackets, its robot success rate; then the means over all
scenarios with success and collision rates (docs/benchmark.md, the Francis suite).
With ``--success``, each cell is the mean and the k of its n episodes in which the
robot reached its goal (k/n), and where k < n the mean over those k after a semicolon
(``–`` where k = 0): ``1.17; 1.09 (99/100)``.

    .venv/bin/python tools/analysis/suite_summary.py results/francis [--without narrow_hallway]
    .venv/bin/python tools/analysis/suite_summary.py results/francis --success

Planners are listed in the order of the run (episodes.csv).
"""

from __future__ import annotations

import argparse
import csv
import math
from collections import defaultdict
from pathlib import Path

Row = dict[str, str]


def frechet(rows: list[Row]) -> float:
    """Mean Fréchet deviation over the rows with a defined value (nan: none)."""
    values = [float(r["frechet_m"]) for r in rows if r["frechet_m"] not in ("", "nan")]
    return sum(values) / len(values) if values else math.nan


def rate(rows: list[Row], key: str) -> float:
    """Percentage of the rows whose 0/1 column ``key`` is 1."""
    return 100.0 * sum(float(r[key]) for r in rows) / len(rows)


def _mean(x: float) -> str:
    return "–" if math.isnan(x) else f"{x:.2f}"


def cell(rows: list[Row], *, success: bool) -> str:
    """One scenario × planner cell: mean (success %), or with ``success`` the mean
    and the k of the n episodes in which the robot reached its goal (k/n), with, where
    k < n, the mean over those k after a semicolon (``–`` where k = 0)."""
    text = _mean(frechet(rows))
    if not success:
        return f"{text} ({rate(rows, 'robot_success'):.0f} %)"
    reached = [r for r in rows if float(r["robot_success"]) == 1.0]
    if len(reached) < len(rows):
        text += f"; {_mean(frechet(reached))}"
    return f"{text} ({len(reached)}/{len(rows)})"


def summary(rows: list[Row], *, without: list[str], success: bool = False) -> list[str]:
    """The Markdown lines: a header, a line per scenario, and the averages."""
    scenarios = list(dict.fromkeys(r["scenario"] for r in rows))
    planners = list(dict.fromkeys(r["planner"] for r in rows))
    cells: dict[tuple[str, str], list[Row]] = defaultdict(list)
    for r in rows:
        cells[r["scenario"], r["planner"]].append(r)
    seeds = {len(v) for v in cells.values()}
    lines = [f"{len(rows)} episodes, seeds per cell: {sorted(seeds)}", ""]
    lines.append("| scenario | " + " | ".join(planners) + " |")
    lines.append("|---|" + "---:|" * len(planners))
    for s in scenarios:
        items = [cell(cells[s, p], success=success) for p in planners]
        lines.append(f"| {s} | " + " | ".join(items) + " |")
    for left_out in [None, *without]:
        chosen = [s for s in scenarios if s != left_out]
        label = f"all {len(chosen)}" + (f" (without {left_out})" if left_out else "")
        items = []
        for p in planners:
            pooled = [r for s in chosen for r in cells[s, p]]
            per_scenario = sum(frechet(cells[s, p]) for s in chosen) / len(chosen)
            items.append(
                f"{per_scenario:.2f} ({rate(pooled, 'robot_success'):.0f} %, "
                f"{rate(pooled, 'robot_collision'):.0f} % coll.)"
            )
        lines.append(f"| **{label}** | " + " | ".join(items) + " |")
    return lines


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("results", type=Path, help="a srfm benchmark --out folder")
    ap.add_argument("--without", action="append", default=[], help="also: means without it")
    ap.add_argument(
        "--success", action="store_true", help="also the mean over successful episodes, n"
    )
    args = ap.parse_args()
    with (args.results / "episodes.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    print("\n".join(summary(rows, without=args.without, success=args.success)))


if __name__ == "__main__":
    main()
