"""Python API over the force kernels: inspect force components, step a crowd."""

from __future__ import annotations

from typing import Final

import attrs
import numpy as np
from numpy.typing import NDArray

from srfm.errors import SimulationError
from srfm.models import _kernels
from srfm.models.params import SRFMParams
from srfm.models.state import CrowdState, Obstacles

__all__ = ["PARALLEL_MIN_AGENTS", "ForceComponents", "RobotBody", "force_components", "step_crowd"]

# From this many pedestrians on the threaded kernel is used by default; below it the
# serial kernel is as fast or faster (tools/bench_crowd_step.py, docs/performance.md).
# The threaded kernel needs idle cores: run parallel workers with parallel=False or
# NUMBA_NUM_THREADS=1.
PARALLEL_MIN_AGENTS: Final = 50

# Largest step (s): with the speed bounds of CrowdState it keeps positions finite.
MAX_DT_S: Final = 1.0

_NO_OBSTACLES: Final = Obstacles()
# The kernels' robot argument when there is no robot (never read then, never written).
_NO_ROBOT: Final = np.zeros(3)


@attrs.frozen(kw_only=True)
class RobotBody:
    """What the pedestrians perceive of the robot: a disc at ``(x, y)`` of ``radius`` (m)."""

    x: float
    y: float
    radius: float = 0.2

    def as_array(self) -> NDArray[np.float64]:
        """(3,) = (x, y, radius), the kernels' layout."""
        return np.array([self.x, self.y, self.radius], dtype=np.float64)


@attrs.frozen(kw_only=True, eq=False)
class ForceComponents:
    """The SRFM force components on each pedestrian, (N, 2) each, in m/s² (unit mass)."""

    goal: NDArray[np.float64]
    pedestrians: NDArray[np.float64]
    robot: NDArray[np.float64]
    obstacles: NDArray[np.float64]

    @property
    def total(self) -> NDArray[np.float64]:
        """Sum of the four components, in the order the step kernel adds them."""
        return self.goal + self.pedestrians + self.robot + self.obstacles


def _robot_args(robot: RobotBody | None) -> tuple[NDArray[np.float64], bool]:
    if robot is None:
        return _NO_ROBOT, False
    arr = robot.as_array()
    if not np.all(np.isfinite(arr)) or arr[2] < 0.0:
        raise SimulationError(f"robot body must be finite with radius >= 0, got {robot!r}")
    return arr, True


def force_components(
    crowd: CrowdState,
    params: SRFMParams | None = None,
    robot: RobotBody | None = None,
    obstacles: Obstacles | None = None,
) -> ForceComponents:
    """Compute each SRFM force component for the current crowd state.

    Args:
        crowd: the pedestrians.
        params: model parameters; the ``agrawal2024`` preset when omitted.
        robot: the robot as the pedestrians perceive it; None for no robot.
        obstacles: walls and pillars; none when omitted.

    Returns:
        The goal, pedestrian, robot and obstacle components, each (N, 2) in m/s².
    """
    params = params or SRFMParams()
    obstacles = obstacles or _NO_OBSTACLES
    robot_arr, robot_on = _robot_args(robot)
    out = np.zeros((4, crowd.n, 2))
    _kernels.force_components_kernel(
        crowd.pos,
        crowd.vel,
        crowd.goal,
        crowd.radius,
        crowd.v0,
        params.for_kernels(),
        robot_arr,
        robot_on,
        obstacles.segments,
        obstacles.circles,
        out,
    )
    return ForceComponents(goal=out[0], pedestrians=out[1], robot=out[2], obstacles=out[3])


def step_crowd(
    crowd: CrowdState,
    dt: float,
    params: SRFMParams | None = None,
    robot: RobotBody | None = None,
    obstacles: Obstacles | None = None,
    *,
    parallel: bool | None = None,
) -> None:
    """Advance ``crowd`` in place by one step of ``dt`` seconds.

    All forces are computed from one snapshot, then every pedestrian is moved with
    semi-implicit Euler (v ← v + F dt, |v| ≤ vmax, x ← x + v dt); the result does not
    depend on the order of the pedestrians.

    Args:
        dt: step (s), in (0, 1].
        parallel: use the threaded kernel; by default for crowds of at least
            ``PARALLEL_MIN_AGENTS`` pedestrians. Both kernels give identical results.
    """
    if not 0.0 < dt <= MAX_DT_S:  # also false for NaN
        raise SimulationError(f"dt must be in (0, {MAX_DT_S:g}] s, got {dt!r}")
    params = params or SRFMParams()
    obstacles = obstacles or _NO_OBSTACLES
    robot_arr, robot_on = _robot_args(robot)
    use_parallel = crowd.n >= PARALLEL_MIN_AGENTS if parallel is None else parallel
    kernel = _kernels.step_parallel if use_parallel else _kernels.step_serial
    kernel(
        crowd.pos,
        crowd.vel,
        crowd.goal,
        crowd.radius,
        crowd.v0,
        crowd.vmax,
        params.for_kernels(),
        robot_arr,
        robot_on,
        obstacles.segments,
        obstacles.circles,
        float(dt),
        np.empty_like(crowd.pos),
    )
