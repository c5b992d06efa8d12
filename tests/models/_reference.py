"""Plain-NumPy reference of the SRFM forces and crowd step, and hypothesis strategies.

The reference is written from the model equations of docs/model.md, independently of
``srfm.models._kernels``: it is vectorised over all (agent, source) pairs instead of
looping, and it is only ever used by the tests. For pedestrian i (unit mass):

    F_i     = f_goal + Σ_j f_ped(i, j) + f_robot(i) + Σ_o f_obs(i, o)
    f_goal  = (v_des − v_i) / τ,   v_des = (g_i − x_i) capped at |v_des| ≤ v0_i
    f_ped   = A_p exp((r_i + r_j − d_ij) / B_p) ψ(φ_ij; λ) n_ji
    f_robot = A_r exp((r_i + r_r − d_ir) / B_r) ψ(φ_ir; λ_r) n_ri
    f_obs   = A_o exp((r_i − d_io) / B_o) n_oi   (d_io to the closest point of the wall,
                                                 or to the surface of the pillar)
    ψ(φ; λ) = λ + (1 − λ)(1 + cos φ) / 2

with n the unit vector from the source to i and φ the angle between i's heading (its
velocity direction, else its desired direction) and the direction from i to the source.

Zero distances (documented in ``srfm.models._kernels``): a source at i's centre exerts no
force (the direction is undefined), and an agent with neither a velocity nor a desired
direction has no heading and feels every source isotropically (ψ = 1). "Zero" here is
anything below ``ZERO``; the strategies below only produce distances and speeds that are
either zero up to rounding (< 1e-14) or far above ``ZERO`` (>= 1e-6), so the exact value
of the kernel's own epsilon never matters.

Semi-implicit Euler, compute-then-apply: F from one snapshot, v ← v + F dt, |v| capped
at vmax, x ← x + v dt.
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np
from hypothesis import strategies as st
from numpy.typing import NDArray

import srfm

__all__ = [
    "ZERO",
    "Forces",
    "Scene",
    "crowd_states",
    "forces",
    "obstacle_sets",
    "params_values",
    "robots",
    "scenes",
    "step",
]

FloatArray = NDArray[np.float64]

ZERO = 1e-9


class Forces(NamedTuple):
    """Reference force components, (N, 2) each, and per-agent magnitude sums (N,).

    The magnitude sums (Σ of |term| over the sources of a component) bound the rounding
    error of a component whose terms cancel; tests scale their tolerance with them.
    """

    goal: FloatArray
    pedestrians: FloatArray
    robot: FloatArray
    obstacles: FloatArray
    goal_scale: FloatArray
    pedestrians_scale: FloatArray
    robot_scale: FloatArray
    obstacles_scale: FloatArray

    @property
    def total(self) -> FloatArray:
        return self.goal + self.pedestrians + self.robot + self.obstacles

    @property
    def total_scale(self) -> FloatArray:
        return self.goal_scale + self.pedestrians_scale + self.robot_scale + self.obstacles_scale


def _norm(v: FloatArray) -> FloatArray:
    return np.sqrt(np.sum(v * v, axis=-1))


def _unit(v: FloatArray, length: FloatArray, valid: FloatArray) -> FloatArray:
    """v / length where valid, 0 elsewhere (no division by zero)."""
    safe = np.where(valid, length, 1.0)
    return np.where(valid[..., None], v / safe[..., None], 0.0)


def desired_velocity(pos: FloatArray, goal: FloatArray, v0: FloatArray) -> FloatArray:
    """(g − x) shortened to length v0 when it is longer (docs/model.md, the goal force)."""
    to_goal = goal - pos
    dist = _norm(to_goal)
    far = dist > v0
    scale = np.where(far, v0 / np.where(far, dist, 1.0), 1.0)
    return to_goal * scale[:, None]


def headings(vel: FloatArray, v_des: FloatArray) -> tuple[FloatArray, NDArray[np.bool_]]:
    """Unit heading of each agent (velocity, else desired direction) and whether it has one."""
    speed = _norm(vel)
    dspeed = _norm(v_des)
    moving = speed > ZERO
    wants = dspeed > ZERO
    h = np.where(
        moving[:, None],
        _unit(vel, speed, moving),
        _unit(v_des, dspeed, wants),
    )
    return h, moving | wants


def anisotropy(
    heading: FloatArray, has_heading: NDArray[np.bool_], to_source: FloatArray, lam: float
) -> FloatArray:
    """ψ = λ + (1 − λ)(1 + cos φ)/2 for unit heading (N, 2) and unit to_source (N, K, 2)."""
    cos_phi = np.sum(heading[:, None, :] * to_source, axis=-1)
    psi = lam + (1.0 - lam) * (1.0 + cos_phi) / 2.0
    return np.where(has_heading[:, None], psi, 1.0)


def _repulsion(
    pos: FloatArray,
    sources: FloatArray,
    reach: FloatArray,
    a: float,
    b: float,
    psi_of: Any,
    skip: NDArray[np.bool_] | None = None,
) -> tuple[FloatArray, FloatArray]:
    """Σ_k a exp((reach_ik − d_ik)/b) ψ_ik n_ki over point sources (K, 2); reach (N, K)."""
    away = pos[:, None, :] - sources[None, :, :]  # from source k to agent i
    dist = _norm(away)
    valid = dist > ZERO
    if skip is not None:
        valid &= ~skip
    n = _unit(away, dist, valid)
    psi = psi_of(-n)
    mag = np.where(valid, a * np.exp((reach - dist) / b) * psi, 0.0)
    return np.sum(mag[..., None] * n, axis=1), np.sum(np.abs(mag), axis=1)


def forces(
    crowd: srfm.CrowdState,
    params: srfm.SRFMParams,
    robot: srfm.RobotBody | None = None,
    obstacles: srfm.Obstacles | None = None,
) -> Forces:
    """All four SRFM force components on every pedestrian of ``crowd``."""
    pos, vel, r = crowd.pos, crowd.vel, crowd.radius
    n_agents = pos.shape[0]
    zeros2 = np.zeros((n_agents, 2))
    zeros1 = np.zeros(n_agents)

    v_des = desired_velocity(pos, crowd.goal, crowd.v0)
    goal = (v_des - vel) / params.tau
    goal_scale = (_norm(v_des) + _norm(vel)) / params.tau
    h, has_h = headings(vel, v_des)

    ped, ped_scale = _repulsion(
        pos,
        pos,
        r[:, None] + r[None, :],
        params.a_ped,
        params.b_ped,
        lambda u: anisotropy(h, has_h, u, params.lambda_ped),
        skip=np.eye(n_agents, dtype=bool),
    )

    if robot is None:
        rob, rob_scale = zeros2, zeros1
    else:
        rob, rob_scale = _repulsion(
            pos,
            np.array([[robot.x, robot.y]]),
            (r + robot.radius)[:, None],
            params.a_robot,
            params.b_robot,
            lambda u: anisotropy(h, has_h, u, params.lambda_robot),
        )

    obs, obs_scale = zeros2.copy(), zeros1.copy()
    if obstacles is not None:
        f, s = wall_forces(pos, r, obstacles.segments, params.a_obs, params.b_obs)
        obs += f
        obs_scale += s
        f, s = pillar_forces(pos, r, obstacles.circles, params.a_obs, params.b_obs)
        obs += f
        obs_scale += s
    return Forces(goal, ped, rob, obs, goal_scale, ped_scale, rob_scale, obs_scale)


def closest_points_on_segments(pos: FloatArray, segments: FloatArray) -> FloatArray:
    """(N, M, 2) closest point of each segment (x1, y1, x2, y2) to each position."""
    start = segments[:, :2]
    along = segments[:, 2:] - start
    len2 = np.sum(along * along, axis=-1)
    rel = pos[:, None, :] - start[None, :, :]
    proj = np.sum(rel * along[None, :, :], axis=-1)
    degenerate = len2 <= 0.0
    t = np.where(degenerate, 0.0, proj / np.where(degenerate, 1.0, len2))
    t = np.clip(t, 0.0, 1.0)
    return start[None, :, :] + t[..., None] * along[None, :, :]


def wall_forces(
    pos: FloatArray, radius: FloatArray, segments: FloatArray, a: float, b: float
) -> tuple[FloatArray, FloatArray]:
    """Σ over walls of A_o exp((r_i − d_io)/B_o) n_oi, n from the wall's closest point."""
    if segments.shape[0] == 0:
        return np.zeros_like(pos), np.zeros(pos.shape[0])
    away = pos[:, None, :] - closest_points_on_segments(pos, segments)
    dist = _norm(away)
    valid = dist > ZERO
    n = _unit(away, dist, valid)
    mag = np.where(valid, a * np.exp((radius[:, None] - dist) / b), 0.0)
    return np.sum(mag[..., None] * n, axis=1), np.sum(mag, axis=1)


