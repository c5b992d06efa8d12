"""numba kernels of the classical planners: DWA, Velocity Obstacles, ORCA, social force.

Plain module-level functions over C-contiguous float64 arrays and floats, as in
:mod:`srfm.models._kernels`: no objects, no allocation inside loops, no I/O, no
raising, no random draws, ``cache=True``, no ``fastmath`` (zero distances use an
explicit epsilon). Every planner makes one kernel call per step that returns its
command as two floats.

Shapes and frames (world frame, SI units):

- ``ped_pos``, ``ped_vel`` (k, 2) and ``ped_radius`` (k,): the observed pedestrians;
- ``segments`` (M, 4) = (x1, y1, x2, y2): walls; ``circles`` (K, 3) = (cx, cy,
  radius): pillars. The world's edges, which the planners keep away from like walls
  by default, are the rectangle in ``params`` (``P_EDGES``, ``P_XMIN`` ...): the
  robot is always inside it, so the distance to the edges is a minimum of four
  differences;
- ``params``: the planner's float64 parameter vector. Its first ``N_COMMON`` entries
  are shared by every planner (``P_*`` below), the rest are the planner's own
  (``DWA_*``, ``VO_*``, ``ORCA_*``, ``SF_*``); the planner classes build it at reset.
- ``near`` (M,) float64 scratch: per-call flags of the walls close enough to matter.

Velocity planners (VO, ORCA, social force) choose a world-frame velocity u and turn it
into the robot's command with :func:`velocity_to_command`: (ux, uy) itself for a
holonomic robot; for a unicycle, heading control ω = clip(k_θ · e, ±ω_max) and
v = |u| · max(cos e, 0), with e the angle from the heading to u.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

EPS = 1e-12
INF = math.inf

# Common parameter vector entries.
P_RADIUS = 0  # robot radius (m)
P_VMAX = 1  # top speed (m/s)
P_WMAX = 2  # top turn rate (rad/s)
P_HEADING_GAIN = 3  # k_θ of the unicycle heading control (1/s)
P_UNICYCLE = 4  # 1.0 for a unicycle robot, 0.0 for a holonomic one
P_MARGIN = 5  # safety margin added to every clearance (m)
P_DT = 6  # simulation step (s)
P_GOAL_RADIUS = 7  # the goal counts as reached within this distance (m)
P_EDGES = 8  # 1.0: keep away from the world's edges like from walls
P_XMIN = 9  # world rectangle (m)
P_XMAX = 10
P_YMIN = 11
P_YMAX = 12
N_COMMON = 13

# Dynamic Window Approach.
DWA_VMIN = N_COMMON + 0  # lowest linear speed sampled (m/s)
DWA_ACCEL = N_COMMON + 1  # linear acceleration limit (m/s²)
DWA_WACCEL = N_COMMON + 2  # angular acceleration limit (rad/s²)
DWA_STEPS = N_COMMON + 3  # rollout steps (integer-valued)
DWA_SIM_STEP = N_COMMON + 4  # rollout step (s)
DWA_NV = N_COMMON + 5  # samples of v (unicycle) or per axis of (vx, vy) (holonomic)
DWA_NW = N_COMMON + 6  # samples of ω (unicycle)
DWA_HEADING_W = N_COMMON + 7  # α
DWA_CLEAR_W = N_COMMON + 8  # β
DWA_VEL_W = N_COMMON + 9  # γ
DWA_CLEAR_CAP = N_COMMON + 10  # clearance at which the clearance term saturates (m)
DWA_PREDICT = N_COMMON + 11  # 1.0: pedestrians move at constant velocity in the rollouts
DWA_WINDOW_T = N_COMMON + 12  # the window holds the velocities reachable within this time (s)
N_DWA = N_COMMON + 13

# Velocity Obstacles.
VO_HORIZON = N_COMMON + 0  # time horizon (s), inf for untruncated cones
N_VO = N_COMMON + 1

# ORCA.
ORCA_TAU = N_COMMON + 0  # time horizon for pedestrians (s)
ORCA_TAU_OBS = N_COMMON + 1  # time horizon for walls, pillars and edges (s)
ORCA_RESP = N_COMMON + 2  # the robot's share of each avoidance, in (0, 1]
N_ORCA = N_COMMON + 3

# Social-force robot.
SF_VDES = N_COMMON + 0  # desired speed (m/s)
SF_TAU = N_COMMON + 1  # relaxation time τ (s)
SF_A = N_COMMON + 2  # pedestrian repulsion strength A (m/s²)
SF_B = N_COMMON + 3  # pedestrian repulsion range B (m)
SF_LAMBDA = N_COMMON + 4  # anisotropy λ
SF_A_OBS = N_COMMON + 5  # wall and pillar strength (m/s²)
SF_B_OBS = N_COMMON + 6  # wall and pillar range (m)
N_SF = N_COMMON + 7

EXP_ARG_MAX = 60.0


# --------------------------------------------------------------------------- geometry


@njit(cache=True, inline="always")
def _wrap(angle: float) -> float:
    """Angle in [−π, π]."""
    return math.atan2(math.sin(angle), math.cos(angle))


@njit(cache=True, inline="always")
def _closest_on_segment(
    x: float, y: float, x1: float, y1: float, x2: float, y2: float
) -> tuple[float, float]:
    """The point of segment (x1, y1)–(x2, y2) closest to (x, y)."""
    sx = x2 - x1
    sy = y2 - y1
    len2 = sx * sx + sy * sy
    t = 0.0
    if len2 > EPS:
        t = min(1.0, max(0.0, ((x - x1) * sx + (y - y1) * sy) / len2))
    return x1 + t * sx, y1 + t * sy


@njit(cache=True, inline="always")
def _edge_gap(x: float, y: float, params: np.ndarray) -> float:
    """Distance (m) from (x, y), inside the world, to its nearest edge; inf when the
    planner ignores the edges."""
    if params[P_EDGES] == 0.0:
        return INF
    gap: float = min(x - params[P_XMIN], params[P_XMAX] - x, y - params[P_YMIN], params[P_YMAX] - y)
    return gap


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
    ux: float, uy: float, theta: float, params: np.ndarray
) -> tuple[float, float]:
    """The robot command that realises the world-frame velocity (ux, uy).

    Holonomic: (ux, uy). Unicycle: (v, ω) with ω = clip(k_θ e, ±ω_max) and
    v = min(|u|, v_max) max(cos e, 0), e = wrap(atan2(uy, ux) − θ); (0, 0) for |u| = 0.
    """
    if params[P_UNICYCLE] == 0.0:
        return ux, uy
    speed = math.sqrt(ux * ux + uy * uy)
    if speed < EPS:
        return 0.0, 0.0
    err = _wrap(math.atan2(uy, ux) - theta)
    wmax = params[P_WMAX]
    w = min(wmax, max(-wmax, params[P_HEADING_GAIN] * err))
    c = math.cos(err)
    v = min(speed, params[P_VMAX]) * c if c > 0.0 else 0.0
    return v, w


@njit(cache=True)
def time_to_collision(px: float, py: float, wx: float, wy: float, r: float) -> float:
    """First time t >= 0 at which |p − w t| <= r.

    Args:
        px, py: the obstacle's centre relative to the robot (m).
        wx, wy: the robot's velocity relative to the obstacle (m/s).
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
    cx, cy = _closest_on_segment(x, y, x1, y1, x2, y2)
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
    """Set ``near[k]`` to 1.0 for the walls closer than ``reach`` to (x, y), else 0.0;
    return how many are near."""
    count = 0
    for k in range(segments.shape[0]):
        cx, cy = _closest_on_segment(
            x, y, segments[k, 0], segments[k, 1], segments[k, 2], segments[k, 3]
        )
        d = math.sqrt((x - cx) * (x - cx) + (y - cy) * (y - cy))
        near[k] = 1.0 if d < reach else 0.0
        if d < reach:
            count += 1
    return count


