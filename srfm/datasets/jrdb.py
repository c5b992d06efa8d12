"""JRDB 3-D pedestrian labels (+ robot odometry) -> :class:`Trajectories`.

Raw layout (``datasets/jrdb.md``), per sequence ``<seq>``:

- ``labels/labels_3d/<seq>.json``: ``{"labels": {"000123.pcd": [{"label_id":
  "pedestrian:12", "box": {"cx", "cy", "cz", "l", "w", "h", "rot_z"}, ...}, ...]}}``,
  box centres in the robot frame (x forward, y left, metres), 15 Hz;
- ``timestamps/<seq>/frames_pc.json``: ``{"data": [{"pointclouds": [{"name":
  "upper_velodyne", "url": ".../000123.pcd", "timestamp": <s>}, ...]}, ...]}``; the
  frame's time is that of its ``upper_velodyne`` cloud (else the first one listed);
  without this file frames are placed at 15 Hz (a warning says so);
- the robot pose per frame, not in the JRDB archives (it comes from the rosbags' wheel
  odometry): a JSON file ``{"odometry": {"000123.pcd": <pose>, ...}}`` with <pose> either
  ``{"position": {"x", "y", "z"}, "orientation": {"x", "y", "z", "w"}}`` (the layout
  exported by Human Scene Transformer's tools) or ``{"x", "y", "yaw"}``.

With odometry, positions are mapped to the odometry (world) frame, p_world = R(yaw) p +
t, using the pose's yaw only (JRDB's odometry is planar), and the robot is an agent at
its pose. Without odometry the scene stays in the robot's own moving frame
(``frame_of_reference = "robot"``) with the robot at the origin: fine for viewing, not
for fitting dynamics.
"""

from __future__ import annotations

import math
import re
import warnings
from pathlib import Path
from typing import Any, Final

import numpy as np

from srfm._text import plain
from srfm._validate import BOUNDS
from srfm.datasets._parse import bounded_int, json_number, load_json, seconds_to_ns
from srfm.datasets._trajectories import PEDESTRIAN, ROBOT, DatasetWarning, Trajectories
from srfm.errors import DatasetError

__all__ = [
    "RATE_HZ",
    "find_odometry",
    "find_timestamps",
    "list_sources",
    "read_jrdb",
    "read_sequence",
]

NAME: Final = "jrdb"
RATE_HZ: Final = 15.0
_FRAME_NAME = re.compile(r"^(\d+)(\.\w+)?$")


def list_sources(src: str | Path) -> list[Path]:
    """The label files to read.

    ``src`` is a ``labels_3d/<seq>.json`` file, a ``labels_3d`` folder, or a JRDB root
    folder holding ``labels/labels_3d/``.
    """
    src = Path(src)
    if src.is_file():
        return [src]
    if not src.is_dir():
        raise DatasetError(f"{src}: no such file or folder")
    folder = src / "labels" / "labels_3d"
    if not folder.is_dir():
        folder = src
    files = sorted(p for p in folder.glob("*.json") if p.is_file())
    if not files:
        raise DatasetError(
            f"{src}: no JRDB label files (expected labels/labels_3d/<sequence>.json)"
        )
    return files


def find_timestamps(labels_path: Path) -> Path | None:
    """``<root>/timestamps/<seq>/frames_pc.json`` for ``<root>/labels/labels_3d/<seq>.json``."""
    labels_path = Path(labels_path)
    if labels_path.parent.name == "labels_3d" and labels_path.parent.parent.name == "labels":
        root = labels_path.parent.parent.parent
        candidate = root / "timestamps" / labels_path.stem / "frames_pc.json"
        if candidate.is_file():
            return candidate
    return None


def find_odometry(odometry: Path, sequence: str) -> Path:
    """The pose file of ``sequence``: ``odometry`` itself if a file, else
    ``<odometry>/<sequence>.json`` or ``<odometry>/*/<sequence>.json`` (train/test split)."""
    odometry = Path(odometry)
    if odometry.is_file():
        return odometry
    if not odometry.is_dir():
        raise DatasetError(f"{odometry}: no such odometry file or folder")
    direct = odometry / f"{sequence}.json"
    if direct.is_file():
        return direct
    nested = sorted(odometry.glob(f"*/{sequence}.json"))
    if nested:
        return nested[0]
    raise DatasetError(f"{odometry}: no odometry file {sequence}.json for sequence {sequence!r}")


