"""The facts about the NavWareSet folder that docs/fitting.md's protocol rests on: how
many scenes, recordings and tracks; how often a position repeats the previous one and
how far people move after such a run; whether the recordings of one scene overlap in
time; how close people pass the robot per scene; how fast the robots drive.

    nice -n 10 .venv/bin/python tools/fitting/navwareset_facts.py \\
        --out docs/fitting_navwareset_facts.json

Reads ``$SRFM_DATA_DIR/navwareset_quant`` (the full scene-13 recording dropped, as
everywhere: ``drop_supersets``). Deterministic; a few seconds.
"""

from __future__ import annotations

import argparse
import itertools
import json
import sys
from collections import Counter
from pathlib import Path
from typing import Any

import numpy as np

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO))

from srfm.datasets import Trajectories  # noqa: E402
from srfm.datasets._trajectories import PEDESTRIAN, ROBOT  # noqa: E402
from srfm.datasets.navwareset import drop_supersets, read_navwareset  # noqa: E402
from srfm.fitting import EVAL_WINDOWS, FIT_WINDOWS, WindowConfig, build_windows  # noqa: E402
from tools.fitting.fit_navwareset import data_folder  # noqa: E402
from tools.results.record import run_record, start  # noqa: E402

DT_S = 0.1
"""NavWareSet's frame interval (10 Hz)."""
MOVING_MPS = 0.1
"""A robot sample counts as driving above this speed."""


def _tracks(scene: Trajectories, kind: str) -> list[tuple[np.ndarray, np.ndarray]]:
    """(frames, xy) of every agent of ``kind``."""
    out = []
    for agent_id, k in zip(scene.agent_ids, scene.kinds, strict=True):
        if k == kind:
            frames, _, xy = scene.track(agent_id)
            out.append((frames, xy))
    return out


def repeats(scenes: list[Trajectories], kind: str) -> dict[str, Any]:
    """Steps (consecutive frames) that repeat the previous position exactly, their runs
    (r repeats in a row) and the distance to the next distinct position after a run."""
    steps = same = 0
    runs: Counter[int] = Counter()
    after: dict[int, list[float]] = {}
    for scene in scenes:
        for frames, xy in _tracks(scene, kind):
            consecutive = np.diff(frames) == 1
            equal = np.all(xy[1:] == xy[:-1], axis=1) & consecutive
            steps += int(consecutive.sum())
            same += int(equal.sum())
            r = 0
            for k in range(equal.size):
                if equal[k]:
                    r += 1
                    continue
                if r and consecutive[k]:
                    runs[r] += 1
                    after.setdefault(r, []).append(float(np.linalg.norm(xy[k + 1] - xy[k])))
                r = 0
    one = np.asarray(after.get(1, []), dtype=float) / (2 * DT_S)
    every = np.concatenate([np.asarray(v) for v in after.values()]) if after else np.zeros(0)
    return {
        "steps": steps,
        "repeated": same,
        "fraction": same / steps if steps else None,
        "runs": {str(r): n for r, n in sorted(runs.items())},
        "runs_total": sum(runs.values()),
        "median_distance_after_run_m": float(np.median(every)) if every.size else None,
        "speed_after_one_repeat_mps": (
            {"median": float(np.median(one)), "p90": float(np.percentile(one, 90))}
            if one.size
            else None
        ),
    }


def overlaps(scenes: list[Trajectories]) -> int:
    """Pairs of recordings of one scene whose time spans overlap."""
    spans: dict[str, list[tuple[int, int]]] = {}
    for s in scenes:
        spans.setdefault(s.source["navwareset_scene"], []).append(
            (int(s.t_ns.min()), int(s.t_ns.max()))
        )
    count = 0
    for items in spans.values():
        items.sort()
        count += sum(1 for a, b in itertools.pairwise(items) if b[0] <= a[1])
    return count


