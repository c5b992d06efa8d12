"""The study's report (issue 30): targets per policy and scenario, and the paper's
claim tested over training seeds.

    PYTHONPATH=. python tools/rl/study_evaluate.py --seeds 1-10       # the benchmarks
    python tools/rl/study_report.py tools/rl/study/report/seed*.csv.gz
    python tools/rl/study_report.py tools/rl/study/report_ttc/seed*.csv.gz   # ttc preset

``study_evaluate.py`` runs ``srfm benchmark`` of each training seed's two policies and
commits the episodes' columns read here (``tools/rl/study/report/seed<s>.csv.gz``).
Several such files or benchmark folders are read as one table; a (scenario, planner,
seed) episode found in two of them is an error. docs/rl.md's tables of the study are
generated from the committed files (``tools/results/rl_study.py``).

``SCENARIOS`` are the report's: the five paper scenarios, the library's held-out set
and corridor_flow (``python tools/rl/study_report.py --scenarios`` prints them
comma-separated). Printed, in Markdown:

1. **Targets**, per policy and scenario (100 seeds each): goal, collision and
   out-of-bounds shares; a cell misses its target when goal < 95 % or collisions > 2 %
   (paper and held-out scenarios) or collisions > 5 % (corridor_flow).
2. **The claim**, per scenario: each training seed's mean Fréchet deviation over the
   episodes where its policy reached the goal; the difference k2 = 2 minus k2 = 0,
   paired by training seed (both arms of a seed share the recipe's first 100,000
   actions), with its 95 % t interval and two-sided paired t-test p-value, Holm-corrected
   over the scenarios; and the equivalence test (TOST, two one-sided paired t-tests at
   ±0.03 m, α = 0.05: equivalent when the 90 % interval lies inside ±0.03 m). The
   answer per scenario is one of "the penalty lowers (raises) deviation by x m",
   "equivalent within ±0.03 m", or "inconclusive: would need n seeds", with
   n = (t₀.₉₅ + t₀.₉)² s² / (0.03 m)² paired seeds for TOST to show equivalence with
   power 0.8 when the true difference is 0 (s the standard deviation of the paired
   differences; normal quantiles, rounded up).
"""

from __future__ import annotations

import csv
import gzip
import math
import re
import sys
from collections import defaultdict
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy import stats

from srfm.metrics.stats import adjust_p_values
from srfm.scenarios import EVALUATION_SCENARIOS
from srfm.scenarios.training import LIBRARY_HELDOUT

REPORT_SCENARIOS = (*EVALUATION_SCENARIOS, *LIBRARY_HELDOUT, "corridor_flow")
POLICY = re.compile(r"tools\.rl\.study_planners:k(\d+(?:\.\d+)?)_seed(\d+)")
MARGIN_M = 0.03
STUDY = Path(__file__).resolve().parent / "study"
ALPHA = 0.05

Table = dict[tuple[str, str], list[dict[str, str]]]


def load(*folders: Path) -> Table:
    """Every episode of the folders' episodes.csv (or of gzip-compressed CSV files of the
    same columns, ``*.csv.gz``), by (scenario, planner)."""
    table: Table = defaultdict(list)
    seen: dict[tuple[str, str, str], Path] = {}
    for folder in folders:
        gz = folder.name.endswith(".csv.gz")
        path = folder if gz else folder / "episodes.csv"
        with (gzip.open if gz else open)(path, "rt", encoding="utf-8", newline="") as fh:
            for row in csv.DictReader(fh):
                key = (row["scenario"], row["planner"], row["seed"])
                if key in seen:
                    raise ValueError(f"episode {key} is in both {seen[key]} and {folder}")
                seen[key] = folder
                table[(row["scenario"], row["planner"])].append(row)
    return table


def share(rows: list[dict[str, str]], key: str) -> float:
    return sum(float(r[key]) for r in rows) / len(rows)


