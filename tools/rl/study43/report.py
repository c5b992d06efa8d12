"""The issue-43 study's report: the targets (part 3) and the paper's claim tested as
written down before training (docs/rl.md, "The issue-43 study").

    PYTHONPATH=. python tools/rl/study43/evaluate.py --seeds 1-10    # the benchmarks
    python tools/rl/study43/report.py tools/rl/study43/report/seed*.csv.gz \\
        > tools/rl/study43/report.md

``evaluate.py`` runs, per training seed, ``srfm benchmark`` of its four policies (both
arms' chosen and final checkpoints) on the 14 report scenarios, seeds 0-99, and commits
the columns read here as ``tools/rl/study43/report/seed<s>.csv.gz``. Several such files
(or benchmark folders) are read as one table (an episode found twice is an error).
Printed, in Markdown:

1. **Shipping rule**: per arm, the run the rule picks (the chosen checkpoint's
   validation success, then collisions, then the lowest training seed; tables in
   ``tools/rl/study43/validation/``), and its target table in the form of docs/rl.md
   (goal / collision / out-of-bounds per scenario, ✗ a missed target).
2. **Targets of every run**: cells missed (of 14) per training seed and arm, for the
   chosen and the final checkpoints.
3. **The claim**, for the chosen checkpoints (primary) and the final ones
   (sensitivity): per scenario, deviation compared on the evaluation seeds where both
   arms of a training seed reach the goal (k/n), paired by training seed, 95 % t
   interval, t-test Holm-corrected over the scenarios, TOST at ±0.03 m; success as the
   co-primary outcome (difference of goal shares, Holm, TOST at ±0.05); the answer
   beside the paper's claim.
"""

from __future__ import annotations

import json
import math
import re
import sys
from collections import defaultdict
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy import stats

ROOT = Path(__file__).resolve().parents[3]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from tools.rl.study_report import REPORT_SCENARIOS, Table, holm, load  # noqa: E402

STUDY = Path(__file__).resolve().parent
POLICY = re.compile(r"tools\.rl\.study43\.planners:k(\d+(?:\.\d+)?)_seed(\d+)(_final)?")
MARGIN_M = 0.03  # deviation equivalence margin (m)
MARGIN_SUCCESS = 0.05  # success equivalence margin (share)
ALPHA = 0.05
# The paper's claim per scenario (Sec. V-C): lower deviation in Scenarios 1, 2, 3, 5.
PAPER = {
    "footpath": "lower",
    "crosswalk": "lower",
    "cross_footpath": "lower",
    "concert": "lower",
    "circle": "no advantage claimed",
}
HELDOUT = (
    "pedestrian_overtaking",
    "down_path",
    "blind_corner",
    "narrow_doorway",
    "exiting_room",
    "circular_crossing",
    "navwareset_blind_corner",
    "navwareset_circular_crossing",
)


def planner_name(k2: str, seed: int, final: bool) -> str:
    return f"tools.rl.study43.planners:k{k2}_seed{seed}" + ("_final" if final else "")


def by_seed(rows: list[dict[str, str]]) -> dict[int, dict[str, str]]:
    return {int(r["seed"]): r for r in rows}


def paired_deviation(
    base: list[dict[str, str]], srfm: list[dict[str, str]]
) -> tuple[float, int, int]:
    """(mean of Fréchet(k2 = 2) − Fréchet(k2 = 0) over the evaluation seeds where both
    reach the goal, k those seeds, n the seeds both ran); NaN when k = 0."""
    a, b = by_seed(base), by_seed(srfm)
    common = sorted(set(a) & set(b))
    both = [
        s
        for s in common
        if float(a[s]["robot_success"]) == 1.0 and float(b[s]["robot_success"]) == 1.0
    ]
    if not both:
        return math.nan, 0, len(common)
    d = [float(b[s]["frechet_m"]) - float(a[s]["frechet_m"]) for s in both]
    return float(np.mean(d)), len(both), len(common)


@dataclass(frozen=True)
class Paired:
    """One-sample statistics of per-training-seed differences."""

    n: int
    mean: float
    lo95: float
    hi95: float
    p: float
    lo90: float
    hi90: float
    sd: float

    def equivalent(self, margin: float) -> bool:
        """TOST at ``margin``, α = 0.05: the 90 % interval inside ±margin."""
        return self.n >= 2 and -margin < self.lo90 and self.hi90 < margin


def paired(values: list[float]) -> Paired:
    """Mean, 95 % and 90 % t intervals and the two-sided t-test p of ``values`` (finite
    ones); NaN where fewer than 2. Values that do not vary give p = 0 when they are not
    0 (the t statistic is infinite) and p = 1 when they are all 0."""
    d = np.array([v for v in values if math.isfinite(v)], dtype=float)
    n = len(d)
    if n < 2:
        mean = float(d.mean()) if n else math.nan
        return Paired(n, mean, math.nan, math.nan, math.nan, math.nan, math.nan, math.nan)
    mean = float(d.mean())
    sd = float(d.std(ddof=1))
    se = sd / math.sqrt(n)
    t975 = float(stats.t.ppf(0.975, n - 1))
    t95 = float(stats.t.ppf(0.95, n - 1))
    degenerate = 0.0 if mean != 0.0 else 1.0
    p = float(stats.ttest_1samp(d, 0.0).pvalue) if sd > 0 else degenerate
    return Paired(
        n, mean, mean - t975 * se, mean + t975 * se, p, mean - t95 * se, mean + t95 * se, sd
    )


