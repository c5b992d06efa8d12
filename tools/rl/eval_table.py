"""The periodic evaluations of training runs as a Markdown table (docs/rl.md): per run
and evaluation step, the success rate, the mean largest twin separation and the success
per evaluation scenario (seeds 10000-, never the benchmark's 0-99).

    python tools/rl/eval_table.py [--every STEPS] RUN_DIR_OR_EVAL_JSONL ...

``--every 25000`` keeps the evaluations at multiples of 25,000 actions (stage 2
evaluates every 5,000).

Each argument is a run folder of ``srfm train`` (its ``eval.jsonl``) or an
``eval.jsonl`` file itself (tools/rl/policies/evals/ keeps those of the shipped runs).
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

SCENARIOS = ("footpath", "crosswalk", "cross_footpath", "circle", "concert")


def rows(path: Path) -> list[dict[str, object]]:
    """The evaluation rows of a run, by step."""
    file = path / "eval.jsonl" if path.is_dir() else path
    found = [json.loads(line) for line in file.read_text().splitlines() if line.strip()]
    return sorted(found, key=lambda row: int(row["steps"]))


def main(args: list[str]) -> int:
    every = 1
    if args[:1] == ["--every"] and len(args) >= 2:
        every = int(args[1])
        args = args[2:]
    paths = args
    if not paths or every < 1:
        print(__doc__, file=sys.stderr)
        return 2
    head = ["run", "step", "k2", "success", "deviation (m)", *SCENARIOS]
    print("| " + " | ".join(head) + " |")
    print("|---|" + "---:|" * (len(head) - 1))
    for name in paths:
        path = Path(name)
        label = path.parent.name if path.is_file() and path.name == "eval.jsonl" else path.stem
        if path.is_dir():
            label = path.name
        for row in rows(path):
            if int(row["steps"]) % every:
                continue
            scenarios = row["per_scenario"]
            assert isinstance(scenarios, dict)
            mark = "" if row.get("eligible", True) else "°"
            cells = [
                label,
                f"{int(row['steps']):,}",
                f"{float(row.get('k2', float('nan'))):.2f}{mark}",
                f"{float(row['success_rate']):.2f}",
                f"{float(row['mean_deviation_m']):.2f}",
                *(f"{float(scenarios[s]['success_rate']):.1f}" for s in SCENARIOS),
            ]
            print("| " + " | ".join(cells) + " |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
