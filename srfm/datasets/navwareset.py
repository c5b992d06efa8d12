"""NavWareSet: real pedestrians meeting a real robot, CSV files -> :class:`Trajectories`.

Two raw layouts (``datasets/navwareset.md``), both 10 Hz, ``timestamp`` in nanoseconds
(written as an integer or a float, ``1.7308255599301187e+18``), positions in metres in
a common world frame, one scene per file:

- format 1, one pedestrian per file:
  ``timestamp,x,y,column,robot_x,robot_y,robot_yaw_rad`` (``column``, the participant
  1–5, and ``robot_yaw_rad`` are optional: the 12-file excerpt has no yaw). Agents
  ``pedestrian:<column>`` (or ``pedestrian`` without a ``column`` column) and ``robot``.
- format 2, the circular-crossing scenes, K pedestrians per row:
  ``timestamp,robot_x,robot_y,robot_yaw_rad,x1,y1,...,xK,yK``. Agents
  ``pedestrian:1`` .. ``pedestrian:K`` and ``robot``.

The frame number is the data row's index (0-based). The robot's heading
(``robot_yaw_rad``) is kept as the robot samples' ``yaw``; its velocity is the
difference of consecutive positions (the replay in :mod:`srfm.fitting` moves it
linearly between them).

The recorded scene (its number from the file name ``track_scene<N>_...`` /
``<N>_full_scene...`` or the folder ``<N>_poses``) and, for the 33 scenes of the
shared selection, its condition (:data:`CONDITIONS`: Francis et al.'s scenario, the
robot, socially compliant or not) go into the scene's ``source`` metadata and from
there into the MCAP file: ``navwareset_scene``, ``scenario``, ``robot``, ``compliant``
(``"true"``/``"false"``), ``format`` (``"1"``/``"2"``).
"""

from __future__ import annotations

import csv
import math
import re
from collections.abc import Sequence
from pathlib import Path
from typing import Final

import numpy as np

from srfm._io import check_columns
from srfm._text import plain
from srfm.datasets._parse import (
    bounded_int,
    coordinate,
    integer,
    median_speed,
    number,
    read_text_lines,
    warn_if_fast,
)
from srfm.datasets._trajectories import MAX_YAW_RAD, PEDESTRIAN, ROBOT, Trajectories
from srfm.errors import DatasetError

__all__ = [
    "CONDITIONS",
    "FORMAT1_COLUMNS",
    "FULL_SCENE_COLUMNS",
    "REQUIRED_COLUMNS",
    "ROBOTS",
    "SCENARIOS",
    "Condition",
    "condition_of",
    "drop_supersets",
    "list_sources",
    "read_file",
    "read_navwareset",
    "scene_number",
]

NAME: Final = "navwareset"
REQUIRED_COLUMNS: Final = ("timestamp", "x", "y", "robot_x", "robot_y")
FORMAT1_COLUMNS: Final = (*REQUIRED_COLUMNS, "column", "robot_yaw_rad")
FULL_SCENE_COLUMNS: Final = ("timestamp", "robot_x", "robot_y")
YAW_COLUMN: Final = "robot_yaw_rad"

SCENARIOS: Final = (
    "frontal_approach",
    "pedestrian_obstruction",
    "blind_corner",
    "perpendicular_crossing",
    "circular_crossing",
)
ROBOTS: Final = ("hsr", "jackal")  # Toyota HSR (about 0.3 m/s), Clearpath Jackal (about 1 m/s)

Condition = tuple[str, str, bool]  # (scenario, robot, socially compliant)


def _conditions() -> dict[int, Condition]:
    # The scene -> condition table of the shared data's README (NavWareSet-Quant):
    # scenario: (HSR compliant, HSR non-compliant, Jackal compliant, Jackal non-compliant).
    table: dict[str, tuple[tuple[int, ...], ...]] = {
        "frontal_approach": ((1, 27), (8, 34), (15,), (21, 47)),
        "pedestrian_obstruction": ((2,), (9, 35), (16, 42), (22,)),
        "blind_corner": ((3, 29), (10,), (17, 43), (23,)),
        "perpendicular_crossing": ((5, 31), (12, 38), (19,), (25,)),
        "circular_crossing": ((6, 32), (13,), (20, 46), (26, 52)),
    }
    cells = (("hsr", True), ("hsr", False), ("jackal", True), ("jackal", False))
    out: dict[int, Condition] = {}
    for scenario, groups in table.items():
        for (robot, compliant), scenes in zip(cells, groups, strict=True):
            for n in scenes:
                out[n] = (scenario, robot, compliant)
    return dict(sorted(out.items()))


CONDITIONS: Final[dict[int, Condition]] = _conditions()