def answer(stat: Paired, p_holm: float, margin: float, unit: str) -> str:
    """The pre-registered answer for one scenario."""
    if not math.isfinite(stat.mean):
        return "too few training seeds"
    if math.isfinite(p_holm) and p_holm < ALPHA:
        verb = "lower" if stat.mean < 0 else "higher"
        return f"{verb} with the penalty by {abs(stat.mean):.3f}{unit}"
    if stat.equivalent(margin):
        return f"equivalent within ±{margin:g}{unit}"
    return "inconclusive"


def arms(table: Table) -> dict[tuple[str, bool], dict[int, str]]:
    """{(k2, final): {training seed: planner}} of the study's planners in the table."""
    out: dict[tuple[str, bool], dict[int, str]] = defaultdict(dict)
    for _, planner in table:
        match = POLICY.fullmatch(planner)
        if match:
            out[(match[1], bool(match[3]))][int(match[2])] = planner
    return out


def claim(table: Table, final: bool) -> list[str]:
    """The claim's table for the chosen (``final`` False) or the final checkpoints."""
    found = arms(table)
    base, srfm = found.get(("0", final), {}), found.get(("2", final), {})
    seeds = sorted(set(base) & set(srfm))
    if not seeds:
        return ["(needs both arms, k2 = 0 and k2 = 2)"]
    dev_rows = []
    succ_rows = []
    for scenario in REPORT_SCENARIOS:
        dev: list[float] = []
        succ: list[float] = []
        k_sum = n_sum = dropped = 0
        goals = {"0": [0, 0], "2": [0, 0]}
        for s in seeds:
            a = table.get((scenario, base[s]), [])
            b = table.get((scenario, srfm[s]), [])
            if not a or not b:
                continue
            d, k, n = paired_deviation(a, b)
            dev.append(d)
            k_sum += k
            n_sum += n
            dropped += k == 0
            ga = sum(float(r["robot_success"]) for r in a)
            gb = sum(float(r["robot_success"]) for r in b)
            goals["0"][0] += int(ga)
            goals["0"][1] += len(a)
            goals["2"][0] += int(gb)
            goals["2"][1] += len(b)
            succ.append(gb / len(b) - ga / len(a))
        dev_rows.append((scenario, paired(dev), k_sum, n_sum, dropped))
        succ_rows.append((scenario, paired(succ), goals))
    dev_holm = holm([r[1].p for r in dev_rows])
    succ_holm = holm([r[1].p for r in succ_rows])
    which = "final (300,000 actions)" if final else "chosen on the validation set"
    lines = [
        f"Checkpoints: {which}; training seeds with both arms: "
        f"{', '.join(map(str, seeds))} (n = {len(seeds)}).",
        "",
        "| scenario | k/n (both reach the goal) | seeds | Δ Fréchet (m) | 95 % CI | p (Holm) "
        "| 90 % CI | deviation | goals k2=0 | goals k2=2 | Δ success | 95 % CI | p (Holm) "
        "| success | paper |",
        "|---|---|---:|---:|---|---:|---|---|---|---|---:|---|---:|---|---|",
    ]
    for (scenario, dv, k, n, dropped), ph, (_, sc, goals), sh in zip(
        dev_rows, dev_holm, succ_rows, succ_holm, strict=True
    ):

        def num(x: float, fmt: str = "+.3f") -> str:
            return format(x, fmt) if math.isfinite(x) else "–"

        seeds_cell = f"{dv.n}" + (f" ({dropped} without)" if dropped else "")
        lines.append(
            f"| {scenario} | {k}/{n} | {seeds_cell} | {num(dv.mean)} | "
            f"{num(dv.lo95)} to {num(dv.hi95)} | {num(ph, '.2g')} | "
            f"{num(dv.lo90)} to {num(dv.hi90)} | {answer(dv, ph, MARGIN_M, ' m')} | "
            f"{goals['0'][0]}/{goals['0'][1]} | {goals['2'][0]}/{goals['2'][1]} | "
            f"{num(sc.mean)} | {num(sc.lo95)} to {num(sc.hi95)} | {num(sh, '.2g')} | "
            f"{answer(sc, sh, MARGIN_SUCCESS, '')} | {PAPER.get(scenario, 'no claim')} |"
        )
    lines += [
        "",
        "Deviation: per training seed, the mean over the evaluation seeds (0-99) where both "
        "arms reach the goal of Fréchet(k2 = 2) − Fréchet(k2 = 0); k/n sums those seeds "
        "over the training seeds; a training seed where no evaluation seed qualifies drops "
        'out ("without"). Across training seeds: mean, 95 % t interval, two-sided t-test '
        "Holm-corrected over the 14 scenarios, TOST at ±0.03 m (90 % interval). Success: "
        "per training seed the difference of goal shares, the same statistics, TOST at "
        "±0.05.",
    ]
    return lines