def pillar_forces(
    pos: FloatArray, radius: FloatArray, circles: FloatArray, a: float, b: float
) -> tuple[FloatArray, FloatArray]:
    """Σ over pillars of A_o exp((r_i − d_io)/B_o) n_oi, d_io to the pillar's surface."""
    if circles.shape[0] == 0:
        return np.zeros_like(pos), np.zeros(pos.shape[0])
    away = pos[:, None, :] - circles[None, :, :2]
    to_centre = _norm(away)
    valid = to_centre > ZERO
    n = _unit(away, to_centre, valid)
    surface = to_centre - circles[None, :, 2]
    mag = np.where(valid, a * np.exp((radius[:, None] - surface) / b), 0.0)
    return np.sum(mag[..., None] * n, axis=1), np.sum(mag, axis=1)


def integrate(
    pos: FloatArray, vel: FloatArray, force: FloatArray, vmax: FloatArray, dt: float
) -> tuple[FloatArray, FloatArray]:
    """Semi-implicit Euler with a speed cap; returns new (pos, vel), inputs untouched."""
    v = vel + force * dt
    speed = _norm(v)
    over = speed > vmax
    v = np.where(over[:, None], v * (vmax / np.where(over, speed, 1.0))[:, None], v)
    return pos + v * dt, v


