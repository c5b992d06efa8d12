"""Check that two results folders hold the same numbers in the columns both have
(issue 41: the new parts must leave every existing result as it was).

    srfm benchmark --quick --no-logs --no-figures --out /tmp/old   # on main
    srfm benchmark --quick --no-logs --no-figures --out /tmp/new   # on the branch
    python tools/bench/same_results.py /tmp/old /tmp/new

Compared: ``episodes.csv`` and ``pedestrians.csv`` column by column (every column of
the old file, text for text: the same bytes of every value); the tables
(``table.md``, ``outcomes.md``, ``table_extended.md`` and their LaTeX) line by line
with the bold marks removed and the legends (lines that start with "Mean ± ") left
out, over the old file's lines (the new file may add lines); ``summary.json``'s cells
(n, undefined, mean, std, marks, every p-value) of the three tables. What differs is
printed; the exit status is 1 then.
"""

from __future__ import annotations

import csv
import json
import re
import sys
from pathlib import Path

TABLES = ("table.md", "outcomes.md", "table_extended.md", "table.tex", "table_extended.tex")
CELL_KEYS = ("n", "undefined", "mean", "std", "marks", "welch_p", "paired_p")


def _csv(old: Path, new: Path) -> list[str]:
    a = list(csv.DictReader(old.open()))
    b = list(csv.DictReader(new.open()))
    if len(a) != len(b):
        return [f"{old.name}: {len(a)} rows against {len(b)}"]
    bad = []
    for k, (ra, rb) in enumerate(zip(a, b, strict=True)):
        for key, value in ra.items():
            if rb.get(key) != value:
                bad.append(f"{old.name} row {k} {key}: {value!r} != {rb.get(key)!r}")
    return bad


def _plain(line: str) -> str:
    return re.sub(r"\\mathbf\{([^{}]*)\}", r"\1", line.replace("**", ""))


def _table(old: Path, new: Path) -> list[str]:
    keep = [
        _plain(x)
        for x in old.read_text().splitlines()
        if not x.startswith(("Mean ± ", "% Mean ± ", "Definitions, units"))
    ]
    got = {_plain(x) for x in new.read_text().splitlines()}
    return [f"{old.name}: line missing: {x[:120]}" for x in keep if x not in got]


def _summary(old: Path, new: Path) -> list[str]:
    a = json.loads(old.read_text())
    b = json.loads(new.read_text())
    bad = []
    for table in ("table", "outcomes", "extended"):
        for scenario, planners in a[table]["scenarios"].items():
            for planner, cells in planners.items():
                for column, cell in cells.items():
                    other = b[table]["scenarios"][scenario][planner][column]
                    for key in CELL_KEYS:
                        if cell.get(key) != other.get(key):
                            bad.append(f"summary {table} {scenario} {planner} {column} {key}")
    return bad


def main() -> int:
    old, new = Path(sys.argv[1]), Path(sys.argv[2])
    problems = []
    for name in ("episodes.csv", "pedestrians.csv"):
        problems += _csv(old / name, new / name)
    for name in TABLES:
        problems += _table(old / name, new / name)
    problems += _summary(old / "summary.json", new / "summary.json")
    for p in problems[:50]:
        print(p)
    print(f"{len(problems)} differences in the old folder's columns")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
