"""Small parsing helpers shared by the adapters: numbers with a location in the message."""

from __future__ import annotations

import json
import math
import warnings
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

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
        raise DatasetError(f"{where}: {what} must be finite, got {text!r}")
    return value


def integer(text: str, where: str, what: str) -> int:
    """Parse an integer written as ``12`` or ``12.0``."""
    try:
        return int(text)
    except ValueError:
        pass
    value = number(text, where, what)
    if not value.is_integer():
        raise DatasetError(f"{where}: {what} must be an integer, got {text!r}")
    return int(value)


def json_number(value: Any, where: str) -> float:
    """A finite JSON number (not a bool, not a string)."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise DatasetError(f"{where}: expected a number, got {value!r}")
    out = float(value)
    if not math.isfinite(out):
        raise DatasetError(f"{where}: expected a finite number, got {value!r}")
    return out


def load_json(path: Path) -> Any:
    """Read a JSON file; errors name the file, line and column."""
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise DatasetError(f"{path}: file not found") from None
    except UnicodeDecodeError as exc:
        raise DatasetError(f"{path}: not UTF-8 text (byte {exc.start})") from None
    except OSError as exc:
        raise DatasetError(f"{path}: cannot read: {exc.strerror}") from None
    if not text.strip():
        raise DatasetError(f"{path}: empty file")
    try:
        return json.loads(text)
    except json.JSONDecodeError as exc:
        raise DatasetError(f"{path}:{exc.lineno}:{exc.colno}: not valid JSON: {exc.msg}") from None


def read_text_lines(path: Path) -> list[str]:
    """The lines of a UTF-8 text file; a missing or unreadable file is a DatasetError."""
    try:
        return path.read_text(encoding="utf-8").splitlines()
    except FileNotFoundError:
        raise DatasetError(f"{path}: file not found") from None
    except IsADirectoryError:
        raise DatasetError(f"{path}: is a directory, expected a file") from None
    except UnicodeDecodeError as exc:
        raise DatasetError(f"{path}: not UTF-8 text (byte {exc.start})") from None
    except OSError as exc:
        raise DatasetError(f"{path}: cannot read: {exc.strerror}") from None


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
