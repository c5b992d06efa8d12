"""Geometry shared by the classical planners' numba kernels, and their common parameters.

Plain module-level functions over floats and C-contiguous float64 arrays, as in
:mod:`srfm.models._kernels`: no objects, no allocation, no I/O, no raising, no random
draws, ``cache=True``, no ``fastmath`` (zero distances use the explicit epsilon
:data:`~srfm.models._primitives.EPS`). The closest point of a wall comes from
:mod:`srfm.models._primitives`, the same function the crowd's forces use.

Shapes and frames (world frame, SI units), shared by every planner kernel module
(:mod:`~srfm.planners._dwa_kernels`, :mod:`~srfm.planners._vo_kernels`,
:mod:`~srfm.planners._orca_kernels`, :mod:`~srfm.planners._social_force_kernels`):

- ``ped_pos``, ``ped_vel`` (k, 2) and ``ped_radius`` (k,): the observed pedestrians;
- ``goal`` (2,): the robot's goal;
- ``segments`` (M, 4) = (x1, y1, x2, y2): walls; ``circles`` (K, 3) = (cx, cy,
  radius): pillars. The world's edges, which the planners keep away from like walls
  by default, are the rectangle of :class:`CommonParams`: the robot is always inside
  it, so the distance to the edges is a minimum of four differences;
- ``near`` (M,) float64 scratch: per-call flags of the walls close enough to matter;
- ``common``: :class:`CommonParams`, the robot and world part of the parameters;
  ``params``: the planner's own NamedTuple. The planner classes build both at reset.

Parameters from Python: the kernels a planner calls each step (``*_command``,
``dwa_*``, :func:`~srfm.planners._dwa_kernels.dynamic_window`) also accept ``common``
and ``params`` as plain tuples of the same fields and rebuild the NamedTuples (a free
copy in compiled code). The planners pass plain tuples: numba's dispatcher types a
NamedTuple argument by encoding the name of every field, 0.15–0.25 µs a field with
numba 0.68 (5–7 µs a step for DWA's 26 fields, more than a whole VO or social-force
step), a plain tuple in about 25 ns a field. Inside the kernels the NamedTuples are
passed by value and cost nothing.

Velocity planners (VO, ORCA, social force) choose a world-frame velocity u and turn it
into the robot's command with :func:`velocity_to_command`: (ux, uy) itself for a
holonomic robot; for a unicycle, heading control ω = clip(k_θ · e, ±ω_max) and
v = |u| · max(cos e, 0), with e the angle from the heading to u.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from srfm.models._primitives import EPS, closest_on_segment

__all__ = [
    "EPS",
    "INF",
    "CommonParams",
    "edge_gap",
    "edge_normal",
    "mark_near_segments",
    "obstacle_offset",
    "time_to_collision",
    "time_to_edges",
    "time_to_segment",
    "velocity_to_command",
    "wrap_angle",
]

INF = math.inf


class CommonParams(NamedTuple):
    """The robot and world part of every classical planner's kernel parameters.

    Attributes:
        radius_m: r_R, the robot's radius (m).
        max_speed_mps: v_max, top speed (m/s).
        max_angular_speed_radps: ω_max, top turn rate (rad/s).
        heading_gain_per_s: k_θ of the unicycle heading control (1/s).
        unicycle: True for a unicycle robot, False for a holonomic one.
        margin_m: safety margin added to every clearance (m).
        dt_s: simulation step (s).
        goal_radius_m: the goal counts as reached within this distance (m).
        avoid_edges: keep away from the world's edges like from walls.
        x_min: the world rectangle's lowest x (m); the four bounds are 0 when
            ``avoid_edges`` is False.
        x_max: its highest x (m).
        y_min: its lowest y (m).
        y_max: its highest y (m).
    """

    radius_m: float
    max_speed_mps: float
    max_angular_speed_radps: float
    heading_gain_per_s: float
    unicycle: bool
    margin_m: float
    dt_s: float
    goal_radius_m: float
    avoid_edges: bool
    x_min: float
    x_max: float
    y_min: float
    y_max: float


@njit(cache=True, inline="always")
def wrap_angle(angle: float) -> float:
    """The angle (rad) in [−π, π]."""
    return math.atan2(math.sin(angle), math.cos(angle))


@njit(cache=True, inline="always")
def edge_gap(x: float, y: float, common: CommonParams) -> float:
    """Distance (m) from (x, y), inside the world, to its nearest edge; inf when the
    planner ignores the edges."""
    if not common.avoid_edges:
        return INF
    gap: float = min(x - common.x_min, common.x_max - x, y - common.y_min, common.y_max - y)
    return gap


@njit(cache=True, inline="always")
def edge_normal(x: float, y: float, k: int, common: CommonParams) -> tuple[float, float, float]:
    """Edge k of the world (0: x_min, 1: x_max, 2: y_min, 3: y_max) seen from (x, y).

    Returns:
        (gap, nx, ny): the distance (m) from (x, y) to the edge and the edge's unit
        normal pointing into the world.
    """
    if k == 0:
        return x - common.x_min, 1.0, 0.0
    if k == 1:
        return common.x_max - x, -1.0, 0.0
    if k == 2:
        return y - common.y_min, 0.0, 1.0
    return common.y_max - y, 0.0, -1.0


@njit(cache=True, inline="always")
def obstacle_offset(
    x: float, y: float, segments: np.ndarray, circles: np.ndarray, k: int
) -> tuple[float, float, float, float]:
    """Static obstacle k (the walls first, then the pillars) seen from (x, y).

    Returns:
        (dx, dy, d, extra): the offset (m) from the obstacle's closest point (a wall's
        closest point, a pillar's centre) to (x, y), its length d (m), and the distance
        from that point to the obstacle's surface (the pillar's radius, 0 for a wall).
    """
    n_seg = segments.shape[0]
    if k < n_seg:
        cx, cy = closest_on_segment(
            x, y, segments[k, 0], segments[k, 1], segments[k, 2], segments[k, 3]
        )
        extra = 0.0
    else:
        m = k - n_seg
        cx = circles[m, 0]
        cy = circles[m, 1]
        extra = circles[m, 2]
    dx = x - cx
    dy = y - cy
    return dx, dy, math.sqrt(dx * dx + dy * dy), extra


@njit(cache=True)
def time_to_edges(
    x: float, y: float, ux: float, uy: float, r: float, x0: float, x1: float, y0: float, y1: float
) -> float:
    """First time t >= 0 at which a disc of radius ``r`` at (x, y) + u t, inside the
    rectangle [x0, x1] × [y0, y1], touches one of its edges (0 when already within
    ``r`` of an edge and moving toward it, inf when never)."""
    best = INF
    if ux < 0.0:
        best = min(best, max(x - x0 - r, 0.0) / -ux)
    elif ux > 0.0:
        best = min(best, max(x1 - x - r, 0.0) / ux)
    if uy < 0.0:
        best = min(best, max(y - y0 - r, 0.0) / -uy)
    elif uy > 0.0:
        best = min(best, max(y1 - y - r, 0.0) / uy)
    return best


@njit(cache=True)
def velocity_to_command(
    ux: float, uy: float, theta: float, common: CommonParams
) -> tuple[float, float]:
    """The robot command that realises the world-frame velocity (ux, uy) (m/s).

    Holonomic: (ux, uy). Unicycle: (v, ω) with ω = clip(k_θ e, ±ω_max) and
    v = min(|u|, v_max) max(cos e, 0), e = wrap(atan2(uy, ux) − θ); (0, 0) for |u| = 0.
    """
    if not common.unicycle:
        return ux, uy
    speed = math.sqrt(ux * ux + uy * uy)
    if speed < EPS:
        return 0.0, 0.0
    err = wrap_angle(math.atan2(uy, ux) - theta)
    wmax = common.max_angular_speed_radps
    w = min(wmax, max(-wmax, common.heading_gain_per_s * err))
    c = math.cos(err)
    v = min(speed, common.max_speed_mps) * c if c > 0.0 else 0.0
    return v, w


@njit(cache=True)
def time_to_collision(px: float, py: float, wx: float, wy: float, r: float) -> float:
    """First time t >= 0 at which |p − w t| <= r.

    Args:
        px: x of the obstacle's centre relative to the robot (m).
        py: y of the same (m).
        wx: x of the robot's velocity relative to the obstacle (m/s).
        wy: y of the same (m/s).
        r: combined radius (m).

    Returns:
        The time (s); 0 when already within ``r`` and closing in (p · w > 0); inf when
        the relative motion never brings the centres within ``r``. The velocity w lies
        in the velocity obstacle with time horizon T exactly when the result is <= T.
    """
    c = px * px + py * py - r * r
    b = px * wx + py * wy
    if c <= 0.0:
        return 0.0 if b > 0.0 else INF
    if b <= 0.0:
        return INF
    a = wx * wx + wy * wy
    disc = b * b - a * c
    if disc < 0.0:
        return INF
    return c / (b + math.sqrt(disc))  # = (b − √disc) / a, stable for small a


@njit(cache=True)
def time_to_segment(
    x: float,
    y: float,
    wx: float,
    wy: float,
    x1: float,
    y1: float,
    x2: float,
    y2: float,
    r: float,
) -> float:
    """First time t >= 0 at which a disc of radius ``r`` at (x, y) + w t touches a
    static segment: the time to collision with the capsule around the segment.

    Returns 0 when already within ``r`` and closing in, inf when never.
    """
    cx, cy = closest_on_segment(x, y, x1, y1, x2, y2)
    dx = x - cx
    dy = y - cy
    if dx * dx + dy * dy <= r * r:
        return 0.0 if dx * wx + dy * wy < 0.0 else INF
    best = min(
        time_to_collision(x1 - x, y1 - y, wx, wy, r),
        time_to_collision(x2 - x, y2 - y, wx, wy, r),
    )
    sx = x2 - x1
    sy = y2 - y1
    length = math.sqrt(sx * sx + sy * sy)
    if length > EPS:
        nx = -sy / length
        ny = sx / length
        s0 = (x - x1) * nx + (y - y1) * ny  # signed distance to the line
        sv = wx * nx + wy * ny
        th = INF
        if s0 > 0.0 and sv < 0.0:
            th = (s0 - r) / -sv
        elif s0 < 0.0 and sv > 0.0:
            th = (-s0 - r) / sv
        if 0.0 <= th < best:
            hx = x + wx * th - x1
            hy = y + wy * th - y1
            u = (hx * sx + hy * sy) / (length * length)
            if 0.0 <= u <= 1.0:
                best = th
    return best


@njit(cache=True)
def mark_near_segments(
    segments: np.ndarray, x: float, y: float, reach: float, near: np.ndarray
) -> int:
    """Set ``near[k]`` to 1.0 for the walls closer than ``reach`` (m) to (x, y), else
    0.0; return how many are near."""
    count = 0
    for k in range(segments.shape[0]):
        cx, cy = closest_on_segment(
            x, y, segments[k, 0], segments[k, 1], segments[k, 2], segments[k, 3]
        )
        d = math.sqrt((x - cx) * (x - cx) + (y - cy) * (y - cy))
        near[k] = 1.0 if d < reach else 0.0
        if d < reach:
            count += 1
    return count
