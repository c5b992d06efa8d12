"""Pick the shipped policy among training runs: print the best.zip of the run whose
best eligible evaluation (eval.jsonl; seeds 10000-, never the benchmark's 0-99) ranks
first: higher success, then fewer collisions, then less deviation.

    python tools/rl/select_policy.py runs/td3-base-seed1 runs/td3-base-seed2 ...
"""

from __future__ import annotations

import json
import sys
from pathlib import Path


def best_row(run: Path) -> tuple[tuple[float, float, float], dict[str, object]] | None:
    """The best eligible evaluation of a run, with its ranking key."""
    best = None
    for line in (run / "eval.jsonl").read_text().splitlines():
        row = json.loads(line) if line.strip() else None
        if not isinstance(row, dict) or not row.get("eligible", True):
            continue
        key = (
            -float(row["success_rate"]),
            float(row["collision_rate"]),
            float(row["mean_deviation_m"]),
        )
        if best is None or key < best[0]:
            best = (key, row)
    return best


def main(runs: list[str]) -> int:
    ranked = []
    for name in runs:
        run = Path(name)
        found = best_row(run)
        if found is None or not (run / "best.zip").is_file():
            print(f"{run}: no eligible evaluation or no best.zip", file=sys.stderr)
            continue
        key, row = found
        print(
            f"{run}: best at step {row['steps']}: success {row['success_rate']:.2f}, "
            f"collisions {row['collision_rate']:.2f}, deviation {row['mean_deviation_m']:.3f} m",
            file=sys.stderr,
        )
        ranked.append((key, str(run)))
    if not ranked:
        print("no run has an eligible evaluation", file=sys.stderr)
        return 1
    print(Path(min(ranked)[1]) / "best.zip")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