# --------------------------------------------------------------------------- DWA
#
# Hot loops index the arrays directly: a call that passes arrays costs reference
# counting, which would dominate a rollout step.


@njit(cache=True, inline="always")
def _window(value: float, step: float, lo: float, hi: float) -> tuple[float, float]:
    """[value − step, value + step] ∩ [lo, hi]; when that is empty (value outside
    [lo, hi] by more than a step), the single reachable value closest to it."""
    a = max(lo, value - step)
    b = min(hi, value + step)
    if a > b:
        a = value + step if value < lo else value - step
        b = a
    return a, b


@njit(cache=True)
def dynamic_window(v: float, w: float, params: np.ndarray) -> tuple[float, float, float, float]:
    """The dynamic window (v_lo, v_hi, ω_lo, ω_hi) of a unicycle moving at (v, ω).

    V_d = [v − a t_w, v + a t_w] × [ω − α t_w, ω + α t_w], intersected with the speed
    limits V_s = [v_min, v_max] × [−ω_max, ω_max] (Fox, Burgard, Thrun 1997, §3.2, where
    the window time t_w is one control step).
    """
    t_w = params[DWA_WINDOW_T]
    v_lo, v_hi = _window(v, params[DWA_ACCEL] * t_w, params[DWA_VMIN], params[P_VMAX])
    wmax = params[P_WMAX]
    w_lo, w_hi = _window(w, params[DWA_WACCEL] * t_w, -wmax, wmax)
    return v_lo, v_hi, w_lo, w_hi


