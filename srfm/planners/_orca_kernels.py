"""numba kernels of ORCA (:mod:`srfm.planners.orca`): its half-planes, the incremental
linear programs over them, and :func:`orca_command`, the planner's step (one call).
The arrays, frames and parameter tuples are those of :mod:`srfm.planners._geometry`.
"""

from __future__ import annotations

import math
from typing import Any, NamedTuple

import numpy as np
from numba import njit

from srfm.models._primitives import FALSE, TRUE, ZERO
from srfm.planners._geometry import (
    EPS,
    CommonParams,
    edge_normal,
    obstacle_offset,
    velocity_to_command,
)

__all__ = [
    "ORCAParams",
    "orca_command",
    "orca_halfplane",
    "orca_lp2",
    "orca_lp3",
    "orca_velocity",
]


class ORCAParams(NamedTuple):
    """The ORCA planner's own kernel parameters.

    Attributes:
        tau_s: τ, the time horizon for pedestrians (s).
        tau_obstacle_s: τ_obs, the time horizon for walls, pillars and edges (s).
        responsibility: the robot's share of each avoidance, in (0, 1].
    """

    tau_s: float
    tau_obstacle_s: float
    responsibility: float


# A half-plane is a row (px, py, nx, ny) of a (n, 4) array: the velocities v with
# (v − p) · n >= 0 are allowed, n is a unit normal pointing into the allowed side.


@njit(cache=True)
def orca_halfplane(
    px: float,
    py: float,
    vx: float,
    vy: float,
    ovx: float,
    ovy: float,
    r: float,
    tau: float,
    dt: float,
    responsibility: float,
) -> tuple[float, float, float, float]:
    """The ORCA half-plane that agent A (the robot) gets from agent B.

    van den Berg, Guy, Lin, Manocha 2011, §4: with the relative position p = x_B − x_A,
    the relative velocity v_rel = v_A − v_B and the truncated velocity obstacle
    VO^τ = {v | ∃ t ∈ [0, τ]: |v t − p| < r}, u is the vector from v_rel to the closest
    point of VO^τ's boundary and n the boundary's outward normal there;
    ORCA = {v | (v − (v_A + responsibility · u)) · n >= 0}. When the discs already
    overlap, the cut-off disc of time dt (one step) replaces the τ one, so that the
    robot moves apart within the step.

    Args:
        px, py: B's centre relative to A (m).
        vx, vy: A's current velocity (m/s).
        ovx, ovy: B's velocity (m/s).
        r: combined radius (m).
        tau: time horizon (s).
        dt: step (s), for the overlapping case.
        responsibility: A's share of the avoidance (0.5 reciprocal, 1 all of it).

    Returns:
        (point x, point y, normal x, normal y) of the half-plane.
    """
    rvx = vx - ovx
    rvy = vy - ovy
    dist2 = px * px + py * py
    r2 = r * r
    if dist2 > r2:
        # w: from the centre of the cut-off disc (p / τ, radius r / τ) to v_rel.
        wx = rvx - px / tau
        wy = rvy - py / tau
        wlen2 = wx * wx + wy * wy
        dot = wx * px + wy * py
        if dot < 0.0 and dot * dot > r2 * wlen2:
            # Closest boundary point on the cut-off circle.
            wlen = math.sqrt(wlen2)
            if wlen < EPS:  # v_rel at the disc centre: push straight back toward A
                nx = -px / math.sqrt(dist2)
                ny = -py / math.sqrt(dist2)
            else:
                nx = wx / wlen
                ny = wy / wlen
            mag = r / tau - wlen
            ux = mag * nx
            uy = mag * ny
        else:
            # Closest boundary point on a leg: the tangent from the origin.
            leg = math.sqrt(dist2 - r2)
            if px * wy - py * wx > 0.0:  # left leg (counter-clockwise of p)
                dx = (px * leg - py * r) / dist2
                dy = (px * r + py * leg) / dist2
                nx = -dy
                ny = dx
            else:  # right leg
                dx = (px * leg + py * r) / dist2
                dy = (-px * r + py * leg) / dist2
                nx = dy
                ny = -dx
            proj = rvx * dx + rvy * dy
            ux = proj * dx - rvx
            uy = proj * dy - rvy
            # n is the leg's outward normal; u is parallel to it (inside) or opposite.
    else:
        # Overlapping: leave the disc of time dt around p / dt.
        wx = rvx - px / dt
        wy = rvy - py / dt
        wlen = math.sqrt(wx * wx + wy * wy)
        if wlen < EPS:
            dist = math.sqrt(dist2)
            if dist < EPS:
                nx = 1.0
                ny = 0.0
            else:
                nx = -px / dist
                ny = -py / dist
        else:
            nx = wx / wlen
            ny = wy / wlen
        mag = r / dt - wlen
        ux = mag * nx
        uy = mag * ny
    return vx + responsibility * ux, vy + responsibility * uy, nx, ny


