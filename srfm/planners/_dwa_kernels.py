"""numba kernels of the Dynamic Window Approach (:mod:`srfm.planners.dwa`).

The planner's step is one call of :func:`dwa_unicycle` or :func:`dwa_holonomic` (arrays,
frames and parameter tuples as in :mod:`srfm.planners._geometry`). The two variants
share the search: the per-step set-up (:func:`_prepare`), the check of a rollout
position (:func:`_probe`), the scoring and the fallback (:func:`_rank`, :func:`_chosen`)
and the inspection table (:func:`_write_row`). Each keeps only its candidate grid, its
rollout kinematics (:func:`_unicycle_step`, :func:`_holonomic_step`) and its heading
term (:func:`dwa_heading`, :func:`_holonomic_heading`).

Hot loops index the arrays directly and their helpers are inlined (``inline="always"``):
a compiled call that passes arrays costs reference counting, which would dominate a
rollout step. So the rollout loops stay in the variants' bodies, the helpers they call
per step or per sample take floats and NamedTuples (passed by value), and only
:func:`_probe` reads the arrays, as a single inlined block.
"""

from __future__ import annotations

import math
from typing import Any, NamedTuple

import numpy as np
from numba import njit

from srfm.models._primitives import closest_on_segment
from srfm.planners._geometry import INF, CommonParams, edge_gap, mark_near_segments, wrap_angle

__all__ = ["DWAParams", "dwa_heading", "dwa_holonomic", "dwa_unicycle", "dynamic_window"]


class DWAParams(NamedTuple):
    """The Dynamic Window Approach's own kernel parameters.

    Attributes:
        min_speed_mps: v_min, the lowest linear speed sampled (m/s).
        accel_mps2: a, linear acceleration limit (m/s²).
        angular_accel_radps2: α, angular acceleration limit (rad/s²).
        steps: rollout steps.
        rollout_step_s: h, the rollout step (s).
        v_samples: samples of v (unicycle), or per axis of (vx, vy) (holonomic).
        omega_samples: samples of ω (unicycle); ``v_samples`` again (holonomic).
        heading_weight: α of G, weight of the heading term.
        clearance_weight: β, weight of the clearance term.
        velocity_weight: γ, weight of the velocity term.
        clearance_cap_m: the clearance at which the clearance term saturates (m).
        predict_pedestrians: pedestrians move at constant velocity in the rollouts.
        window_time_s: t_w, the window holds the velocities reachable within this
            time (s).
    """

    min_speed_mps: float
    accel_mps2: float
    angular_accel_radps2: float
    steps: int
    rollout_step_s: float
    v_samples: int
    omega_samples: int
    heading_weight: float
    clearance_weight: float
    velocity_weight: float
    clearance_cap_m: float
    predict_pedestrians: bool
    window_time_s: float


class _Rollouts(NamedTuple):
    """What every rollout of one DWA step needs besides the arrays (built by
    :func:`_prepare`)."""

    steps: int  # rollout steps
    h: float  # rollout step (s)
    radius: float  # robot radius + safety margin (m)
    predict: bool  # pedestrians move in the rollouts
    edges: bool  # the world's edges are within reach
    check: bool  # anything is within reach (else every gap is inf: skip the rollouts)
    at_goal: bool  # the robot is inside the goal radius now
    gx: float  # goal (m)
    gy: float
    goal_r2: float  # goal radius squared (m²)
    x0: float  # world rectangle (m)
    x1: float
    y0: float
    y1: float


class _Choice(NamedTuple):
    """The search state of one DWA step: the best admissible sample so far, and the
    fallback among the inadmissible ones (latest first contact, then largest gap)."""

    score: float  # G of the best admissible sample (−inf: none yet)
    a: float  # that sample: (v, ω) or (vx, vy)
    b: float
    fb_t: float  # first contact of the fallback (s)
    fb_clear: float  # its smallest gap (m)
    fb_a: float  # the fallback sample
    fb_b: float


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


