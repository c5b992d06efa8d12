"""Crowd state (struct of arrays) and static obstacles."""

from __future__ import annotations

import weakref
from typing import Any

import attrs
import numpy as np
from numpy.typing import NDArray

from srfm._text import plain
from srfm._validate import float_array, physical_array
from srfm.errors import SimulationError
from srfm.models._arrays import CrowdArrays, ObstacleArrays

__all__ = ["CrowdState", "Obstacles"]

FloatArray = NDArray[np.float64]

# Bounds that keep every force and step finite in float64 (see srfm.models._kernels).
MAX_SPEED_MPS = 1e3
MAX_RADIUS_M = 1e3


@attrs.frozen(kw_only=True, eq=False)
class CrowdState:
    """Pedestrians as a struct of arrays (float64, C-contiguous).

    The fields cannot be reassigned; the simulator updates the arrays in place. The
    constructor checks every array (dtype, contiguity, shape, finite, non-negative
    radii and speeds) because the kernels read them without bounds checks;
    :meth:`create` converts lists and broadcasts scalars first.

    Attributes:
        pos: (N, 2) positions (m).
        vel: (N, 2) velocities (m/s).
        goal: (N, 2) goals (m).
        radius: (N,) body radii (m), >= 0.
        v0: (N,) desired speeds (m/s), >= 0.
        vmax: (N,) speed caps (m/s), >= 0.
    """

    pos: FloatArray
    vel: FloatArray
    goal: FloatArray
    radius: FloatArray
    v0: FloatArray
    vmax: FloatArray

    def __attrs_post_init__(self) -> None:
        n = _check_field(self.pos, "pos", (None, 2))
        for name in ("vel", "goal"):
            _check_field(getattr(self, name), name, (n, 2))
        for name in ("pos", "goal"):  # the coordinate bound of srfm._validate.BOUNDS
            physical_array(getattr(self, name), name, "coordinate", SimulationError)
        for name, upper in (
            ("radius", MAX_RADIUS_M),
            ("v0", MAX_SPEED_MPS),
            ("vmax", MAX_SPEED_MPS),
        ):
            arr = getattr(self, name)
            _check_field(arr, name, (n,))
            bad = (arr < 0.0) | (arr > upper)
            if np.any(bad):
                i = int(np.argmax(bad))
                raise SimulationError(
                    f"{name} must be in [0, {upper:g}], got {float(arr[i])!r} for pedestrian {i}"
                )

    @classmethod
    def create(
        cls,
        *,
        pos: Any,
        goal: Any,
        vel: Any = None,
        radius: Any = 0.3,
        v0: Any = 1.25,
        vmax: Any = None,
    ) -> CrowdState:
        """Build and validate a crowd; scalars broadcast to every pedestrian.

        ``vel`` defaults to zero and ``vmax`` to ``v0``.
        """
        pos_a = float_array(pos, "pos", (None, 2), SimulationError)
        n = pos_a.shape[0]
        goal_a = float_array(goal, "goal", (n, 2), SimulationError)
        vel_a = (
            np.zeros((n, 2)) if vel is None else float_array(vel, "vel", (n, 2), SimulationError)
        )
        radius_a = _per_agent(radius, "radius", n)
        v0_a = _per_agent(v0, "v0", n)
        vmax_a = v0_a.copy() if vmax is None else _per_agent(vmax, "vmax", n)
        return cls(pos=pos_a, vel=vel_a, goal=goal_a, radius=radius_a, v0=v0_a, vmax=vmax_a)

    @property
    def n(self) -> int:
        """Number of pedestrians."""
        return int(self.pos.shape[0])

    def for_kernels(self, m: int | None = None) -> CrowdArrays:
        """The kernels' view of the first ``m`` pedestrians (all for None): views of
        these arrays, so a kernel's update is this crowd's."""
        if m is None or m == self.n:
            return CrowdArrays(self.pos, self.vel, self.goal, self.radius, self.v0, self.vmax)
        return CrowdArrays(
            self.pos[:m], self.vel[:m], self.goal[:m], self.radius[:m], self.v0[:m], self.vmax[:m]
        )

    def copy(self) -> CrowdState:
        """A deep copy (every array copied)."""
        return CrowdState(
            pos=self.pos.copy(),
            vel=self.vel.copy(),
            goal=self.goal.copy(),
            radius=self.radius.copy(),
            v0=self.v0.copy(),
            vmax=self.vmax.copy(),
        )