@njit(cache=True, inline="always")
def _approach(value: float, target: float, step: float) -> float:
    """``value`` moved toward ``target`` by at most ``step``."""
    if target > value + step:
        return value + step
    if target < value - step:
        return value - step
    return target


@njit(cache=True, inline="always")
def _ramp_integral(x0: float, target: float, rate: float, duration: float) -> float:
    """∫ x dt over [0, duration] while x goes from x0 to ``target`` at ``rate``, then holds."""
    gap = target - x0
    t_r = abs(gap) / rate
    if t_r >= duration:
        return x0 * duration + 0.5 * math.copysign(rate, gap) * duration * duration
    return 0.5 * (x0 + target) * t_r + target * (duration - t_r)


@njit(cache=True, inline="always")
def _sample(lo: float, hi: float, i: int, n: int) -> float:
    if n <= 1:
        return hi
    return lo + (hi - lo) * i / (n - 1)


@njit(cache=True)
def dwa_heading(
    x: float,
    y: float,
    theta: float,
    v: float,
    w: float,
    vc: float,
    wc: float,
    gx: float,
    gy: float,
    accel: float,
    waccel: float,
    t_w: float,
) -> float:
    """Fox et al.'s heading term: 1 − |θ_goal| / π, θ_goal the angle of the goal
    relative to the robot's heading at its predicted pose.

    As in the paper, the pose is predicted by moving toward the candidate (vc, ωc) at
    the acceleration limits ``accel`` (m/s²) and ``waccel`` (rad/s²) for the window
    time ``t_w`` (one step in the paper), then braking to rest at the same limits.
    Turn angles and distances of both phases are exact; each phase moves along its
    mid-phase heading.
    """
    d1 = _ramp_integral(v, vc, accel, t_w)
    a1 = _ramp_integral(w, wc, waccel, t_w)
    v1 = _approach(v, vc, accel * t_w)
    w1 = _approach(w, wc, waccel * t_w)
    d2 = 0.5 * v1 * abs(v1) / accel  # braking distance (signed)
    a2 = 0.5 * w1 * abs(w1) / waccel  # turn while braking (signed)
    m1 = theta + 0.5 * a1
    m2 = theta + a1 + 0.5 * a2
    px = x + d1 * math.cos(m1) + d2 * math.cos(m2)
    py = y + d1 * math.sin(m1) + d2 * math.sin(m2)
    err = math.atan2(gy - py, gx - px) - (theta + a1 + a2)
    err -= 2.0 * math.pi * math.floor((err + math.pi) / (2.0 * math.pi))
    heading: float = 1.0 - abs(err) / math.pi
    return heading


@njit(cache=True, inline="always")
def _dwa_score(heading: float, min_clear: float, speed: float, params: np.ndarray) -> float:
    cap = params[DWA_CLEAR_CAP]
    score: float = (
        params[DWA_HEADING_W] * heading
        + params[DWA_CLEAR_W] * min(min_clear, cap) / cap
        + params[DWA_VEL_W] * speed / params[P_VMAX]
    )
    return score


