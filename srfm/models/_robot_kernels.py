"""numba kernels of the robot: the motion update and the events that end its episode.

The one implementation of the robot: :func:`srfm.apply_command` wraps
:func:`move_robot`, and the episode's step kernels (:mod:`srfm.sim._kernels`, which
the simulator and the environment ``srfm/SocialNav-v0`` both run) call
:func:`move_robot` and :func:`robot_event` once per step.

Layouts and parameters:

- ``robot`` (7,) float64: x, y (m), theta (rad, in (−π, π]), vx, vy (m/s, world frame),
  v (m/s), omega (rad/s), the fields of :class:`srfm.RobotState` in order (rows
  ``X`` … ``OMEGA``);
- :class:`RobotLimits`: the robot's body and limits (:meth:`srfm.RobotConfig.for_kernels`);
- :class:`RobotTask`: the robot's goal, the world rectangle and the horizon;
- ``crowd``: the factual pedestrians (:class:`~srfm.models._arrays.CrowdArrays`);
  ``obstacles``: walls and pillars (:class:`~srfm.models._arrays.ObstacleArrays`).
"""

from __future__ import annotations

import math
from typing import Any, Final, NamedTuple

import numpy as np
from numba import njit

from srfm.models._arrays import CrowdArrays, ObstacleArrays
from srfm.models._kernels import nearest_clearance, segment_distance

__all__ = [
    "EVENT_COLLISION",
    "EVENT_GOAL",
    "EVENT_NONE",
    "EVENT_OBSTACLE",
    "EVENT_OUT_OF_BOUNDS",
    "EVENT_TIMEOUT",
    "ROBOT_SIZE",
    "RobotLimits",
    "RobotTask",
    "move_robot",
    "robot_event",
    "robot_task",
    "wrap_angle",
]

# Rows of the robot state array (the fields of srfm.RobotState, in order).
X, Y, THETA, VX, VY, V, OMEGA = range(7)
ROBOT_SIZE: Final = 7

# Robot events at a sample, in the order they are checked; EVENT_NONE: the episode goes on.
EVENT_NONE: Final = 0
EVENT_COLLISION: Final = 1  # with a pedestrian
EVENT_OBSTACLE: Final = 2  # overlap with a wall or a pillar
EVENT_OUT_OF_BOUNDS: Final = 3
EVENT_GOAL: Final = 4
EVENT_TIMEOUT: Final = 5

_PI = math.pi
_TWO_PI = 2.0 * math.pi


class RobotLimits(NamedTuple):
    """The robot's body and limits as the kernels take them (see :class:`srfm.RobotConfig`).

    Built once per simulator or environment by :meth:`srfm.RobotConfig.for_kernels`.

    Attributes:
        holonomic: True for a holonomic robot (command (vx, vy)), False for a unicycle
            (command (v, ω)).
        radius_m: body radius (m).
        max_speed_mps: v_max (m/s).
        max_angular_speed_radps: ω_max (rad/s), unicycle only.
        max_accel_mps2: largest change of linear velocity per second (m/s²).
        max_angular_accel_radps2: largest change of ω per second (rad/s²).
        goal_radius_m: the goal counts as reached closer than this (m).
    """

    holonomic: bool
    radius_m: float
    max_speed_mps: float
    max_angular_speed_radps: float
    max_accel_mps2: float
    max_angular_accel_radps2: float
    goal_radius_m: float


class RobotTask(NamedTuple):
    """What ends the robot's episode besides a collision: its goal, the world, the horizon.

    Attributes:
        goal_x, goal_y: the robot's goal (m).
        x_min, x_max, y_min, y_max: the world rectangle (m), edges inside.
        horizon_steps: the last sample of the episode (a timeout there).
    """

    goal_x: float
    goal_y: float
    x_min: float
    x_max: float
    y_min: float
    y_max: float
    horizon_steps: int


def robot_task(goal: Any, world: Any, horizon_steps: int) -> RobotTask:
    """The :class:`RobotTask` of an episode.

    Args:
        goal: (2,) the robot's goal (m).
        world: the world rectangle (a :class:`srfm.scenarios.WorldBounds`: anything with
            ``x_min``, ``x_max``, ``y_min``, ``y_max`` in m).
        horizon_steps: the episode's horizon (steps).
    """
    return RobotTask(
        goal_x=float(goal[0]),
        goal_y=float(goal[1]),
        x_min=float(world.x_min),
        x_max=float(world.x_max),
        y_min=float(world.y_min),
        y_max=float(world.y_max),
        horizon_steps=int(horizon_steps),
    )


@njit(cache=True)
def wrap_angle(angle: float) -> float:
    """The angle in (−π, π] (rad): angle − 2πn for the integer n that puts it there.

    Exact: ``np.fmod`` is exact and so is the one subtraction or addition of 2π
    (Sterbenz's lemma), so the result equals ``math.remainder(angle, 2π)`` with −π
    mapped to π. Finite input only.
    """
    if -_PI < angle <= _PI:
        return angle
    r: float = np.fmod(angle, _TWO_PI)
    if r > _PI:
        return r - _TWO_PI
    if r <= -_PI:
        return r + _TWO_PI
    return r