@njit(cache=True)
def _lp1(
    lines: np.ndarray,
    i: int,
    vmax: float,
    ox: float,
    oy: float,
    direction: bool,
) -> tuple[bool, float, float]:
    """Optimise on the boundary line of half-plane i, subject to |v| <= vmax and the
    half-planes 0..i−1: the point closest to (ox, oy), or the farthest along the unit
    direction (ox, oy) when ``direction``. Returns (feasible, x, y)."""
    p_x = lines[i, 0]
    p_y = lines[i, 1]
    d_x = lines[i, 3]  # direction along the line: the normal turned clockwise
    d_y = -lines[i, 2]
    pd = p_x * d_x + p_y * d_y
    disc = pd * pd - (p_x * p_x + p_y * p_y) + vmax * vmax
    if disc < 0.0:
        return False, 0.0, 0.0
    sq = math.sqrt(disc)
    t_lo = -pd - sq
    t_hi = -pd + sq
    for j in range(i):
        njx = lines[j, 2]
        njy = lines[j, 3]
        denom = d_x * njx + d_y * njy
        rhs = (lines[j, 0] - p_x) * njx + (lines[j, 1] - p_y) * njy
        if abs(denom) < EPS:
            if rhs > EPS:  # parallel and entirely outside half-plane j
                return False, 0.0, 0.0
            continue
        t = rhs / denom
        if denom > 0.0:
            t_lo = max(t_lo, t)
        else:
            t_hi = min(t_hi, t)
        if t_lo > t_hi:
            return False, 0.0, 0.0
    if direction:
        t = t_hi if ox * d_x + oy * d_y > 0.0 else t_lo
    else:
        t = min(t_hi, max(t_lo, (ox - p_x) * d_x + (oy - p_y) * d_y))
    return True, p_x + t * d_x, p_y + t * d_y


@njit(cache=True)
def orca_lp2(
    lines: np.ndarray, n: int, vmax: float, ox: float, oy: float, direction: bool
) -> tuple[int, float, float]:
    """Incremental 2-D linear program over half-planes 0..n−1 and |v| <= vmax.

    Objective: the point closest to (ox, oy), or the farthest along the unit vector
    (ox, oy) when ``direction`` (de Berg et al., Computational Geometry, §4.4; the ORCA
    paper's §5.2). Returns (n, x, y) on success, else (index of the first half-plane
    that cannot be met, x, y of the optimum over the earlier ones).
    """
    if direction:
        rx = ox * vmax
        ry = oy * vmax
    else:
        norm = math.sqrt(ox * ox + oy * oy)
        if norm > vmax:
            rx = ox * vmax / norm
            ry = oy * vmax / norm
        else:
            rx = ox
            ry = oy
    for i in range(n):
        if (rx - lines[i, 0]) * lines[i, 2] + (ry - lines[i, 1]) * lines[i, 3] < 0.0:
            ok, x_new, y_new = _lp1(lines, i, vmax, ox, oy, direction)
            if not ok:
                return i, rx, ry
            rx = x_new
            ry = y_new
    return n, rx, ry


@njit(cache=True)
def orca_lp3(
    lines: np.ndarray,
    n: int,
    n_hard: int,
    begin: int,
    vmax: float,
    x: float,
    y: float,
    proj: np.ndarray,
) -> tuple[float, float]:
    """When the half-planes have no common point: the velocity that minimises the
    largest violation of the soft half-planes n_hard..n−1 while meeting the hard ones
    0..n_hard−1 (the ORCA paper's §5.2, a 3-D program solved as a sequence of 2-D
    ones). (x, y) is the result of :func:`orca_lp2`, which failed at ``begin``;
    ``proj`` is (n, 4) scratch."""
    dist = 0.0
    for i in range(begin, n):
        nix = lines[i, 2]
        niy = lines[i, 3]
        if -((x - lines[i, 0]) * nix + (y - lines[i, 1]) * niy) <= dist:
            continue
        count = ZERO
        for j in range(n_hard):
            proj[count, 0] = lines[j, 0]
            proj[count, 1] = lines[j, 1]
            proj[count, 2] = lines[j, 2]
            proj[count, 3] = lines[j, 3]
            count += 1
        pi_n = lines[i, 0] * nix + lines[i, 1] * niy
        for j in range(n_hard, i):
            # Where half-plane j is violated no more than i: v·(n_j − n_i) >= p_j·n_j − p_i·n_i.
            mx = lines[j, 2] - nix
            my = lines[j, 3] - niy
            mlen = math.sqrt(mx * mx + my * my)
            if mlen < EPS:  # parallel, same side: i's objective serves j as well
                continue
            rhs = (lines[j, 0] * lines[j, 2] + lines[j, 1] * lines[j, 3] - pi_n) / mlen
            mx /= mlen
            my /= mlen
            proj[count, 0] = mx * rhs
            proj[count, 1] = my * rhs
            proj[count, 2] = mx
            proj[count, 3] = my
            count += 1
        fail, rx, ry = orca_lp2(proj, count, vmax, nix, niy, TRUE)
        if fail == count:  # otherwise keep (x, y): can only fail by rounding
            x = rx
            y = ry
        dist = -((x - lines[i, 0]) * nix + (y - lines[i, 1]) * niy)
    return x, y


