"""A compact view of a run's rank probabilities under parameter draws (issue 29).

Reads ``rankings.json`` (``srfm benchmark --param-draws K``) and the run's own
``summary.json`` (the base parameters, the same seeds) and prints Markdown: per
scenario and planner, P(first), P(last), the expected rank over the draws, the
interval of the mean Fréchet deviation over the draws and the rank at the base
parameters; then the full rank tables (``rankings.md``).

    .venv/bin/python tools/analysis/rank_summary.py results/draws
"""

from __future__ import annotations

import json
import sys
from pathlib import Path


def main(folder: Path) -> None:
    doc = json.loads((folder / "rankings.json").read_text(encoding="utf-8"))
    summary = json.loads((folder / "summary.json").read_text(encoding="utf-8"))
    planners = doc["planners"]
    print(
        "| Scenario | Planner | P(1st) | P(last) | E[rank] | Fréchet over the draws (m): "
        "2.5 % · median · 97.5 % | rank at the base parameters (mean, m) |"
    )
    print("|---|---|--:|--:|--:|--:|--:|")
    for scenario, rows in doc["scenarios"].items():
        base = {
            p: summary["table"]["scenarios"][scenario][p]["frechet_m"]["mean"] for p in planners
        }
        order = sorted(planners, key=lambda p: base[p])
        for planner in planners:
            probs = rows[planner]["rank_probabilities"]
            expected = sum((r + 1) * v for r, v in enumerate(probs))
            low, mid, high = rows[planner]["interval"]
            print(
                f"| {scenario} | {planner} | {probs[0]:.2f} | {probs[-1]:.2f} | {expected:.2f} | "
                f"{low:.3f} · {mid:.3f} · {high:.3f} | {order.index(planner) + 1} "
                f"({base[planner]:.3f}) |"
            )
    print()
    print((folder / "rankings.md").read_text(encoding="utf-8"))


if __name__ == "__main__":
    main(Path(sys.argv[1]))
