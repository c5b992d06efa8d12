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
(210, the issue-43 set), and the report cells it misses of 14 (``tools/rl/study/report.md``,
seeds 0-99). Then, per validation set, Spearman's rank correlation between validation
success and cells missed (20 runs), and the run the shipping rule (highest success, then
fewest collisions, then lowest seed) picks per arm, with the cells it misses.
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
STUDY30 = ROOT / "tools" / "rl" / "study"
PLANNER = re.compile(r"tools\.rl\.study_planners:k(\d+)_seed(\d+)")
COLUMN = re.compile(r"k2=(\d+) seed (\d+)")


def missed_cells(report: Path) -> dict[str, int]:
    """Cells marked ✗ per run in the issue-30 report's target table."""
    lines = report.read_text().split("## The claim")[0].splitlines()
    header = next(line for line in lines if line.startswith("| scenario |"))
    runs = []
    for name in header.strip("|").split("|")[1:]:
        match = COLUMN.fullmatch(name.strip())
        runs.append(f"k{match[1]}-seed{match[2]}" if match else "")
    counts = dict.fromkeys(runs, 0)
    for line in lines:
        if not line.startswith("| ") or line.startswith(("| scenario", "|---")):
            continue
        for run, cell in zip(runs, line.strip("|").split("|")[1:], strict=True):
            counts[run] += "✗" in cell
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


def main(argv: list[str]) -> int:
    if len(argv) != 1:
        print(__doc__, file=sys.stderr)
        return 2
    scenes = scene_outcomes(Path(argv[0]))
    missed = missed_cells(STUDY30 / "report.md")
    rows = []
    for run in sorted(scenes, key=lambda r: (r.split("-")[0], int(r.split("seed")[1]))):
        best = json.loads((STUDY30 / "validation" / f"{run}.json").read_text())["best"]
        n_old = int(best["episodes"])
        g_old = round(float(best["success_rate"]) * n_old)
        c_old = round(float(best["collision_rate"]) * n_old)
        g_new, c_new, n_new = scenes[run]
        rows.append((run, (g_old, c_old, n_old), (g_new, c_new, n_new), missed[run]))
    print("| run | issue-30 set (goal / coll.) | new scenes | both (issue-43 set) | cells missed |")
    print("|---|---|---|---|---:|")

    def share(g: int, c: int, n: int) -> str:
        return f"{g / n:.3f} / {c / n:.3f}"

    for run, old, new, m in rows:
        both = (old[0] + new[0], old[1] + new[1], old[2] + new[2])
        print(f"| {run} | {share(*old)} | {share(*new)} | {share(*both)} | {m} |")
    print()
    Counts = tuple[int, int, int]

    def on(label: str, old: Counts, new: Counts) -> Counts:
        if label == "issue-30 set":
            return old
        if label == "new scenes":
            return new
        return (old[0] + new[0], old[1] + new[1], old[2] + new[2])

    print("| validation set | Spearman ρ (success, cells missed), 20 runs | p ", end="")
    print("| k2 = 0 pick | k2 = 2 pick |")
    print("|---|---:|---:|---|---|")
    for label in ("issue-30 set", "new scenes", "issue-43 set"):
        counts = [on(label, old, new) for _, old, new, _ in rows]
        success = [g / n for g, _, n in counts]
        rho, p = stats.spearmanr(success, [m for *_, m in rows])
        picks = []
        for arm in ("k0-", "k2-"):
            ranked = sorted(
                (-g / n, c / n, int(run.split("seed")[1]), run, m)
                for (run, *_, m), (g, c, n) in zip(rows, counts, strict=True)
                if run.startswith(arm)
            )
            picks.append(f"{ranked[0][3]} (misses {ranked[0][4]})")
        print(f"| {label} | {rho:+.2f} | {p:.2g} | {picks[0]} | {picks[1]} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