def misses_target(scenario: str, goal: float, collision: float) -> bool:
    """Whether a policy's shares in a scenario miss issue 30's targets: goal < 95 % or
    collisions > 2 %; in corridor_flow collisions > 5 % only."""
    if scenario == "corridor_flow":
        return collision > 0.05
    return collision > 0.02 or goal < 0.95


@dataclass(frozen=True)
class Shares:
    """A policy's goal, collision and out-of-bounds shares in one scenario, and whether
    they miss the target."""

    goal: float
    collision: float
    out_of_bounds: float
    miss: bool

    def text(self) -> str:
        mark = " ✗" if self.miss else ""
        return f"{self.goal:.2f} / {self.collision:.2f} / {self.out_of_bounds:.2f}{mark}"


def shares(table: Table, scenario: str, planner: str) -> Shares | None:
    """The policy's shares in the scenario (None without episodes)."""
    rows = table.get((scenario, planner), [])
    if not rows:
        return None
    goal = share(rows, "robot_success")
    col = share(rows, "robot_collision")
    oob = share(rows, "robot_out_of_bounds")
    return Shares(goal, col, oob, misses_target(scenario, goal, col))


def targets(table: Table, planners: list[str]) -> list[str]:
    lines = [
        "| scenario | " + " | ".join(short(p) for p in planners) + " |",
        "|---|" + "---|" * len(planners),
    ]
    misses = 0
    for scenario in REPORT_SCENARIOS:
        cells = []
        for planner in planners:
            cell = shares(table, scenario, planner)
            misses += cell is not None and cell.miss
            cells.append("–" if cell is None else cell.text())
        lines.append(f"| {scenario} | " + " | ".join(cells) + " |")
    lines.append("")
    lines.append(
        "Cells: goal / collision / out-of-bounds shares over seeds 0-99 (n = 100 each); "
        f"✗ misses the target ({misses} cells)."
    )
    return lines


def short(planner: str) -> str:
    match = POLICY.fullmatch(planner)
    return f"k2={match[1]} seed {match[2]}" if match else planner


def holm(p: list[float]) -> list[float]:
    """Holm-adjusted p-values (NaN stays NaN): srfm's one definition."""
    return [float(x) for x in adjust_p_values(p, "holm")]


def seed_means(table: Table, scenario: str, planner: str) -> float:
    rows = table.get((scenario, planner), [])
    good = [float(r["frechet_m"]) for r in rows if float(r["robot_success"]) == 1.0]
    return float(np.mean(good)) if good else math.nan


@dataclass(frozen=True)
class ClaimRow:
    """One scenario's test of the claim (NaN where fewer than 2 seeds have a mean)."""

    scenario: str
    n: int
    mean: float
    lo: float
    hi: float
    p: float
    p_holm: float
    lo90: float
    hi90: float
    answer: str


def arms_of(planners: list[str]) -> dict[str, dict[int, str]]:
    """k2 -> training seed -> planner, for the study's policies among the planners."""
    arms: dict[str, dict[int, str]] = defaultdict(dict)
    for planner in planners:
        match = POLICY.fullmatch(planner)
        if match:
            arms[match[1]][int(match[2])] = planner
    return arms