def step(
    crowd: srfm.CrowdState,
    dt: float,
    params: srfm.SRFMParams,
    robot: srfm.RobotBody | None = None,
    obstacles: srfm.Obstacles | None = None,
) -> tuple[FloatArray, FloatArray]:
    """New (pos, vel) after one compute-then-apply step; ``crowd`` is not modified."""
    f = forces(crowd, params, robot, obstacles)
    return integrate(crowd.pos, crowd.vel, f.total, crowd.vmax, dt)


# --------------------------------------------------------------------------------------
# Hypothesis strategies. Coordinates mix a coarse binary grid (so coincident agents,
# agents on walls and agents at their goal are common) with arbitrary floats.

WORLD = 4.0


def _snap(x: float) -> float:
    return 0.0 if abs(x) < 1e-6 else x


coords = st.one_of(
    st.integers(0, int(WORLD * 8)).map(lambda k: k / 8.0),
    st.floats(0.0, WORLD).map(_snap),
)
points = st.tuples(coords, coords)
velocities = st.tuples(
    st.floats(-1.5, 1.5).map(_snap),
    st.floats(-1.5, 1.5).map(_snap),
)


@st.composite
def crowd_states(draw: st.DrawFn, min_n: int = 1, max_n: int = 7) -> srfm.CrowdState:
    """A small crowd with random positions, velocities, goals, radii and speeds."""
    n = draw(st.integers(min_n, max_n))
    pos = draw(st.lists(points, min_size=n, max_size=n))
    goal = draw(st.lists(points, min_size=n, max_size=n))
    vel = draw(st.lists(velocities, min_size=n, max_size=n))
    radius = draw(st.lists(st.floats(0.0, 0.5), min_size=n, max_size=n))
    v0 = draw(st.lists(st.floats(0.0, 1.5).map(_snap), min_size=n, max_size=n))
    vmax = draw(st.lists(st.floats(0.0, 2.0).map(_snap), min_size=n, max_size=n))
    return srfm.CrowdState.create(
        pos=np.array(pos, dtype=np.float64).reshape(n, 2),
        goal=np.array(goal, dtype=np.float64).reshape(n, 2),
        vel=np.array(vel, dtype=np.float64).reshape(n, 2),
        radius=radius,
        v0=v0,
        vmax=vmax,
    )


@st.composite
def params_values(draw: st.DrawFn) -> srfm.SRFMParams:
    """Valid SRFM parameters over a plausible range (exponents stay moderate)."""
    return srfm.SRFMParams(
        a_ped=draw(st.floats(0.0, 5.0)),
        b_ped=draw(st.floats(0.1, 2.0)),
        lambda_ped=draw(st.floats(0.0, 1.0)),
        tau=draw(st.floats(0.1, 2.0)),
        a_robot=draw(st.floats(0.0, 10.0)),
        b_robot=draw(st.floats(0.1, 2.0)),
        lambda_robot=draw(st.floats(0.0, 1.0)),
        a_obs=draw(st.floats(0.0, 30.0)),
        b_obs=draw(st.floats(0.05, 0.5)),
    )


robots = st.builds(
    lambda p, r: srfm.RobotBody(x=p[0], y=p[1], radius=r), points, st.floats(0.0, 0.5)
)


@st.composite
def _segment(draw: st.DrawFn) -> tuple[float, float, float, float]:
    x1, y1 = draw(points)
    if draw(st.booleans()):
        x2, y2 = x1, y1  # a degenerate wall: a single point
    else:
        x2, y2 = draw(points.filter(lambda p: (p[0] - x1) ** 2 + (p[1] - y1) ** 2 > 1e-6))
    return x1, y1, x2, y2


@st.composite
def obstacle_sets(draw: st.DrawFn) -> srfm.Obstacles:
    """Up to three walls (possibly degenerate) and three pillars (possibly of radius 0)."""
    segments = draw(st.lists(_segment(), max_size=3))
    circles = draw(st.lists(st.tuples(coords, coords, st.floats(0.0, 1.0)), max_size=3))
    return srfm.Obstacles.create(segments=segments, circles=circles)


class Scene(NamedTuple):
    crowd: srfm.CrowdState
    params: srfm.SRFMParams
    robot: srfm.RobotBody | None
    obstacles: srfm.Obstacles


@st.composite
def scenes(draw: st.DrawFn, min_n: int = 1, max_n: int = 7) -> Scene:
    """A crowd, parameters, an optional robot and some obstacles."""
    return Scene(
        crowd=draw(crowd_states(min_n, max_n)),
        params=draw(params_values()),
        robot=draw(st.none() | robots),
        obstacles=draw(obstacle_sets()),
    )