@njit(cache=True, inline="always")
def dynamic_window(
    v: float,
    w: float,
    common: CommonParams | tuple[Any, ...],
    params: DWAParams | tuple[Any, ...],
) -> tuple[float, float, float, float]:
    """The dynamic window (v_lo, v_hi, ω_lo, ω_hi) of a unicycle moving at (v, ω).

    V_d = [v − a t_w, v + a t_w] × [ω − α t_w, ω + α t_w], intersected with the speed
    limits V_s = [v_min, v_max] × [−ω_max, ω_max] (Fox, Burgard, Thrun 1997, §3.2, where
    the window time t_w is one control step). ``common`` and ``params`` may be plain
    tuples of their fields.
    """
    c = CommonParams(*common)
    p = DWAParams(*params)
    t_w = p.window_time_s
    v_lo, v_hi = _window(v, p.accel_mps2 * t_w, p.min_speed_mps, c.max_speed_mps)
    wmax = c.max_angular_speed_radps
    w_lo, w_hi = _window(w, p.angular_accel_radps2 * t_w, -wmax, wmax)
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
def _sample(lo: float, hi: float, i: int, n: int) -> float:
    """Sample i of n spread evenly over [lo, hi] (``hi`` when n = 1)."""
    if n <= 1:
        return hi
    return lo + (hi - lo) * i / (n - 1)


@njit(cache=True, inline="always")
def _prepare(
    x: float,
    y: float,
    goal: np.ndarray,
    ped_pos: np.ndarray,
    segments: np.ndarray,
    circles: np.ndarray,
    near: np.ndarray,
    common: CommonParams,
    params: DWAParams,
) -> _Rollouts:
    """The per-step constants of the rollouts from (x, y); flags in ``near`` the walls
    within reach of any rollout (robot radius + margin + v_max · horizon + the
    clearance cap)."""
    steps = params.steps
    h = params.rollout_step_s
    radius = common.radius_m + common.margin_m
    goal_r2 = common.goal_radius_m * common.goal_radius_m
    gx = goal[0]
    gy = goal[1]
    reach = radius + common.max_speed_mps * steps * h + params.clearance_cap_m
    n_near = mark_near_segments(segments, x, y, reach, near)
    edges = edge_gap(x, y, common) < reach
    check = edges or n_near > 0 or ped_pos.shape[0] > 0 or circles.shape[0] > 0
    at_goal = (x - gx) * (x - gx) + (y - gy) * (y - gy) < goal_r2
    return _Rollouts(
        steps, h, radius, params.predict_pedestrians, edges, check, at_goal, gx, gy, goal_r2,
        common.x_min, common.x_max, common.y_min, common.y_max,
    )  # fmt: skip