def claim_rows(table: Table, planners: list[str]) -> list[ClaimRow]:
    """The claim per scenario of the report, over the training seeds with both arms."""
    arms = arms_of(planners)
    seeds = sorted(set(arms["0"]) & set(arms["2"]))
    raw = []
    for scenario in REPORT_SCENARIOS:
        d = np.array(
            [
                seed_means(table, scenario, arms["2"][s])
                - seed_means(table, scenario, arms["0"][s])
                for s in seeds
            ]
        )
        d = d[np.isfinite(d)]
        n = len(d)
        if n < 2:
            raw.append((scenario, n, *[math.nan] * 7))
            continue
        mean = float(d.mean())
        sd = float(d.std(ddof=1))
        se = sd / math.sqrt(n)
        t975 = float(stats.t.ppf(0.975, n - 1))
        t95 = float(stats.t.ppf(0.95, n - 1))
        p = float(stats.ttest_1samp(d, 0.0).pvalue) if sd > 0 else math.nan
        lo90, hi90 = mean - t95 * se, mean + t95 * se
        raw.append((scenario, n, mean, mean - t975 * se, mean + t975 * se, p, lo90, hi90, sd))
    adjusted = holm([float(r[5]) for r in raw])
    z = float(stats.norm.ppf(0.95) + stats.norm.ppf(0.9))
    rows = []
    for (scenario, n, mean, lo, hi, p, lo90, hi90, sd), p_holm in zip(raw, adjusted, strict=True):
        if not math.isfinite(mean):
            answer = "too few seeds"
        elif math.isfinite(p_holm) and p_holm < ALPHA:
            verb = "lowers" if mean < 0 else "raises"
            answer = f"the penalty {verb} deviation by {abs(mean):.3f} m ({lo:+.3f} to {hi:+.3f})"
        elif lo90 > -MARGIN_M and hi90 < MARGIN_M:
            answer = "equivalent within ±0.03 m"
        else:
            need = math.ceil((z * sd / MARGIN_M) ** 2)
            answer = f"inconclusive: would need about {need} seeds"
        rows.append(ClaimRow(str(scenario), int(n), mean, lo, hi, p, p_holm, lo90, hi90, answer))
    return rows


def claim(table: Table, planners: list[str]) -> list[str]:
    arms = arms_of(planners)
    if set(arms) < {"0", "2"}:
        return ["(needs both arms, k2 = 0 and k2 = 2)"]
    seeds = sorted(set(arms["0"]) & set(arms["2"]))
    lines = [
        f"Training seeds with both arms: {', '.join(map(str, seeds))} (n = {len(seeds)}).",
        "",
        "| scenario | n seeds | Δ Fréchet (m), k2=2 − k2=0 | 95 % CI | p | p (Holm) "
        "| 90 % CI (TOST ±0.03 m) | answer |",
        "|---|---:|---:|---|---:|---:|---|---|",
    ]
    for r in claim_rows(table, planners):
        if not math.isfinite(r.mean):
            lines.append(f"| {r.scenario} | {r.n} | – | – | – | – | – | {r.answer} |")
            continue
        lines.append(
            f"| {r.scenario} | {r.n} | {r.mean:+.3f} | {r.lo:+.3f} to {r.hi:+.3f} | "
            f"{r.p:.2g} | {r.p_holm:.2g} | {r.lo90:+.3f} to {r.hi90:+.3f} | {r.answer} |"
        )
    return lines


def planners_of(table: Table) -> list[str]:
    """The table's planners, the study's policies first (by name)."""
    return sorted({p for _, p in table}, key=lambda p: (POLICY.fullmatch(p) is None, p))


def committed(part: str = "report") -> Table:
    """The issue-30 study's committed episodes, ``tools/rl/study/<part>/seed*.csv.gz``
    (``report`` or ``report_ttc``; written by ``tools/rl/study_evaluate.py``)."""
    files = sorted((STUDY / part).glob("seed*.csv.gz"))
    if not files:
        raise SystemExit(f"{STUDY / part}: no seed*.csv.gz (tools/rl/study_evaluate.py)")
    return load(*files)


def main(argv: list[str]) -> int:
    if argv == ["--scenarios"]:
        print(",".join(REPORT_SCENARIOS))
        return 0
    if not argv or any(a.startswith("-") for a in argv):
        print(__doc__, file=sys.stderr)
        return 2
    table = load(*map(Path, argv))
    planners = planners_of(table)
    print("## Targets (seeds 0-99)\n")
    print("\n".join(targets(table, planners)))
    print("\n## The claim over training seeds\n")
    print("\n".join(claim(table, planners)))
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