def closest_passes(scenes: list[Trajectories]) -> dict[str, float]:
    """Per scene, the median over its tracks of the closest centre distance to the robot
    (m)."""
    per: dict[str, list[float]] = {}
    for s in scenes:
        robot = _tracks(s, ROBOT)[0]
        rpos = dict(zip(robot[0].tolist(), robot[1], strict=True))
        for frames, xy in _tracks(s, PEDESTRIAN):
            common = [k for k, f in enumerate(frames.tolist()) if f in rpos]
            if not common:
                continue
            d = np.linalg.norm(
                xy[common] - np.array([rpos[int(frames[k])] for k in common]), axis=1
            )
            per.setdefault(s.source["navwareset_scene"], []).append(float(d.min()))
    return {k: float(np.median(v)) for k, v in sorted(per.items(), key=lambda kv: int(kv[0]))}


def robot_speeds(scenes: list[Trajectories]) -> dict[str, float]:
    """The median driving speed (m/s) of each robot over its samples above 0.1 m/s."""
    speeds: dict[str, list[np.ndarray]] = {}
    for s in scenes:
        frames, xy = _tracks(s, ROBOT)[0]
        consecutive = np.diff(frames) == 1
        v = np.linalg.norm(np.diff(xy, axis=0), axis=1)[consecutive] / DT_S
        speeds.setdefault(s.source["robot"], []).append(v[v > MOVING_MPS])
    return {r: float(np.median(np.concatenate(v))) for r, v in sorted(speeds.items())}


def track_lengths(scenes: list[Trajectories], scenario: str, robot: str) -> dict[str, float]:
    """The median duration (s) and start-to-end distance (m) of the pedestrian tracks of
    one scenario and robot."""
    durations, distances = [], []
    for s in scenes:
        if (s.source.get("scenario"), s.source.get("robot")) != (scenario, robot):
            continue
        for agent_id, kind in zip(s.agent_ids, s.kinds, strict=True):
            if kind == PEDESTRIAN:
                _, t_ns, xy = s.track(agent_id)
                durations.append((t_ns[-1] - t_ns[0]) * 1e-9)
                distances.append(float(np.linalg.norm(xy[-1] - xy[0])))
    return {
        "tracks": len(durations),
        "median_duration_s": float(np.median(durations)),
        "median_distance_m": float(np.median(distances)),
    }


def window_counts(scenes: list[Trajectories], config: WindowConfig) -> dict[str, int]:
    """Windows of the protocol: all, interaction, and the tracks of each kind."""
    w = build_windows(scenes, config)
    inter = w.interaction
    return {
        "windows": w.n_windows,
        "interaction": int(inter.sum()),
        "interaction_tracks": int(np.unique(w.track[inter]).size),
        "non_interaction": int((~inter).sum()),
        "non_interaction_tracks": int(np.unique(w.track[~inter]).size),
    }


def main() -> None:
    ap = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument("--data", default=None, help="NavWareSet folder")
    ap.add_argument("--out", type=Path, default=None, help="JSON results")
    args = ap.parse_args()
    began = start()
    scenes, dropped = drop_supersets(read_navwareset(data_folder(args.data)))
    passes = closest_passes(scenes)
    doc: dict[str, Any] = {
        "scenes": len({s.source["navwareset_scene"] for s in scenes}),
        "recordings": len(scenes),
        "dropped": dropped,
        "pedestrian_tracks": sum(len(_tracks(s, PEDESTRIAN)) for s in scenes),
        "repeats": {"pedestrian": repeats(scenes, PEDESTRIAN), "robot": repeats(scenes, ROBOT)},
        "overlapping_recordings": overlaps(scenes),
        "closest_pass_median_per_scene_m": passes,
        "robot_speed_mps": robot_speeds(scenes),
        "frontal_approach_hsr": track_lengths(scenes, "frontal_approach", "hsr"),
        "fit_windows": window_counts(scenes, FIT_WINDOWS),
        "test_windows": window_counts(scenes, EVAL_WINDOWS),
        "run": run_record(*began),
    }
    print(json.dumps({k: v for k, v in doc.items() if k != "closest_pass_median_per_scene_m"}))
    if args.out:
        args.out.write_text(json.dumps(doc, indent=1) + "\n", encoding="utf-8")


if __name__ == "__main__":
    main()
