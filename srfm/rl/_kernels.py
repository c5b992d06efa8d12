"""numba kernels of the gymnasium environment: one fused call per environment step.

The crowd dynamics are not re-implemented here: :func:`env_step` calls the core
kernels of :mod:`srfm.models._kernels` (the same ``twin_step_serial`` /
``step_serial`` and ``mark_arrivals`` that :class:`srfm.TwinSimulator` calls), and the
robot update and event checks below reproduce :func:`srfm.apply_command` and the
simulator's robot checks operation for operation, so that an environment episode is
bit-identical to a :class:`~srfm.TwinSimulator` episode under the same commands
(tested in ``tests/rl/test_equivalence.py``).

Layouts (all C-contiguous):

- ``crowd`` (6, N, 2) float64: factual pos, vel, goal, counterfactual pos, vel, goal;
- ``agent`` (3, N) float64: radius, desired speed v0, speed cap vmax;
- ``robot`` (7,) float64: x, y, theta, vx, vy, v, omega (:class:`srfm.RobotState`);
- ``cfg`` (CFG_SIZE,) float64: the ``C_*`` entries below;
- ``flags`` (4, N) bool: factual arrived, counterfactual arrived, factual new,
  counterfactual new (as the simulator's arrival bookkeeping);
- ``obs`` (OBS_SIZE(K),) float32, see :func:`build_observation`.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from srfm.models._kernels import (
    EPS,
    _agent_forces,
    mark_arrivals,
    nearest_clearance,
    segment_distance,
    step_serial,
    twin_step_serial,
)

# crowd rows
F_POS, F_VEL, F_GOAL, C_POS, C_VEL, C_GOAL = 0, 1, 2, 3, 4, 5
# agent rows
A_RADIUS, A_V0, A_VMAX = 0, 1, 2
# robot entries
R_X, R_Y, R_THETA, R_VX, R_VY, R_V, R_OMEGA = 0, 1, 2, 3, 4, 5, 6
ROBOT_SIZE = 7

# cfg entries
C_DT = 0
C_ROBOT_RADIUS = 1
C_VMAX = 2
C_WMAX = 3
C_ACCEL = 4
C_ANG_ACCEL = 5
C_GOAL_RADIUS = 6
C_HOLONOMIC = 7  # 1.0 for a holonomic robot
C_X_MIN, C_X_MAX, C_Y_MIN, C_Y_MAX = 8, 9, 10, 11
C_GOAL_X, C_GOAL_Y = 12, 13
C_ZONE = 14  # social zone radius (m)
C_K1, C_K2 = 15, 16
C_SUCCESS, C_TIMEOUT_PEN, C_COLLISION_PEN = 17, 18, 19
C_GOAL_DIST0 = 20  # goal distance at reset (m), the r_dist normaliser
C_GOAL_SCALE = 21  # goal-distance normaliser of the observation (m)
C_VEL_SCALE = 22  # relative-velocity normaliser of the observation (m/s)
C_PED_GOAL_RADIUS = 23
C_TWIN = 24  # 1.0: step the full counterfactual crowd
C_REGOAL = 25  # 1.0: arrivals get new goals (in Python), else they are marked arrived
C_HORIZON = 26  # horizon in steps
C_MAX_PEDS = 27  # K, observed pedestrian slots
C_OBSTACLES = 28  # 1.0 when there are walls or pillars
CFG_SIZE = 29

# step results (``out``)
O_REWARD, O_R_DIST, O_R_DIV, O_R_TERM, O_N_NEW_F, O_N_NEW_C = 0, 1, 2, 3, 4, 5
OUT_SIZE = 6

# event codes, in the simulator's order of checks
EV_NONE, EV_COLLISION, EV_OBSTACLE, EV_OUT_OF_BOUNDS, EV_GOAL, EV_TIMEOUT = 0, 1, 2, 3, 4, 5

# observation layout
OBS_GOAL = 0  # goal distance / goal scale, cos, sin of the goal bearing (robot frame)
OBS_VEL = 3  # the robot's velocity, normalised
OBS_ACTION = 5  # the last action, in [-1, 1]
OBS_FLAGS = 7  # success, terminated
OBS_PEDS = 9  # K slots of PED_FEATURES
PED_FEATURES = 6  # present, distance / zone, cos, sin, relative vx, vy (robot frame)

_TWO_PI = 2.0 * math.pi


def obs_size(max_peds: int) -> int:
    """Length of the observation vector with ``max_peds`` pedestrian slots."""
    return OBS_PEDS + PED_FEATURES * max_peds


@njit(cache=True)
def _wrap(angle: float) -> float:
    """``srfm.models.robot._wrap``: math.remainder(angle, 2π) mapped into (−π, π], exactly.

    numba has no ``math.remainder``; the IEEE remainder is reduced from the exact
    ``fmod`` by 4π (which keeps the parity of the quotient) with subtractions that are
    exact by Sterbenz's lemma, ties to an even quotient as ``math.remainder`` does.
    """
    y = _TWO_PI
    h = 0.5 * y
    r = np.fmod(angle, 2.0 * y)
    if r >= 0.0:
        if r <= h:
            out = r
        elif r < 3.0 * h:
            out = r - y
        else:
            out = r - 2.0 * y
    elif r >= -h:
        out = r
    elif r > -3.0 * h:
        out = r + y
    else:
        out = r + 2.0 * y
    return math.pi if out == -math.pi else out


@njit(cache=True, inline="always")
def _split(x: float) -> tuple[float, float]:
    t = x * 134217729.0  # Veltkamp: 2**27 + 1
    hi = t - (t - x)
    return hi, x - hi


@njit(cache=True, inline="always")
def _exact_square(x: float) -> tuple[float, float]:
    """(hi, lo) with hi + lo == x * x exactly (Dekker)."""
    hi, lo = _split(x)
    p = hi * hi
    q = hi * lo + lo * hi
    z = p + q
    return z, p - z + q + lo * lo


@njit(cache=True)
def py_hypot(x: float, y: float) -> float:
    """CPython's ``math.hypot(x, y)``, bit for bit (numba's ``math.hypot`` is libm's,
    which differs in the last bit for about 0.5 % of inputs).

    The algorithm of CPython's ``vector_norm``: scale by a power of two, sum the exact
    squares in extended precision, take the square root, apply one differential
    correction. Finite inputs only (the simulation has no others).
    """
    ax = abs(x)
    ay = abs(y)
    mx = max(ax, ay)
    if mx == 0.0 or math.isinf(mx):
        return mx
    if ax != ax or ay != ay:
        return math.nan
    tiny = 2.2250738585072014e-308  # DBL_MIN
    outer = 1.0
    _, e = math.frexp(mx)
    if e < -1023:
        ax /= tiny
        ay /= tiny
        outer = tiny
        _, e = math.frexp(mx / tiny)
    scale = math.ldexp(1.0, -e)
    csum = 1.0
    frac1 = 0.0
    frac2 = 0.0
    for k in range(2):
        v = (ax if k == 0 else ay) * scale
        phi, plo = _exact_square(v)
        s = csum + phi
        frac2 += (csum - s) + phi
        csum = s
        frac1 += plo
    h = math.sqrt(csum - 1.0 + (frac1 + frac2))
    phi, plo = _exact_square(h)
    phi = -phi
    plo = -plo
    s = csum + phi
    frac2 += (csum - s) + phi
    csum = s
    frac1 += plo
    corr = csum - 1.0 + (frac1 + frac2)
    h += corr / (2.0 * h)
    return outer * (h / scale)


@njit(cache=True)
def action_to_command(
    a0: float, a1: float, theta: float, holonomic: bool, vmax: float, wmax: float
) -> tuple[float, float]:
    """Scale an action in [−1, 1]² (clipped; NaN-free input assumed) to a command.

    Unicycle: (v, ω) = (a0 v_max, a1 ω_max). Holonomic: the action is a velocity in
    the robot frame, (a0, a1) v_max, rotated into the world frame by the heading.
    """
    a0 = min(1.0, max(-1.0, a0))
    a1 = min(1.0, max(-1.0, a1))
    if not holonomic:
        return a0 * vmax, a1 * wmax
    cx = a0 * vmax
    cy = a1 * vmax
    c = math.cos(theta)
    s = math.sin(theta)
    return cx * c - cy * s, cx * s + cy * c


@njit(cache=True, inline="always")
def _clip(value: float, lo: float, hi: float) -> float:
    # The same comparisons as srfm.models.robot._clip.
    return lo if value < lo else hi if value > hi else value


@njit(cache=True)
def apply_command_kernel(robot: np.ndarray, c0: float, c1: float, cfg: np.ndarray) -> None:
    """:func:`srfm.apply_command` in place on ``robot`` (7,), operation for operation."""
    dt = cfg[C_DT]
    dv_max = cfg[C_ACCEL] * dt
    theta = robot[R_THETA]
    if cfg[C_HOLONOMIC] == 0.0:
        vmax = cfg[C_VMAX]
        wmax = cfg[C_WMAX]
        dw_max = cfg[C_ANG_ACCEL] * dt
        v = _clip(_clip(c0, -vmax, vmax), robot[R_V] - dv_max, robot[R_V] + dv_max)
        w = _clip(_clip(c1, -wmax, wmax), robot[R_OMEGA] - dw_max, robot[R_OMEGA] + dw_max)
        mid = theta + 0.5 * w * dt
        vx = v * math.cos(mid)
        vy = v * math.sin(mid)
        robot[R_X] = robot[R_X] + vx * dt
        robot[R_Y] = robot[R_Y] + vy * dt
        robot[R_THETA] = _wrap(theta + w * dt)
        robot[R_VX] = vx
        robot[R_VY] = vy
        robot[R_V] = v
        robot[R_OMEGA] = w
        return
    speed = py_hypot(c0, c1)
    if speed > cfg[C_VMAX]:
        c0 *= cfg[C_VMAX] / speed
        c1 *= cfg[C_VMAX] / speed
    ddx = c0 - robot[R_VX]
    ddy = c1 - robot[R_VY]
    dnorm = py_hypot(ddx, ddy)
    if dnorm > dv_max:
        ddx *= dv_max / dnorm
        ddy *= dv_max / dnorm
    vx = robot[R_VX] + ddx
    vy = robot[R_VY] + ddy
    speed = py_hypot(vx, vy)
    new_theta = math.atan2(vy, vx) if speed > 1e-9 else theta
    robot[R_X] = robot[R_X] + vx * dt
    robot[R_Y] = robot[R_Y] + vy * dt
    robot[R_THETA] = new_theta
    robot[R_VX] = vx
    robot[R_VY] = vy
    robot[R_V] = speed
    robot[R_OMEGA] = _wrap(new_theta - theta) / dt


@njit(cache=True)
def robot_event(
    f_pos: np.ndarray,
    radius: np.ndarray,
    robot: np.ndarray,
    cfg: np.ndarray,
    segments: np.ndarray,
    pillar_xy: np.ndarray,
    pillar_r: np.ndarray,
    step_index: int,
) -> int:
    """The simulator's robot checks at a sample, in its order; an ``EV_*`` code."""
    x = robot[R_X]
    y = robot[R_Y]
    rr = cfg[C_ROBOT_RADIUS]
    clearance, _ = nearest_clearance(f_pos, radius, x, y)
    if clearance < rr:
        return EV_COLLISION
    if cfg[C_OBSTACLES] != 0.0:
        c2, _ = nearest_clearance(pillar_xy, pillar_r, x, y)
        if c2 < rr or segment_distance(segments, x, y) < rr:
            return EV_OBSTACLE
    if not (cfg[C_X_MIN] <= x <= cfg[C_X_MAX] and cfg[C_Y_MIN] <= y <= cfg[C_Y_MAX]):
        return EV_OUT_OF_BOUNDS
    if py_hypot(x - cfg[C_GOAL_X], y - cfg[C_GOAL_Y]) < cfg[C_GOAL_RADIUS]:
        return EV_GOAL
    if step_index >= cfg[C_HORIZON]:
        return EV_TIMEOUT
    return EV_NONE