@njit(cache=True, inline="always")
def _gap(
    px: float,
    py: float,
    t: float,
    radius: float,
    edges: bool,
    x0: float,
    x1: float,
    y0: float,
    y1: float,
    ped_pos: np.ndarray,
    ped_vel: np.ndarray,
    ped_radius: np.ndarray,
    segments: np.ndarray,
    near: np.ndarray,
    circles: np.ndarray,
) -> float:
    """Smallest gap (m) from a robot disc of ``radius`` at (px, py) to the world's edges
    (when ``edges``), the pedestrians moved on for ``t`` seconds at constant velocity,
    the walls flagged in ``near`` and the pillars; inf when there is nothing."""
    gap = INF
    if edges:
        gap = min(px - x0, x1 - px, py - y0, y1 - py) - radius
    for q in range(ped_pos.shape[0]):
        ex = px - (ped_pos[q, 0] + ped_vel[q, 0] * t)
        ey = py - (ped_pos[q, 1] + ped_vel[q, 1] * t)
        g = math.sqrt(ex * ex + ey * ey) - radius - ped_radius[q]
        gap = min(gap, g)
    for q in range(segments.shape[0]):
        if near[q] != 0.0:
            cx, cy = _closest_on_segment(
                px, py, segments[q, 0], segments[q, 1], segments[q, 2], segments[q, 3]
            )
            ex = px - cx
            ey = py - cy
            gap = min(gap, math.sqrt(ex * ex + ey * ey) - radius)
    for q in range(circles.shape[0]):
        ex = px - circles[q, 0]
        ey = py - circles[q, 1]
        g = math.sqrt(ex * ex + ey * ey) - radius - circles[q, 2]
        gap = min(gap, g)
    return gap


