"""Does the deviation metric rank real robot behaviour right? (issue 15, item 4)

Every pedestrian of every NavWareSet-Quant recording is replayed around the recorded
robot from its walking start to the end of its track (srfm.fitting.replay_encounter),
with and without the robot force; the benchmark's deviation (Fréchet distance between
the two simulated paths) of the compliant and the non-compliant recordings of each
scenario and robot is compared with Welch's t-test, beside the same test on what the
people observably did (closest pass, detour, slow-down).

    nice .venv/bin/python tools/fitting/navwareset_compliance.py --params agrawal2024 \\
        --out docs/fitting_compliance.json
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np
from scipy import stats

from srfm.cli._common import load_params_option
from srfm.datasets import PEDESTRIAN
from srfm.datasets.navwareset import SCENARIOS, condition_of, drop_supersets, read_navwareset
from srfm.fitting import replay_encounter

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO))
from tools.results.record import run_record, start  # noqa: E402

MEASURES = ("deviation_m", "ade_factual_m", "min_distance_m", "detour", "slowdown")


def welch(a: np.ndarray, b: np.ndarray) -> float:
    a, b = a[np.isfinite(a)], b[np.isfinite(b)]
    if a.size < 2 or b.size < 2:
        return math.nan
    return float(stats.ttest_ind(a, b, equal_var=False).pvalue)


def main() -> None:
    ap = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument("--params", default="agrawal2024", help="preset or parameter file")
    ap.add_argument("--data", default=None, help="default $SRFM_DATA_DIR/navwareset_quant")
    ap.add_argument("--out", type=Path, default=None, help="JSON results")
    ap.add_argument(
        "--episodes",
        action="store_true",
        help="instead: one benchmark twin episode per recording (recorded-robot planner)",
    )
    args = ap.parse_args()
    root = Path(os.environ.get("SRFM_DATA_DIR", REPO.parent / "shared" / "data"))
    data = Path(args.data) if args.data else root / "navwareset_quant"
    t0 = time.perf_counter()
    began = start()
    params = load_params_option(args.params)
    scenes, _ = drop_supersets(read_navwareset(data))
    if args.episodes:
        episodes(scenes, params, args)
        return
    records: list[dict[str, Any]] = []
    skipped = 0
    for scene in scenes:
        cond = condition_of(scene)
        if cond is None:
            continue
        for agent_id, kind in zip(scene.agent_ids, scene.kinds, strict=True):
            if kind != PEDESTRIAN:
                continue
            enc = replay_encounter(scene, agent_id, params)
            if enc is None:
                skipped += 1
                continue
            records.append(
                {
                    "scene": scene.source.get("navwareset_scene", scene.scene),
                    "recording": scene.scene,
                    "agent": agent_id,
                    "scenario": cond[0],
                    "robot": cond[1],
                    "compliant": cond[2],
                    **{m: getattr(enc, m) for m in MEASURES},
                }
            )
    elapsed = time.perf_counter() - t0
    rows = []
    cells = [(s, r) for s in SCENARIOS for r in ("hsr", "jackal")] + [
        ("all", "hsr"),
        ("all", "jackal"),
        ("all", "all"),
    ]
    for scenario, robot in cells:
        sel = [
            x
            for x in records
            if (scenario == "all" or x["scenario"] == scenario)
            and (robot == "all" or x["robot"] == robot)
        ]
        c = [x for x in sel if x["compliant"]]
        n = [x for x in sel if not x["compliant"]]
        row: dict[str, Any] = {
            "scenario": scenario,
            "robot": robot,
            "n_compliant": len(c),
            "n_non_compliant": len(n),
        }
        for m in MEASURES:
            a = np.array([x[m] for x in c], dtype=float)
            b = np.array([x[m] for x in n], dtype=float)
            row[m] = {
                "compliant": float(np.nanmean(a)) if a.size else math.nan,
                "non_compliant": float(np.nanmean(b)) if b.size else math.nan,
                "welch_p": welch(a, b),
            }
        rows.append(row)
    print(f"params {args.params}: {len(records)} encounters ({skipped} skipped) in {elapsed:.1f} s")
    print()
    print("\n".join(replay_lines(rows)))
    if args.out:
        args.out.write_text(
            json.dumps(
                {
                    "params": args.params,
                    "n": len(records),
                    "skipped": skipped,
                    "time_s": round(elapsed, 1),
                    "rows": rows,
                    "encounters": records,
                    "run": run_record(*began),
                },
                separators=(",", ":"),
                default=float,
            )
            + "\n"
        )


def replay_lines(rows: list[dict[str, Any]]) -> list[str]:
    """The table of the replayed encounters: compliant against non-compliant per cell."""
    lines = [
        "| scenario | robot | n C / NC | deviation C / NC (m), p | closest pass C / NC (m), p "
        "| detour C / NC, p | slow-down C / NC, p | ADE factual C / NC (m) |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for row in rows:
        parts = [
            row["scenario"].replace("_", " "),
            row["robot"],
            f"{row['n_compliant']} / {row['n_non_compliant']}",
        ]
        for m, fmt in (
            ("deviation_m", ".3f"),
            ("min_distance_m", ".2f"),
            ("detour", ".3f"),
            ("slowdown", ".2f"),
        ):
            v = row[m]
            parts.append(
                f"{v['compliant']:{fmt}} / {v['non_compliant']:{fmt}}, p = {v['welch_p']:.2g}"
            )
        v = row["ade_factual_m"]
        parts.append(f"{v['compliant']:.2f} / {v['non_compliant']:.2f}")
        lines.append("| " + " | ".join(parts) + " |")
    return lines


def episodes_lines(records: list[dict[str, Any]]) -> list[str]:
    """The table of the benchmark's twin episodes, one per recording: compliant against
    non-compliant per scenario and robot (Welch's t-test over recordings)."""
    lines = [
        "| scenario | robot | recordings C / NC | deviation C / NC (m), Welch p "
        "| collisions C / NC |",
        "|---|---|---|---|---|",
    ]
    cells = [(sc, r) for sc in SCENARIOS for r in ("hsr", "jackal")] + [("all", "all")]
    for scenario, robot in cells:
        sel = [
            x
            for x in records
            if scenario in ("all", x["scenario"]) and robot in ("all", x["robot"])
        ]
        if not sel:
            continue
        c = np.array([x["frechet_m"] for x in sel if x["compliant"]])
        n = np.array([x["frechet_m"] for x in sel if not x["compliant"]])
        cc = sum(x["outcome"] == "collision" for x in sel if x["compliant"])
        nc = sum(x["outcome"] == "collision" for x in sel if not x["compliant"])
        lines.append(
            f"| {scenario.replace('_', ' ')} | {robot} | {c.size} / {n.size} "
            f"| {np.nanmean(c):.3f} / {np.nanmean(n):.3f}, p = {welch(c, n):.2g} | {cc} / {nc} |"
        )
    return lines


def episodes(scenes: list[Any], params: Any, args: argparse.Namespace) -> None:
    """The benchmark itself: srfm.run_episode with the recorded-robot planner on the
    scenario of each recording; its deviation (frechet_m, mean over the recording's
    pedestrians) and outcome, compliant vs non-compliant per scenario and robot."""
    import srfm
    from srfm.errors import ScenarioError
    from srfm.metrics.episode import episode_metrics
    from srfm.planners.recorded import recorded_encounter

    began = start()
    t0 = time.perf_counter()
    records = []
    skipped = []
    for scene in scenes:
        cond = condition_of(scene)
        if cond is None or scene.robot_index is None:
            continue
        try:
            scenario, planner = recorded_encounter(scene)
        except ScenarioError as exc:  # e.g. a person starting in contact with the robot
            print(f"skipped: {exc}")
            skipped.append({"recording": scene.scene, "reason": str(exc)})
            continue
        rec = srfm.run_episode(scenario, 0, planner, params)
        m = episode_metrics(rec)
        records.append(
            {
                "recording": scene.scene,
                "scenario": cond[0],
                "robot": cond[1],
                "compliant": cond[2],
                "outcome": rec.outcome,
                "frechet_m": float(m.values["frechet_m"]),
                "min_robot_distance_m": float(m.values["min_robot_distance_m"]),
            }
        )
    elapsed = time.perf_counter() - t0
    print(f"params {args.params}: {len(records)} twin episodes in {elapsed:.1f} s")
    print()
    print("\n".join(episodes_lines(records)))
    if args.out:
        args.out.write_text(
            json.dumps(
                {
                    "params": args.params,
                    "time_s": round(elapsed, 1),
                    "episodes": records,
                    "skipped": skipped,
                    "run": run_record(*began),
                },
                separators=(",", ":"),
            )
            + "\n"
        )


if __name__ == "__main__":
    main()