@njit(cache=True)
def one_step_deviation(
    crowd: np.ndarray,
    agent: np.ndarray,
    params: np.ndarray,
    body: np.ndarray,
    segments: np.ndarray,
    circles: np.ndarray,
    dt: float,
    zone: float,
) -> float:
    """r_div: the one-step counterfactual deviation summed over the social zone (m).

    From the current factual state and the robot ``body`` (3,) = (x, y, radius), each
    pedestrian i closer than ``zone`` to the robot centre is stepped twice, with and
    without the robot force (all other forces from the same snapshot, the same
    semi-implicit Euler step and speed cap as the simulator); r_div = Σ_i
    |x̂_i(with robot) − x̂_i(without robot)|. Exactly 0 when A_r = 0.
    """
    pos = crowd[F_POS]
    vel = crowd[F_VEL]
    goal = crowd[F_GOAL]
    radius = agent[A_RADIUS]
    v0 = agent[A_V0]
    vmax = agent[A_VMAX]
    z2 = zone * zone
    total = 0.0
    for i in range(pos.shape[0]):
        dx = pos[i, 0] - body[0]
        dy = pos[i, 1] - body[1]
        if not dx * dx + dy * dy < z2:
            continue
        g0, g1, p0, p1, r0, r1, o0, o1 = _agent_forces(
            i, pos, vel, goal, radius, v0, params, body, True, segments, circles
        )
        px = pos[i, 0]
        py = pos[i, 1]
        # With the robot (the sum in the simulator's order) ...
        vx = vel[i, 0] + (g0 + p0 + r0 + o0) * dt
        vy = vel[i, 1] + (g1 + p1 + r1 + o1) * dt
        speed = math.sqrt(vx * vx + vy * vy)
        if speed > vmax[i]:
            vx *= vmax[i] / speed
            vy *= vmax[i] / speed
        # ... and without it (as the counterfactual twin adds a zero robot term).
        ux = vel[i, 0] + (g0 + p0 + 0.0 + o0) * dt
        uy = vel[i, 1] + (g1 + p1 + 0.0 + o1) * dt
        speed = math.sqrt(ux * ux + uy * uy)
        if speed > vmax[i]:
            ux *= vmax[i] / speed
            uy *= vmax[i] / speed
        ex = (px + vx * dt) - (px + ux * dt)
        ey = (py + vy * dt) - (py + uy * dt)
        total += math.sqrt(ex * ex + ey * ey)
    return total


