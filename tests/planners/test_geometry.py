"""Geometry of the classical planners: VO cones, ORCA half-planes and linear programs,
the DWA window, the velocity-to-command conversion, the social force."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from srfm.models.robot import RobotConfig, RobotState, apply_command
from srfm.models.state import Obstacles
from srfm.planners import (
    DWAConfig,
    DWAPlanner,
    ORCAConfig,
    ORCAPlanner,
    SocialForcePlanner,
    VelocityObstaclePlanner,
    _dwa_kernels,
    _geometry,
    _orca_kernels,
)
from srfm.planners._base import Observation, PlannerContext
from srfm.planners.orca import orca_halfplane
from srfm.planners.velocity_obstacles import in_velocity_obstacle
from srfm.scenarios import WorldBounds

DT = 1.0 / 15.0
coord = st.floats(-5.0, 5.0, allow_nan=False)
speed = st.floats(-2.0, 2.0, allow_nan=False)


def context(robot: RobotConfig | None = None, obstacles: Obstacles | None = None) -> PlannerContext:
    return PlannerContext(
        scenario="test",
        seed=0,
        dt_s=DT,
        horizon_steps=100,
        robot=robot or RobotConfig(),
        robot_goal=np.array([10.0, 0.0]),
        world=WorldBounds(x_min=-100.0, x_max=100.0, y_min=-100.0, y_max=100.0),
        obstacles=obstacles or Obstacles(),
    )


def observation(
    robot: RobotState,
    goal: tuple[float, float],
    peds: list[tuple[float, float, float, float]] = (),  # type: ignore[assignment]
    radius: float = 0.3,
) -> Observation:
    arr = np.array(peds, dtype=np.float64).reshape(-1, 4)
    return Observation(
        step=0,
        time_s=0.0,
        robot=robot,
        robot_goal=np.array(goal, dtype=np.float64),
        ped_ids=np.arange(arr.shape[0]),
        ped_pos=np.ascontiguousarray(arr[:, :2]),
        ped_vel=np.ascontiguousarray(arr[:, 2:]),
        ped_radius=np.full(arr.shape[0], radius),
        obstacles=Obstacles(),
    )


# --------------------------------------------------------------------------- VO


@pytest.mark.parametrize(
    ("rel_pos", "obstacle_vel", "velocity", "horizon", "inside"),
    [
        # Static disc at 2 m, combined radius 0.5: half-angle asin(0.25) = 14.48°.
        ((2.0, 0.0), (0.0, 0.0), (1.0, 0.2), None, True),  # 11.31° off the axis
        ((2.0, 0.0), (0.0, 0.0), (1.0, 0.3), None, False),  # 16.70°
        ((2.0, 0.0), (0.0, 0.0), (1.0, -0.25), None, True),  # 14.04°
        ((2.0, 0.0), (0.0, 0.0), (1.0, -0.26), None, False),  # 14.57°
        ((2.0, 0.0), (0.0, 0.0), (-1.0, 0.0), None, False),  # moving away
        ((2.0, 0.0), (0.0, 0.0), (0.0, 0.0), None, False),  # standing still
        # Truncated cone: contact after (2 − 0.5) / |u| seconds.
        ((2.0, 0.0), (0.0, 0.0), (1.0, 0.0), 1.0, False),  # 1.5 s > 1 s
        ((2.0, 0.0), (0.0, 0.0), (1.0, 0.0), 1.5, True),  # exactly at the horizon
        ((2.0, 0.0), (0.0, 0.0), (2.0, 0.0), 1.0, True),  # 0.75 s
        # Moving obstacle: the cone is shifted by its velocity.
        ((2.0, 0.0), (0.5, 0.0), (1.0, 0.0), None, True),  # closing at 0.5 m/s: 3 s
        ((2.0, 0.0), (0.5, 0.0), (1.0, 0.0), 2.0, False),
        ((2.0, 0.0), (0.5, 0.0), (0.5, 0.5), None, False),  # relative motion sideways
        ((2.0, 0.0), (-1.0, 0.0), (0.0, 0.0), None, True),  # it walks into a standing robot
        ((2.0, 0.0), (-1.0, 0.0), (0.0, 1.0), None, False),  # 45°, outside the 14.48° cone
        # Already overlapping: closing velocities are inside, opening ones outside.
        ((0.3, 0.0), (0.0, 0.0), (0.1, 0.0), 0.5, True),
        ((0.3, 0.0), (0.0, 0.0), (-0.1, 0.0), 0.5, False),
    ],
)
def test_vo_cone_membership_hand_cases(
    rel_pos: tuple[float, float],
    obstacle_vel: tuple[float, float],
    velocity: tuple[float, float],
    horizon: float | None,
    inside: bool,
) -> None:
    assert in_velocity_obstacle(rel_pos, obstacle_vel, velocity, 0.5, horizon) is inside


def test_time_to_collision_hand_cases() -> None:
    assert _geometry.time_to_collision(3.0, 4.0, 0.6, 0.8, 1.0) == pytest.approx(4.0)
    assert _geometry.time_to_collision(3.0, 4.0, -0.6, -0.8, 1.0) == math.inf
    assert _geometry.time_to_collision(0.1, 0.0, 1.0, 0.0, 1.0) == 0.0
    # A static capsule: the wall y = 2 for x in [-1, 1], radius 0.5.
    assert _geometry.time_to_segment(0.0, 0.0, 0.0, 1.0, -1.0, 2.0, 1.0, 2.0, 0.5) == pytest.approx(
        1.5
    )
    assert _geometry.time_to_segment(0.0, 0.0, 0.0, 1.0, 1.0, 2.0, 3.0, 2.0, 0.5) == math.inf
    # Past the end of the wall: the rounded end cap, a disc of 0.5 around (1, 2).
    t = _geometry.time_to_segment(1.3, 0.0, 0.0, 1.0, -1.0, 2.0, 1.0, 2.0, 0.5)
    assert t == pytest.approx(2.0 - math.sqrt(0.25 - 0.09))
    assert _geometry.time_to_segment(0.0, 1.7, 0.0, 1.0, -1.0, 2.0, 1.0, 2.0, 0.5) == 0.0
    # The world's edges: the box [0, 10] × [0, 5], from (2, 4) with radius 0.5.
    assert _geometry.time_to_edges(2.0, 4.0, 0.0, 1.0, 0.5, 0.0, 10.0, 0.0, 5.0) == pytest.approx(
        0.5
    )
    assert _geometry.time_to_edges(2.0, 4.0, -1.0, 1.0, 0.5, 0.0, 10.0, 0.0, 5.0) == pytest.approx(
        0.5
    )
    assert _geometry.time_to_edges(2.0, 4.0, -3.0, 0.0, 0.5, 0.0, 10.0, 0.0, 5.0) == pytest.approx(
        0.5
    )
    assert _geometry.time_to_edges(2.0, 4.0, 0.0, 0.0, 0.5, 0.0, 10.0, 0.0, 5.0) == math.inf
    assert _geometry.time_to_edges(2.0, 4.7, 0.1, 0.1, 0.5, 0.0, 10.0, 0.0, 5.0) == 0.0


def closest_approach(px: float, py: float, wx: float, wy: float, horizon: float) -> float:
    """Plain reference: min over t in [0, horizon] of |p − w t|."""
    w2 = wx * wx + wy * wy
    t = 0.0 if w2 == 0.0 else min(max((px * wx + py * wy) / w2, 0.0), horizon)
    return math.hypot(px - wx * t, py - wy * t)


@settings(deadline=None, max_examples=300)
@given(px=coord, py=coord, wx=speed, wy=speed, r=st.floats(0.1, 2.0), horizon=st.floats(0.1, 10.0))
def test_vo_membership_matches_the_closest_approach(
    px: float, py: float, wx: float, wy: float, r: float, horizon: float
) -> None:
    assume(math.hypot(px, py) > r + 1e-6)
    d = closest_approach(px, py, wx, wy, horizon)
    assume(abs(d - r) > 1e-7)
    t = _geometry.time_to_collision(px, py, wx, wy, r)
    assert (t <= horizon) == (d < r)
    assert _geometry.time_to_collision.py_func(px, py, wx, wy, r) == t


def test_vo_planner_keeps_its_choice_out_of_every_cone() -> None:
    planner = VelocityObstaclePlanner()
    planner.reset(context(RobotConfig(kinematics="holonomic")), np.random.default_rng(0))
    robot = RobotState(x=0.0, y=0.0, theta=0.0, vx=0.5, vy=0.0, v=0.5)
    peds = [(1.5, 0.05, -1.0, 0.0), (1.2, 1.0, 0.0, -0.5)]
    u = planner.act(observation(robot, (10.0, 0.0), peds))
    assert math.hypot(*u) <= 0.5 + 1e-12
    for x, y, vx, vy in peds:
        assert not in_velocity_obstacle((x, y), (vx, vy), u, 0.2 + 0.3 + 0.1, 3.0)
    # The preferred velocity, straight at the goal, is blocked, so u deviates from it.
    assert u[1] != 0.0
    free = planner.act(observation(robot, (10.0, 0.0)))
    np.testing.assert_allclose(free, [0.5, 0.0])


# --------------------------------------------------------------------------- ORCA


def test_orca_head_on_halfplanes_are_reciprocal_hand_case() -> None:
    # A at the origin moving +x at 1 m/s, B 4 m ahead moving −x at 1 m/s, r = 1, τ = 4:
    # v_rel = (2, 0) lies on the cone's axis; the closest boundary point is on the right
    # leg, at distance |v_rel| sin(asin(r / |p|)) = 0.5.
    s15 = math.sqrt(15.0)
    point, normal = orca_halfplane((4.0, 0.0), (1.0, 0.0), (-1.0, 0.0), 1.0, 4.0, DT, 0.5)
    np.testing.assert_allclose(normal, (-0.25, -s15 / 4), atol=1e-12)
    np.testing.assert_allclose(point, (1.0 - 1 / 16, -s15 / 16), atol=1e-12)
    point_b, normal_b = orca_halfplane((-4.0, 0.0), (-1.0, 0.0), (1.0, 0.0), 1.0, 4.0, DT, 0.5)
    np.testing.assert_allclose(normal_b, (0.25, s15 / 4), atol=1e-12)
    np.testing.assert_allclose(point_b, (-1.0 + 1 / 16, s15 / 16), atol=1e-12)
    # Each keeps right: A may not keep its velocity, and must turn toward −y.
    assert np.dot(np.subtract((1.0, 0.0), point), normal) == pytest.approx(-0.25)
    assert np.dot(np.subtract((1.0, -0.3), point), normal) > 0.0


def test_orca_crossing_halfplanes_hand_cases() -> None:
    # B 2 m right and 2 m behind A's path, crossing it; they would meet at t = 2 s.
    # τ = 1 s: the collision is beyond the horizon, the cut-off circle is closest,
    # w = v_rel − p/τ = (−1, 1), u = (r/τ − |w|) ŵ, A's velocity stays allowed.
    point, normal = orca_halfplane((2.0, -2.0), (1.0, 0.0), (0.0, 1.0), 0.5, 1.0, DT, 0.5)
    s2 = math.sqrt(2.0)
    np.testing.assert_allclose(normal, (-1 / s2, 1 / s2), atol=1e-12)
    u = (0.5 - s2) * np.array([-1 / s2, 1 / s2])
    np.testing.assert_allclose(point, np.array([1.0, 0.0]) + 0.5 * u, atol=1e-12)
    assert np.dot(np.subtract((1.0, 0.0), point), normal) == pytest.approx(-0.5 * (0.5 - s2))
    # τ = 3 s: the collision counts; v_rel = (1, −1) lies along p, so u has length
    # |v_rel| r / |p| = √2 · 0.5 / √8 = 0.25 and points out of the cone.
    point, normal = orca_halfplane((2.0, -2.0), (1.0, 0.0), (0.0, 1.0), 0.5, 3.0, DT, 1.0)
    u = np.subtract(point, (1.0, 0.0))
    assert np.linalg.norm(u) == pytest.approx(0.25)
    np.testing.assert_allclose(u / 0.25, normal, atol=1e-12)
    assert np.dot(normal, (2.0, -2.0)) < 0.0  # away from B


@settings(deadline=None, max_examples=300)
@given(
    px=coord, py=coord, vx=speed, vy=speed, ox=speed, oy=speed,
    r=st.floats(0.1, 1.0), tau=st.floats(0.5, 5.0),
)  # fmt: skip
def test_orca_u_reaches_the_truncated_cone_boundary(
    px: float, py: float, vx: float, vy: float, ox: float, oy: float, r: float, tau: float
) -> None:
    assume(math.hypot(px, py) > r + 1e-3)
    point, normal = orca_halfplane((px, py), (vx, vy), (ox, oy), r, tau, DT, 1.0)
    assert math.hypot(*normal) == pytest.approx(1.0)
    u = np.subtract(point, (vx, vy))
    rel = np.array([vx - ox, vy - oy])
    assume(np.linalg.norm(u) > 1e-6)
    # u is parallel to n, and v_rel + u lies on the boundary of VO^τ.
    assert abs(u[0] * normal[1] - u[1] * normal[0]) < 1e-9
    boundary = rel + u
    assert closest_approach(px, py, *boundary, tau) == pytest.approx(r, abs=1e-7)
    # Inside the cone u points outward (along n), outside it inward.
    inside = closest_approach(px, py, *rel, tau) < r
    assert (np.dot(u, normal) > 0.0) == inside
    # Past the boundary along n, a little: outside the cone.
    beyond = boundary + 1e-4 * np.asarray(normal)
    assert closest_approach(px, py, *beyond, tau) >= r


def test_orca_linear_programs() -> None:
    lines = np.zeros((4, 4))
    lines[0] = (0.2, 0.0, 1.0, 0.0)  # x >= 0.2
    fail, x, y = _orca_kernels.orca_lp2(lines, 1, 1.0, -0.3, 0.1, False)
    assert (fail, x, y) == (1, pytest.approx(0.2), pytest.approx(0.1))
    lines[1] = (0.0, 0.5, 0.0, -1.0)  # y <= 0.5
    fail, x, y = _orca_kernels.orca_lp2(lines, 2, 1.0, 2.0, 2.0, False)  # beyond the speed limit
    assert fail == 2
    assert (x, y) == (pytest.approx(math.sqrt(0.75)), pytest.approx(0.5))
    # x >= 0.5 and x <= -0.5 cannot both hold: the largest violation is minimised at x = 0.
    lines[0] = (0.5, 0.0, 1.0, 0.0)
    lines[1] = (-0.5, 0.0, -1.0, 0.0)
    fail, x, y = _orca_kernels.orca_lp2(lines, 2, 1.0, 0.3, 0.0, False)
    assert fail == 1
    x, y = _orca_kernels.orca_lp3(lines, 2, 0, fail, 1.0, x, y, np.zeros((4, 4)))
    assert x == pytest.approx(0.0, abs=1e-12)
    assert math.hypot(x, y) <= 1.0 + 1e-12
    # A hard half-plane (the first) is kept: only the soft ones give way.
    x, y = _orca_kernels.orca_lp3(lines, 2, 1, 1, 1.0, 0.5, 0.0, np.zeros((4, 4)))
    assert x == pytest.approx(0.5)


@pytest.mark.parametrize(
    ("starts", "goals"),
    [
        ([[0.0, 0.0], [6.0, 0.05]], [[6.0, 0.0], [0.0, 0.05]]),  # nearly head-on
        ([[0.0, 0.0], [6.0, 0.4]], [[6.0, 0.0], [0.0, 0.4]]),
        ([[0.0, 0.0], [3.0, -3.0]], [[6.0, 0.0], [3.0, 3.0]]),  # crossing at right angles
    ],
)
def test_two_orca_agents_swap_without_collision(
    starts: list[list[float]], goals: list[list[float]]
) -> None:
    """Two holonomic ORCA agents (the robot planner, each seeing the other as the only
    pedestrian) swap places; ORCA guarantees no contact when both follow their velocity.
    (Exactly symmetric head-on agents decelerate into a standstill, as in ORCA itself.)"""
    robot = RobotConfig(kinematics="holonomic", radius_m=0.25)
    config = ORCAConfig(safety_margin_m=0.0, responsibility=0.5, detection_range_m=None)
    agents = [ORCAPlanner(config), ORCAPlanner(config)]
    for a in agents:
        a.reset(context(robot), np.random.default_rng(0))
    pos = np.array(starts)
    goal = np.array(goals)
    vel = np.zeros((2, 2))
    closest = math.inf
    for _ in range(400):
        new = np.zeros((2, 2))
        for i in range(2):
            j = 1 - i
            state = RobotState(x=pos[i, 0], y=pos[i, 1], theta=0.0, vx=vel[i, 0], vy=vel[i, 1])
            obs = observation(state, tuple(goal[i]), [(*pos[j], *vel[j])], radius=0.25)
            new[i] = agents[i].act(obs)
        vel = new
        pos = pos + vel * DT
        closest = min(closest, float(np.linalg.norm(pos[0] - pos[1])))
    assert closest >= 0.5 - 1e-9
    np.testing.assert_allclose(pos, goal, atol=0.05)


# --------------------------------------------------------------------------- DWA


def test_dwa_window_bounds() -> None:
    planner = DWAPlanner(DWAConfig(window_time_s=None))  # one step: Fox et al.
    planner.reset(context(), np.random.default_rng(0))
    a = 1.0 * DT  # max_accel_mps2 · dt
    al = 2.0 * math.pi * DT  # max_angular_accel_radps2 · dt
    lo, hi, wlo, whi = planner.window(0.3, 0.0)
    assert (lo, hi) == (pytest.approx(0.3 - a), pytest.approx(0.3 + a))
    assert (wlo, whi) == (pytest.approx(-al), pytest.approx(al))
    lo, hi, wlo, whi = planner.window(0.48, 3.0)  # capped at v_max and ω_max
    assert (lo, hi) == (pytest.approx(0.48 - a), 0.5)
    assert (wlo, whi) == (pytest.approx(3.0 - al), math.pi)
    lo, hi, _, _ = planner.window(0.0, 0.0)  # v_min = 0: forward only
    assert (lo, hi) == (0.0, pytest.approx(a))
    wide = DWAPlanner(DWAConfig(window_time_s=0.25, min_speed_mps=0.3))
    wide.reset(context(), np.random.default_rng(0))
    lo, hi, wlo, whi = wide.window(0.2, -3.0)
    assert (lo, hi) == (0.3, pytest.approx(0.45))
    assert (wlo, whi) == (-math.pi, pytest.approx(-3.0 + 0.5 * math.pi))
    # Below v_min by more than the window: only the nearest reachable speed is left.
    lo, hi, _, _ = wide.window(-0.5, 0.0)
    assert lo == hi == pytest.approx(-0.25)


@settings(deadline=None, max_examples=60)
@given(
    v=st.floats(0.0, 0.5), w=st.floats(-math.pi, math.pi),
    px=st.floats(0.4, 2.0), py=st.floats(-1.0, 1.0),
)  # fmt: skip
def test_dwa_command_lies_in_the_window_and_is_admissible_when_possible(
    v: float, w: float, px: float, py: float
) -> None:
    planner = DWAPlanner()
    planner.reset(context(), np.random.default_rng(0))
    robot = RobotState(x=0.0, y=0.0, theta=0.0, v=v, omega=w, vx=v)
    obs = observation(robot, (10.0, 0.0), [(px, py, -0.5, 0.0)])
    cv, cw = planner.act(obs)
    lo, hi, wlo, whi = planner.window(v, w)
    assert lo - 1e-12 <= cv <= hi + 1e-12
    assert wlo - 1e-12 <= cw <= whi + 1e-12
    table = planner.table
    c = planner.config
    assert table.shape == (c.v_samples * c.omega_samples, 5)
    np.testing.assert_allclose(table[[0, -1], 0], [lo, hi])
    np.testing.assert_allclose(table[[0, -1], 1], [wlo, whi])
    chosen = table[(table[:, 0] == cv) & (table[:, 1] == cw)][0]
    admissible = table[:, 3] == math.inf
    assert np.array_equal(admissible, table[:, 4] > -math.inf)
    assert np.all(table[admissible, 2] >= 0.0)
    if admissible.any():  # the best admissible sample wins
        assert chosen[3] == math.inf
        assert chosen[4] == table[:, 4].max()
    else:  # the latest contact wins
        assert chosen[3] == table[:, 3].max()
    # The rollout really clears the pedestrian: replay the chosen sample by hand.
    if chosen[3] == math.inf:
        h = planner.params.rollout_step_s
        state = RobotState(x=0.0, y=0.0, theta=0.0, v=v, omega=w)
        drive = RobotConfig(max_accel_mps2=1.0, max_angular_accel_radps2=2.0 * math.pi)
        for k in range(1, planner.params.steps + 1):
            state = apply_command(state, (cv, cw), drive, h)
            ped = np.array([px - 0.5 * k * h, py])
            gap = math.hypot(state.x - ped[0], state.y - ped[1]) - 0.6
            assert gap >= -1e-9  # the robot's own update is the same up to rounding
    assert _dwa_kernels.dwa_unicycle.py_func(
        0.0, 0.0, 0.0, v, w, obs.robot_goal, obs.ped_pos, obs.ped_vel, obs.ped_radius,
        np.zeros((0, 4)), np.zeros((0, 3)), planner.common, planner.params, np.zeros(0),
        table.copy(),
    ) == (cv, cw)  # fmt: skip


def test_dwa_heading_term() -> None:
    planner = DWAPlanner()
    planner.reset(context(), np.random.default_rng(0))
    lim = (1.0, 2.0 * math.pi, 0.25)  # accelerations and window time
    # At rest, facing the goal, staying at rest: perfectly aligned.
    assert _dwa_kernels.dwa_heading(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 5.0, 0.0, *lim) == 1.0
    # Facing away from the goal: 0.
    assert _dwa_kernels.dwa_heading(
        0.0, 0.0, math.pi, 0.0, 0.0, 0.0, 0.0, 5.0, 0.0, *lim
    ) == pytest.approx(0.0)
    # Goal to the left: turning left scores higher than turning right.
    left = _dwa_kernels.dwa_heading(0.0, 0.0, 0.0, 0.5, 0.0, 0.5, 1.0, 0.0, 5.0, *lim)
    right = _dwa_kernels.dwa_heading(0.0, 0.0, 0.0, 0.5, 0.0, 0.5, -1.0, 0.0, 5.0, *lim)
    assert left > right


def test_dwa_swerves_around_a_person_ahead() -> None:
    planner = DWAPlanner()
    planner.reset(context(), np.random.default_rng(0))
    robot = RobotState(x=0.0, y=0.0, theta=0.0, v=0.5, vx=0.5)
    _, w = planner.act(observation(robot, (10.0, 0.0), [(1.2, 0.0, 0.0, 0.0)]))
    assert w != 0.0
    v_free, w_free = planner.act(observation(robot, (10.0, 0.0)))
    assert (v_free, w_free) == (0.5, 0.0)


# --------------------------------------------------------------------------- conversion


def test_velocity_to_unicycle_command() -> None:
    p = _geometry.CommonParams(
        radius_m=0.0, max_speed_mps=0.5, max_angular_speed_radps=math.pi,
        heading_gain_per_s=4.0, unicycle=True, margin_m=0.0, dt_s=0.0, goal_radius_m=0.0,
        avoid_edges=False, x_min=0.0, x_max=0.0, y_min=0.0, y_max=0.0,
    )  # fmt: skip
    assert _geometry.velocity_to_command(0.4, 0.0, 0.0, p) == (pytest.approx(0.4), 0.0)
    v, w = _geometry.velocity_to_command(0.0, 0.5, 0.0, p)  # 90° to the left: turn on the spot
    assert v == pytest.approx(0.0, abs=1e-15)
    assert w == math.pi
    v, w = _geometry.velocity_to_command(0.3, -0.3, 0.0, p)  # 45° to the right
    assert v == pytest.approx(0.3 * math.sqrt(2.0) * math.cos(math.pi / 4))
    assert w == -math.pi
    v, w = _geometry.velocity_to_command(0.5, 0.05, 0.0, p)
    assert w == pytest.approx(4.0 * math.atan2(0.05, 0.5))
    assert _geometry.velocity_to_command(-0.5, 0.0, 0.0, p) == (0.0, pytest.approx(math.pi))
    assert _geometry.velocity_to_command(0.0, 0.0, 1.0, p) == (0.0, 0.0)
    p = p._replace(unicycle=False)
    assert _geometry.velocity_to_command(0.1, -0.2, 1.0, p) == (0.1, -0.2)


# --------------------------------------------------------------------------- social force


def social_force_reference(
    pos: np.ndarray,
    theta: float,
    vel: np.ndarray,
    goal: np.ndarray,
    peds: np.ndarray,
    radii: np.ndarray,
    cfg: dict[str, float],
) -> np.ndarray:
    """Plain NumPy social force step of the robot (no obstacles)."""
    desired = goal - pos
    dist = np.linalg.norm(desired)
    if dist > cfg["vdes"]:
        desired = desired * cfg["vdes"] / dist
    force = (desired - vel) / cfg["tau"]
    heading = np.array([math.cos(theta), math.sin(theta)])
    diff = pos - peds
    d = np.linalg.norm(diff, axis=1)
    n = diff / d[:, None]
    cos_phi = -(n @ heading)
    psi = cfg["lam"] + (1 - cfg["lam"]) * (1 + cos_phi) / 2
    mag = cfg["a"] * np.exp((cfg["r"] + radii - d) / cfg["b"]) * psi
    force = force + (mag[:, None] * n).sum(axis=0)
    out = vel + force * DT
    s = np.linalg.norm(out)
    return np.asarray(out * 0.5 / s if s > 0.5 else out)


@settings(deadline=None, max_examples=100)
@given(
    peds=st.lists(st.tuples(coord, coord), min_size=0, max_size=4),
    vx=st.floats(-0.35, 0.35), vy=st.floats(-0.35, 0.35), theta=st.floats(-3.0, 3.0),
)  # fmt: skip
def test_social_force_matches_a_numpy_reference(
    peds: list[tuple[float, float]], vx: float, vy: float, theta: float
) -> None:
    planner = SocialForcePlanner()
    planner.reset(context(RobotConfig(kinematics="holonomic")), np.random.default_rng(0))
    arr = np.array([(x, y, 0.0, 0.0) for x, y in peds]).reshape(-1, 4)
    assume(np.all(np.hypot(arr[:, 0] - 1.0, arr[:, 1] - 2.0) > 0.05))
    robot = RobotState(x=1.0, y=2.0, theta=theta, vx=vx, vy=vy)
    got = planner.act(observation(robot, (10.0, 0.0), [tuple(r) for r in arr]))
    c = planner.config
    cfg = {"vdes": 0.5, "tau": c.tau_s, "lam": c.anisotropy, "a": c.ped_strength_mps2,
           "b": c.ped_range_m, "r": 0.2}  # fmt: skip
    want = social_force_reference(
        np.array([1.0, 2.0]), theta, np.array([vx, vy]), np.array([10.0, 0.0]),
        arr[:, :2], np.full(len(arr), 0.3), cfg,
    )  # fmt: skip
    np.testing.assert_allclose(got, want, rtol=1e-9, atol=1e-12)
