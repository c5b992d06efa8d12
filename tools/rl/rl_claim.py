"""The paper's claim, tested on a benchmark folder: does the SRFM-aware policy cause
less deviation than RL_base and the classical planners at equal success, and what
does it cost in time and path length? (docs/rl.md, "The claim")

    python tools/rl/rl_claim.py RESULTS_DIR > claim.md

RESULTS_DIR is an ``srfm benchmark`` folder over seeds 0-99 with the shipped
``td3-srfm`` and ``td3-base``, the classical planners, and the per-training-seed
policies ``tools.rl.seed_planners:{srfm,base}_seed{11,12,13}``. Printed, in Markdown:

1. outcomes of every planner and scenario (success, collisions, out of bounds, n);
2. paired comparisons of ``td3-srfm`` with every other planner, per scenario, over the
   benchmark seeds where both reached the goal ("at equal success"): the mean
   difference of the Fréchet deviation, the robot's time to goal and path length, with
   n and the two-sided Wilcoxon signed-rank p-value (scipy.stats.wilcoxon);
3. the spread over training seeds: per variant and scenario, the success rate and the
   mean Fréchet deviation of successful episodes of each training seed, their mean and
   standard deviation over the seeds, and Welch's t-test of the three SRFM-aware
   against the three RL_base per-seed means (n = 3 + 3).
"""

from __future__ import annotations

import csv
import math
import re
import sys
from collections import defaultdict
from pathlib import Path

import numpy as np
from scipy import stats

SCENARIOS = ("footpath", "crosswalk", "cross_footpath", "circle", "concert")
SEED_PLANNER = re.compile(r"tools\.rl\.seed_planners:(srfm|base)_seed(\d+)")
STAGE1_PLANNER = re.compile(r"tools\.rl\.seed_planners:stage1_seed(\d+)")


def load(folder: Path) -> dict[tuple[str, str], dict[int, dict[str, float | str]]]:
    """episodes.csv as {(scenario, planner): {seed: row}}."""
    table: dict[tuple[str, str], dict[int, dict[str, float | str]]] = defaultdict(dict)
    with (folder / "episodes.csv").open() as fh:
        for row in csv.DictReader(fh):
            values: dict[str, float | str] = {}
            for key, value in row.items():
                try:
                    values[key] = float(value)
                except ValueError:
                    values[key] = value
            table[(row["scenario"], row["planner"])][int(row["seed"])] = values
    return table


def short(planner: str) -> str:
    match = SEED_PLANNER.fullmatch(planner)
    if match:
        return f"td3-{match.group(1)} seed {match.group(2)}"
    stage1 = STAGE1_PLANNER.fullmatch(planner)
    return f"stage-1 RL_base seed {stage1.group(1)}" if stage1 else planner


def fmt(x: float, digits: int = 2) -> str:
    return "–" if not math.isfinite(x) else f"{x:.{digits}f}"


def outcomes(table, planners) -> list[str]:
    lines = ["| planner | " + " | ".join(SCENARIOS) + " |", "|---|" + "---|" * len(SCENARIOS)]
    for planner in planners:
        cells = []
        for scenario in SCENARIOS:
            rows = list(table.get((scenario, planner), {}).values())
            if not rows:
                cells.append("–")
                continue
            n = len(rows)
            ok = sum(r["robot_success"] for r in rows) / n
            col = sum(r["robot_collision"] for r in rows) / n
            oob = sum(r["robot_out_of_bounds"] for r in rows) / n
            cells.append(f"{ok:.2f} / {col:.2f} / {oob:.2f} (n={n})")
        lines.append(f"| {short(planner)} | " + " | ".join(cells) + " |")
    return lines


def paired(table, mine: str, others) -> list[str]:
    lines = [
        "| scenario | vs | n (both at goal) | Δ Fréchet (m) | p | Δ robot time (s) | p "
        "| Δ path length (m) | p |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for scenario in SCENARIOS:
        a = table.get((scenario, mine), {})
        for other in others:
            b = table.get((scenario, other), {})
            both = sorted(
                s for s in a if s in b and a[s]["robot_success"] and b[s]["robot_success"]
            )
            cells = [scenario, short(other), str(len(both))]
            for key in ("frechet_m", "robot_time_to_goal_s", "robot_path_length_m"):
                if len(both) < 2:
                    cells += ["–", "–"]
                    continue
                d = np.array([float(a[s][key]) - float(b[s][key]) for s in both])
                p = float("nan") if not np.any(d) else float(stats.wilcoxon(d).pvalue)
                cells += [f"{d.mean():+.3f}", "–" if math.isnan(p) else f"{p:.2g}"]
            lines.append("| " + " | ".join(cells) + " |")
    return lines


def seed_spread(table, planners) -> list[str]:
    per: dict[str, dict[int, str]] = defaultdict(dict)
    for planner in planners:
        match = SEED_PLANNER.fullmatch(planner)
        if match:
            per[match.group(1)][int(match.group(2))] = planner
    lines = [
        "| scenario | variant | success per seed | mean | Fréchet (m) per seed | mean ± sd |",
        "|---|---|---|---:|---|---:|",
    ]
    means: dict[tuple[str, str], list[float]] = {}
    for scenario in SCENARIOS:
        for variant in ("srfm", "base"):
            succ, dev = [], []
            for seed in sorted(per[variant]):
                rows = list(table.get((scenario, per[variant][seed]), {}).values())
                succ.append(sum(r["robot_success"] for r in rows) / max(len(rows), 1))
                good = [float(r["frechet_m"]) for r in rows if r["robot_success"]]
                dev.append(float(np.mean(good)) if good else float("nan"))
            means[(scenario, variant)] = dev
            sd = float(np.std(dev, ddof=1)) if len(dev) > 1 else float("nan")
            lines.append(
                f"| {scenario} | {variant} | {', '.join(fmt(s) for s in succ)} | "
                f"{fmt(float(np.mean(succ)))} | {', '.join(fmt(d, 3) for d in dev)} | "
                f"{fmt(float(np.mean(dev)), 3)} ± {fmt(sd, 3)} |"
            )
    lines += [
        "",
        "| scenario | Welch t-test of per-seed mean Fréchet, SRFM-aware vs RL_base |",
        "|---|---|",
    ]
    for scenario in SCENARIOS:
        a, b = means[(scenario, "srfm")], means[(scenario, "base")]
        if len(a) > 1 and len(b) > 1 and all(map(math.isfinite, a + b)):
            t = stats.ttest_ind(a, b, equal_var=False)
            text = (
                f"Δ = {np.mean(a) - np.mean(b):+.3f} m, t = {t.statistic:.2f}, p = {t.pvalue:.2g}"
            )
        else:
            text = "–"
        lines.append(f"| {scenario} | {text} |")
    return lines


def main(folder: str) -> int:
    table = load(Path(folder))
    planners = sorted({planner for _, planner in table}, key=lambda p: (p.startswith("tools"), p))
    print("### Outcomes: success / collisions / out of bounds (n episodes)\n")
    print("\n".join(outcomes(table, planners)))
    others = [p for p in planners if p != "td3-srfm" and not p.startswith("tools.")]
    print("\n### Paired: td3-srfm minus the other planner, seeds where both reached the goal\n")
    print("\n".join(paired(table, "td3-srfm", others)))
    print("\n### Spread over training seeds\n")
    print("\n".join(seed_spread(table, planners)))
    return 0


if __name__ == "__main__":
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    sys.exit(main(sys.argv[1]))