@njit(cache=True, inline="always")
def _unit_clip(x: float) -> float:
    return min(1.0, max(-1.0, x))


@njit(cache=True)
def build_observation(
    ped_pos: np.ndarray,
    ped_vel: np.ndarray,
    robot: np.ndarray,
    last_action: np.ndarray,
    success: bool,
    terminated: bool,
    cfg: np.ndarray,
    dist_buf: np.ndarray,
    idx_buf: np.ndarray,
    obs: np.ndarray,
) -> int:
    """Write the observation (float32, every entry in [−1, 1]) into ``obs``.

    Layout (robot frame: x forward along the heading, y to the left):

    - [0:3] goal: min(distance / goal scale, 1), cos and sin of the goal bearing;
    - [3:5] the robot's velocity: unicycle (v / v_max, ω / ω_max); holonomic the
      robot-frame (vx, vy) / v_max;
    - [5:7] the last action (the agent's, clipped to [−1, 1]; zeros after reset);
    - [7:9] success and terminated flags (1.0 or 0.0);
    - then K slots, closest pedestrian first (ties by index), of the pedestrians whose
      centre is closer than the social zone to the robot centre (the same test as
      :func:`srfm.models._kernels.within_range`): present (1.0), distance / zone, cos
      and sin of the bearing, relative velocity (pedestrian − robot) / velocity scale;
      empty slots are zeros.

    ``ped_pos``/``ped_vel`` may hold every pedestrian or only those a planner observes
    within the zone: the result is the same. Returns the number of pedestrians in the
    zone (which may exceed K).
    """
    x = robot[R_X]
    y = robot[R_Y]
    c = math.cos(robot[R_THETA])
    s = math.sin(robot[R_THETA])
    gdx = cfg[C_GOAL_X] - x
    gdy = cfg[C_GOAL_Y] - y
    gd = math.sqrt(gdx * gdx + gdy * gdy)
    obs[OBS_GOAL] = min(1.0, gd / cfg[C_GOAL_SCALE])
    if gd > EPS:
        obs[OBS_GOAL + 1] = (c * gdx + s * gdy) / gd
        obs[OBS_GOAL + 2] = (-s * gdx + c * gdy) / gd
    else:
        obs[OBS_GOAL + 1] = 1.0
        obs[OBS_GOAL + 2] = 0.0
    rvx = robot[R_VX]
    rvy = robot[R_VY]
    if cfg[C_HOLONOMIC] == 0.0:
        obs[OBS_VEL] = _unit_clip(robot[R_V] / cfg[C_VMAX])
        obs[OBS_VEL + 1] = _unit_clip(robot[R_OMEGA] / cfg[C_WMAX])
    else:
        obs[OBS_VEL] = _unit_clip((c * rvx + s * rvy) / cfg[C_VMAX])
        obs[OBS_VEL + 1] = _unit_clip((-s * rvx + c * rvy) / cfg[C_VMAX])
    obs[OBS_ACTION] = _unit_clip(last_action[0])
    obs[OBS_ACTION + 1] = _unit_clip(last_action[1])
    obs[OBS_FLAGS] = 1.0 if success else 0.0
    obs[OBS_FLAGS + 1] = 1.0 if terminated else 0.0

    # Pedestrians in the zone, insertion-sorted by squared distance (stable).
    zone = cfg[C_ZONE]
    z2 = zone * zone
    k = 0
    for i in range(ped_pos.shape[0]):
        dx = ped_pos[i, 0] - x
        dy = ped_pos[i, 1] - y
        d2 = dx * dx + dy * dy
        if not d2 < z2:
            continue
        j = k
        while j > 0 and dist_buf[j - 1] > d2:
            dist_buf[j] = dist_buf[j - 1]
            idx_buf[j] = idx_buf[j - 1]
            j -= 1
        dist_buf[j] = d2
        idx_buf[j] = i
        k += 1
    slots = int(cfg[C_MAX_PEDS])
    vscale = cfg[C_VEL_SCALE]
    for m in range(slots):
        base = OBS_PEDS + PED_FEATURES * m
        if m >= k:
            for f in range(PED_FEATURES):
                obs[base + f] = 0.0
            continue
        i = idx_buf[m]
        dx = ped_pos[i, 0] - x
        dy = ped_pos[i, 1] - y
        d = math.sqrt(dist_buf[m])
        obs[base] = 1.0
        obs[base + 1] = min(1.0, d / zone)
        if d > EPS:
            obs[base + 2] = (c * dx + s * dy) / d
            obs[base + 3] = (-s * dx + c * dy) / d
        else:
            obs[base + 2] = 1.0
            obs[base + 3] = 0.0
        wx = ped_vel[i, 0] - rvx
        wy = ped_vel[i, 1] - rvy
        obs[base + 4] = _unit_clip((c * wx + s * wy) / vscale)
        obs[base + 5] = _unit_clip((-s * wx + c * wy) / vscale)
    return k


