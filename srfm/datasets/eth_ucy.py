"""ETH (BIWI) and UCY pedestrian tracks: four-column text files -> :class:`Trajectories`.

Raw layout (``datasets/eth_ucy.md``): one row per pedestrian per annotated frame,
whitespace-separated ``frame ped_id x y`` (frame and id may be written as floats,
``780.0``), positions in metres in a fixed world frame, rows sorted by frame. Frame
ids advance by a fixed step (10 in the common copies); the time between two annotated
frames, ``dt_s``, is not in the file and must be given per file (0.4 s by convention,
but about 0.667 s for ``biwi_eth.txt``). Every file is one scene without a robot.

The original ETH/UCY annotations ("obsmat", e.g. ``seq_eth_obsmat.txt``) have eight
columns, ``frame ped_id x z y vx vz vy`` in scientific notation (z and vz are 0): the
adapter reads them too (x from column 3, y from column 5; the velocities are not
used), recognising the layout by the column count of the first row.

Timestamps: t = frame / frame_step · dt_s, frame_step the most common difference
between consecutive distinct frame ids (the smallest of equally common ones). In the
four-column copies every gap is a multiple of it, as the greatest common divisor; the
original ETH annotation steps by 6 frames but has a few gaps of other lengths (395
frames), whose divisor would be 1.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Final

import numpy as np

from srfm._text import plain
from srfm._validate import MAX_INT64
from srfm.datasets._parse import (
    coordinate,
    frame_interval,
    integer,
    median_speed,
    number,
    read_text_lines,
    warn_if_fast,
)
from srfm.datasets._trajectories import PEDESTRIAN, Trajectories
from srfm.errors import DatasetError

__all__ = ["DEFAULT_DT_S", "check_overrides", "dt_for", "list_sources", "read_eth_ucy", "read_file"]

DEFAULT_DT_S: Final = 0.4
OBSMAT_NAMES: Final = ("frame", "ped_id", "x", "z", "y", "vx", "vz", "vy")
LAYOUTS: Final = {
    4: "4 columns (frame ped_id x y)",
    8: "8 columns (obsmat: frame ped_id x z y vx vz vy)",
}
_LAYOUT_TEXT: Final = "4 columns (frame ped_id x y) or 8 (obsmat: frame ped_id x z y vx vz vy)"
NAME: Final = "eth-ucy"
SUFFIXES: Final = (".txt", ".tsv", ".csv")
NOT_TRACKS: Final = ("_H", "_info")  # homography and notes beside the obsmat files


def list_sources(src: str | Path) -> list[Path]:
    """The files to read: ``src`` itself, or the ``*.txt`` / ``*.tsv`` files of a folder,
    except the homographies and notes that come with the original annotations
    (``*_H.txt``, ``*_info.txt``)."""
    src = Path(src)
    if src.is_file():
        return [src]
    if src.is_dir():
        files = sorted(
            p
            for p in src.iterdir()
            if p.is_file() and p.suffix in SUFFIXES and not p.stem.endswith(NOT_TRACKS)
        )
        if not files:
            raise DatasetError(f"{src}: no ETH/UCY files (*.txt) in this folder")
        return files
    raise DatasetError(f"{src}: no such file or folder")


def dt_for(path: Path, dt_s: float, overrides: Mapping[str, float] | None) -> float:
    """The frame interval for ``path``: an override keyed by file name or stem, else ``dt_s``."""
    for key in (path.name, path.stem):
        if overrides and key in overrides:
            return overrides[key]
    return dt_s


def read_eth_ucy(
    src: str | Path,
    dt_s: float = DEFAULT_DT_S,
    dt_overrides: Mapping[str, float] | None = None,
) -> list[Trajectories]:
    """Read one ETH/UCY file or every file of a folder, one scene per file.

    Args:
        src: a file or a folder of files.
        dt_s: time between consecutive annotated frames (s), for every file.
        dt_overrides: per-file ``dt_s`` keyed by file name or stem
            (e.g. ``{"biwi_eth.txt": 0.6667}``); a key matching no file is an error.

    Returns:
        One scene per file, named after the file's stem.

    Raises:
        DatasetError: a malformed file (the message names the file and line).
    """
    files = list_sources(src)
    check_overrides(files, dt_overrides)
    return [read_file(f, dt_for(f, dt_s, dt_overrides)) for f in files]


def check_overrides(files: list[Path], overrides: Mapping[str, float] | None) -> None:
    known = {f.name for f in files} | {f.stem for f in files}
    for key in overrides or {}:
        if key not in known:
            names = ", ".join(f.name for f in files)
            raise DatasetError(f"dt given for {key!r}, which is not among the files: {names}")


def read_file(path: str | Path, dt_s: float = DEFAULT_DT_S) -> Trajectories:
    """Read one four-column ETH/UCY file into a scene named after the file's stem.

    Warns (:class:`srfm.datasets.DatasetWarning`) when the median walking speed
    exceeds 2 m/s, the sign of a wrong ``dt_s``.

    Args:
        path: the file.
        dt_s: time between consecutive annotated frames (s), > 0.

    Raises:
        DatasetError: empty file, wrong column count, non-numeric or non-finite value,
            non-integer frame or id, a pedestrian's frames going backwards, or a
            pedestrian twice in a frame; the message names the file and line.
    """
    path = Path(path)
    dt_s = frame_interval(dt_s, str(path))
    frames: list[int] = []
    ids: list[int] = []
    xy: list[tuple[float, float]] = []
    seen: dict[tuple[int, int], int] = {}
    columns = 0  # 4 (frame ped_id x y) or 8 (obsmat), fixed by the first data row
    # Rows may come frame by frame or pedestrian by pedestrian (UCY zara03 in the
    # Trajectron++ copy): each pedestrian's frames must increase; samples are sorted by
    # (frame, id) below.
    last_of: dict[int, tuple[int, int]] = {}
    for lineno, line in enumerate(read_text_lines(path), start=1):
        fields = line.split()
        if not fields:
            continue
        where = f"{path}:{lineno}"
        if not columns and len(fields) in LAYOUTS:
            columns = len(fields)
        if len(fields) != columns:
            raise DatasetError(
                f"{where}: expected {LAYOUTS.get(columns, _LAYOUT_TEXT)}, got {len(fields)} "
                f"columns: {line.strip()[:120]!r}"
            )
        frame = integer(fields[0], where, "frame (column 1)")
        pid = integer(fields[1], where, "pedestrian id (column 2)")
        x = coordinate(fields[2], where, "x (column 3)")
        if columns == 8:
            y = coordinate(fields[4], where, "y (column 5)")
            for k in range(5, 8):
                coordinate(fields[k], where, f"{OBSMAT_NAMES[k]} (column {k + 1})")
            if number(fields[3], where, "z (column 4)") != 0.0:
                raise DatasetError(
                    f"{where}: z (column 4) of the obsmat layout must be 0, got {plain(fields[3])}"
                )
        else:
            y = coordinate(fields[3], where, "y (column 4)")
        previous = last_of.get(pid)
        if previous is not None and frame < previous[0]:
            raise DatasetError(
                f"{where}: frames go backwards for pedestrian {pid}: frame {frame} after "
                f"frame {previous[0]} (line {previous[1]}); each pedestrian's rows must be "
                "in frame order"
            )
        if frame < 0:
            raise DatasetError(f"{where}: frame must be >= 0, got {frame}")
        if (frame, pid) in seen:
            raise DatasetError(
                f"{where}: pedestrian {pid} appears twice in frame {frame} "
                f"(also line {seen[(frame, pid)]})"
            )
        seen[(frame, pid)] = lineno
        last_of[pid] = (frame, lineno)
        frames.append(frame)
        ids.append(pid)
        xy.append((x, y))
    if not frames:
        raise DatasetError(f"{path}: no data rows (empty file)")

    order = np.lexsort((np.array(ids, dtype=np.int64), np.array(frames, dtype=np.int64)))
    frames = [frames[i] for i in order]
    ids = [ids[i] for i in order]
    xy = [xy[i] for i in order]
    frame_a = np.array(frames, dtype=np.int64)
    distinct = np.unique(frame_a)
    step = 1
    if distinct.size > 1:
        gaps, counts = np.unique(np.diff(distinct), return_counts=True)
        step = int(gaps[np.argmax(counts)])  # the first maximum: the smallest common gap
    # Integer nanoseconds per frame step, then exact integer arithmetic per frame.
    t_float = frame_a.astype(np.float64) * (dt_s * 1e9 / step)
    if t_float[-1] >= float(MAX_INT64):
        raise DatasetError(
            f"{path}: frame {int(frame_a[-1])} at dt = {dt_s:g} s per frame step of {step} "
            f"is {t_float[-1] * 1e-9:.4g} s, beyond the int64 nanosecond clock (292 years); "
            "check the frame numbers or --dt"
        )
    t_ns = np.rint(t_float).astype(np.int64)
    uniq_ids = sorted(set(ids))
    index = {pid: i for i, pid in enumerate(uniq_ids)}
    agent = np.array([index[p] for p in ids], dtype=np.int64)
    xy_a = np.array(xy, dtype=np.float64)
    speed = median_speed(agent, t_ns, xy_a)
    warn_if_fast(
        f"{path}",
        speed,
        f"is dt = {dt_s:g} s per frame step right? (biwi_eth.txt needs about 0.667 s; "
        "set it with --dt FILE=SECONDS, see datasets/eth_ucy.md)",
    )
    return Trajectories.from_samples(
        scene=path.stem,
        agent_ids=[str(p) for p in uniq_ids],
        kinds=[PEDESTRIAN] * len(uniq_ids),
        agent=agent,
        frame=frame_a,
        t_ns=t_ns,
        xy=xy_a,
        frame_of_reference="world",
        source={
            "dataset": NAME,
            "file": path.name,
            "dt_s": repr(float(dt_s)),
            "frame_step": str(step),
            "layout": "obsmat" if columns == 8 else "frame ped_id x y",
            "median_speed_mps": f"{speed:.3f}",
        },
    )