def read_jrdb(src: str | Path, *, odometry: str | Path | None = None) -> list[Trajectories]:
    """Read every JRDB sequence under ``src`` (see :func:`list_sources`).

    Args:
        src: a label file, a ``labels_3d`` folder or a JRDB root folder.
        odometry: a pose file (one sequence only) or a folder of ``<sequence>.json``
            pose files; None keeps every scene in the robot frame.
    """
    files = list_sources(src)
    if odometry is not None and Path(odometry).is_file() and len(files) > 1:
        raise DatasetError(
            f"{odometry}: one odometry file given for {len(files)} sequences; "
            "pass a folder of <sequence>.json pose files"
        )
    return [read_sequence(f, odometry=odometry) for f in files]


def _frame_number(name: str, where: str) -> int:
    match = _FRAME_NAME.fullmatch(Path(name).name)
    if match is None:
        raise DatasetError(
            f"{where}: frame name must be a number like '000123.pcd', got {plain(name)}"
        )
    return bounded_int(int(match.group(1)), where, "frame number")


def _read_timestamps(path: Path) -> dict[int, int]:
    """frame number -> timestamp (ns) from a ``frames_pc.json`` file."""
    data = load_json(path)
    entries = data.get("data") if isinstance(data, dict) else None
    if not isinstance(entries, list):
        raise DatasetError(f"{path}: missing key 'data' (a list of frames)")
    out: dict[int, int] = {}
    for k, entry in enumerate(entries):
        where = f"{path}: data[{k}]"
        if not isinstance(entry, dict):
            raise DatasetError(f"{where}: expected an object")
        clouds = entry.get("pointclouds")
        if isinstance(clouds, list) and clouds:
            named = [c for c in clouds if isinstance(c, dict) and c.get("name") == "upper_velodyne"]
            cloud = named[0] if named else clouds[0]
            j = clouds.index(cloud)
            if not isinstance(cloud, dict) or "url" not in cloud or "timestamp" not in cloud:
                raise DatasetError(f"{where}.pointclouds[{j}]: missing key 'url' or 'timestamp'")
            frame = _frame_number(str(cloud["url"]), f"{where}.pointclouds[{j}].url")
            t_s = json_number(cloud["timestamp"], f"{where}.pointclouds[{j}].timestamp")
        elif "frame_id" in entry and "timestamp" in entry:
            fid = entry["frame_id"]
            if isinstance(fid, bool) or not isinstance(fid, int):
                raise DatasetError(f"{where}.frame_id: expected an integer, got {plain(fid)}")
            frame = bounded_int(fid, f"{where}.frame_id", "frame_id")
            t_s = json_number(entry["timestamp"], f"{where}.timestamp")
        else:
            raise DatasetError(f"{where}: missing key 'pointclouds'")
        if t_s < 0:
            raise DatasetError(f"{where}: negative timestamp {t_s!r}")
        if frame in out:
            raise DatasetError(f"{where}: frame {frame} listed twice")
        out[frame] = seconds_to_ns(t_s, where)
    if not out:
        raise DatasetError(f"{path}: no frames in 'data'")
    previous: tuple[int, int] | None = None
    for frame in sorted(out):
        if previous is not None and out[frame] <= previous[1]:
            raise DatasetError(
                f"{path}: timestamps go backwards: frame {frame} at {out[frame] * 1e-9:.6f} s "
                f"is not after frame {previous[0]} at {previous[1] * 1e-9:.6f} s"
            )
        previous = (frame, out[frame])
    return out


def _coordinate(value: Any, where: str) -> float:
    """A JSON position coordinate (m) within the physical bound (±1e7 m)."""
    out = json_number(value, where)
    lo, hi, unit = BOUNDS["coordinate"]
    if not lo <= out <= hi:
        raise DatasetError(f"{where}: must be in [{lo:g}, {hi:g}] {unit}, got {plain(value)}")
    return out