@njit(cache=True)
def dwa_unicycle(
    x: float,
    y: float,
    theta: float,
    v: float,
    w: float,
    gx: float,
    gy: float,
    ped_pos: np.ndarray,
    ped_vel: np.ndarray,
    ped_radius: np.ndarray,
    segments: np.ndarray,
    circles: np.ndarray,
    params: np.ndarray,
    near: np.ndarray,
    table: np.ndarray,
) -> tuple[float, float]:
    """DWA for a unicycle: the best (v, ω) of the dynamic window.

    Each of the ``DWA_NV`` × ``DWA_NW`` samples (vc, ωc) of the window is rolled out
    for ``DWA_STEPS`` steps of ``DWA_SIM_STEP`` seconds (midpoint rule, as the robot
    moves): the velocity approaches (vc, ωc) at the acceleration limits, then holds it.
    Each rollout position is checked against the pedestrians (moved at constant
    velocity when ``DWA_PREDICT`` is set), the near walls, the pillars and the world's
    edges, all inflated by the safety margin; a rollout stops at the first contact or
    inside the goal radius. With nothing within reach the rollouts are skipped (every
    gap is then infinite). Rollouts with a contact are inadmissible; the admissible one
    with the highest G = α heading (:func:`dwa_heading`) + β clearance + γ velocity
    wins. When none is admissible the one whose first contact comes latest (then:
    larger clearance) wins.

    ``table`` (>= DWA_NV · DWA_NW, 5) receives one row per sample: vc, ωc, smallest
    gap (m), time of the first contact (s, inf for none), G (−inf when inadmissible).
    """
    v_lo, v_hi, w_lo, w_hi = dynamic_window(v, w, params)
    nv = int(params[DWA_NV])
    nw = int(params[DWA_NW])
    n_steps = int(params[DWA_STEPS])
    h = params[DWA_SIM_STEP]
    accel = params[DWA_ACCEL]
    waccel = params[DWA_WACCEL]
    t_w = params[DWA_WINDOW_T]
    dv = accel * h
    dw = waccel * h
    radius = params[P_RADIUS] + params[P_MARGIN]
    predict = params[DWA_PREDICT]
    goal_r2 = params[P_GOAL_RADIUS] * params[P_GOAL_RADIUS]
    x0 = params[P_XMIN]
    x1 = params[P_XMAX]
    y0 = params[P_YMIN]
    y1 = params[P_YMAX]
    reach = radius + params[P_VMAX] * n_steps * h + params[DWA_CLEAR_CAP]
    n_near = mark_near_segments(segments, x, y, reach, near)
    edges = _edge_gap(x, y, params) < reach
    n_peds = ped_pos.shape[0]
    n_circ = circles.shape[0]
    check = edges or n_near > 0 or n_peds > 0 or n_circ > 0
    at_goal_now = (x - gx) * (x - gx) + (y - gy) * (y - gy) < goal_r2
    hx0 = math.cos(theta)
    hy0 = math.sin(theta)
    best = -INF
    best_v = v_lo
    best_w = 0.5 * (w_lo + w_hi)
    fb_t = -1.0
    fb_clear = -INF
    fb_v = best_v
    fb_w = best_w
    row = 0
    for i in range(nv):
        vc = _sample(v_lo, v_hi, i, nv)
        for j in range(nw):
            wc = _sample(w_lo, w_hi, j, nw)
            min_clear = INF
            t_hit = INF
            at_goal = at_goal_now
            if check:
                hx = hx0
                hy = hy0
                px = x
                py = y
                vr = v
                wr = w - 2.0 * dw - 1.0  # differs from every ω reached: sets c and s
                c = 1.0
                s = 0.0
                for k in range(1, n_steps + 1):
                    vr = _approach(vr, vc, dv)
                    w_new = _approach(w if k == 1 else wr, wc, dw)
                    if w_new != wr:  # half-step rotation, recomputed while ω changes
                        wr = w_new
                        c = math.cos(0.5 * wr * h)
                        s = math.sin(0.5 * wr * h)
                    mx = hx * c - hy * s  # mid-step heading
                    my = hy * c + hx * s
                    px += vr * mx * h
                    py += vr * my * h
                    hx = mx * c - my * s
                    hy = my * c + mx * s
                    # Smallest gap to everything at time k h.
                    t = k * h * predict
                    gap = _gap(
                        px, py, t, radius, edges, x0, x1, y0, y1,
                        ped_pos, ped_vel, ped_radius, segments, near, circles,
                    )  # fmt: skip
                    min_clear = min(min_clear, gap)
                    if gap < 0.0:
                        t_hit = k * h
                        break
                    if (px - gx) * (px - gx) + (py - gy) * (py - gy) < goal_r2:
                        at_goal = True
                        break
            score = -INF
            if t_hit == INF:
                if at_goal:
                    heading = 1.0
                else:
                    heading = dwa_heading(x, y, theta, v, w, vc, wc, gx, gy, accel, waccel, t_w)
                score = _dwa_score(heading, min_clear, vc, params)
                if score > best:
                    best = score
                    best_v = vc
                    best_w = wc
            elif t_hit > fb_t or (t_hit == fb_t and min_clear > fb_clear):
                fb_t = t_hit
                fb_clear = min_clear
                fb_v = vc
                fb_w = wc
            table[row, 0] = vc
            table[row, 1] = wc
            table[row, 2] = min_clear
            table[row, 3] = t_hit
            table[row, 4] = score
            row += 1
    if best > -INF:
        return best_v, best_w
    return fb_v, fb_w