def _check_field(arr: Any, name: str, shape: tuple[int | None, ...]) -> int:
    """Check one state array in place (no conversion); return its length."""
    if not isinstance(arr, np.ndarray) or arr.dtype != np.float64:
        raise SimulationError(f"{name} must be a float64 numpy array, got {plain(arr)}")
    if not (arr.flags.c_contiguous and arr.flags.writeable):
        raise SimulationError(f"{name} must be C-contiguous and writeable")
    float_array(arr, name, shape, SimulationError)  # shape and finiteness
    return int(arr.shape[0])


def _per_agent(value: Any, name: str, n: int) -> FloatArray:
    arr = (
        np.broadcast_to(np.asarray(value, dtype=np.float64), (n,)) if np.ndim(value) == 0 else value
    )
    out = float_array(arr, name, (n,), SimulationError)
    if np.any(out < 0.0):
        i = int(np.argmax(out < 0.0))
        raise SimulationError(f"{name} must be >= 0, got {plain(out[i])} for pedestrian {i}")
    return out.copy()


def _read_only(arr: FloatArray) -> FloatArray:
    arr.setflags(write=False)
    return arr


@attrs.frozen(kw_only=True, eq=False)
class Obstacles:
    """Static obstacles: wall segments and circular pillars (read-only arrays).

    Attributes:
        segments: (M, 4) walls as (x1, y1, x2, y2) (m).
        circles: (K, 3) pillars as (cx, cy, radius) (m), radius >= 0.
    """

    segments: FloatArray = attrs.field(factory=lambda: np.zeros((0, 4)))
    circles: FloatArray = attrs.field(factory=lambda: np.zeros((0, 3)))

    def __attrs_post_init__(self) -> None:
        seg = float_array(self.segments, "segments", (None, 4), SimulationError)
        circ = float_array(self.circles, "circles", (None, 3), SimulationError)
        # The one rule for physical inputs (srfm._validate.BOUNDS).
        physical_array(seg, "wall coordinates", "coordinate", SimulationError)
        physical_array(circ[:, :2], "pillar centres", "coordinate", SimulationError)
        physical_array(circ[:, 2], "pillar radius", "radius", SimulationError)
        # Private read-only copies: nobody can change an obstacle after the fact.
        object.__setattr__(self, "segments", _read_only(seg.copy()))
        object.__setattr__(self, "circles", _read_only(circ.copy()))

    def __reduce__(self) -> tuple[Any, ...]:
        # Unpickled (e.g. in a benchmark worker) through the constructor, so that the
        # arrays are read-only there too: pickle itself gives writable arrays.
        return (_obstacles, (self.segments, self.circles))

    @classmethod
    def create(cls, *, segments: Any = (), circles: Any = ()) -> Obstacles:
        """Validate and build; empty inputs give no obstacles."""
        seg = np.zeros((0, 4)) if len(segments) == 0 else segments
        circ = np.zeros((0, 3)) if len(circles) == 0 else circles
        return cls(segments=seg, circles=circ)

    @property
    def empty(self) -> bool:
        """True when there are no walls and no pillars."""
        return bool(self.segments.shape[0] == 0 and self.circles.shape[0] == 0)

    def for_kernels(self) -> ObstacleArrays:
        """The kernels' copies of the obstacles: writable and C-contiguous.

        numba compiles a kernel once per argument type, and read-only is part of an
        array's type: these arrays are read-only where they were built but writable
        where they were unpickled (a benchmark worker), which would make every worker
        compile the crowd step and the robot's checks again (seconds of CPU each with
        an empty cache). The copies are the same type everywhere.
        """
        arrays = _KERNEL_ARRAYS.get(self)
        if arrays is None:  # made once per Obstacles (the kernels only read them)
            segments = np.array(self.segments, dtype=np.float64, order="C")
            circles = np.array(self.circles, dtype=np.float64, order="C")
            arrays = ObstacleArrays(
                segments=segments,
                circles=circles,
                pillar_xy=np.array(circles[:, :2], order="C"),
                pillar_r=np.array(circles[:, 2], order="C"),
            )
            _KERNEL_ARRAYS[self] = arrays
        return arrays


# The kernels' arrays of each Obstacles, kept beside it rather than in it, so that an
# obstacle's content (what a scenario's fingerprint hashes) is only its walls and pillars.
_KERNEL_ARRAYS: weakref.WeakKeyDictionary[Obstacles, ObstacleArrays] = weakref.WeakKeyDictionary()


def _obstacles(segments: FloatArray, circles: FloatArray) -> Obstacles:
    """:class:`Obstacles` from its two arrays (how it is unpickled)."""
    return Obstacles(segments=segments, circles=circles)
