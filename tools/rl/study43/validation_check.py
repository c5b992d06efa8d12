"""Would the issue-43 validation set have told issue 30's runs apart?

    S=$(ls tools/rl/study43/validation_scenes/*.toml | paste -sd,)
    P=$(for k in 0 2; do for s in $(seq 1 10); do
        printf "tools.rl.study_planners:k${k}_seed${s},"; done; done)
    PYTHONPATH=. srfm benchmark -s $S -p ${P%,} --seeds 20000-20009 --no-logs --no-figures \\
        --out runs/val30
    python tools/rl/study43/validation_check.py runs/val30 > tools/rl/study43/validation_check.md

Per issue-30 run (its chosen checkpoint, ``tools/rl/study/policies/``): the success and
collision shares on the issue-30 validation set (``tools/rl/study/validation/``, 150
episodes), on the six new scenes (the benchmark folder, 60 episodes), on both together
(210, the issue-43 set), and the report cells it misses of 14 (the study's committed
episodes ``tools/rl/study/report/``, seeds 0-99). Then, per validation set, Spearman's
rank correlation between validation success and cells missed (20 runs), and the run the
shipping rule (highest success, then fewest collisions, then lowest seed) picks per arm,
with the cells it misses. docs/rl.md's table is generated from the same functions
(``tools/results/rl_study.py``).
"""

from __future__ import annotations

import csv
import json
import re
import sys
from collections import defaultdict
from pathlib import Path

from scipy import stats

ROOT = Path(__file__).resolve().parents[3]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from tools.rl import study_report  # noqa: E402

STUDY30 = ROOT / "tools" / "rl" / "study"
PLANNER = re.compile(r"tools\.rl\.study_planners:k(\d+)_seed(\d+)")


def missed_cells() -> dict[str, int]:
    """Cells missed per issue-30 run (of 14), from the study's committed episodes
    (``tools/rl/study/report/``, ``tools/rl/study_report.py``'s rule)."""
    table = study_report.committed()
    counts = {}
    for planner in study_report.planners_of(table):
        match = PLANNER.fullmatch(planner)
        if match is None:
            continue
        cells = (study_report.shares(table, s, planner) for s in study_report.REPORT_SCENARIOS)
        counts[f"k{match[1]}-seed{match[2]}"] = sum(c is not None and c.miss for c in cells)
    return counts


def scene_outcomes(folder: Path) -> dict[str, tuple[int, int, int]]:
    """Per run: (goals, collisions, episodes) on the new scenes."""
    out: dict[str, list[int]] = defaultdict(lambda: [0, 0, 0])
    with (folder / "episodes.csv").open() as fh:
        for row in csv.DictReader(fh):
            match = PLANNER.fullmatch(row["planner"])
            if match is None:
                continue
            cell = out[f"k{match[1]}-seed{match[2]}"]
            cell[0] += int(float(row["robot_success"]))
            cell[1] += int(float(row["robot_collision"]))
            cell[2] += 1
    return {run: (g, c, n) for run, (g, c, n) in out.items()}


Counts = tuple[int, int, int]
Row = tuple[str, Counts, Counts, int]
"""A run: its (goals, collisions, episodes) on the issue-30 set and on the new scenes,
and the report cells it misses."""
SETS = ("issue-30 set", "new scenes", "issue-43 set")


def rows_of(folder: Path) -> list[Row]:
    """Every run of the benchmark folder, k2 = 0 first, by training seed."""
    scenes = scene_outcomes(folder)
    missed = missed_cells()
    rows = []
    for run in sorted(scenes, key=lambda r: (r.split("-")[0], int(r.split("seed")[1]))):
        best = json.loads((STUDY30 / "validation" / f"{run}.json").read_text())["best"]
        n_old = int(best["episodes"])
        g_old = round(float(best["success_rate"]) * n_old)
        c_old = round(float(best["collision_rate"]) * n_old)
        rows.append((run, (g_old, c_old, n_old), scenes[run], missed[run]))
    return rows


def on(label: str, old: Counts, new: Counts) -> Counts:
    """A run's counts on one of ``SETS``."""
    if label == "issue-30 set":
        return old
    if label == "new scenes":
        return new
    return (old[0] + new[0], old[1] + new[1], old[2] + new[2])


def ranking(rows: list[Row], label: str) -> tuple[float, float, int, int]:
    """On one of ``SETS``: Spearman's rho between validation success and cells missed,
    its p, and the row indices of the runs the shipping rule picks for k2 = 0 and
    k2 = 2 (success, then collisions, then the lowest seed)."""
    counts = [on(label, old, new) for _, old, new, _ in rows]
    rho, p = stats.spearmanr([g / n for g, _, n in counts], [m for *_, m in rows])
    picks = []
    for arm in ("k0-", "k2-"):
        ranked = sorted(
            (-g / n, c / n, int(run.split("seed")[1]), i)
            for i, ((run, *_), (g, c, n)) in enumerate(zip(rows, counts, strict=True))
            if run.startswith(arm)
        )
        picks.append(ranked[0][3])
    return float(rho), float(p), picks[0], picks[1]


def main(argv: list[str]) -> int:
    if len(argv) != 1:
        print(__doc__, file=sys.stderr)
        return 2
    rows = rows_of(Path(argv[0]))
    print("| run | issue-30 set (goal / coll.) | new scenes | both (issue-43 set) | cells missed |")
    print("|---|---|---|---|---:|")

    def share(g: int, c: int, n: int) -> str:
        return f"{g / n:.3f} / {c / n:.3f}"

    for run, old, new, m in rows:
        print(f"| {run} | {share(*old)} | {share(*new)} | {share(*on('both', old, new))} | {m} |")
    print()
    print("| validation set | Spearman ρ (success, cells missed), 20 runs | p ", end="")
    print("| k2 = 0 pick | k2 = 2 pick |")
    print("|---|---:|---:|---|---|")
    for label in SETS:
        rho, p, k0, k2 = ranking(rows, label)
        picks = [f"{rows[i][0]} (misses {rows[i][3]})" for i in (k0, k2)]
        print(f"| {label} | {rho:+.2f} | {p:.2g} | {picks[0]} | {picks[1]} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
