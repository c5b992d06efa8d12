"""One line per scenario of a benchmark results folder: every planner's mean Fréchet
deviation (m) and, in brackets, its robot success rate; then the means over all
scenarios with success and collision rates (docs/benchmark.md, the Francis suite).

    .venv/bin/python tools/analysis/suite_summary.py results/francis [--without narrow_hallway]
"""

from __future__ import annotations

import argparse
import csv
import math
from collections import defaultdict
from pathlib import Path


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("results", type=Path, help="a srfm benchmark --out folder")
    ap.add_argument("--without", action="append", default=[], help="also: means without it")
    args = ap.parse_args()
    with (args.results / "episodes.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    scenarios = list(dict.fromkeys(r["scenario"] for r in rows))
    planners = sorted({r["planner"] for r in rows})
    cell: dict[tuple[str, str], list[dict[str, str]]] = defaultdict(list)
    for r in rows:
        cell[r["scenario"], r["planner"]].append(r)
    seeds = {len(v) for v in cell.values()}
    print(f"{len(rows)} episodes, seeds per cell: {sorted(seeds)}\n")
    print("| scenario | " + " | ".join(planners) + " |")
    print("|---|" + "---:|" * len(planners))

    def frechet(rs: list[dict[str, str]]) -> float:
        values = [float(r["frechet_m"]) for r in rs if r["frechet_m"] not in ("", "nan")]
        return sum(values) / len(values) if values else math.nan

    def rate(rs: list[dict[str, str]], key: str) -> float:
        return 100.0 * sum(float(r[key]) for r in rs) / len(rs)

    for s in scenarios:
        items = [
            f"{frechet(cell[s, p]):.2f} ({rate(cell[s, p], 'robot_success'):.0f} %)"
            for p in planners
        ]
        print(f"| {s} | " + " | ".join(items) + " |")
    for left_out in [None, *args.without]:
        chosen = [s for s in scenarios if s != left_out]
        label = f"all {len(chosen)}" + (f" (without {left_out})" if left_out else "")
        items = []
        for p in planners:
            rs = [r for s in chosen for r in cell[s, p]]
            per_scenario = sum(frechet(cell[s, p]) for s in chosen) / len(chosen)
            items.append(
                f"{per_scenario:.2f} ({rate(rs, 'robot_success'):.0f} %, "
                f"{rate(rs, 'robot_collision'):.0f} % coll.)"
            )
        print(f"| **{label}** | " + " | ".join(items) + " |")


if __name__ == "__main__":
    main()
