"""Learning curves of the shipped recipe: success rate and deviation against training
steps, one line per training seed, from each run's ``eval.jsonl`` (the periodic
evaluation on the five evaluation scenarios, seeds 10000-10019 in stage 2).

    python tools/rl/plot_learning_curves.py runs docs/rl_learning_curves.png

Runs are the folders ``<variant>-seed<k>`` in the runs folder (tools/rl/train_policies.sh).
"""

from __future__ import annotations

import json
import re
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

VARIANTS = {"td3-srfm": "SRFM-aware (k2: 0 → 2)", "td3-base": "RL_base (k2 = 0)"}
COLOURS = {"td3-srfm": "tab:blue", "td3-base": "tab:orange"}
STYLES = ("-", "--", ":", "-.")


def read(run: Path) -> list[dict[str, float]]:
    """The evaluation rows of a run, by step."""
    rows = [json.loads(line) for line in (run / "eval.jsonl").read_text().splitlines() if line]
    return sorted(rows, key=lambda row: row["steps"])


def main(runs_dir: str, out: str) -> int:
    fig, axes = plt.subplots(1, 2, figsize=(11, 4), constrained_layout=True)
    found = 0
    episodes: set[int] = set()
    for run in sorted(Path(runs_dir).iterdir()):
        match = re.fullmatch(r"(td3-srfm|td3-base)-seed(\d+)", run.name)
        if match is None or not (run / "eval.jsonl").is_file():
            continue
        variant, seed = match.group(1), int(match.group(2))
        rows = read(run)
        episodes.update(int(row["episodes"]) for row in rows)
        steps = [row["steps"] / 1000 for row in rows]
        style = STYLES[(seed - 1) % len(STYLES)]
        label = f"{VARIANTS[variant]}, seed {seed}"
        axes[0].plot(
            steps, [row["success_rate"] for row in rows], style, color=COLOURS[variant], label=label
        )
        axes[1].plot(
            steps,
            [row["mean_deviation_m"] for row in rows],
            style,
            color=COLOURS[variant],
            label=label,
        )
        found += 1
    if not found:
        print(f"no runs <variant>-seed<k> with eval.jsonl in {runs_dir}", file=sys.stderr)
        return 1
    counts = " or ".join(str(n) for n in sorted(episodes))
    axes[0].set_ylabel(f"success rate ({counts} episodes per evaluation)")
    axes[0].set_ylim(-0.02, 1.02)
    axes[1].set_ylabel("mean largest twin separation (m)")
    for ax in axes:
        ax.set_xlabel("training actions (thousands; an action is held 4 simulation steps)")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=7, loc="lower right")
    fig.suptitle("Periodic evaluation: five evaluation scenarios × seeds 10000-10019")
    fig.savefig(out, dpi=120)
    print(f"wrote {out} ({found} runs)")
    return 0


if __name__ == "__main__":
    if len(sys.argv) != 3:
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    sys.exit(main(sys.argv[1], sys.argv[2]))