def _yaw_from_pose(pose: Any, where: str) -> tuple[float, float, float]:
    """(x, y, yaw) of a pose entry in either accepted layout."""
    if not isinstance(pose, dict):
        raise DatasetError(f"{where}: expected a pose object, got {plain(pose)}")
    if "position" in pose or "orientation" in pose:
        pos, ori = pose.get("position"), pose.get("orientation")
        if not isinstance(pos, dict) or not isinstance(ori, dict):
            raise DatasetError(f"{where}: 'position' and 'orientation' must both be objects")
        for key in ("x", "y"):
            if key not in pos:
                raise DatasetError(f"{where}.position: missing key {key!r}")
        for key in ("x", "y", "z", "w"):
            if key not in ori:
                raise DatasetError(f"{where}.orientation: missing key {key!r}")
        x = _coordinate(pos["x"], f"{where}.position.x")
        y = _coordinate(pos["y"], f"{where}.position.y")
        qx, qy, qz, qw = (json_number(ori[k], f"{where}.orientation.{k}") for k in "xyzw")
        if qx * qx + qy * qy + qz * qz + qw * qw < 1e-12:
            raise DatasetError(f"{where}.orientation: zero quaternion")
        yaw = math.atan2(2.0 * (qw * qz + qx * qy), 1.0 - 2.0 * (qy * qy + qz * qz))
        return x, y, yaw
    for key in ("x", "y", "yaw"):
        if key not in pose:
            raise DatasetError(
                f"{where}: missing key {key!r} "
                "(a pose is {position, orientation} or {x, y, yaw})"
            )
    return (
        _coordinate(pose["x"], f"{where}.x"),
        _coordinate(pose["y"], f"{where}.y"),
        json_number(pose["yaw"], f"{where}.yaw"),
    )


def _read_odometry(path: Path) -> dict[int, tuple[float, float, float]]:
    """frame number -> (x, y, yaw) of the robot."""
    data = load_json(path)
    poses = data.get("odometry") if isinstance(data, dict) else None
    if not isinstance(poses, dict):
        raise DatasetError(f"{path}: missing key 'odometry' (an object keyed by frame name)")
    out: dict[int, tuple[float, float, float]] = {}
    for name, pose in poses.items():
        where = f"{path}: odometry[{name!r}]"
        frame = _frame_number(name, where)
        if frame in out:
            raise DatasetError(f"{where}: frame {frame} listed twice")
        out[frame] = _yaw_from_pose(pose, where)
    return out


