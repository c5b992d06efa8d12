"""NavWareSet tracks: one pedestrian and the robot per CSV file -> :class:`Trajectories`.

Raw layout (``datasets/navwareset.md``): CSV with a header naming at least
``timestamp,x,y,robot_x,robot_y`` (the distributed files also have ``column``, a
track-group id); ``timestamp`` in nanoseconds, written as an integer or a float
(``1.7308255599301187e+18``); positions in metres in a common world frame, about 10 Hz.
Each row holds the pedestrian (``x, y``) and the robot (``robot_x, robot_y``) at the same
instant. Every file is one scene with two agents, ``pedestrian:<column>`` (or
``pedestrian`` without a ``column`` column) and ``robot``; the frame number is the data
row's index (0-based).

The full-scene files of the circular-crossing scenario (format 2) have no ``x,y`` but
``timestamp,robot_x,robot_y,...,x1,y1,...,xK,yK``: the robot and K pedestrians per row,
read into one scene with agents ``pedestrian:1`` .. ``pedestrian:K`` and ``robot``.
"""

from __future__ import annotations

import csv
import math
from pathlib import Path
from typing import Final

import numpy as np

from srfm.datasets._parse import (
    bounded_int,
    coordinate,
    integer,
    median_speed,
    number,
    read_text_lines,
    warn_if_fast,
)
from srfm.datasets._trajectories import PEDESTRIAN, ROBOT, Trajectories
from srfm.errors import DatasetError

__all__ = ["FULL_SCENE_COLUMNS", "REQUIRED_COLUMNS", "list_sources", "read_file", "read_navwareset"]

NAME: Final = "navwareset"
REQUIRED_COLUMNS: Final = ("timestamp", "x", "y", "robot_x", "robot_y")


def list_sources(src: str | Path) -> list[Path]:
    """The files to read: ``src`` itself, or the ``*.csv`` files of a folder and its
    subfolders (the distributed set keeps each scene's tracks in ``<scene>_poses/``)."""
    src = Path(src)
    if src.is_file():
        return [src]
    if src.is_dir():
        files = sorted(p for p in src.rglob("*.csv") if p.is_file())
        if not files:
            raise DatasetError(f"{src}: no NavWareSet files (*.csv) in this folder")
        return files
    raise DatasetError(f"{src}: no such file or folder")


def read_navwareset(src: str | Path) -> list[Trajectories]:
    """Read one NavWareSet CSV or every CSV of a folder, one scene per file."""
    return [read_file(f) for f in list_sources(src)]


def _timestamp_ns(text: str, where: str) -> int:
    # Integers are exact; floats (how the distributed files store ns) are rounded.
    try:
        value = int(text)
    except ValueError:
        value = round(number(text, where, "timestamp"))
    if value < 0:
        raise DatasetError(f"{where}: timestamp must be >= 0 ns, got {text!r}")
    return bounded_int(value, where, "timestamp (ns)")


def read_file(path: str | Path) -> Trajectories:
    """Read one NavWareSet CSV into a scene named after the file's stem.

    Raises:
        DatasetError: empty file, missing column, non-numeric or non-finite value,
            timestamps not strictly increasing; the message names the file and line.
    """
    path = Path(path)
    lines = read_text_lines(path)
    rows = list(csv.reader(lines))
    if not rows or not any(cell.strip() for cell in rows[0]):
        raise DatasetError(f"{path}: empty file (no header)")
    header = [c.strip() for c in rows[0]]
    seen: set[str] = set()
    for name in header:
        if name in seen:
            raise DatasetError(
                f"{path}:1: column {name!r} appears twice in the header "
                f"({','.join(header)}); which one holds the data is ambiguous"
            )
        seen.add(name)
    if "x" not in header and "x1" in header:
        return _read_full_scene(path, header, rows)
    missing = [c for c in REQUIRED_COLUMNS if c not in header]
    if missing:
        raise DatasetError(
            f"{path}:1: missing column {missing[0]!r} (header: {','.join(header)}); "
            f"expected {','.join(REQUIRED_COLUMNS)}"
        )
    col = {name: header.index(name) for name in header}
    has_group = "column" in col
    t_list: list[int] = []
    ped: list[tuple[float, float]] = []
    rob: list[tuple[float, float]] = []
    group: int | None = None
    for lineno, row in enumerate(rows[1:], start=2):
        if not row or not any(cell.strip() for cell in row):
            continue
        where = f"{path}:{lineno}"
        if len(row) != len(header):
            raise DatasetError(f"{where}: expected {len(header)} fields, got {len(row)}")
        t = _timestamp_ns(row[col["timestamp"]].strip(), where)
        if t_list and t <= t_list[-1]:
            raise DatasetError(
                f"{where}: timestamps go backwards or repeat: {t} ns after {t_list[-1]} ns"
            )
        ped.append(
            (
                coordinate(row[col["x"]], where, "x"),
                coordinate(row[col["y"]], where, "y"),
            )
        )
        rob.append(
            (
                coordinate(row[col["robot_x"]], where, "robot_x"),
                coordinate(row[col["robot_y"]], where, "robot_y"),
            )
        )
        if has_group:
            g = integer(row[col["column"]].strip(), where, "column")
            if group is not None and g != group:
                raise DatasetError(f"{where}: column changes from {group} to {g} within a file")
            group = g
        t_list.append(t)
    if not t_list:
        raise DatasetError(f"{path}: no data rows")
    n = len(t_list)
    t_ns = np.array(t_list, dtype=np.int64)
    frame = np.arange(n, dtype=np.int64)
    ped_id = PEDESTRIAN if group is None else f"{PEDESTRIAN}:{group}"
    speed = median_speed(np.zeros(n, np.int64), t_ns, np.array(ped, dtype=np.float64))
    warn_if_fast(f"{path}", speed, "check the timestamp unit (nanoseconds expected)")
    dt = float(np.median(np.diff(t_ns))) * 1e-9 if n > 1 else math.nan
    return Trajectories.from_samples(
        scene=path.stem,
        agent_ids=[ped_id, ROBOT],
        kinds=[PEDESTRIAN, ROBOT],
        agent=np.repeat(np.array([[0, 1]], dtype=np.int64), n, axis=0).ravel(),
        frame=np.repeat(frame, 2),
        t_ns=np.repeat(t_ns, 2),
        xy=np.stack([np.array(ped), np.array(rob)], axis=1).reshape(-1, 2),
        frame_of_reference="world",
        source={
            "dataset": NAME,
            "file": path.name,
            "median_dt_s": f"{dt:.6f}",
            "median_speed_mps": f"{speed:.3f}",
        },
    )