@njit(cache=True)
def dwa_holonomic(
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
    params: np.ndarray,
    near: np.ndarray,
    table: np.ndarray,
) -> tuple[float, float]:
    """DWA for a holonomic robot: the best (vx, vy) of the dynamic window.

    The window is the disc of velocities within the window time of acceleration of
    (vx, vy) (the points of a ``DWA_NV`` × ``DWA_NV`` grid inside it), capped at v_max.
    Each rollout approaches the candidate at the acceleration limit, then holds it;
    checks as in :func:`dwa_unicycle`. The heading term compares the direction of the
    candidate velocity with the direction to the goal from the position predicted
    after the window time at the candidate and braking; it is 0.5 for the zero
    velocity (no direction). Scoring, fallback and ``table`` (rows vx, vy, gap,
    contact time, G) as in :func:`dwa_unicycle`.
    """
    n = int(params[DWA_NV])
    n_steps = int(params[DWA_STEPS])
    h = params[DWA_SIM_STEP]
    accel = params[DWA_ACCEL]
    t_w = params[DWA_WINDOW_T]
    dv = accel * t_w
    dvh = accel * h
    vmax = params[P_VMAX]
    radius = params[P_RADIUS] + params[P_MARGIN]
    predict = params[DWA_PREDICT]
    goal_r2 = params[P_GOAL_RADIUS] * params[P_GOAL_RADIUS]
    x0 = params[P_XMIN]
    x1 = params[P_XMAX]
    y0 = params[P_YMIN]
    y1 = params[P_YMAX]
    reach = radius + vmax * n_steps * h + params[DWA_CLEAR_CAP]
    n_near = mark_near_segments(segments, x, y, reach, near)
    edges = _edge_gap(x, y, params) < reach
    n_peds = ped_pos.shape[0]
    n_circ = circles.shape[0]
    check = edges or n_near > 0 or n_peds > 0 or n_circ > 0
    at_goal_now = (x - gx) * (x - gx) + (y - gy) * (y - gy) < goal_r2
    best = -INF
    best_x = vx
    best_y = vy
    fb_t = -1.0
    fb_clear = -INF
    fb_x = vx
    fb_y = vy
    row = 0
    for i in range(n):
        ox = _sample(-dv, dv, i, n) if n > 1 else 0.0
        for j in range(n):
            oy = _sample(-dv, dv, j, n) if n > 1 else 0.0
            if ox * ox + oy * oy > dv * dv * (1.0 + 1e-9):
                continue
            cvx = vx + ox
            cvy = vy + oy
            speed = math.sqrt(cvx * cvx + cvy * cvy)
            if speed > vmax:
                cvx *= vmax / speed
                cvy *= vmax / speed
                speed = vmax
            min_clear = INF
            t_hit = INF
            at_goal = at_goal_now
            if check:
                px = x
                py = y
                rx = vx
                ry = vy
                for k in range(1, n_steps + 1):
                    ex = cvx - rx
                    ey = cvy - ry
                    e = math.sqrt(ex * ex + ey * ey)
                    if e > dvh:
                        rx += ex * dvh / e
                        ry += ey * dvh / e
                    else:
                        rx = cvx
                        ry = cvy
                    px += rx * h
                    py += ry * h
                    t = k * h * predict
                    gap = _gap(
                        px, py, t, radius, edges, x0, x1, y0, y1,
                        ped_pos, ped_vel, ped_radius, segments, near, circles,
                    )  # fmt: skip
                    min_clear = min(min_clear, gap)
                    if gap < 0.0:
                        t_hit = k * h
                        break
                    if (px - gx) * (px - gx) + (py - gy) * (py - gy) < goal_r2:
                        at_goal = True
                        break
            score = -INF
            if t_hit == INF:
                if at_goal:
                    heading = 1.0
                elif speed < 1e-9:
                    heading = 0.5  # at rest a holonomic robot faces no direction
                else:
                    lead = t_w + 0.5 * speed / accel
                    qx = x + cvx * lead
                    qy = y + cvy * lead
                    err = _wrap(math.atan2(gy - qy, gx - qx) - math.atan2(cvy, cvx))
                    heading = 1.0 - abs(err) / math.pi
                score = _dwa_score(heading, min_clear, speed, params)
                if score > best:
                    best = score
                    best_x = cvx
                    best_y = cvy
            elif t_hit > fb_t or (t_hit == fb_t and min_clear > fb_clear):
                fb_t = t_hit
                fb_clear = min_clear
                fb_x = cvx
                fb_y = cvy
            table[row, 0] = cvx
            table[row, 1] = cvy
            table[row, 2] = min_clear
            table[row, 3] = t_hit
            table[row, 4] = score
            row += 1
    if best > -INF:
        return best_x, best_y
    return fb_x, fb_y


# --------------------------------------------------------------------------- VO


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
    params: np.ndarray,
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
    vmax = params[P_VMAX]
    horizon = params[VO_HORIZON]
    radius = params[P_RADIUS] + params[P_MARGIN]
    dx = gx - x
    dy = gy - y
    dist = math.sqrt(dx * dx + dy * dy)
    if dist < EPS:
        return 0.0, 0.0
    cg = dx / dist
    sg = dy / dist
    reach = radius + vmax * horizon if horizon < INF else INF
    mark_near_segments(segments, x, y, reach, near)
    edges = params[P_EDGES] != 0.0
    x0 = params[P_XMIN]
    x1 = params[P_XMAX]
    y0 = params[P_YMIN]
    y1 = params[P_YMAX]
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