def cell(rows: list[dict[str, str]], scenario: str) -> tuple[str, bool]:
    """A target cell "goal / collision / out of bounds" and whether it misses."""
    n = len(rows)
    goal = sum(float(r["robot_success"]) for r in rows) / n
    col = sum(float(r["robot_collision"]) for r in rows) / n
    oob = sum(float(r["robot_out_of_bounds"]) for r in rows) / n
    miss = col > 0.05 if scenario == "corridor_flow" else (goal < 0.95 or col > 0.02)
    return f"{goal:.2f} / {col:.2f} / {oob:.2f}" + (" ✗" if miss else ""), miss


def missed(table: Table, planner: str) -> int | None:
    """Cells of the 14 missed by a planner; None when it has no complete report."""
    count = 0
    for scenario in REPORT_SCENARIOS:
        rows = table.get((scenario, planner), [])
        if not rows:
            return None
        count += cell(rows, scenario)[1]
    return count


def missed_table(table: Table) -> list[str]:
    found = arms(table)
    seeds = sorted({s for runs in found.values() for s in runs})
    if not seeds:
        return ["(no study planners in the results)"]
    lines = [
        "| run | " + " | ".join(map(str, seeds)) + " |",
        "|---|" + "---|" * len(seeds),
    ]
    for final in (False, True):
        for k2 in sorted({k for k, _ in found}):
            runs = found.get((k2, final), {})
            cells = []
            for s in seeds:
                m = missed(table, runs[s]) if s in runs else None
                cells.append("–" if m is None else str(m))
            label = f"k2 = {k2}, {'final' if final else 'chosen'}"
            lines.append(f"| {label} | " + " | ".join(cells) + " |")
    lines += ["", "Cells missed of 14 (seeds 0-99 each); – not reported yet."]
    return lines


def validation_choice(folder: Path, k2: str) -> tuple[int, float, float] | None:
    """The shipping rule over the arm's validated runs: (training seed, success,
    collisions) of the best chosen checkpoint (highest success, then fewest collisions,
    then lowest seed); None without any."""
    best: tuple[float, float, int] | None = None
    for path in folder.glob(f"k{k2}-seed*.json"):
        match = re.fullmatch(rf"k{re.escape(k2)}-seed(\d+)\.json", path.name)
        if match is None:
            continue
        chosen = json.loads(path.read_text()).get("best")
        if not chosen:
            continue
        key = (-float(chosen["success_rate"]), float(chosen["collision_rate"]), int(match[1]))
        if best is None or key < best:
            best = key
    if best is None:
        return None
    return best[2], -best[0], best[1]


def ship_table(table: Table, validation: Path) -> list[str]:
    picks = {k2: validation_choice(validation, k2) for k2 in ("0", "2")}
    if picks["0"] is None or picks["2"] is None:
        return ["(both arms need a validated run)"]
    base, srfm = picks["0"], picks["2"]
    lines = [
        f"The rule picks k0-seed{base[0]} (validation success {base[1]:.3f}, collisions "
        f"{base[2]:.3f}) and k2-seed{srfm[0]} ({srfm[1]:.3f}, {srfm[2]:.3f}).",
        "",
        f"| scenario | set | `td3-base` (`k0-seed{base[0]}`) | `td3-srfm` (`k2-seed{srfm[0]}`) |",
        "|---|---|---|---|",
    ]
    for scenario in REPORT_SCENARIOS:
        kind = (
            "held out"
            if scenario in HELDOUT
            else ("training" if scenario == "corridor_flow" else "paper")
        )
        cells = []
        for k2, (seed, _, _) in (("0", base), ("2", srfm)):
            rows = table.get((scenario, planner_name(k2, seed, False)), [])
            cells.append(cell(rows, scenario)[0] if rows else "–")
        lines.append(f"| {scenario} | {kind} | {cells[0]} | {cells[1]} |")
    return lines


def main(argv: list[str]) -> int:
    if not argv or any(a.startswith("-") for a in argv):
        print(__doc__, file=sys.stderr)
        return 2
    table = load(*map(Path, argv))
    print("## The shipping rule and its targets (seeds 0-99)\n")
    print("\n".join(ship_table(table, STUDY / "validation")))
    print("\n## Targets of every run\n")
    print("\n".join(missed_table(table)))
    print("\n## The claim, chosen checkpoints (primary)\n")
    print("\n".join(claim(table, final=False)))
    print("\n## The claim, final checkpoints (sensitivity)\n")
    print("\n".join(claim(table, final=True)))
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
