"""numba kernels of the Velocity Obstacles planner (:mod:`srfm.planners.velocity_obstacles`):
one call of :func:`vo_command` per step. Arrays, frames and parameters as described in
:mod:`srfm.planners._geometry`."""

from __future__ import annotations

import math
from typing import Any, NamedTuple

import numpy as np
from numba import njit

from srfm.planners._geometry import (
    EPS,
    INF,
    CommonParams,
    mark_near_segments,
    time_to_collision,
    time_to_edges,
    time_to_segment,
    velocity_to_command,
)

__all__ = ["VOParams", "vo_command", "vo_velocity"]


class VOParams(NamedTuple):
    """The Velocity Obstacles planner's own kernel parameters.

    Attributes:
        horizon_s: T, only collisions within T seconds count (s); inf for untruncated
            cones.
    """

    horizon_s: float


@njit(cache=True)
def vo_velocity(
    x: float,
    y: float,
    gx: float,
    gy: float,
    ped_pos: np.ndarray,
    ped_vel: np.ndarray,
    ped_radius: np.ndarray,
    segments: np.ndarray,
    circles: np.ndarray,
    common: CommonParams,
    params: VOParams,
    candidates: np.ndarray,
    near: np.ndarray,
) -> tuple[float, float]:
    """Velocity Obstacles: the admissible candidate velocity closest to the preferred one.

    ``candidates`` (n, 2) are velocities in the goal frame (x toward the goal), sorted
    by their distance to the preferred velocity (v_max, 0); the first is that velocity.
    A candidate u is admissible when it lies in no velocity obstacle: its time to
    collision with every pedestrian (at constant velocity), pillar, near wall and world
    edge, all inflated by the robot radius and the margin, exceeds the time horizon.
    The first admissible candidate is taken; when there is none, the one with the
    latest collision (then: the earliest in the order).
    """
    vmax = common.max_speed_mps
    horizon = params.horizon_s
    radius = common.radius_m + common.margin_m
    dx = gx - x
    dy = gy - y
    dist = math.sqrt(dx * dx + dy * dy)
    if dist < EPS:
        return 0.0, 0.0
    cg = dx / dist
    sg = dy / dist
    reach = radius + vmax * horizon if horizon < INF else INF
    mark_near_segments(segments, x, y, reach, near)
    edges = common.avoid_edges
    x0 = common.x_min
    x1 = common.x_max
    y0 = common.y_min
    y1 = common.y_max
    n_peds = ped_pos.shape[0]
    n_seg = segments.shape[0]
    n_circ = circles.shape[0]
    best_t = -1.0
    best_x = 0.0
    best_y = 0.0
    # Pass 0 stops at the first admissible candidate; pass 1 (when there is none)
    # finds the latest collision over all candidates.
    for phase in range(2):
        stop_at = horizon if phase == 0 else -1.0
        for c in range(candidates.shape[0]):
            ux = candidates[c, 0] * cg - candidates[c, 1] * sg
            uy = candidates[c, 0] * sg + candidates[c, 1] * cg
            t_min = INF
            if edges:
                t_min = time_to_edges(x, y, ux, uy, radius, x0, x1, y0, y1)
            for q in range(n_peds):
                if t_min <= stop_at and t_min < INF:  # already inadmissible
                    break
                t = time_to_collision(
                    ped_pos[q, 0] - x, ped_pos[q, 1] - y,
                    ux - ped_vel[q, 0], uy - ped_vel[q, 1], radius + ped_radius[q],
                )  # fmt: skip
                t_min = min(t_min, t)
            for q in range(n_circ):
                if t_min <= stop_at and t_min < INF:  # already inadmissible
                    break
                t = time_to_collision(
                    circles[q, 0] - x, circles[q, 1] - y, ux, uy, radius + circles[q, 2]
                )
                t_min = min(t_min, t)
            for q in range(n_seg):
                if t_min <= stop_at and t_min < INF:  # already inadmissible
                    break
                if near[q] != 0.0:
                    t = time_to_segment(
                        x, y, ux, uy, segments[q, 0], segments[q, 1], segments[q, 2],
                        segments[q, 3], radius,
                    )  # fmt: skip
                    t_min = min(t_min, t)
            if phase == 0:
                if t_min > horizon or t_min == INF:  # no contact within the horizon
                    return ux, uy
            elif t_min > best_t:
                best_t = t_min
                best_x = ux
                best_y = uy
    return best_x, best_y


@njit(cache=True)
def vo_command(
    x: float,
    y: float,
    theta: float,
    goal: np.ndarray,
    ped_pos: np.ndarray,
    ped_vel: np.ndarray,
    ped_radius: np.ndarray,
    segments: np.ndarray,
    circles: np.ndarray,
    common: CommonParams | tuple[Any, ...],
    params: VOParams | tuple[Any, ...],
    candidates: np.ndarray,
    near: np.ndarray,
) -> tuple[float, float]:
    """:func:`vo_velocity` toward ``goal`` (2,) as a command
    (:func:`~srfm.planners._geometry.velocity_to_command`); ``common`` and ``params``
    may be plain tuples of their fields."""
    c = CommonParams(*common)
    p = VOParams(*params)
    ux, uy = vo_velocity(
        x, y, goal[0], goal[1], ped_pos, ped_vel, ped_radius, segments, circles, c, p,
        candidates, near,
    )  # fmt: skip
    return velocity_to_command(ux, uy, theta, c)