@njit(cache=True)
def reward_and_observation(
    crowd: np.ndarray,
    agent: np.ndarray,
    params: np.ndarray,
    robot: np.ndarray,
    body: np.ndarray,
    cfg: np.ndarray,
    segments: np.ndarray,
    circles: np.ndarray,
    event: int,
    last_action: np.ndarray,
    dist_buf: np.ndarray,
    idx_buf: np.ndarray,
    obs: np.ndarray,
    out: np.ndarray,
) -> None:
    """Reward terms into ``out`` and the observation into ``obs`` after a step.

    r = r_term − k1 r_dist − k2 r_div, with r_dist = min(goal distance / goal distance
    at reset, 1) (the paper's range [0, 1]), r_div from :func:`one_step_deviation` at
    the robot's new position, and r_term = +success reward at the goal, −timeout
    penalty on timeout, −collision penalty on a collision with a pedestrian or an
    obstacle or on leaving the world.
    """
    body[0] = robot[R_X]
    body[1] = robot[R_Y]
    gdx = cfg[C_GOAL_X] - robot[R_X]
    gdy = cfg[C_GOAL_Y] - robot[R_Y]
    r_dist = min(1.0, math.sqrt(gdx * gdx + gdy * gdy) / cfg[C_GOAL_DIST0])
    r_div = one_step_deviation(
        crowd, agent, params, body, segments, circles, cfg[C_DT], cfg[C_ZONE]
    )
    if event == EV_GOAL:
        r_term = cfg[C_SUCCESS]
    elif event == EV_TIMEOUT:
        r_term = -cfg[C_TIMEOUT_PEN]
    elif event != EV_NONE:
        r_term = -cfg[C_COLLISION_PEN]
    else:
        r_term = 0.0
    out[O_R_DIST] = r_dist
    out[O_R_DIV] = r_div
    out[O_R_TERM] = r_term
    out[O_REWARD] = r_term - cfg[C_K1] * r_dist - cfg[C_K2] * r_div
    build_observation(
        crowd[F_POS],
        crowd[F_VEL],
        robot,
        last_action,
        event == EV_GOAL,
        event != EV_NONE,
        cfg,
        dist_buf,
        idx_buf,
        obs,
    )