@njit(cache=True, inline="always")
def _probe(
    px: float,
    py: float,
    k: int,
    min_clear: float,
    at_goal: bool,
    ro: _Rollouts,
    ped_pos: np.ndarray,
    ped_vel: np.ndarray,
    ped_radius: np.ndarray,
    segments: np.ndarray,
    near: np.ndarray,
    circles: np.ndarray,
) -> tuple[float, float, bool, bool]:
    """Check rollout position (px, py) after k steps.

    The gap (m) from the robot disc (radius + margin) to the world's edges (when within
    reach), the pedestrians (moved on for k h seconds when predicted), the walls
    flagged in ``near`` and the pillars.

    Returns:
        (min_clear, t_hit, at_goal, stop): ``min_clear`` lowered to that gap; the
        contact time k h (s) when the gap is negative, else inf; ``at_goal`` set when
        (px, py) lies inside the goal radius; whether the rollout ends here (a contact,
        or the goal reached).
    """
    t = k * ro.h if ro.predict else 0.0
    radius = ro.radius
    gap = INF
    if ro.edges:
        gap = min(px - ro.x0, ro.x1 - px, py - ro.y0, ro.y1 - py) - radius
    for q in range(ped_pos.shape[0]):
        ex = px - (ped_pos[q, 0] + ped_vel[q, 0] * t)
        ey = py - (ped_pos[q, 1] + ped_vel[q, 1] * t)
        g = math.sqrt(ex * ex + ey * ey) - radius - ped_radius[q]
        gap = min(gap, g)
    for q in range(segments.shape[0]):
        if near[q] != 0.0:
            cx, cy = closest_on_segment(
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
    min_clear = min(min_clear, gap)
    if gap < 0.0:
        return min_clear, k * ro.h, at_goal, True
    if (px - ro.gx) * (px - ro.gx) + (py - ro.gy) * (py - ro.gy) < ro.goal_r2:
        return min_clear, INF, True, True
    return min_clear, INF, at_goal, False


@njit(cache=True, inline="always")
def _rank(
    choice: _Choice,
    a: float,
    b: float,
    speed: float,
    heading: float,
    min_clear: float,
    t_hit: float,
    common: CommonParams,
    params: DWAParams,
) -> tuple[_Choice, float]:
    """Score sample (a, b) and keep it in ``choice`` when it beats the best so far.

    Admissible (t_hit = inf): G = α heading + β min(gap, cap) / cap + γ speed / v_max.
    Inadmissible: it becomes the fallback when its first contact comes later (then:
    its smallest gap is larger).

    Returns:
        (choice, G), G = −inf when inadmissible.
    """
    score = -INF
    if t_hit == INF:
        cap = params.clearance_cap_m
        score = (
            params.heading_weight * heading
            + params.clearance_weight * min(min_clear, cap) / cap
            + params.velocity_weight * speed / common.max_speed_mps
        )
        if score > choice.score:
            choice = _Choice(score, a, b, choice.fb_t, choice.fb_clear, choice.fb_a, choice.fb_b)
    elif t_hit > choice.fb_t or (t_hit == choice.fb_t and min_clear > choice.fb_clear):
        choice = _Choice(choice.score, choice.a, choice.b, t_hit, min_clear, a, b)
    return choice, score


@njit(cache=True, inline="always")
def _write_row(
    table: np.ndarray, row: int, a: float, b: float, gap: float, t_hit: float, score: float
) -> None:
    """``table[row]`` = (a, b, gap, t_hit, score): one sample of the search."""
    table[row, 0] = a
    table[row, 1] = b
    table[row, 2] = gap
    table[row, 3] = t_hit
    table[row, 4] = score


@njit(cache=True, inline="always")
def _chosen(choice: _Choice) -> tuple[float, float]:
    """The best admissible sample, else the fallback."""
    if choice.score > -INF:
        return choice.a, choice.b
    return choice.fb_a, choice.fb_b


@njit(cache=True, inline="always")
def _unicycle_step(
    px: float,
    py: float,
    hx: float,
    hy: float,
    vr: float,
    w_from: float,
    wr: float,
    c: float,
    s: float,
    vc: float,
    wc: float,
    dv: float,
    dw: float,
    h: float,
) -> tuple[float, float, float, float, float, float, float, float]:
    """One rollout step of a unicycle at (px, py) with unit heading (hx, hy).

    The speed vr approaches vc by at most dv, the turn rate approaches ωc from
    ``w_from`` by at most dω; the robot moves h seconds along its mid-step heading.
    (c, s) = (cos, sin) of the half-step rotation at turn rate ``wr``, recomputed only
    when the turn rate changes.

    Returns:
        (px, py, hx, hy, vr, wr, c, s) after the step.
    """
    vr = _approach(vr, vc, dv)
    w_new = _approach(w_from, wc, dw)
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
    return px, py, hx, hy, vr, wr, c, s


@njit(cache=True, inline="always")
def _holonomic_step(
    px: float, py: float, rx: float, ry: float, cvx: float, cvy: float, dvh: float, h: float
) -> tuple[float, float, float, float]:
    """One rollout step of a holonomic robot at (px, py) moving at (rx, ry): the velocity
    approaches (cvx, cvy) by at most ``dvh``, then the robot moves h seconds at it.

    Returns:
        (px, py, rx, ry) after the step.
    """
    ex = cvx - rx
    ey = cvy - ry
    e = math.sqrt(ex * ex + ey * ey)
    if e > dvh:
        rx += ex * dvh / e
        ry += ey * dvh / e
    else:
        rx = cvx
        ry = cvy
    return px + rx * h, py + ry * h, rx, ry


@njit(cache=True, inline="always")
def _holonomic_heading(
    x: float,
    y: float,
    cvx: float,
    cvy: float,
    speed: float,
    gx: float,
    gy: float,
    accel: float,
    t_w: float,
) -> float:
    """1 − |e| / π, e the angle between the velocity (cvx, cvy) and the direction to the
    goal from the position reached after t_w at that velocity and braking; 0.5 at
    rest (a holonomic robot at rest faces no direction)."""
    if speed < 1e-9:
        return 0.5
    lead = t_w + 0.5 * speed / accel
    qx = x + cvx * lead
    qy = y + cvy * lead
    err = wrap_angle(math.atan2(gy - qy, gx - qx) - math.atan2(cvy, cvx))
    heading: float = 1.0 - abs(err) / math.pi
    return heading


@njit(cache=True)
def dwa_unicycle(
    x: float,
    y: float,
    theta: float,
    v: float,
    w: float,
    goal: np.ndarray,
    ped_pos: np.ndarray,
    ped_vel: np.ndarray,
    ped_radius: np.ndarray,
    segments: np.ndarray,
    circles: np.ndarray,
    common: CommonParams | tuple[Any, ...],
    params: DWAParams | tuple[Any, ...],
    near: np.ndarray,
    table: np.ndarray,
) -> tuple[float, float]:
    """DWA for a unicycle: the best (v, ω) of the dynamic window toward ``goal`` (2,).

    Each of the ``v_samples`` × ``omega_samples`` samples (vc, ωc) of the window is
    rolled out for ``steps`` steps of ``rollout_step_s`` seconds (midpoint rule, as the
    robot moves): the velocity approaches (vc, ωc) at the acceleration limits, then
    holds it. Each rollout position is checked against the pedestrians (moved at
    constant velocity when ``predict_pedestrians``), the near walls, the pillars and the
    world's edges, all inflated by the safety margin; a rollout stops at the first
    contact or inside the goal radius. With nothing within reach the rollouts are
    skipped (every gap is then infinite). Rollouts with a contact are inadmissible; the
    admissible one with the highest G = α heading (:func:`dwa_heading`) + β clearance
    + γ velocity wins. When none is admissible the one whose first contact comes
    latest (then: larger clearance) wins.

    ``table`` (>= v_samples · omega_samples, 5) receives one row per sample: vc, ωc,
    smallest gap (m), time of the first contact (s, inf for none), G (−inf when
    inadmissible). ``common`` and ``params`` may be plain tuples of their fields.
    """
    c = CommonParams(*common)
    p = DWAParams(*params)
    v_lo, v_hi, w_lo, w_hi = dynamic_window(v, w, c, p)
    ro = _prepare(x, y, goal, ped_pos, segments, circles, near, c, p)
    nv = p.v_samples
    nw = p.omega_samples
    h = ro.h
    dv = p.accel_mps2 * h
    dw = p.angular_accel_radps2 * h
    hx0 = math.cos(theta)
    hy0 = math.sin(theta)
    w_mid = 0.5 * (w_lo + w_hi)
    choice = _Choice(-INF, v_lo, w_mid, -1.0, -INF, v_lo, w_mid)
    row = 0
    for i in range(nv):
        vc = _sample(v_lo, v_hi, i, nv)
        for j in range(nw):
            wc = _sample(w_lo, w_hi, j, nw)
            min_clear = INF
            t_hit = INF
            at_goal = ro.at_goal
            if ro.check:
                px, py, hx, hy, vr = x, y, hx0, hy0, v
                wr = w - 2.0 * dw - 1.0  # differs from every ω reached: sets cs and sn
                cs = 1.0
                sn = 0.0
                for k in range(1, ro.steps + 1):
                    px, py, hx, hy, vr, wr, cs, sn = _unicycle_step(
                        px, py, hx, hy, vr, w if k == 1 else wr, wr, cs, sn, vc, wc, dv, dw, h
                    )
                    min_clear, t_hit, at_goal, stop = _probe(
                        px, py, k, min_clear, at_goal, ro,
                        ped_pos, ped_vel, ped_radius, segments, near, circles,
                    )  # fmt: skip
                    if stop:
                        break
            heading = 1.0
            if not at_goal and t_hit == INF:
                heading = dwa_heading(
                    x, y, theta, v, w, vc, wc, ro.gx, ro.gy, p.accel_mps2,
                    p.angular_accel_radps2, p.window_time_s,
                )  # fmt: skip
            choice, score = _rank(choice, vc, wc, vc, heading, min_clear, t_hit, c, p)
            _write_row(table, row, vc, wc, min_clear, t_hit, score)
            row += 1
    return _chosen(choice)


@njit(cache=True)
def dwa_holonomic(
    x: float,
    y: float,
    vx: float,
    vy: float,
    goal: np.ndarray,
    ped_pos: np.ndarray,
    ped_vel: np.ndarray,
    ped_radius: np.ndarray,
    segments: np.ndarray,
    circles: np.ndarray,
    common: CommonParams | tuple[Any, ...],
    params: DWAParams | tuple[Any, ...],
    near: np.ndarray,
    table: np.ndarray,
) -> tuple[float, float]:
    """DWA for a holonomic robot: the best (vx, vy) of the dynamic window.

    The window is the disc of velocities within the window time of acceleration of
    (vx, vy) (the points of a ``v_samples`` × ``v_samples`` grid inside it), capped at
    v_max. Each rollout approaches the candidate at the acceleration limit, then holds
    it; checks as in :func:`dwa_unicycle`. The heading term compares the direction of
    the candidate velocity with the direction to the goal from the position predicted
    after the window time at the candidate and braking; it is 0.5 for the zero
    velocity (no direction). Scoring, fallback and ``table`` (rows vx, vy, gap,
    contact time, G) as in :func:`dwa_unicycle`.
    """
    c = CommonParams(*common)
    p = DWAParams(*params)
    ro = _prepare(x, y, goal, ped_pos, segments, circles, near, c, p)
    n = p.v_samples
    accel = p.accel_mps2
    t_w = p.window_time_s
    dv = accel * t_w
    dvh = accel * ro.h
    vmax = c.max_speed_mps
    choice = _Choice(-INF, vx, vy, -1.0, -INF, vx, vy)
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
            at_goal = ro.at_goal
            if ro.check:
                px, py, rx, ry = x, y, vx, vy
                for k in range(1, ro.steps + 1):
                    px, py, rx, ry = _holonomic_step(px, py, rx, ry, cvx, cvy, dvh, ro.h)
                    min_clear, t_hit, at_goal, stop = _probe(
                        px, py, k, min_clear, at_goal, ro,
                        ped_pos, ped_vel, ped_radius, segments, near, circles,
                    )  # fmt: skip
                    if stop:
                        break
            heading = 1.0
            if not at_goal and t_hit == INF:
                heading = _holonomic_heading(x, y, cvx, cvy, speed, ro.gx, ro.gy, accel, t_w)
            choice, score = _rank(choice, cvx, cvy, speed, heading, min_clear, t_hit, c, p)
            _write_row(table, row, cvx, cvy, min_clear, t_hit, score)
            row += 1
    return _chosen(choice)
