"""The paper suite's noise floor, direct / knock-on split and suite statistics (issue 41;
docs/metrics.md).

    nice -n 5 .venv/bin/srfm benchmark --suite paper --seeds 0-99 --no-logs -j 2 \\
        -p straight,oracle,stay,dwa,orca,social-force,td3-base,td3-srfm,vo \\
        --out results/paper41
    # the committed data: what the tables of docs/metrics.md are made of
    .venv/bin/python tools/analysis/attribution.py extract results/paper41 \\
        --json docs/attribution/paper.json
    # those tables, from the committed file alone
    .venv/bin/python tools/analysis/attribution.py tables docs/attribution/paper.json

``extract`` keeps of the folder's ``summary.json``: every (scenario, seed)'s floor, the
split per scenario and planner, the pairs whose difference is below the floor's spread,
each scenario's headroom and the planners' normalised scores with k/n, and the suite
statistics (IQMs, probabilities of improvement) with their intervals.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any


def extract(folder: Path, out: Path) -> None:
    summary = json.loads((folder / "summary.json").read_text(encoding="utf-8"))
    attribution = summary["attribution"]
    suite = summary["suite"]
    request = summary["request"]
    doc: dict[str, Any] = {
        "source": "srfm benchmark --suite paper --seeds 0-99 --no-logs -j 2 -p "
        + ",".join(request["planners"]),
        "planners": request["planners"],
        "seeds": [request["seeds"][0], request["seeds"][-1]],
        "legend": attribution["legend"],
        "felt_force_mps2": attribution["felt_force_mps2"],
        "nudge_m": attribution["nudge_m"],
        "scenarios": {},
        "suite": {k: suite[k] for k in ("legend", "deviation_iqm", "score_iqm", "improvement")},
        "score_scenarios": suite["score_scenarios"],
    }
    refs = summary["table"].get("references", {})
    for scenario, entry in attribution["scenarios"].items():
        ref = refs.get(scenario, {})
        doc["scenarios"][scenario] = {
            "floor": entry["floor"],
            "not_attributable": [
                [d["a"], d["b"], d["difference_m"]]
                for d in entry.get("differences", [])
                if not d["attributable"]
            ],
            "split": entry["split"],
            "frechet_m": {
                p: summary["table"]["scenarios"][scenario][p]["frechet_m"]["mean"]
                for p in request["planners"]
            },
            "goal": {
                p: summary["table"]["outcomes"][scenario][p]["goal_reached"]
                for p in request["planners"]
            },
            "headroom": ref.get("headroom"),
            "beats_oracle": ref.get("beats_oracle"),
            "scores": ref.get("scores"),
        }
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(doc, indent=1) + "\n", encoding="utf-8")
    print(f"-> {out}")


def _iv(x: dict[str, Any] | None, digits: int = 2) -> str:
    if not x or x.get("estimate") is None:
        return "–"
    if x.get("low") is None:
        return f"{x['estimate']:.{digits}f}"
    return f"{x['estimate']:.{digits}f} [{x['low']:.{digits}f}, {x['high']:.{digits}f}]"


def table_lines(path: Path) -> list[str]:
    """The tables of docs/metrics.md from the committed file alone."""
    out: list[str] = []
    doc = json.loads(path.read_text(encoding="utf-8"))
    planners = doc["planners"]
    _emit(out, "Noise floor and attribution per scenario:\n")
    _emit(
        out,
        "| scenario | floor (m), mean ± SD over seeds | floor max (m) | planners' mean "
        "deviation (m) | floor / deviation | measures | pairs below the floor's spread |",
    )
    _emit(out, "|---|--:|--:|--:|--:|---|--:|")
    for s, e in doc["scenarios"].items():
        f = e["floor"]
        pairs = len(planners) * (len(planners) - 1) // 2
        _emit(
            out,
            f"| {s} | {f['mean']:.4f} ± {f['std']:.4f} | {max(f['values']):.4f} | "
            f"{f['deviation']:.3f} | {100 * f['share']:.2f} % | {f['verdict']} | "
            f"{len(e['not_attributable'])} of {pairs} |",
        )
    _emit(
        out,
        "\nDirect / knock-on deviation (m, mean over seeds) and pedestrians who felt the robot:\n",
    )
    _emit(out, "| scenario | " + " | ".join(planners) + " |")
    _emit(out, "|---|" + "|".join(["--:"] * len(planners)) + "|")
    for s, e in doc["scenarios"].items():
        cells = []
        for p in planners:
            x = e["split"][p]
            cells.append(
                f"{x['frechet_direct_m']['mean']:.3f} / {x['frechet_knock_on_m']['mean']:.3f} "
                f"({x['pedestrians_felt']['mean']:.1f})"
            )
        _emit(out, f"| {s} | " + " | ".join(cells) + " |")
    _emit(
        out,
        "\nNormalised scores (k = seeds where planner, straight and oracle reached the goal):\n",
    )
    _emit(out, "| scenario | headroom (m) | " + " | ".join(planners) + " |")
    _emit(out, "|---|--:|" + "|".join(["--:"] * len(planners)) + "|")
    for s, e in doc["scenarios"].items():
        if not e["scores"]:
            continue
        room = _iv(e["headroom"], 3) + (" (lower bound)" if e["beats_oracle"] else "")
        cells = []
        for p in planners:
            x = e["scores"][p]
            k = f"k={x['n']}"
            cells.append("undefined" if x["estimate"] is None else f"{_iv(x)} {k}")
        _emit(out, f"| {s} | {room} | " + " | ".join(cells) + " |")
    suite = doc["suite"]
    _emit(
        out, "\nSuite (every scenario and seed): IQMs with stratified bootstrap 95 % intervals:\n"
    )
    _emit(out, "| planner | IQM deviation (m) | IQM norm. score | scenarios of the score |")
    _emit(out, "|---|--:|--:|---|")
    for p in planners:
        named = ", ".join(doc["score_scenarios"].get(p, [])) or "none"
        _emit(
            out,
            f"| {p} | {_iv(suite['deviation_iqm'][p], 3)} | "
            f"{_iv(suite['score_iqm'].get(p))} | {named} |",
        )
    _emit(
        out, "\nP(row < column), the probability that the row's planner deviates a person less:\n"
    )
    _emit(out, "| | " + " | ".join(planners) + " |")
    _emit(out, "|---|" + "|".join(["--:"] * len(planners)) + "|")
    for a in planners:
        cells = ["–" if a == b else _iv(suite["improvement"][a][b]) for b in planners]
        _emit(out, f"| {a} | " + " | ".join(cells) + " |")
    return out


def _emit(out: list[str], *texts: str) -> None:
    """Append ``texts`` as lines (a leading or trailing newline: an empty line)."""
    for text in texts:
        out.extend(text.split("\n"))


def tables(path: Path) -> None:
    print("\n".join(table_lines(path)))


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = parser.add_subparsers(dest="command", required=True)
    e = sub.add_parser("extract")
    e.add_argument("folder", type=Path)
    e.add_argument("--json", type=Path, required=True)
    t = sub.add_parser("tables")
    t.add_argument("json", type=Path)
    args = parser.parse_args()
    if args.command == "extract":
        extract(args.folder, args.json)
    else:
        tables(args.json)
    return 0


if __name__ == "__main__":
    sys.exit(main())
