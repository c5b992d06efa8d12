"""numba kernels of the Social Robot Force Model.

Plain module-level functions over C-contiguous float64 arrays: no objects, no
allocation inside loops, no I/O, no raising, no random draws. Shapes: ``pos``, ``vel``,
``goal`` (N, 2); ``radius``, ``v0``, ``vmax`` (N,); ``params`` the vector of
:meth:`srfm.SRFMParams.as_array`; ``robot`` (3,) = (x, y, radius); ``segments`` (M, 4)
= (x1, y1, x2, y2); ``circles`` (K, 3) = (cx, cy, radius). All forces are accelerations
(m/s², unit mass).

Exponents are capped at ``EXP_ARG_MAX`` (e^60 ≈ 1e26), far beyond any force that
changes a step (the speed cap clips it), so that extreme but valid inputs (tiny B,
deep overlap with a large pillar) give huge finite forces instead of inf and NaN.

Zero distances use an explicit epsilon: two coincident centres exert no force on each
other (the direction is undefined), an agent at rest with no desired direction has no
heading and is treated isotropically (ψ = 1).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

EPS = 1e-12
EXP_ARG_MAX = 60.0

# Parameter vector layout, see srfm.models.params.
_A_PED, _B_PED, _LAMBDA_PED, _TAU = 0, 1, 2, 3
_A_ROBOT, _B_ROBOT, _LAMBDA_ROBOT = 4, 5, 6
_A_OBS, _B_OBS = 7, 8


@njit(cache=True, inline="always")
def _capped_exp(arg: float) -> float:
    """exp(min(arg, EXP_ARG_MAX))."""
    return math.exp(min(arg, EXP_ARG_MAX))


@njit(cache=True, inline="always")
def _desired_velocity(px: float, py: float, gx: float, gy: float, v0: float) -> tuple[float, float]:
    """(g − x) capped at the desired speed v0: walk at v0, slow down within v0·1 s of the goal."""
    dx = gx - px
    dy = gy - py
    dist = math.sqrt(dx * dx + dy * dy)
    if dist > v0:
        scale = v0 / dist
        return dx * scale, dy * scale
    return dx, dy


@njit(cache=True, inline="always")
def _heading(vx: float, vy: float, dvx: float, dvy: float) -> tuple[float, float, bool]:
    """Unit heading: the velocity direction, else the desired direction, else none."""
    speed = math.sqrt(vx * vx + vy * vy)
    if speed > EPS:
        return vx / speed, vy / speed, True
    dspeed = math.sqrt(dvx * dvx + dvy * dvy)
    if dspeed > EPS:
        return dvx / dspeed, dvy / dspeed, True
    return 0.0, 0.0, False


@njit(cache=True, inline="always")
def _anisotropy(hx: float, hy: float, has_heading: bool, ux: float, uy: float, lam: float) -> float:
    """ψ = λ + (1 − λ)(1 + cos φ)/2, φ between the heading and the unit vector u to the source."""
    if not has_heading:
        return 1.0
    cos_phi = hx * ux + hy * uy
    return lam + (1.0 - lam) * (1.0 + cos_phi) * 0.5


@njit(cache=True, inline="always")
def _agent_forces(
    i: int,
    pos: np.ndarray,
    vel: np.ndarray,
    goal: np.ndarray,
    radius: np.ndarray,
    v0: np.ndarray,
    params: np.ndarray,
    robot: np.ndarray,
    robot_on: bool,
    segments: np.ndarray,
    circles: np.ndarray,
) -> tuple[float, float, float, float, float, float, float, float]:
    """The four force components on agent i: goal, pedestrians, robot, obstacles (x, y each)."""
    px = pos[i, 0]
    py = pos[i, 1]
    vx = vel[i, 0]
    vy = vel[i, 1]
    ri = radius[i]
    dvx, dvy = _desired_velocity(px, py, goal[i, 0], goal[i, 1], v0[i])
    hx, hy, has_h = _heading(vx, vy, dvx, dvy)

    tau = params[_TAU]
    gfx = (dvx - vx) / tau
    gfy = (dvy - vy) / tau

    # Pedestrian repulsion, summed over j in index order (deterministic).
    a_p = params[_A_PED]
    b_p = params[_B_PED]
    lam_p = params[_LAMBDA_PED]
    pfx = 0.0
    pfy = 0.0
    if a_p != 0.0:
        for j in range(pos.shape[0]):
            if j == i:
                continue
            dx = px - pos[j, 0]  # from j to i
            dy = py - pos[j, 1]
            d = math.sqrt(dx * dx + dy * dy)
            if d < EPS:
                continue
            nx = dx / d
            ny = dy / d
            psi = _anisotropy(hx, hy, has_h, -nx, -ny, lam_p)
            mag = a_p * _capped_exp((ri + radius[j] - d) / b_p) * psi
            pfx += mag * nx
            pfy += mag * ny

    # Robot repulsion (absent in the counterfactual twin, or when A_r = 0).
    rfx = 0.0
    rfy = 0.0
    a_r = params[_A_ROBOT]
    if robot_on and a_r != 0.0:
        dx = px - robot[0]
        dy = py - robot[1]
        d = math.sqrt(dx * dx + dy * dy)
        if d >= EPS:
            nx = dx / d
            ny = dy / d
            psi = _anisotropy(hx, hy, has_h, -nx, -ny, params[_LAMBDA_ROBOT])
            mag = a_r * _capped_exp((ri + robot[2] - d) / params[_B_ROBOT]) * psi
            rfx = mag * nx
            rfy = mag * ny

    # Obstacle repulsion from the closest point of every wall segment and pillar.
    ofx = 0.0
    ofy = 0.0
    a_o = params[_A_OBS]
    b_o = params[_B_OBS]
    if a_o != 0.0:
        for k in range(segments.shape[0]):
            x1 = segments[k, 0]
            y1 = segments[k, 1]
            sx = segments[k, 2] - x1
            sy = segments[k, 3] - y1
            len2 = sx * sx + sy * sy
            t = 0.0
            if len2 > EPS:
                t = ((px - x1) * sx + (py - y1) * sy) / len2
                t = min(1.0, max(0.0, t))
            dx = px - (x1 + t * sx)
            dy = py - (y1 + t * sy)
            d = math.sqrt(dx * dx + dy * dy)
            if d < EPS:
                continue
            mag = a_o * _capped_exp((ri - d) / b_o)
            ofx += mag * dx / d
            ofy += mag * dy / d
        for k in range(circles.shape[0]):
            dx = px - circles[k, 0]
            dy = py - circles[k, 1]
            dc = math.sqrt(dx * dx + dy * dy)
            if dc < EPS:
                continue
            d = dc - circles[k, 2]  # distance to the pillar's surface
            mag = a_o * _capped_exp((ri - d) / b_o)
            ofx += mag * dx / dc
            ofy += mag * dy / dc
    return gfx, gfy, pfx, pfy, rfx, rfy, ofx, ofy


@njit(cache=True)
def force_components_kernel(
    pos: np.ndarray,
    vel: np.ndarray,
    goal: np.ndarray,
    radius: np.ndarray,
    v0: np.ndarray,
    params: np.ndarray,
    robot: np.ndarray,
    robot_on: bool,
    segments: np.ndarray,
    circles: np.ndarray,
    out: np.ndarray,
) -> None:
    """Write the components into ``out`` (4, N, 2): goal, pedestrians, robot, obstacles."""
    for i in range(pos.shape[0]):
        g0, g1, p0, p1, r0, r1, o0, o1 = _agent_forces(
            i, pos, vel, goal, radius, v0, params, robot, robot_on, segments, circles
        )
        out[0, i, 0] = g0
        out[0, i, 1] = g1
        out[1, i, 0] = p0
        out[1, i, 1] = p1
        out[2, i, 0] = r0
        out[2, i, 1] = r1
        out[3, i, 0] = o0
        out[3, i, 1] = o1


@njit(cache=True, inline="always")
def _total(
    i: int,
    pos: np.ndarray,
    vel: np.ndarray,
    goal: np.ndarray,
    radius: np.ndarray,
    v0: np.ndarray,
    params: np.ndarray,
    robot: np.ndarray,
    robot_on: bool,
    segments: np.ndarray,
    circles: np.ndarray,
) -> tuple[float, float]:
    g0, g1, p0, p1, r0, r1, o0, o1 = _agent_forces(
        i, pos, vel, goal, radius, v0, params, robot, robot_on, segments, circles
    )
    return g0 + p0 + r0 + o0, g1 + p1 + r1 + o1


@njit(cache=True)
def total_forces_serial(
    pos: np.ndarray,
    vel: np.ndarray,
    goal: np.ndarray,
    radius: np.ndarray,
    v0: np.ndarray,
    params: np.ndarray,
    robot: np.ndarray,
    robot_on: bool,
    segments: np.ndarray,
    circles: np.ndarray,
    out: np.ndarray,
) -> None:
    """Total force on every agent into ``out`` (N, 2), one agent after another."""
    for i in range(pos.shape[0]):
        fx, fy = _total(i, pos, vel, goal, radius, v0, params, robot, robot_on, segments, circles)
        out[i, 0] = fx
        out[i, 1] = fy


@njit(cache=True, parallel=True)
def total_forces_parallel(
    pos: np.ndarray,
    vel: np.ndarray,
    goal: np.ndarray,
    radius: np.ndarray,
    v0: np.ndarray,
    params: np.ndarray,
    robot: np.ndarray,
    robot_on: bool,
    segments: np.ndarray,
    circles: np.ndarray,
    out: np.ndarray,
) -> None:
    """As :func:`total_forces_serial`, agents split over threads; bit-identical results."""
    for i in prange(pos.shape[0]):
        fx, fy = _total(i, pos, vel, goal, radius, v0, params, robot, robot_on, segments, circles)
        out[i, 0] = fx
        out[i, 1] = fy


@njit(cache=True)
def integrate(
    pos: np.ndarray, vel: np.ndarray, force: np.ndarray, vmax: np.ndarray, dt: float
) -> None:
    """Semi-implicit Euler in place: v ← v + F dt, |v| capped at vmax, x ← x + v dt."""
    for i in range(pos.shape[0]):
        vx = vel[i, 0] + force[i, 0] * dt
        vy = vel[i, 1] + force[i, 1] * dt
        speed = math.sqrt(vx * vx + vy * vy)
        if speed > vmax[i]:
            scale = vmax[i] / speed
            vx *= scale
            vy *= scale
        vel[i, 0] = vx
        vel[i, 1] = vy
        pos[i, 0] += vx * dt
        pos[i, 1] += vy * dt


@njit(cache=True)
def step_serial(
    pos: np.ndarray,
    vel: np.ndarray,
    goal: np.ndarray,
    radius: np.ndarray,
    v0: np.ndarray,
    vmax: np.ndarray,
    params: np.ndarray,
    robot: np.ndarray,
    robot_on: bool,
    segments: np.ndarray,
    circles: np.ndarray,
    dt: float,
    force_buf: np.ndarray,
) -> None:
    """One crowd step in place: all forces from one snapshot, then integrate."""
    total_forces_serial(
        pos, vel, goal, radius, v0, params, robot, robot_on, segments, circles, force_buf
    )
    integrate(pos, vel, force_buf, vmax, dt)


@njit(cache=True)
def step_parallel(
    pos: np.ndarray,
    vel: np.ndarray,
    goal: np.ndarray,
    radius: np.ndarray,
    v0: np.ndarray,
    vmax: np.ndarray,
    params: np.ndarray,
    robot: np.ndarray,
    robot_on: bool,
    segments: np.ndarray,
    circles: np.ndarray,
    dt: float,
    force_buf: np.ndarray,
) -> None:
    """As :func:`step_serial` with the force pass split over threads (for large crowds)."""
    total_forces_parallel(
        pos, vel, goal, radius, v0, params, robot, robot_on, segments, circles, force_buf
    )
    integrate(pos, vel, force_buf, vmax, dt)


@njit(cache=True)
def mark_arrivals(
    pos: np.ndarray, goal: np.ndarray, goal_radius: float, arrived: np.ndarray, new: np.ndarray
) -> int:
    """Flag in ``new`` the agents within ``goal_radius`` of their goal that have not
    ``arrived`` yet; return how many. ``arrived`` is left unchanged."""
    r2 = goal_radius * goal_radius
    count = 0
    for i in range(pos.shape[0]):
        dx = pos[i, 0] - goal[i, 0]
        dy = pos[i, 1] - goal[i, 1]
        hit = dx * dx + dy * dy < r2 and not arrived[i]
        new[i] = hit
        if hit:
            count += 1
    return count


@njit(cache=True)
def nearest_clearance(pos: np.ndarray, radius: np.ndarray, x: float, y: float) -> tuple[float, int]:
    """Smallest (centre distance − agent radius) from (x, y) to an agent, and its index.

    Returns (inf, -1) for an empty crowd.
    """
    best = np.inf
    idx = -1
    for i in range(pos.shape[0]):
        dx = pos[i, 0] - x
        dy = pos[i, 1] - y
        c = math.sqrt(dx * dx + dy * dy) - radius[i]
        if c < best:
            best = c
            idx = i
    return best, idx


@njit(cache=True)
def within_range(pos: np.ndarray, x: float, y: float, max_range: float, out: np.ndarray) -> int:
    """Write into ``out`` the indices of agents closer than ``max_range`` to (x, y);
    return the count."""
    r2 = max_range * max_range
    k = 0
    for i in range(pos.shape[0]):
        dx = pos[i, 0] - x
        dy = pos[i, 1] - y
        if dx * dx + dy * dy < r2:
            out[k] = i
            k += 1
    return k


@njit(cache=True)
def segment_distance(segments: np.ndarray, x: float, y: float) -> float:
    """Smallest distance from (x, y) to any segment (x1, y1, x2, y2); inf when none."""
    best = np.inf
    for k in range(segments.shape[0]):
        x1 = segments[k, 0]
        y1 = segments[k, 1]
        sx = segments[k, 2] - x1
        sy = segments[k, 3] - y1
        len2 = sx * sx + sy * sy
        t = 0.0
        if len2 > EPS:
            t = min(1.0, max(0.0, ((x - x1) * sx + (y - y1) * sy) / len2))
        dx = x - (x1 + t * sx)
        dy = y - (y1 + t * sy)
        best = min(best, math.sqrt(dx * dx + dy * dy))
    return best


@njit(cache=True)
def twin_step_serial(
    f_pos: np.ndarray,
    f_vel: np.ndarray,
    f_goal: np.ndarray,
    c_pos: np.ndarray,
    c_vel: np.ndarray,
    c_goal: np.ndarray,
    radius: np.ndarray,
    v0: np.ndarray,
    vmax: np.ndarray,
    params: np.ndarray,
    robot: np.ndarray,
    segments: np.ndarray,
    circles: np.ndarray,
    dt: float,
    force_buf: np.ndarray,
    goal_radius: float,
    f_arrived: np.ndarray,
    c_arrived: np.ndarray,
    f_new: np.ndarray,
    c_new: np.ndarray,
) -> int:
    """Step the factual (robot on) and counterfactual (robot off) crowds, then flag
    new arrivals of each twin (see :func:`mark_arrivals`); return how many in total."""
    step_serial(
        f_pos,
        f_vel,
        f_goal,
        radius,
        v0,
        vmax,
        params,
        robot,
        True,
        segments,
        circles,
        dt,
        force_buf,
    )
    step_serial(
        c_pos,
        c_vel,
        c_goal,
        radius,
        v0,
        vmax,
        params,
        robot,
        False,
        segments,
        circles,
        dt,
        force_buf,
    )
    count = mark_arrivals(f_pos, f_goal, goal_radius, f_arrived, f_new)
    return count + mark_arrivals(c_pos, c_goal, goal_radius, c_arrived, c_new)


@njit(cache=True)
def twin_step_parallel(
    f_pos: np.ndarray,
    f_vel: np.ndarray,
    f_goal: np.ndarray,
    c_pos: np.ndarray,
    c_vel: np.ndarray,
    c_goal: np.ndarray,
    radius: np.ndarray,
    v0: np.ndarray,
    vmax: np.ndarray,
    params: np.ndarray,
    robot: np.ndarray,
    segments: np.ndarray,
    circles: np.ndarray,
    dt: float,
    force_buf: np.ndarray,
    goal_radius: float,
    f_arrived: np.ndarray,
    c_arrived: np.ndarray,
    f_new: np.ndarray,
    c_new: np.ndarray,
) -> int:
    """As :func:`twin_step_serial` with the threaded force pass (identical results)."""
    step_parallel(
        f_pos,
        f_vel,
        f_goal,
        radius,
        v0,
        vmax,
        params,
        robot,
        True,
        segments,
        circles,
        dt,
        force_buf,
    )
    step_parallel(
        c_pos,
        c_vel,
        c_goal,
        radius,
        v0,
        vmax,
        params,
        robot,
        False,
        segments,
        circles,
        dt,
        force_buf,
    )
    count = mark_arrivals(f_pos, f_goal, goal_radius, f_arrived, f_new)
    return count + mark_arrivals(c_pos, c_goal, goal_radius, c_arrived, c_new)