@njit(cache=True)
def env_step(
    crowd: np.ndarray,
    agent: np.ndarray,
    flags: np.ndarray,
    params: np.ndarray,
    robot: np.ndarray,
    body: np.ndarray,
    cfg: np.ndarray,
    segments: np.ndarray,
    circles: np.ndarray,
    pillar_xy: np.ndarray,
    pillar_r: np.ndarray,
    force_buf: np.ndarray,
    action: np.ndarray,
    step_index: int,
    dist_buf: np.ndarray,
    idx_buf: np.ndarray,
    obs: np.ndarray,
    out: np.ndarray,
) -> int:
    """One environment step (sample k = ``step_index`` to k + 1); returns the event.

    1. the action becomes a command (:func:`action_to_command`); the next robot state
       is computed (:func:`apply_command_kernel`);
    2. the crowds take one SRFM step with the robot where it is at sample k: the
       factual and, when ``cfg[C_TWIN]``, the counterfactual crowd, through the core
       ``twin_step_serial`` / ``step_serial`` kernels; new arrivals are flagged;
    3. the robot moves; in scenarios without re-goaling new arrivals are marked;
    4. the robot event at k + 1;
    5. unless factual pedestrians arrived in a re-goaling scenario (then the caller
       sets their new goals and calls :func:`reward_and_observation` itself), the
       reward terms and the observation.

    ``action`` (2,) is the agent's action; it is clipped to [−1, 1] and stored as the
    last action in ``action`` itself.
    """
    a0 = min(1.0, max(-1.0, action[0]))
    a1 = min(1.0, max(-1.0, action[1]))
    action[0] = a0
    action[1] = a1
    c0, c1 = action_to_command(
        a0, a1, robot[R_THETA], cfg[C_HOLONOMIC] != 0.0, cfg[C_VMAX], cfg[C_WMAX]
    )
    body[0] = robot[R_X]
    body[1] = robot[R_Y]
    apply_command_kernel(robot, c0, c1, cfg)
    dt = cfg[C_DT]
    goal_radius = cfg[C_PED_GOAL_RADIUS]
    radius = agent[A_RADIUS]
    if cfg[C_TWIN] != 0.0:
        twin_step_serial(
            crowd[F_POS],
            crowd[F_VEL],
            crowd[F_GOAL],
            crowd[C_POS],
            crowd[C_VEL],
            crowd[C_GOAL],
            radius,
            agent[A_V0],
            agent[A_VMAX],
            params,
            body,
            segments,
            circles,
            dt,
            force_buf,
            goal_radius,
            flags[0],
            flags[1],
            flags[2],
            flags[3],
        )
    else:
        step_serial(
            crowd[F_POS],
            crowd[F_VEL],
            crowd[F_GOAL],
            radius,
            agent[A_V0],
            agent[A_VMAX],
            params,
            body,
            True,
            segments,
            circles,
            dt,
            force_buf,
        )
        mark_arrivals(crowd[F_POS], crowd[F_GOAL], goal_radius, flags[0], flags[2])
    n_f = 0
    n_c = 0
    n = radius.shape[0]
    for i in range(n):
        if flags[2, i]:
            n_f += 1
        if cfg[C_TWIN] != 0.0 and flags[3, i]:
            n_c += 1
    if cfg[C_REGOAL] == 0.0:
        for i in range(n):
            if flags[2, i]:
                flags[0, i] = True
            if flags[3, i]:
                flags[1, i] = True
    out[O_N_NEW_F] = n_f
    out[O_N_NEW_C] = n_c
    event = robot_event(
        crowd[F_POS], radius, robot, cfg, segments, pillar_xy, pillar_r, step_index + 1
    )
    if cfg[C_REGOAL] == 0.0 or n_f == 0:
        reward_and_observation(
            crowd,
            agent,
            params,
            robot,
            body,
            cfg,
            segments,
            circles,
            event,
            action,
            dist_buf,
            idx_buf,
            obs,
            out,
        )
    return event
