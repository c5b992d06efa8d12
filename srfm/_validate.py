"""Validators shared by every input path: numbers, physical bounds, names and seeds.

Physical bounds: one rule for every input path (scenario files, parameters, command-line
options, datasets). A physical quantity is a finite number within the range of its kind
(:data:`BOUNDS`); the ranges are far outside anything physical, and chosen so that
every product and square the kernels form stays finite in float64:

========================  ==========================  ===================================
kind                      range                       examples
========================  ==========================  ===================================
``coordinate``            [-1e7, 1e7] m               positions, goals, walls, world
``length``                [0, 1e7] m                  distances, margins, noise
``radius``                [0, 1e3] m                  body, goal and pillar radii
``speed``                 [0, 1e3] m/s                desired and top speeds
``pedestrian_speed``      [0, 12.5] m/s               a scenario's pedestrians
``angular_speed``         [0, 1e3] rad/s              ω_max
``acceleration``          [0, 1e6] m/s² or rad/s²     robot acceleration limits
``duration``              [0, 86400] s                dataset frame intervals, windows
========================  ==========================  ===================================

Integers: frame numbers and timestamps (ns) are in [0, 2⁶³ − 1] (int64); seeds in
[0, :data:`MAX_SEED`]. An integer given as text (a seed or a count on the command line,
a seed range of a sweep spec) is plain ASCII decimal digits (:func:`decimal`): not
``1_000``, not ``٣``, not ``+3`` or `` 3``, which Python's ``int()`` all accepts.

Keyword options of the public configuration classes: an unknown name is an error
naming it and the known ones (:func:`keyword_options`), not a raw ``TypeError``.

Names that become path components (scenario and planner names) pass :func:`path_name`.
"""

from __future__ import annotations

import math
import re
from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

from srfm._text import plain
from srfm.errors import SrfmError

MAX_COORDINATE_M: Final = 1e7
"""|x|, |y| of any position (m): geo-referenced datasets (UTM northings) fit."""
MAX_RADIUS_M: Final = 1e3
"""Largest body, goal or pillar radius (m) (the pedestrian bound of CrowdState)."""
MAX_SPEED_MPS: Final = 1e3
"""Largest speed (m/s) (the pedestrian bound of CrowdState)."""
MAX_PEDESTRIAN_SPEED_MPS: Final = 12.5
"""Largest desired or top speed (m/s) of a scenario's pedestrians: faster than anyone
runs (the 100 m world record peaks at 12.4 m/s); 1000 m/s is a typo, not a person."""
MAX_DURATION_S: Final = 86400.0
"""Largest duration (s) an option or a dataset's frame interval may have (one day)."""
MAX_INT64: Final = 2**63 - 1
"""Largest frame number or timestamp (ns) (int64)."""
MAX_SEED: Final = 2**32 - 1
"""Largest episode seed (seeds are unsigned 32-bit integers)."""
MAX_NAME_LENGTH: Final = 100
"""Longest scenario or planner name (characters): it becomes a folder name."""

BOUNDS: Final[dict[str, tuple[float, float, str]]] = {
    "coordinate": (-MAX_COORDINATE_M, MAX_COORDINATE_M, "m"),
    "length": (0.0, MAX_COORDINATE_M, "m"),
    "radius": (0.0, MAX_RADIUS_M, "m"),
    "speed": (0.0, MAX_SPEED_MPS, "m/s"),
    "pedestrian_speed": (0.0, MAX_PEDESTRIAN_SPEED_MPS, "m/s"),
    "angular_speed": (0.0, 1e3, "rad/s"),
    "acceleration": (0.0, 1e6, "per s²"),
    "duration": (0.0, MAX_DURATION_S, "s"),
}
"""kind -> (lowest, highest, unit) of every physical input (see the module doc)."""