_FILE_SCENE: Final = re.compile(r"(?:^|_)scene(\d+)_")
_FULL_SCENE: Final = re.compile(r"^(\d+)_full_scene")
_FOLDER_SCENE: Final = re.compile(r"^(\d+)_poses$")


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


def scene_number(path: str | Path) -> int | None:
    """The recorded NavWareSet scene of a file, from its name (``track_scene12_...``,
    ``s_track_scene12_...``, ``12_full_scene...``) or its folder (``12_poses``); None
    when neither names one.

    Raises:
        DatasetError: the file name and the folder name give different scenes.
    """
    path = Path(path)
    match = _FILE_SCENE.search(path.stem) or _FULL_SCENE.match(path.stem)
    from_file = int(match.group(1)) if match else None
    folder = _FOLDER_SCENE.match(path.parent.name)
    from_folder = int(folder.group(1)) if folder else None
    if from_file is not None and from_folder is not None and from_file != from_folder:
        raise DatasetError(
            f"{path}: the file name says scene {from_file} but the folder "
            f"{path.parent.name!r} says scene {from_folder}"
        )
    return from_file if from_file is not None else from_folder


def condition_of(scene: Trajectories) -> Condition | None:
    """(scenario, robot, compliant) of a converted NavWareSet scene, from its metadata;
    None when the recorded scene is not in :data:`CONDITIONS`."""
    src = scene.source
    if not {"scenario", "robot", "compliant"} <= set(src):
        return None
    return (src["scenario"], src["robot"], src["compliant"] == "true")


def drop_supersets(scenes: Sequence[Trajectories]) -> tuple[list[Trajectories], list[str]]:
    """Drop every recording whose time span covers another recording of the same
    NavWareSet scene, so no track is counted twice.

    The shared folder holds scene 13 twice: its nine selected slices in ``13_poses/``
    and the whole 250 s recording (``13_full_scene_robot_and_participants.csv``), which
    contains them. Slices never overlap one another (each is one pass), so the rule
    keeps the slices and drops the full recording. Scenes without a
    ``navwareset_scene`` number are kept as they are.

    Returns:
        The kept scenes (in their order) and the names of the dropped ones.
    """
    spans: dict[str, list[tuple[int, int, int]]] = {}
    for i, s in enumerate(scenes):
        key = s.source.get("navwareset_scene")
        if key is not None and s.n_samples:
            spans.setdefault(key, []).append((int(s.t_ns[0]), int(s.t_ns[-1]), i))
    drop: set[int] = set()
    for members in spans.values():
        for a0, a1, i in members:
            if any(j != i and a0 <= b0 and b1 <= a1 for b0, b1, j in members):
                drop.add(i)
    kept = [s for i, s in enumerate(scenes) if i not in drop]
    return kept, [scenes[i].scene for i in sorted(drop)]


def _timestamp_ns(text: str, where: str) -> int:
    # Integers are exact; floats (how the distributed files store ns) are rounded.
    try:
        value = int(text)
    except ValueError:
        value = round(number(text, where, "timestamp"))
    if value < 0:
        raise DatasetError(f"{where}: timestamp must be >= 0 ns, got {plain(text)}")
    return bounded_int(value, where, "timestamp (ns)")


def _yaw(text: str, where: str) -> float:
    value = number(text, where, YAW_COLUMN)
    if abs(value) > MAX_YAW_RAD:
        raise DatasetError(
            f"{where}: {YAW_COLUMN} must be in [-2π, 2π] rad, got {plain(text)} (degrees?)"
        )
    return value


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _check_header(path: Path, header: list[str]) -> None:
    """The header names each column once; data in its place, unknown columns, and a mix
    of the two formats are errors."""
    if all(_is_number(c) for c in header if c):
        raise DatasetError(
            f"{path}:1: the first line is data, not a header ({','.join(header)[:80]}); "
            f"expected a header such as {','.join(FORMAT1_COLUMNS)} (format 1) or "
            f"{','.join(FULL_SCENE_COLUMNS)},{YAW_COLUMN},x1,y1,... (format 2)"
        )
    check_columns(header, f"{path}:1", DatasetError)
    full = "x" not in header and "x1" in header
    if not full and any(re.fullmatch(r"[xy]\d+", c) for c in header):
        raise DatasetError(
            f"{path}:1: header mixes format 1 (x,y) and format 2 (x1,y1,...) columns: "
            f"{','.join(header)}"
        )
    known = {*FULL_SCENE_COLUMNS, YAW_COLUMN} if full else set(FORMAT1_COLUMNS)
    unknown = [c for c in header if c not in known and not (full and re.fullmatch(r"[xy]\d+", c))]
    if unknown:
        expected = (
            f"{','.join(FULL_SCENE_COLUMNS)},{YAW_COLUMN},x1,y1,..."
            if full
            else ",".join(FORMAT1_COLUMNS)
        )
        raise DatasetError(f"{path}:1: unknown column {unknown[0]!r}; expected {expected}")