def read_sequence(
    labels_path: str | Path,
    *,
    timestamps: str | Path | None = None,
    odometry: str | Path | None = None,
) -> Trajectories:
    """Read one JRDB sequence.

    Args:
        labels_path: ``labels/labels_3d/<seq>.json``.
        timestamps: its ``frames_pc.json``; found next to the labels when omitted
            (:func:`find_timestamps`); frames at 15 Hz, with a warning, if there is none.
        odometry: a pose file or a folder of them (:func:`find_odometry`); None keeps the
            scene in the robot frame.

    Returns:
        One scene named after the sequence: pedestrians (``label_id`` starting with
        ``pedestrian``) and the robot.

    Raises:
        DatasetError: missing keys, non-numeric or non-finite values, an empty label
            file, timestamps going backwards, or a labelled frame without a timestamp or
            pose; the message names the file and the JSON location.
    """
    labels_path = Path(labels_path)
    seq = labels_path.stem
    data = load_json(labels_path)
    labels = data.get("labels") if isinstance(data, dict) else None
    if not isinstance(labels, dict):
        raise DatasetError(f"{labels_path}: missing key 'labels' (an object keyed by frame name)")
    if not labels:
        raise DatasetError(f"{labels_path}: no frames under 'labels'")

    ts_path = Path(timestamps) if timestamps is not None else find_timestamps(labels_path)
    ts = _read_timestamps(ts_path) if ts_path is not None else None
    odo_path = find_odometry(Path(odometry), seq) if odometry is not None else None
    poses = _read_odometry(odo_path) if odo_path is not None else None

    frame_names = {_frame_number(name, f"{labels_path}: labels[{name!r}]"): name for name in labels}
    if len(frame_names) != len(labels):
        raise DatasetError(f"{labels_path}: two frame names with the same number under 'labels'")
    if ts is None:
        warnings.warn(
            f"{labels_path}: no timestamps file (timestamps/{seq}/frames_pc.json); "
            f"frames placed at {RATE_HZ:g} Hz",
            DatasetWarning,
            stacklevel=2,
        )

    ids: dict[str, int] = {ROBOT: 0}
    agent: list[int] = []
    frame_l: list[int] = []
    t_l: list[int] = []
    xy: list[tuple[float, float]] = []
    skipped = 0
    for frame in sorted(frame_names):
        name = frame_names[frame]
        where_f = f"{labels_path}: labels[{name!r}]"
        if ts is None:
            t_ns = seconds_to_ns(frame / RATE_HZ, where_f, f"frame {frame} at {RATE_HZ:g} Hz")
        elif frame in ts:
            t_ns = ts[frame]
        else:
            raise DatasetError(f"{ts_path}: no timestamp for frame {name!r} of {labels_path.name}")
        if poses is None:
            rx, ry, yaw = 0.0, 0.0, 0.0
        elif frame in poses:
            rx, ry, yaw = poses[frame]
        else:
            raise DatasetError(
                f"{odo_path}: no robot pose for frame {name!r} of {labels_path.name}"
            )
        c, s = math.cos(yaw), math.sin(yaw)
        agent.append(0)
        frame_l.append(frame)
        t_l.append(t_ns)
        xy.append((rx, ry))
        boxes = labels[name]
        if not isinstance(boxes, list):
            raise DatasetError(f"{where_f}: expected a list of labels, got {type(boxes).__name__}")
        in_frame: set[str] = set()
        for j, item in enumerate(boxes):
            where = f"{where_f}[{j}]"
            if not isinstance(item, dict):
                raise DatasetError(f"{where}: expected an object")
            if "label_id" not in item:
                raise DatasetError(f"{where}: missing key 'label_id'")
            label_id = item["label_id"]
            if not isinstance(label_id, str) or not label_id:
                raise DatasetError(f"{where}.label_id: expected a string, got {plain(label_id)}")
            if not label_id.startswith(PEDESTRIAN):
                skipped += 1
                continue
            if label_id == ROBOT:
                raise DatasetError(f"{where}.label_id: {label_id!r} is reserved for the robot")
            if label_id in in_frame:
                raise DatasetError(f"{where}: {label_id!r} appears twice in frame {name!r}")
            in_frame.add(label_id)
            box = item.get("box")
            if not isinstance(box, dict):
                raise DatasetError(f"{where}: missing key 'box'")
            for key in ("cx", "cy"):
                if key not in box:
                    raise DatasetError(f"{where}.box: missing key {key!r}")
            bx = _coordinate(box["cx"], f"{where}.box.cx")
            by = _coordinate(box["cy"], f"{where}.box.cy")
            agent.append(ids.setdefault(label_id, len(ids)))
            frame_l.append(frame)
            t_l.append(t_ns)
            xy.append((rx + c * bx - s * by, ry + s * bx + c * by))
    agent_ids = list(ids)
    return Trajectories.from_samples(
        scene=seq,
        agent_ids=agent_ids,
        kinds=[ROBOT] + [PEDESTRIAN] * (len(agent_ids) - 1),
        agent=np.array(agent, dtype=np.int64),
        frame=np.array(frame_l, dtype=np.int64),
        t_ns=np.array(t_l, dtype=np.int64),
        xy=np.array(xy, dtype=np.float64),
        frame_of_reference="robot" if poses is None else "world",
        source={
            "dataset": NAME,
            "file": labels_path.name,
            "timestamps": ts_path.name if ts_path is not None else f"none ({RATE_HZ:g} Hz)",
            "odometry": odo_path.name if odo_path is not None else "none (robot frame)",
            "skipped_labels": str(skipped),
        },
    )
