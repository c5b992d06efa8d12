"""Small parsing helpers shared by the adapters: numbers with a location in the message.

Every raw file is read through :func:`srfm._io.read_input_text` (regular files of at
most 1 GiB, UTF-8 with an optional byte-order mark), and every number through the
bounds of :mod:`srfm._validate`: positions within ±1e7 m, frame numbers and timestamps
(ns) within [0, 2⁶³ − 1], frame intervals within (0, 86400] s.
"""

from __future__ import annotations

import json
import math
import warnings
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from srfm._io import MAX_DATASET_FILE_BYTES, read_input_text
from srfm._text import plain
from srfm._validate import BOUNDS, MAX_INT64
from srfm.datasets._trajectories import DatasetWarning
from srfm.errors import DatasetError

# Median walking speeds above this are implausible for pedestrians (m/s).
MAX_PLAUSIBLE_MEDIAN_SPEED_MPS = 2.0


def number(text: str, where: str, what: str) -> float:
    """Parse a finite float from ``text``; ``where`` is ``file:line`` for the message."""
    try:
        value = float(text)
    except ValueError:
        raise DatasetError(f"{where}: {what} is not a number: {text!r}") from None
    if not math.isfinite(value):
        raise DatasetError(f"{where}: {what} must be finite, got {plain(text)}")
    return value


def coordinate(text: str, where: str, what: str) -> float:
    """A position coordinate (m): a finite number within ±1e7 m (the physical bound)."""
    value = number(text, where, what)
    lo, hi, unit = BOUNDS["coordinate"]
    if not lo <= value <= hi:
        raise DatasetError(f"{where}: {what} must be in [{lo:g}, {hi:g}] {unit}, got {plain(text)}")
    return value


def integer(text: str, where: str, what: str, *, signed: bool = True) -> int:
    """Parse an integer written as ``12`` or ``12.0``, within int64 (also >= 0 unless
    ``signed``)."""
    try:
        value = int(text)
    except ValueError:
        as_float = number(text, where, what)
        if not as_float.is_integer():
            raise DatasetError(f"{where}: {what} must be an integer, got {plain(text)}") from None
        value = int(as_float)
    return bounded_int(value, where, what, signed=signed)


def bounded_int(value: int, where: str, what: str, *, signed: bool = False) -> int:
    """``value`` if it fits int64 (and is >= 0 unless ``signed``), else a DatasetError."""
    lo = -MAX_INT64 - 1 if signed else 0
    if not lo <= value <= MAX_INT64:
        span = "[-2^63, 2^63 - 1]" if signed else "[0, 2^63 - 1]"
        raise DatasetError(f"{where}: {what} must be in {span}, got {value}")
    return value


def seconds_to_ns(seconds: float, where: str, what: str = "timestamp") -> int:
    """A time in seconds (>= 0) as integer nanoseconds that fit int64."""
    if not (math.isfinite(seconds) and 0.0 <= seconds <= MAX_INT64 * 1e-9):
        raise DatasetError(
            f"{where}: {what} must be in [0, {MAX_INT64 * 1e-9:.4g}] s (int64 ns), "
            f"got {plain(seconds)}"
        )
    return bounded_int(round(seconds * 1e9), where, what)


def frame_interval(dt_s: object, where: str) -> float:
    """A frame interval (s) in (0, 86400]."""
    lo, hi, _ = BOUNDS["duration"]
    if (
        isinstance(dt_s, bool)
        or not isinstance(dt_s, int | float)
        or not lo < float(dt_s) <= hi  # also false for NaN
    ):
        raise DatasetError(f"{where}: dt_s must be in (0, {hi:g}] s, got {plain(dt_s)}")
    return float(dt_s)


def json_number(value: Any, where: str) -> float:
    """A finite JSON number (not a bool, not a string)."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise DatasetError(f"{where}: expected a number, got {plain(value)}")
    out = float(value)
    if not math.isfinite(out):
        raise DatasetError(f"{where}: expected a finite number, got {plain(value)}")
    return out


def load_json(path: Path) -> Any:
    """Read a JSON file; errors name the file, line and column."""
    text = _read(path)
    if not text.strip():
        raise DatasetError(f"{path}: empty file")
    try:
        return json.loads(text)
    except json.JSONDecodeError as exc:
        raise DatasetError(f"{path}:{exc.lineno}:{exc.colno}: not valid JSON: {exc.msg}") from None
    except RecursionError:
        raise DatasetError(f"{path}: not valid JSON: nested too deeply") from None


def _read(path: Path) -> str:
    return read_input_text(path, max_bytes=MAX_DATASET_FILE_BYTES, error=DatasetError, what="file")


def read_text_lines(path: Path) -> list[str]:
    """The lines of a UTF-8 text file (a byte-order mark is dropped); a missing,
    unreadable, special (FIFO, device) or oversized file is a DatasetError."""
    return _read(path).splitlines()


def median_speed(
    agent: NDArray[np.int64], t_ns: NDArray[np.int64], xy: NDArray[np.float64]
) -> float:
    """Median speed (m/s) over consecutive samples of the same agent; NaN if none.

    Samples must be sorted by time within each agent (any interleaving of agents).
    """
    order = np.lexsort((t_ns, agent))
    a, t, p = agent[order], t_ns[order], xy[order]
    same = (a[1:] == a[:-1]) & (t[1:] > t[:-1])
    if not np.any(same):
        return math.nan
    dist = np.linalg.norm(p[1:] - p[:-1], axis=1)[same]
    dt = (t[1:] - t[:-1])[same] * 1e-9
    return float(np.median(dist / dt))


def warn_if_fast(where: str, speed: float, hint: str) -> None:
    """Warn (:class:`DatasetWarning`) when a median walking speed is implausible."""
    if math.isfinite(speed) and speed > MAX_PLAUSIBLE_MEDIAN_SPEED_MPS:
        warnings.warn(
            f"{where}: median pedestrian speed {speed:.2f} m/s is implausible "
            f"(> {MAX_PLAUSIBLE_MEDIAN_SPEED_MPS:g} m/s); {hint}",
            DatasetWarning,
            stacklevel=3,
        )