# --------------------------------------------------------------------------- ORCA
#
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
        count = 0
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
        fail, rx, ry = orca_lp2(proj, count, vmax, nix, niy, True)
        if fail == count:  # otherwise keep (x, y): can only fail by rounding
            x = rx
            y = ry
        dist = -((x - lines[i, 0]) * nix + (y - lines[i, 1]) * niy)
    return x, y


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
    params: np.ndarray,
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
    vmax = params[P_VMAX]
    radius = params[P_RADIUS]
    margin = params[P_MARGIN]
    tau = params[ORCA_TAU]
    tau_obs = params[ORCA_TAU_OBS]
    n = 0
    for k in range(segments.shape[0] + circles.shape[0]):
        if k < segments.shape[0]:
            cx, cy = _closest_on_segment(
                x, y, segments[k, 0], segments[k, 1], segments[k, 2], segments[k, 3]
            )
            extra = 0.0
        else:
            m = k - segments.shape[0]
            cx = circles[m, 0]
            cy = circles[m, 1]
            extra = circles[m, 2]
        dx = x - cx
        dy = y - cy
        d = math.sqrt(dx * dx + dy * dy)
        gap = d - extra - radius - margin
        if gap >= vmax * tau_obs or d < EPS:
            continue
        nx = dx / d
        ny = dy / d
        s = -gap / tau_obs
        lines[n, 0] = nx * s
        lines[n, 1] = ny * s
        lines[n, 2] = nx
        lines[n, 3] = ny
        n += 1
    if params[P_EDGES] != 0.0:
        for k in range(4):
            if k == 0:
                gap = x - params[P_XMIN]
                nx, ny = 1.0, 0.0
            elif k == 1:
                gap = params[P_XMAX] - x
                nx, ny = -1.0, 0.0
            elif k == 2:
                gap = y - params[P_YMIN]
                nx, ny = 0.0, 1.0
            else:
                gap = params[P_YMAX] - y
                nx, ny = 0.0, -1.0
            gap -= radius + margin
            if gap >= vmax * tau_obs:
                continue
            s = -gap / tau_obs
            lines[n, 0] = nx * s
            lines[n, 1] = ny * s
            lines[n, 2] = nx
            lines[n, 3] = ny
            n += 1
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
            params[P_DT],
            params[ORCA_RESP],
        )
        lines[n, 0] = a
        lines[n, 1] = b
        lines[n, 2] = c
        lines[n, 3] = d
        n += 1
    prefx, prefy = _preferred_velocity(x, y, gx, gy, vmax)
    fail, rx, ry = orca_lp2(lines, n, vmax, prefx, prefy, False)
    if fail < n:
        if fail < n_hard:  # the obstacles alone leave no room: relax everything
            n_hard = 0
        rx, ry = orca_lp3(lines, n, n_hard, fail, vmax, rx, ry, proj)
    return rx, ry