@njit(cache=True, inline="always")
def _preferred_velocity(
    x: float, y: float, gx: float, gy: float, vmax: float
) -> tuple[float, float]:
    """v_max toward the goal (zero at the goal)."""
    dx = gx - x
    dy = gy - y
    dist = math.sqrt(dx * dx + dy * dy)
    if dist < EPS:
        return 0.0, 0.0
    return vmax * dx / dist, vmax * dy / dist


@njit(cache=True, inline="always")
def _add_line(lines: np.ndarray, n: int, px: float, py: float, nx: float, ny: float) -> int:
    """Write half-plane (px, py, nx, ny) into row n of ``lines``; return n + 1."""
    lines[n, 0] = px
    lines[n, 1] = py
    lines[n, 2] = nx
    lines[n, 3] = ny
    return n + 1


@njit(cache=True)
def orca_velocity(
    x: float,
    y: float,
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
    params: ORCAParams,
    lines: np.ndarray,
    proj: np.ndarray,
) -> tuple[float, float]:
    """ORCA: the velocity closest to the preferred one within every ORCA half-plane.

    Hard half-planes first, one per wall, pillar or world edge whose surface is within
    ``v_max · τ_obs`` of the robot: n · v >= −(d − r − margin) / τ_obs, with d the
    distance to the closest point and n the unit vector from it to the robot (the
    robot keeps out of reach of the obstacle for τ_obs). Then one soft half-plane per
    pedestrian (:func:`orca_halfplane`). ``lines`` and ``proj`` are scratch with at
    least (pedestrians + walls + pillars + 4) rows.
    """
    vmax = common.max_speed_mps
    radius = common.radius_m
    margin = common.margin_m
    tau = params.tau_s
    tau_obs = params.tau_obstacle_s
    n = ZERO  # not a literal (srfm.models._primitives.ZERO)
    for k in range(segments.shape[0] + circles.shape[0]):
        dx, dy, d, extra = obstacle_offset(x, y, segments, circles, k)
        gap = d - extra - radius - margin
        if gap >= vmax * tau_obs or d < EPS:
            continue
        nx = dx / d
        ny = dy / d
        s = -gap / tau_obs
        n = _add_line(lines, n, nx * s, ny * s, nx, ny)
    if common.avoid_edges:
        for k in range(4):
            gap, nx, ny = edge_normal(x, y, k, common)
            gap -= radius + margin
            if gap >= vmax * tau_obs:
                continue
            s = -gap / tau_obs
            n = _add_line(lines, n, nx * s, ny * s, nx, ny)
    n_hard = n
    for j in range(ped_pos.shape[0]):
        a, b, c, d = orca_halfplane(
            ped_pos[j, 0] - x,
            ped_pos[j, 1] - y,
            vx,
            vy,
            ped_vel[j, 0],
            ped_vel[j, 1],
            radius + ped_radius[j] + margin,
            tau,
            common.dt_s,
            params.responsibility,
        )
        n = _add_line(lines, n, a, b, c, d)
    prefx, prefy = _preferred_velocity(x, y, gx, gy, vmax)
    fail, rx, ry = orca_lp2(lines, n, vmax, prefx, prefy, FALSE)
    if fail < n:
        if fail < n_hard:  # the obstacles alone leave no room: relax everything
            n_hard = ZERO
        rx, ry = orca_lp3(lines, n, n_hard, fail, vmax, rx, ry, proj)
    return rx, ry


@njit(cache=True)
def orca_command(
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
    params: ORCAParams | tuple[Any, ...],
    lines: np.ndarray,
    proj: np.ndarray,
) -> tuple[float, float]:
    """:func:`orca_velocity` toward ``goal`` (2,) as a command
    (:func:`~srfm.planners._geometry.velocity_to_command`); ``common`` and ``params``
    may be plain tuples of their fields."""
    c = CommonParams(*common)
    p = ORCAParams(*params)
    ux, uy = orca_velocity(
        x, y, vx, vy, goal[0], goal[1], ped_pos, ped_vel, ped_radius, segments, circles, c, p,
        lines, proj,
    )  # fmt: skip
    return velocity_to_command(ux, uy, theta, c)