def _source(path: Path, fmt: str, dt: float, speed: float) -> dict[str, str]:
    source = {
        "dataset": NAME,
        "file": path.name,
        "format": fmt,
        "median_dt_s": f"{dt:.6f}",
        "median_speed_mps": f"{speed:.3f}",
    }
    number_ = scene_number(path)
    if number_ is not None:
        source["navwareset_scene"] = str(number_)
        if number_ in CONDITIONS:
            scenario, robot, compliant = CONDITIONS[number_]
            source.update(
                scenario=scenario, robot=robot, compliant="true" if compliant else "false"
            )
    return source


def read_file(path: str | Path) -> Trajectories:
    """Read one NavWareSet CSV (either format) into a scene named after the file's stem.

    Raises:
        DatasetError: empty file, a header that is data, names a column twice, mixes the
            formats or names an unknown column; a missing column; a wrong field count;
            a non-numeric or non-finite value; a heading outside [-2π, 2π] rad;
            timestamps not strictly increasing; a file name and folder naming different
            scenes. The message names the file and line.
    """
    path = Path(path)
    lines = read_text_lines(path)
    rows = list(csv.reader(lines))
    if not rows or not any(cell.strip() for cell in rows[0]):
        raise DatasetError(f"{path}: empty file (no header)")
    header = [c.strip() for c in rows[0]]
    _check_header(path, header)
    scene_number(path)  # a file name and folder that disagree fail before the data
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
    has_yaw = YAW_COLUMN in col
    t_list: list[int] = []
    ped: list[tuple[float, float]] = []
    rob: list[tuple[float, float]] = []
    yaw: list[float] = []
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
        if has_yaw:
            yaw.append(_yaw(row[col[YAW_COLUMN]], where))
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
    yaw_samples = None
    if has_yaw:
        yaw_samples = np.stack([np.full(n, np.nan), np.array(yaw)], axis=1).ravel()
    return Trajectories.from_samples(
        scene=path.stem,
        agent_ids=[ped_id, ROBOT],
        kinds=[PEDESTRIAN, ROBOT],
        agent=np.repeat(np.array([[0, 1]], dtype=np.int64), n, axis=0).ravel(),
        frame=np.repeat(frame, 2),
        t_ns=np.repeat(t_ns, 2),
        xy=np.stack([np.array(ped), np.array(rob)], axis=1).reshape(-1, 2),
        frame_of_reference="world",
        source=_source(path, "1", dt, speed),
        yaw=yaw_samples,
    )


def _read_full_scene(path: Path, header: list[str], rows: list[list[str]]) -> Trajectories:
    """Format 2 (circular-crossing scenes): ``timestamp,robot_x,robot_y,...,x1,y1,..,xK,yK``,
    the robot and K pedestrians per row; pedestrian ``k`` becomes ``pedestrian:<k>``."""
    missing = [c for c in FULL_SCENE_COLUMNS if c not in header]
    k_max = 0
    while f"x{k_max + 1}" in header:
        k_max += 1
    missing += [f"y{k}" for k in range(1, k_max + 1) if f"y{k}" not in header]
    stray = [c for c in header if re.fullmatch(r"[xy]\d+", c) and not 1 <= int(c[1:]) <= k_max]
    if missing:
        raise DatasetError(
            f"{path}:1: missing column {missing[0]!r} (header: {','.join(header)}); "
            f"expected {','.join(FULL_SCENE_COLUMNS)},x1,y1,..."
        )
    if stray:
        raise DatasetError(
            f"{path}:1: column {stray[0]!r} without the columns x1..x{int(stray[0][1:]) - 1} "
            f"before it (header: {','.join(header)})"
        )
    col = {name: header.index(name) for name in header}
    has_yaw = YAW_COLUMN in col
    t_list: list[int] = []
    frames: list[list[tuple[float, float]]] = []
    yaw: list[float] = []
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
        if has_yaw:
            yaw.append(_yaw(row[col[YAW_COLUMN]], where))
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
    yaw_samples = None
    if has_yaw:
        yaw_samples = np.full((n, m), np.nan)
        yaw_samples[:, k_max] = yaw
    return Trajectories.from_samples(
        scene=path.stem,
        agent_ids=[f"{PEDESTRIAN}:{k}" for k in range(1, k_max + 1)] + [ROBOT],
        kinds=[PEDESTRIAN] * k_max + [ROBOT],
        agent=np.tile(np.arange(m, dtype=np.int64), n),
        frame=np.repeat(np.arange(n, dtype=np.int64), m),
        t_ns=np.repeat(t_ns, m),
        xy=xyz.reshape(-1, 2),
        frame_of_reference="world",
        source=_source(path, "2", dt, speed),
        yaw=None if yaw_samples is None else yaw_samples.ravel(),
    )
