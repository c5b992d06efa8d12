"""The arrays of a crowd, of its obstacles and of what it feels, as the kernels take them.

``typing.NamedTuple`` bundles, so that a kernel takes a crowd, a set of obstacles or
everything a crowd feels besides itself as one argument instead of four to six. numba
compiles a kernel once per tuple type (the dtype, dimensions and contiguity of each
array), and reading a field costs nothing once compiled. This module imports no numba:
the Python API builds the bundles (:meth:`srfm.CrowdState.for_kernels`,
:meth:`srfm.Obstacles.for_kernels`) without loading the kernels.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from srfm.models.params import SRFMKernelParams

__all__ = ["CrowdArrays", "ForceContext", "ObstacleArrays"]


class CrowdArrays(NamedTuple):
    """One crowd, struct of arrays (float64, C-contiguous; N pedestrians).

    Attributes:
        pos: (N, 2) positions (m).
        vel: (N, 2) velocities (m/s).
        goal: (N, 2) goals or current waypoints (m).
        radius: (N,) body radii (m).
        v0: (N,) desired speeds (m/s).
        vmax: (N,) speed caps (m/s).
    """

    pos: np.ndarray
    vel: np.ndarray
    goal: np.ndarray
    radius: np.ndarray
    v0: np.ndarray
    vmax: np.ndarray


class ObstacleArrays(NamedTuple):
    """Walls and pillars (float64, C-contiguous, writable).

    Attributes:
        segments: (M, 4) walls as (x1, y1, x2, y2) (m).
        circles: (K, 3) pillars as (cx, cy, radius) (m).
        pillar_xy: (K, 2) the pillars' centres (m), ``circles[:, :2]`` (the robot's
            collision check takes centres and radii apart).
        pillar_r: (K,) the pillars' radii (m), ``circles[:, 2]``.
    """

    segments: np.ndarray
    circles: np.ndarray
    pillar_xy: np.ndarray
    pillar_r: np.ndarray


class ForceContext(NamedTuple):
    """What a crowd feels besides itself: the model, the robot, walls and pillars.

    Attributes:
        params: SRFM parameters (:meth:`srfm.SRFMParams.for_kernels`).
        robot: (5,) the robot's body as the crowd perceives it: x, y, radius (m) and
            velocity vx, vy (m/s) (the anticipatory forms of the robot force read it).
        robot_on: the crowd feels the robot (False: the counterfactual twin, or no
            robot).
        obstacles: walls and pillars.
        cut: (2,) the pedestrian and the obstacle cut-off (m), ``inf`` for none
            (:func:`srfm.models.forces.kernel_cutoffs`).
    """

    params: SRFMKernelParams
    robot: np.ndarray
    robot_on: bool
    obstacles: ObstacleArrays
    cut: np.ndarray
