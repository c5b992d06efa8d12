"""Small validators shared by the parameter, scenario and state classes."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from srfm.errors import SrfmError


def finite_float(value: Any, name: str, error: type[SrfmError]) -> float:
    """Return ``value`` as a float, raising ``error`` unless it is a finite real number."""
    if isinstance(value, bool) or not isinstance(value, int | float | np.integer | np.floating):
        raise error(f"{name} must be a number, got {value!r}")
    out = float(value)
    if not math.isfinite(out):
        raise error(f"{name} must be finite, got {value!r}")
    return out


def positive(value: Any, name: str, error: type[SrfmError]) -> float:
    """A finite float > 0."""
    out = finite_float(value, name, error)
    if out <= 0.0:
        raise error(f"{name} must be > 0, got {value!r}")
    return out


def non_negative(value: Any, name: str, error: type[SrfmError]) -> float:
    """A finite float >= 0."""
    out = finite_float(value, name, error)
    if out < 0.0:
        raise error(f"{name} must be >= 0, got {value!r}")
    return out


def unit_interval(value: Any, name: str, error: type[SrfmError]) -> float:
    """A finite float in [0, 1]."""
    out = finite_float(value, name, error)
    if not 0.0 <= out <= 1.0:
        raise error(f"{name} must be in [0, 1], got {value!r}")
    return out


def float_array(
    value: Any, name: str, shape: tuple[int | None, ...], error: type[SrfmError]
) -> NDArray[np.float64]:
    """A finite, C-contiguous float64 array of the given shape (None = any length)."""
    try:
        arr = np.ascontiguousarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise error(f"{name} must be a numeric array, got {value!r}") from exc
    if arr.ndim != len(shape) or any(
        want is not None and got != want for got, want in zip(arr.shape, shape, strict=True)
    ):
        want_s = "(" + ", ".join("n" if s is None else str(s) for s in shape) + ")"
        raise error(f"{name} must have shape {want_s}, got {arr.shape}")
    if not np.all(np.isfinite(arr)):
        where = tuple(int(i) for i in np.argwhere(~np.isfinite(arr))[0])
        raise error(f"{name} must be finite, got {float(arr[where])!r} at index {where}")
    return arr