_DECIMAL_RE: Final = re.compile(r"[0-9]{1,20}", re.ASCII)
_PATH_NAME_RE: Final = re.compile(r"[A-Za-z0-9][A-Za-z0-9._:-]*")
_REGISTRY_NAME_RE: Final = re.compile(r"[A-Za-z0-9][A-Za-z0-9_-]*")
_SPEC_RE: Final = re.compile(r"[A-Za-z_]\w*(?:\.[A-Za-z_]\w*)*:[A-Za-z_]\w*", re.ASCII)


def finite_float(value: Any, name: str, error: type[SrfmError]) -> float:
    """Return ``value`` as a float, raising ``error`` unless it is a finite real number."""
    if isinstance(value, bool) or not isinstance(value, int | float | np.integer | np.floating):
        raise error(f"{name} must be a number, got {plain(value)}")
    out = float(value)
    if not math.isfinite(out):
        raise error(f"{name} must be finite, got {plain(value)}")
    return out


def positive(value: Any, name: str, error: type[SrfmError]) -> float:
    """A finite float > 0."""
    out = finite_float(value, name, error)
    if out <= 0.0:
        raise error(f"{name} must be > 0, got {plain(value)}")
    return out


def non_negative(value: Any, name: str, error: type[SrfmError]) -> float:
    """A finite float >= 0."""
    out = finite_float(value, name, error)
    if out < 0.0:
        raise error(f"{name} must be >= 0, got {plain(value)}")
    return out


def unit_interval(value: Any, name: str, error: type[SrfmError]) -> float:
    """A finite float in [0, 1]."""
    out = finite_float(value, name, error)
    if not 0.0 <= out <= 1.0:
        raise error(f"{name} must be in [0, 1], got {plain(value)}")
    return out


def float_array(
    value: Any, name: str, shape: tuple[int | None, ...], error: type[SrfmError]
) -> NDArray[np.float64]:
    """A finite, C-contiguous float64 array of the given shape (None = any length)."""
    try:
        arr = np.ascontiguousarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise error(f"{name} must be a numeric array, got {plain(value)}") from exc
    if arr.ndim != len(shape) or any(
        want is not None and got != want for got, want in zip(arr.shape, shape, strict=True)
    ):
        want_s = "(" + ", ".join("n" if s is None else str(s) for s in shape) + ")"
        raise error(f"{name} must have shape {want_s}, got {arr.shape}")
    if not np.all(np.isfinite(arr)):
        where = tuple(int(i) for i in np.argwhere(~np.isfinite(arr))[0])
        raise error(f"{name} must be finite, got {plain(float(arr[where]))} at index {where}")
    return arr


def physical(
    value: Any, name: str, kind: str, error: type[SrfmError], *, strict: bool = False
) -> float:
    """A finite float within the range of its ``kind`` (:data:`BOUNDS`).

    Args:
        value: the number.
        name: what it is, for the message (e.g. ``"robot.radius_m"``).
        kind: a key of :data:`BOUNDS`.
        error: the error class raised.
        strict: the lower bound itself is excluded (e.g. a radius > 0).
    """
    out = finite_float(value, name, error)
    lo, hi, unit = BOUNDS[kind]
    if out > hi or out < lo or (strict and out == lo):
        low = "(" if strict else "["
        raise error(f"{name} must be in {low}{lo:g}, {hi:g}] {unit}, got {plain(value)}")
    return out


def physical_array(
    arr: NDArray[np.float64], name: str, kind: str, error: type[SrfmError]
) -> NDArray[np.float64]:
    """Check every element of a finite float array against :data:`BOUNDS` ``[kind]``."""
    lo, hi, unit = BOUNDS[kind]
    bad = ~((arr >= lo) & (arr <= hi))  # also true for NaN
    if np.any(bad):
        where = tuple(int(i) for i in np.argwhere(bad)[0])
        raise error(
            f"{name} must be in [{lo:g}, {hi:g}] {unit}, got {plain(float(arr[where]))} at "
            f"index {where if len(where) > 1 else where[0]}"
        )
    return arr


