"""Two benchmark results folders of the same suite and planners side by side, e.g. under
two parameter presets (docs/benchmark.md, "Real-data presets"): per scenario, every
planner's mean Fréchet deviation (m) and its rank under each, Kendall's τ between the
two rankings, and the ratio of the deviations; then the same over the suite's scenario
means. ``--planners`` compares only those planners (e.g. when one folder also holds the
reference planners `stay` and `oracle`).

    .venv/bin/python tools/analysis/compare_presets.py results/a results/b --labels A B
    .venv/bin/python tools/analysis/compare_presets.py results/a results/b --planners dwa,orca
"""

from __future__ import annotations

import argparse
import csv
import math
from collections import defaultdict
from pathlib import Path

from scipy import stats


def means(
    folder: Path, planners: frozenset[str] | None = None
) -> tuple[dict[tuple[str, str], float], list[str], list[str], int]:
    """Mean Fréchet deviation per (scenario, planner), the scenarios, planners and the
    number of episodes of the folder's episodes.csv (only ``planners``' rows when given;
    a planner the folder does not hold is an error)."""
    with (folder / "episodes.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    return means_of_rows(rows, planners, str(folder))


def means_of_rows(
    rows: list[dict[str, str]], planners: frozenset[str] | None = None, name: str = "rows"
) -> tuple[dict[tuple[str, str], float], list[str], list[str], int]:
    """:func:`means` of episodes.csv rows (``scenario``, ``planner``, ``frechet_m``)."""
    if planners is not None:
        missing = sorted(planners - {r["planner"] for r in rows})
        if missing:
            raise SystemExit(f"{name}: no episodes of planner(s) {', '.join(missing)}")
        rows = [r for r in rows if r["planner"] in planners]
    values: dict[tuple[str, str], list[float]] = defaultdict(list)
    for r in rows:
        if r["frechet_m"] not in ("", "nan"):
            values[r["scenario"], r["planner"]].append(float(r["frechet_m"]))
    scenarios = list(dict.fromkeys(r["scenario"] for r in rows))
    planners = sorted({r["planner"] for r in rows})
    out = {k: sum(v) / len(v) for k, v in values.items()}
    return out, scenarios, planners, len(rows)


def ranks(values: list[float]) -> list[int]:
    """1 = the lowest deviation; ties share the lower rank."""
    return [1 + sum(other < v for other in values) for v in values]


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("a", type=Path)
    ap.add_argument("b", type=Path)
    ap.add_argument("--labels", nargs=2, default=("a", "b"))
    ap.add_argument("--planners", help="comma-separated planners to compare (default: all)")
    args = ap.parse_args(argv)
    only = None if args.planners is None else frozenset(args.planners.split(","))
    ma, scenarios, planners, na = means(args.a, only)
    mb, scenarios_b, planners_b, nb = means(args.b, only)
    if (scenarios, planners) != (scenarios_b, planners_b):
        raise SystemExit("the two folders hold different scenarios or planners")
    la, lb = args.labels
    print(f"{la}: {na} episodes; {lb}: {nb} episodes\n")
    print("\n".join(comparison(ma, mb, scenarios, planners, (la, lb))))


def comparison(
    ma: dict[tuple[str, str], float],
    mb: dict[tuple[str, str], float],
    scenarios: list[str],
    planners: list[str],
    labels: tuple[str, str],
) -> list[str]:
    """The Markdown lines of the comparison of two sets of means."""
    la, lb = labels
    out: list[str] = []
    add = out.append
    add(f"Mean Fréchet deviation (m), {la} / {lb}, and the planner's rank (1 = lowest) under each:")
    add("")
    add("| scenario | " + " | ".join(planners) + f" | Kendall τ | {lb} / {la} |")
    add("|---|" + "---:|" * len(planners) + "---:|---:|")
    suite_a = {p: 0.0 for p in planners}
    suite_b = {p: 0.0 for p in planners}
    for s in scenarios:
        va = [ma[s, p] for p in planners]
        vb = [mb[s, p] for p in planners]
        ra, rb = ranks(va), ranks(vb)
        tau = stats.kendalltau(va, vb).statistic
        ratio = sum(vb) / sum(va)
        cells = [
            f"{x:.2f} / {y:.2f} ({i} / {j})" for x, y, i, j in zip(va, vb, ra, rb, strict=True)
        ]
        tau_text = "–" if math.isnan(tau) else f"{tau:+.2f}"
        add(f"| {s} | " + " | ".join(cells) + f" | {tau_text} | {ratio:.2f} |")
        for p, x, y in zip(planners, va, vb, strict=True):
            suite_a[p] += x / len(scenarios)
            suite_b[p] += y / len(scenarios)
    va = [suite_a[p] for p in planners]
    vb = [suite_b[p] for p in planners]
    ra, rb = ranks(va), ranks(vb)
    tau = stats.kendalltau(va, vb).statistic
    cells = [f"{x:.2f} / {y:.2f} ({i} / {j})" for x, y, i, j in zip(va, vb, ra, rb, strict=True)]
    add(
        f"| **mean of {len(scenarios)}** | "
        + " | ".join(cells)
        + f" | {tau:+.2f} | {sum(vb) / sum(va):.2f} |"
    )
    return out


if __name__ == "__main__":
    main()