# --------------------------------------------------------------------------- social force


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
    params: np.ndarray,
) -> tuple[float, float]:
    """The robot's next velocity under a social force model (semi-implicit Euler).

    F = (v_des − v)/τ + Σ_j A exp((r + r_j − d_j)/B) ψ(φ_j; λ) n_j
        + Σ_o A_o exp((r − d_o)/B_o) n_o,
    v_des = (g − x) capped at the desired speed, o over the walls, pillars and (when
    ``P_EDGES``) the world's edges, n the unit vector from the pedestrian (closest
    obstacle point) to the robot, ψ = λ + (1 − λ)(1 + cos φ)/2 with φ the
    angle between the robot's heading θ and the direction to the pedestrian. Returns
    v + F dt capped at v_max.
    """
    vdes = params[SF_VDES]
    radius = params[P_RADIUS]
    dx = gx - x
    dy = gy - y
    dist = math.sqrt(dx * dx + dy * dy)
    if dist > vdes:
        dx *= vdes / dist
        dy *= vdes / dist
    tau = params[SF_TAU]
    fx = (dx - vx) / tau
    fy = (dy - vy) / tau
    a = params[SF_A]
    b = params[SF_B]
    lam = params[SF_LAMBDA]
    hx = math.cos(theta)
    hy = math.sin(theta)
    for j in range(ped_pos.shape[0]):
        ex = x - ped_pos[j, 0]
        ey = y - ped_pos[j, 1]
        d = math.sqrt(ex * ex + ey * ey)
        if d < EPS:
            continue
        nx = ex / d
        ny = ey / d
        psi = lam + (1.0 - lam) * (1.0 - (hx * nx + hy * ny)) * 0.5
        mag = a * math.exp(min((radius + ped_radius[j] - d) / b, EXP_ARG_MAX)) * psi
        fx += mag * nx
        fy += mag * ny
    a_o = params[SF_A_OBS]
    b_o = params[SF_B_OBS]
    for k in range(segments.shape[0] + circles.shape[0]):
        if k < segments.shape[0]:
            cx, cy = _closest_on_segment(
                x, y, segments[k, 0], segments[k, 1], segments[k, 2], segments[k, 3]
            )
            extra = 0.0
        else:
            m = k - segments.shape[0]
            cx = circles[m, 0]
            cy = circles[m, 1]
            extra = circles[m, 2]
        ex = x - cx
        ey = y - cy
        d = math.sqrt(ex * ex + ey * ey)
        if d < EPS:
            continue
        mag = a_o * math.exp(min((radius + extra - d) / b_o, EXP_ARG_MAX))
        fx += mag * ex / d
        fy += mag * ey / d
    if params[P_EDGES] != 0.0:
        for k in range(4):
            if k == 0:
                gap = x - params[P_XMIN]
                nx, ny = 1.0, 0.0
            elif k == 1:
                gap = params[P_XMAX] - x
                nx, ny = -1.0, 0.0
            elif k == 2:
                gap = y - params[P_YMIN]
                nx, ny = 0.0, 1.0
            else:
                gap = params[P_YMAX] - y
                nx, ny = 0.0, -1.0
            mag = a_o * math.exp(min((radius - gap) / b_o, EXP_ARG_MAX))
            fx += mag * nx
            fy += mag * ny
    dt = params[P_DT]
    ux = vx + fx * dt
    uy = vy + fy * dt
    speed = math.sqrt(ux * ux + uy * uy)
    vmax = params[P_VMAX]
    if speed > vmax:
        ux *= vmax / speed
        uy *= vmax / speed
    return ux, uy


# --------------------------------------------------------------------------- commands
#
# One call per step: the planner's velocity turned into the robot's command.


@njit(cache=True)
def vo_command(
    x: float,
    y: float,
    theta: float,
    gx: float,
    gy: float,
    ped_pos: np.ndarray,
    ped_vel: np.ndarray,
    ped_radius: np.ndarray,
    segments: np.ndarray,
    circles: np.ndarray,
    params: np.ndarray,
    candidates: np.ndarray,
    near: np.ndarray,
) -> tuple[float, float]:
    """:func:`vo_velocity` as a command (:func:`velocity_to_command`)."""
    ux, uy = vo_velocity(
        x, y, gx, gy, ped_pos, ped_vel, ped_radius, segments, circles, params, candidates, near
    )
    return velocity_to_command(ux, uy, theta, params)


@njit(cache=True)
def orca_command(
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
    params: np.ndarray,
    lines: np.ndarray,
    proj: np.ndarray,
) -> tuple[float, float]:
    """:func:`orca_velocity` as a command (:func:`velocity_to_command`)."""
    ux, uy = orca_velocity(
        x, y, vx, vy, gx, gy, ped_pos, ped_vel, ped_radius, segments, circles, params, lines, proj
    )
    return velocity_to_command(ux, uy, theta, params)


@njit(cache=True)
def social_force_command(
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
    params: np.ndarray,
) -> tuple[float, float]:
    """:func:`social_force_velocity` as a command (:func:`velocity_to_command`)."""
    ux, uy = social_force_velocity(
        x, y, theta, vx, vy, gx, gy, ped_pos, ped_vel, ped_radius, segments, circles, params
    )
    return velocity_to_command(ux, uy, theta, params)