FULL_SCENE_COLUMNS: Final = ("timestamp", "robot_x", "robot_y")


def _read_full_scene(path: Path, header: list[str], rows: list[list[str]]) -> Trajectories:
    """Format 2 (circular-crossing scenes): ``timestamp,robot_x,robot_y,...,x1,y1,..,xK,yK``,
    the robot and K pedestrians per row; pedestrian ``k`` becomes ``pedestrian:<k>``."""
    missing = [c for c in FULL_SCENE_COLUMNS if c not in header]
    k_max = 0
    while f"x{k_max + 1}" in header:
        k_max += 1
    missing += [f"y{k}" for k in range(1, k_max + 1) if f"y{k}" not in header]
    if missing:
        raise DatasetError(
            f"{path}:1: missing column {missing[0]!r} (header: {','.join(header)}); "
            f"expected {','.join(FULL_SCENE_COLUMNS)},x1,y1,..."
        )
    col = {name: header.index(name) for name in header}
    t_list: list[int] = []
    frames: list[list[tuple[float, float]]] = []
    for lineno, row in enumerate(rows[1:], start=2):
        if not row or not any(cell.strip() for cell in row):
            continue
        where = f"{path}:{lineno}"
        if len(row) != len(header):
            raise DatasetError(f"{where}: expected {len(header)} fields, got {len(row)}")
        t = _timestamp_ns(row[col["timestamp"]].strip(), where)
        if t_list and t <= t_list[-1]:
            raise DatasetError(
                f"{where}: timestamps go backwards or repeat: {t} ns after {t_list[-1]} ns"
            )
        xy = [
            (
                coordinate(row[col[f"x{k}"]], where, f"x{k}"),
                coordinate(row[col[f"y{k}"]], where, f"y{k}"),
            )
            for k in range(1, k_max + 1)
        ]
        xy.append(
            (
                coordinate(row[col["robot_x"]], where, "robot_x"),
                coordinate(row[col["robot_y"]], where, "robot_y"),
            )
        )
        frames.append(xy)
        t_list.append(t)
    if not t_list:
        raise DatasetError(f"{path}: no data rows")
    n = len(t_list)
    m = k_max + 1
    t_ns = np.array(t_list, dtype=np.int64)
    xyz = np.array(frames, dtype=np.float64)  # (n, m, 2)
    speed = median_speed(
        np.repeat(np.arange(k_max, dtype=np.int64), n),
        np.tile(t_ns, k_max),
        xyz[:, :k_max].transpose(1, 0, 2).reshape(-1, 2),
    )
    warn_if_fast(f"{path}", speed, "check the timestamp unit (nanoseconds expected)")
    dt = float(np.median(np.diff(t_ns))) * 1e-9 if n > 1 else math.nan
    return Trajectories.from_samples(
        scene=path.stem,
        agent_ids=[f"{PEDESTRIAN}:{k}" for k in range(1, k_max + 1)] + [ROBOT],
        kinds=[PEDESTRIAN] * k_max + [ROBOT],
        agent=np.tile(np.arange(m, dtype=np.int64), n),
        frame=np.repeat(np.arange(n, dtype=np.int64), m),
        t_ns=np.repeat(t_ns, m),
        xy=xyz.reshape(-1, 2),
        frame_of_reference="world",
        source={
            "dataset": NAME,
            "file": path.name,
            "median_dt_s": f"{dt:.6f}",
            "median_speed_mps": f"{speed:.3f}",
        },
    )
