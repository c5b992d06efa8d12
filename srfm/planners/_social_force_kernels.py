"""numba kernels of the social-force robot (:mod:`srfm.planners.social_force`), whose
step is one call of :func:`social_force_command` (arrays, frames and parameter tuples
as in :mod:`srfm.planners._geometry`). The force terms are the SRFM crowd's own
primitives (:mod:`srfm.models._primitives`): the desired velocity, the pedestrian push
:func:`~srfm.models._primitives.disc_repulsion` (the same function the crowd step calls
for a pedestrian on a pedestrian) and the capped exponential of a wall's repulsion.
"""

from __future__ import annotations

import math
from typing import Any, NamedTuple

import numpy as np
from numba import njit

from srfm.models._primitives import TRUE, capped_exp, desired_velocity, disc_repulsion
from srfm.planners._geometry import (
    EPS,
    CommonParams,
    edge_normal,
    obstacle_offset,
    velocity_to_command,
)

__all__ = ["SocialForceParams", "social_force_command", "social_force_velocity"]


class SocialForceParams(NamedTuple):
    """The social-force robot's own kernel parameters.

    Attributes:
        desired_speed_mps: speed toward the goal (m/s).
        tau_s: τ, relaxation time of the goal term (s).
        ped_strength_mps2: A, strength of the pedestrian repulsion (m/s²).
        ped_range_m: B, range of the pedestrian repulsion (m).
        anisotropy: λ in [0, 1], the weight of pedestrians behind the robot.
        obstacle_strength_mps2: A_o, strength of the wall, pillar and edge repulsion (m/s²).
        obstacle_range_m: B_o, range of the wall, pillar and edge repulsion (m).
    """

    desired_speed_mps: float
    tau_s: float
    ped_strength_mps2: float
    ped_range_m: float
    anisotropy: float
    obstacle_strength_mps2: float
    obstacle_range_m: float


@njit(cache=True)
def social_force_velocity(
    x: float,
    y: float,
    theta: float,
    vx: float,
    vy: float,
    gx: float,
    gy: float,
    ped_pos: np.ndarray,
    ped_vel: np.ndarray,
    ped_radius: np.ndarray,
    segments: np.ndarray,
    circles: np.ndarray,
    common: CommonParams,
    params: SocialForceParams,
) -> tuple[float, float]:
    """The robot's next velocity under a social force model (semi-implicit Euler).

    F = (v_des − v)/τ + Σ_j A exp((r + r_j − d_j)/B) ψ(φ_j; λ) n_j
        + Σ_o A_o exp((r − d_o)/B_o) n_o,
    v_des = (g − x) capped at the desired speed, o over the walls, pillars and (when
    ``common.avoid_edges``) the world's edges, n the unit vector from the pedestrian
    (closest obstacle point) to the robot, ψ = λ + (1 − λ)(1 + cos φ)/2 with φ the
    angle between the robot's heading θ and the direction to the pedestrian. Returns
    v + F dt capped at v_max.
    """
    radius = common.radius_m
    dx, dy = desired_velocity(x, y, gx, gy, params.desired_speed_mps)
    tau = params.tau_s
    fx = (dx - vx) / tau
    fy = (dy - vy) / tau
    a = params.ped_strength_mps2
    b = params.ped_range_m
    lam = params.anisotropy
    hx = math.cos(theta)
    hy = math.sin(theta)
    for j in range(ped_pos.shape[0]):
        # A pedestrian closer than EPS pushes (0.0, 0.0) instead of being skipped: that
        # can only turn a −0.0 sum into +0.0, and a sum is −0.0 only while it is the
        # goal term with vx = +0.0 (−0.0 − +0.0), where ux = vx + fx·dt is +0.0 either way.
        px, py = disc_repulsion(
            x, y, ped_pos[j, 0], ped_pos[j, 1], radius + ped_radius[j], a, b, hx, hy, TRUE, lam
        )
        fx += px
        fy += py
    a_o = params.obstacle_strength_mps2
    b_o = params.obstacle_range_m
    for k in range(segments.shape[0] + circles.shape[0]):
        ex, ey, d, extra = obstacle_offset(x, y, segments, circles, k)
        if d < EPS:
            continue
        mag = a_o * capped_exp((radius + extra - d) / b_o)
        fx += mag * ex / d
        fy += mag * ey / d
    if common.avoid_edges:
        for k in range(4):
            gap, nx, ny = edge_normal(x, y, k, common)
            mag = a_o * capped_exp((radius - gap) / b_o)
            fx += mag * nx
            fy += mag * ny
    dt = common.dt_s
    ux = vx + fx * dt
    uy = vy + fy * dt
    speed = math.sqrt(ux * ux + uy * uy)
    vmax = common.max_speed_mps
    if speed > vmax:
        ux *= vmax / speed
        uy *= vmax / speed
    return ux, uy


@njit(cache=True)
def social_force_command(
    x: float,
    y: float,
    theta: float,
    vx: float,
    vy: float,
    goal: np.ndarray,
    ped_pos: np.ndarray,
    ped_vel: np.ndarray,
    ped_radius: np.ndarray,
    segments: np.ndarray,
    circles: np.ndarray,
    common: CommonParams | tuple[Any, ...],
    params: SocialForceParams | tuple[Any, ...],
) -> tuple[float, float]:
    """:func:`social_force_velocity` toward ``goal`` (2,) as a command
    (:func:`~srfm.planners._geometry.velocity_to_command`); ``common`` and ``params``
    may be plain tuples of their fields."""
    c = CommonParams(*common)
    p = SocialForceParams(*params)
    ux, uy = social_force_velocity(
        x, y, theta, vx, vy, goal[0], goal[1], ped_pos, ped_vel, ped_radius, segments,
        circles, c, p,
    )  # fmt: skip
    return velocity_to_command(ux, uy, theta, c)