def int64(value: int, name: str, error: type[SrfmError]) -> int:
    """An integer in [0, 2⁶³ − 1] (frame numbers, timestamps in ns)."""
    if not 0 <= value <= MAX_INT64:
        raise error(f"{name} must be in [0, 2^63 - 1], got {value}")
    return value


def seed(value: Any, error: type[SrfmError]) -> int:
    """An episode seed: an integer in [0, :data:`MAX_SEED`] (bools refused)."""
    import operator

    try:
        out = operator.index(value)
    except TypeError:
        out = -1
    if isinstance(value, bool) or not 0 <= out <= MAX_SEED:
        raise error(
            f"seed must be a non-negative integer at most {MAX_SEED} (2^32 - 1), got {plain(value)}"
        )
    return out


def decimal(text: str) -> int | None:
    """The integer written as plain ASCII decimal digits (at most 20), or None for any
    other text: ``int()`` also takes ``1_000``, ``٣`` (an Arabic-Indic digit), ``+3`` and
    surrounding spaces, none of which is a plain seed or count."""
    return int(text) if _DECIMAL_RE.fullmatch(text) else None


def keyword_options(
    cls: type, args: tuple[Any, ...], options: dict[str, Any], error: type[SrfmError]
) -> None:
    """Refuse positional arguments and unknown keyword options of an attrs class before
    its ``__init__`` runs (call it from the class's ``__new__``): one ``error`` naming
    the option and the known ones, instead of Python's ``TypeError``."""
    import attrs

    known = [f.name for f in attrs.fields(cls) if f.init]
    if args:
        raise error(f"{cls.__name__} takes keyword options only ({', '.join(known)})")
    unknown = sorted(set(options) - set(known))
    if unknown:
        raise error(f"{cls.__name__}: unknown option {unknown[0]!r}; known: {', '.join(known)}")


def _name_problem(value: Any, what: str) -> str | None:
    if not isinstance(value, str):
        return f"{what} must be a string, got {plain(value)}"
    if not value:
        return f"{what} must not be empty"
    if len(value) > MAX_NAME_LENGTH:
        return f"{what} must be at most {MAX_NAME_LENGTH} characters, got {len(value)}"
    return None


def path_name(value: Any, what: str, error: type[SrfmError]) -> str:
    """A name that becomes a folder or file name (scenario, planner).

    A non-empty string of at most :data:`MAX_NAME_LENGTH` characters: letters, digits,
    ``.``, ``_``, ``:`` and ``-``, starting with a letter or digit; so no ``/``, no
    ``..``, no leading ``.`` or ``-``, no whitespace (a newline would split table rows).
    """
    problem = _name_problem(value, what)
    if problem is None and not _PATH_NAME_RE.fullmatch(value):
        problem = (
            f"{what} {value!r} cannot name a folder: use letters, digits, '.', '_', ':' "
            "and '-', starting with a letter or digit"
        )
    if problem is not None:
        raise error(problem)
    return str(value)


def planner_name(value: Any, error: type[SrfmError]) -> str:
    """A planner as the command line and the benchmark name it: a registry name
    (letters, digits, ``-``, ``_``), ``external:NAME`` (an external planner, NAME a
    registry-style name) or ``module.path:attribute`` (Python identifiers), also a
    valid :func:`path_name`."""
    problem = _name_problem(value, "planner name")
    if problem is None:
        if value.startswith("external:"):
            if not _REGISTRY_NAME_RE.fullmatch(value[len("external:") :]):
                problem = (
                    f"planner {value!r}: an external planner's NAME must be letters, "
                    "digits, '-' or '_'"
                )
        elif ":" in value:
            if not _SPEC_RE.fullmatch(value):
                problem = (
                    f"planner {value!r} is not module:attribute (a dotted Python module "
                    "path, ':', then a name in it, e.g. mypackage.planners:MyPlanner)"
                )
        elif not _REGISTRY_NAME_RE.fullmatch(value):
            problem = (
                f"planner name {value!r} must be letters, digits, '-' or '_' (a registry "
                "name), or module:attribute"
            )
    if problem is not None:
        raise error(problem)
    return str(value)