@njit(cache=True, inline="always")
def _clip(value: float, lo: float, hi: float) -> float:
    return lo if value < lo else hi if value > hi else value


@njit(cache=True)
def move_robot(robot: np.ndarray, c0: float, c1: float, limits: RobotLimits, dt: float) -> None:
    """Move the robot one step of ``dt`` seconds under the command, within its limits.

    In place on ``robot`` (7,). Unicycle, command (v, ω): v is clipped to
    [−v_max, v_max] and then to within max_accel · dt of the previous v, ω likewise
    with ω_max and max_angular_accel; the heading turns by ω dt and the robot moves
    v dt along the mid-step heading θ + ω dt / 2. Holonomic, command (vx, vy) in the
    world frame: the speed is capped at v_max, then the change of the velocity vector
    at max_accel · dt; the heading follows the direction of motion (kept when the
    speed is below 1e-9 m/s) and omega is its change per second.

    Args:
        robot: (7,) the robot state, overwritten with the state after the step.
        c0, c1: the command, finite.
        limits: the robot's limits.
        dt: step (s).
    """
    dv_max = limits.max_accel_mps2 * dt
    theta = robot[THETA]
    if not limits.holonomic:
        vmax = limits.max_speed_mps
        wmax = limits.max_angular_speed_radps
        dw_max = limits.max_angular_accel_radps2 * dt
        v = _clip(_clip(c0, -vmax, vmax), robot[V] - dv_max, robot[V] + dv_max)
        w = _clip(_clip(c1, -wmax, wmax), robot[OMEGA] - dw_max, robot[OMEGA] + dw_max)
        mid = theta + 0.5 * w * dt
        vx = v * math.cos(mid)
        vy = v * math.sin(mid)
        robot[X] = robot[X] + vx * dt
        robot[Y] = robot[Y] + vy * dt
        robot[THETA] = wrap_angle(theta + w * dt)
        robot[VX] = vx
        robot[VY] = vy
        robot[V] = v
        robot[OMEGA] = w
        return
    vmax = limits.max_speed_mps
    speed = math.hypot(c0, c1)
    if speed > vmax:
        c0 *= vmax / speed
        c1 *= vmax / speed
    ddx = c0 - robot[VX]
    ddy = c1 - robot[VY]
    dnorm = math.hypot(ddx, ddy)
    if dnorm > dv_max:
        ddx *= dv_max / dnorm
        ddy *= dv_max / dnorm
    vx = robot[VX] + ddx
    vy = robot[VY] + ddy
    speed = math.hypot(vx, vy)
    new_theta = math.atan2(vy, vx) if speed > 1e-9 else theta
    robot[X] = robot[X] + vx * dt
    robot[Y] = robot[Y] + vy * dt
    robot[THETA] = new_theta
    robot[VX] = vx
    robot[VY] = vy
    robot[V] = speed
    robot[OMEGA] = wrap_angle(new_theta - theta) / dt


# Compiled apart, not inline="always": see the comment above step_exact in
# srfm/models/_kernels.py.
@njit(cache=True)
def robot_event(
    robot: np.ndarray,
    crowd: CrowdArrays,
    obstacles: ObstacleArrays,
    limits: RobotLimits,
    task: RobotTask,
    step_index: int,
) -> tuple[int, int]:
    """The event that ends the robot's episode at sample ``step_index``, if any.

    Checked in this order, the first that holds wins:

    1. ``EVENT_COLLISION``: a pedestrian centre closer than the sum of radii;
    2. ``EVENT_OBSTACLE``: the robot's disc overlaps a pillar or a wall;
    3. ``EVENT_OUT_OF_BOUNDS``: the centre is outside the world rectangle;
    4. ``EVENT_GOAL``: the centre is closer than ``limits.goal_radius_m`` to the goal;
    5. ``EVENT_TIMEOUT``: ``step_index`` is the horizon;

    else ``EVENT_NONE``.

    Returns:
        (event, pedestrian): the event code, and for ``EVENT_COLLISION`` the index of
        the pedestrian with the smallest clearance (−1 otherwise).
    """
    x = robot[X]
    y = robot[Y]
    rr = limits.radius_m
    clearance, nearest = nearest_clearance(crowd.pos, crowd.radius, x, y)
    if clearance < rr:
        return EVENT_COLLISION, nearest
    pillar_clearance, _ = nearest_clearance(obstacles.pillar_xy, obstacles.pillar_r, x, y)
    if pillar_clearance < rr or segment_distance(obstacles.segments, x, y) < rr:
        return EVENT_OBSTACLE, -1
    if not (task.x_min <= x <= task.x_max and task.y_min <= y <= task.y_max):
        return EVENT_OUT_OF_BOUNDS, -1
    if math.hypot(x - task.goal_x, y - task.goal_y) < limits.goal_radius_m:
        return EVENT_GOAL, -1
    if step_index >= task.horizon_steps:
        return EVENT_TIMEOUT, -1
    return EVENT_NONE, -1
