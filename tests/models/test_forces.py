"""SRFM force components against the NumPy reference, and physical invariants."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import srfm
from srfm.models import _kernels
from srfm.models._arrays import ForceContext
from tests.models import _reference as ref

# Relative tolerance against the reference: the kernel and the reference add the same
# terms in a different order and with different rounding (hypot vs sqrt, vectorised
# sums), so agreement is to a few ulps of the largest term.
RTOL = 1e-12

COMPONENTS = ("goal", "pedestrians", "robot", "obstacles")


def assert_component(got: np.ndarray, want: np.ndarray, scale: np.ndarray) -> None:
    """|got − want| within RTOL of the component's own terms (they may cancel)."""
    atol = RTOL * max(float(np.max(scale, initial=0.0)), 1e-300)
    np.testing.assert_allclose(got, want, rtol=RTOL, atol=atol)


def crowd(pos, goal=None, vel=None, **kw) -> srfm.CrowdState:
    pos = np.asarray(pos, dtype=np.float64)
    return srfm.CrowdState.create(pos=pos, goal=pos.copy() if goal is None else goal, vel=vel, **kw)


# --------------------------------------------------------------------------------------
# Every component against the reference, on random states.


@settings(deadline=None, max_examples=150)
@given(scene=ref.scenes())
def test_goal_force_matches_reference(scene: ref.Scene) -> None:
    got = srfm.force_components(scene.crowd, scene.params, scene.robot, scene.obstacles)
    want = ref.forces(scene.crowd, scene.params, scene.robot, scene.obstacles)
    assert_component(got.goal, want.goal, want.goal_scale)


@settings(deadline=None, max_examples=150)
@given(scene=ref.scenes(min_n=2))
def test_pedestrian_force_matches_reference(scene: ref.Scene) -> None:
    got = srfm.force_components(scene.crowd, scene.params, scene.robot, scene.obstacles)
    want = ref.forces(scene.crowd, scene.params, scene.robot, scene.obstacles)
    assert_component(got.pedestrians, want.pedestrians, want.pedestrians_scale)


@settings(deadline=None, max_examples=150)
@given(scene=ref.scenes(), robot=ref.robots)
def test_robot_force_matches_reference(scene: ref.Scene, robot: srfm.RobotBody) -> None:
    got = srfm.force_components(scene.crowd, scene.params, robot, scene.obstacles)
    want = ref.forces(scene.crowd, scene.params, robot, scene.obstacles)
    assert_component(got.robot, want.robot, want.robot_scale)


@settings(deadline=None, max_examples=150)
@given(scene=ref.scenes())
def test_obstacle_force_matches_reference(scene: ref.Scene) -> None:
    got = srfm.force_components(scene.crowd, scene.params, scene.robot, scene.obstacles)
    want = ref.forces(scene.crowd, scene.params, scene.robot, scene.obstacles)
    assert_component(got.obstacles, want.obstacles, want.obstacles_scale)


@settings(deadline=None, max_examples=60)
@given(scene=ref.scenes())
def test_total_is_sum_of_components_and_matches_reference(scene: ref.Scene) -> None:
    got = srfm.force_components(scene.crowd, scene.params, scene.robot, scene.obstacles)
    want = ref.forces(scene.crowd, scene.params, scene.robot, scene.obstacles)
    np.testing.assert_array_equal(got.total, got.goal + got.pedestrians + got.robot + got.obstacles)
    assert_component(got.total, want.total, want.total_scale)


def test_no_robot_and_no_obstacles_give_zero_components() -> None:
    c = crowd([[0.0, 0.0], [1.0, 0.0]], goal=[[5.0, 0.0], [5.0, 1.0]])
    f = srfm.force_components(c)
    np.testing.assert_array_equal(f.robot, 0.0)
    np.testing.assert_array_equal(f.obstacles, 0.0)
    assert np.all(np.abs(f.pedestrians[:, 0]) > 0.0)


def test_default_params_are_agrawal2024() -> None:
    c = crowd([[0.0, 0.0], [0.7, 0.2]], goal=[[5.0, 0.0], [5.0, 1.0]], vel=[[0.5, 0.1], [0, 0]])
    robot = srfm.RobotBody(x=0.3, y=0.8)
    walls = srfm.Obstacles.create(segments=[[-1.0, -0.4, 3.0, -0.4]], circles=[[1.0, 1.0, 0.2]])
    default = srfm.force_components(c, robot=robot, obstacles=walls)
    preset = ref.forces(c, srfm.SRFMParams.preset("agrawal2024"), robot, walls)
    for name in COMPONENTS:
        assert_component(getattr(default, name), getattr(preset, name), preset.total_scale)


def test_known_value_of_a_pedestrian_pair() -> None:
    # i walks along +x towards j, 1 m ahead: ψ = 1; j stands still with no goal: ψ = 1.
    p = srfm.SRFMParams()
    c = crowd([[0.0, 0.0], [1.0, 0.0]], vel=[[1.0, 0.0], [0.0, 0.0]], radius=0.3)
    f = srfm.force_components(c, p).pedestrians
    mag = 2.0 * math.exp((0.6 - 1.0) / 0.89)
    np.testing.assert_allclose(f, [[-mag, 0.0], [mag, 0.0]], rtol=1e-14, atol=0.0)


def test_known_value_of_the_goal_force() -> None:
    p = srfm.SRFMParams(tau=0.5)
    # Far from the goal: desired velocity v0 e; within v0 of it: g − x.
    c = crowd(
        [[0.0, 0.0], [10.0, 0.0]],
        goal=[[3.0, 4.0], [10.5, 0.0]],
        vel=[[1.0, 0.0], [0.0, 0.0]],
        v0=1.25,
    )
    f = srfm.force_components(c, p).goal
    np.testing.assert_allclose(f[0], [(0.75 - 1.0) / 0.5, 1.0 / 0.5], rtol=1e-14)
    np.testing.assert_allclose(f[1], [0.5 / 0.5, 0.0], rtol=1e-14)


# --------------------------------------------------------------------------------------
# The jitted kernel and its pure-Python body agree.


def _kernel_args(scene: ref.Scene) -> tuple:
    robot = scene.robot.as_array() if scene.robot is not None else np.zeros(5)
    c = scene.crowd
    return (
        c.for_kernels(),
        ForceContext(
            scene.params.for_kernels(),
            robot,
            scene.robot is not None,
            scene.obstacles.for_kernels(),
            np.full(2, np.inf),
        ),
    )


def _fixed_scene() -> ref.Scene:
    rng = np.random.default_rng(7)
    n = 9
    c = srfm.CrowdState.create(
        pos=rng.uniform(0, 4, (n, 2)),
        goal=rng.uniform(0, 4, (n, 2)),
        vel=rng.uniform(-1, 1, (n, 2)),
        radius=rng.uniform(0.1, 0.4, n),
        v0=rng.uniform(0.5, 1.5, n),
    )
    c.pos[3] = c.pos[4]  # coincident pair
    c.vel[5] = 0.0
    c.goal[5] = c.pos[5]  # at rest at its goal
    obstacles = srfm.Obstacles.create(
        segments=[[0.0, 0.0, 4.0, 0.0], [1.0, 1.0, 1.0, 1.0], [0.0, 4.0, 2.0, 1.0]],
        circles=[[2.0, 2.0, 0.3], [*c.pos[6], 0.2]],  # agent 6 on a pillar's centre
    )
    params = srfm.SRFMParams(lambda_robot=0.3)
    return ref.Scene(c, params, srfm.RobotBody(x=1.5, y=2.5, radius=0.25), obstacles)


def test_jitted_and_python_force_kernels_agree() -> None:
    scene = _fixed_scene()
    args = _kernel_args(scene)
    jit_out = np.zeros((4, scene.crowd.n, 2))
    py_out = np.zeros((4, scene.crowd.n, 2))
    _kernels.force_components_kernel(*args, jit_out)
    _kernels.force_components_kernel.py_func(*args, py_out)
    np.testing.assert_allclose(py_out, jit_out, rtol=1e-13, atol=1e-15)
    # The per-agent body too, in pure Python all the way down to the helpers.
    for i in range(scene.crowd.n):
        total = np.zeros((1, 2))
        got = _kernels._agent_forces.py_func(i, i + 1, *args, np.zeros((0, 2)), total)
        np.testing.assert_allclose(got, jit_out[:, i, :].ravel(), rtol=1e-13, atol=1e-15)
        np.testing.assert_allclose(total[0], jit_out[:, i, :].sum(axis=0), rtol=1e-13, atol=1e-15)
    want = ref.forces(*scene)
    for k, name in enumerate(COMPONENTS):
        assert_component(jit_out[k], getattr(want, name), want.total_scale)
    # The fixed scene exercises every component.
    assert np.all(np.any(np.abs(jit_out) > 1e-3, axis=(1, 2)))


# --------------------------------------------------------------------------------------
# Physical invariants.


@settings(deadline=None, max_examples=100)
@given(
    a=ref.points,
    b=ref.points,
    ra=st.floats(0.0, 0.5),
    rb=st.floats(0.0, 0.5),
    va=ref.velocities,
    vb=ref.velocities,
)
def test_isotropic_pair_forces_are_equal_and_opposite(a, b, ra, rb, va, vb) -> None:
    p = srfm.SRFMParams(lambda_ped=1.0)
    c = crowd([a, b], goal=[b, a], vel=[va, vb], radius=[ra, rb])
    f = srfm.force_components(c, p).pedestrians
    np.testing.assert_allclose(f[0], -f[1], rtol=1e-14, atol=0.0)
    if a != b:  # and along the line between them, pushing i away from j
        away = np.subtract(a, b)
        assert np.dot(f[0], away) > 0.0
        cross = f[0][0] * away[1] - f[0][1] * away[0]
        assert abs(cross) <= 1e-12 * np.linalg.norm(f[0]) * np.linalg.norm(away)


def test_anisotropic_pair_forces_are_not_equal_and_opposite() -> None:
    # Sanity check of the test above: with λ < 1 the pair force is not symmetric.
    c = crowd([[0.0, 0.0], [1.0, 0.0]], vel=[[1.0, 0.0], [1.0, 0.0]])
    f = srfm.force_components(c, srfm.SRFMParams(lambda_ped=0.4)).pedestrians
    assert not np.allclose(f[0], -f[1])


def _pair_force(d: float, params: srfm.SRFMParams, heading=(1.0, 0.0), ry=0.0) -> np.ndarray:
    """Force on a pedestrian at the origin walking along ``heading`` from one at (d, ry)."""
    c = crowd([[0.0, 0.0], [d, ry]], vel=[heading, [0.0, 0.0]], radius=[0.3, 0.25])
    return srfm.force_components(c, params).pedestrians[0]


@settings(deadline=None, max_examples=60)
@given(
    d=st.floats(0.05, 5.0),
    delta=st.floats(0.01, 3.0),
    b_ped=st.floats(0.1, 2.0),
    angle=st.floats(-math.pi, math.pi),
)
def test_pedestrian_force_decays_exponentially(d, delta, b_ped, angle) -> None:
    p = srfm.SRFMParams(b_ped=b_ped, lambda_ped=0.3)
    u = (math.cos(angle), math.sin(angle))
    near = _pair_force(d, p, heading=u)
    far = _pair_force(d + delta, p, heading=u)
    ratio = np.linalg.norm(far) / np.linalg.norm(near)
    assert ratio == pytest.approx(math.exp(-delta / b_ped), rel=1e-12)


@settings(deadline=None, max_examples=60)
@given(d=st.floats(0.05, 5.0), delta=st.floats(0.01, 3.0), b=st.floats(0.1, 2.0))
def test_robot_and_obstacle_forces_decay_exponentially(d, delta, b) -> None:
    p = srfm.SRFMParams(b_robot=b, b_obs=b, lambda_robot=0.5)

    def magnitudes(dist: float) -> tuple[float, float, float]:
        c = crowd([[0.0, 0.0]], goal=[[0.0, 5.0]])
        robot = srfm.RobotBody(x=dist, y=0.0)
        f_r = srfm.force_components(c, p, robot=robot).robot[0]
        wall = srfm.Obstacles.create(segments=[[-3.0, -dist, 3.0, -dist]])
        f_w = srfm.force_components(c, p, obstacles=wall).obstacles[0]
        pillar = srfm.Obstacles.create(circles=[[-dist - 0.4, 0.0, 0.4]])
        f_p = srfm.force_components(c, p, obstacles=pillar).obstacles[0]
        return np.linalg.norm(f_r), np.linalg.norm(f_w), np.linalg.norm(f_p)

    want = math.exp(-delta / b)
    for near, far in zip(magnitudes(d), magnitudes(d + delta), strict=True):
        assert far / near == pytest.approx(want, rel=1e-12)


@pytest.mark.parametrize("lam", [0.0, 0.4, 0.59, 1.0])
@pytest.mark.parametrize("heading", [(1.0, 0.0), (0.0, -2.0), (-0.6, 0.8)])
def test_anisotropy_ahead_versus_behind_is_one_to_lambda(lam, heading) -> None:
    p = srfm.SRFMParams(lambda_ped=lam)
    u = np.asarray(heading) / np.linalg.norm(heading)
    d = 0.9

    def force_from(offset: np.ndarray) -> np.ndarray:
        c = crowd([[1.0, 1.0], 1.0 + offset], vel=[heading, [0.0, 0.0]])
        return srfm.force_components(c, p).pedestrians[0]

    ahead = force_from(d * u)
    behind = force_from(-d * u)
    side = force_from(d * np.array([-u[1], u[0]]))
    full = 2.0 * math.exp((0.6 - d) / 0.89)
    np.testing.assert_allclose(ahead, -full * u, rtol=1e-13)
    np.testing.assert_allclose(behind, lam * full * u, rtol=1e-13, atol=1e-300)
    # Sideways (cos φ = 0): ψ = (1 + λ)/2.
    np.testing.assert_allclose(np.linalg.norm(side), (1 + lam) / 2 * full, rtol=1e-13)
    if lam < 1.0:
        assert np.linalg.norm(ahead) > np.linalg.norm(side) > np.linalg.norm(behind)


@pytest.mark.parametrize("lam", [0.0, 0.25, 1.0])
def test_robot_anisotropy_uses_lambda_r(lam) -> None:
    p = srfm.SRFMParams(lambda_robot=lam, lambda_ped=0.9)
    c = crowd([[0.0, 0.0]], vel=[[0.0, 1.0]], goal=[[0.0, 9.0]])
    ahead = srfm.force_components(c, p, robot=srfm.RobotBody(x=0.0, y=1.0)).robot[0]
    behind = srfm.force_components(c, p, robot=srfm.RobotBody(x=0.0, y=-1.0)).robot[0]
    full = 7.93 * math.exp((0.3 + 0.2 - 1.0) / 0.99)
    np.testing.assert_allclose(ahead, [0.0, -full], rtol=1e-13)
    np.testing.assert_allclose(behind, [0.0, lam * full], rtol=1e-13, atol=1e-300)


def test_robot_force_is_isotropic_by_default() -> None:
    c = crowd([[0.0, 0.0]], vel=[[1.0, 0.0]], goal=[[9.0, 0.0]])
    ahead = srfm.force_components(c, robot=srfm.RobotBody(x=1.0, y=0.0)).robot[0]
    behind = srfm.force_components(c, robot=srfm.RobotBody(x=-1.0, y=0.0)).robot[0]
    np.testing.assert_allclose(ahead, -behind, rtol=1e-15)


def test_heading_at_rest_is_the_desired_direction() -> None:
    # At rest, walking to +x: the pedestrian ahead (+x) counts fully, behind with λ.
    p = srfm.SRFMParams(lambda_ped=0.2)
    ahead = crowd([[0.0, 0.0], [1.0, 0.0]], goal=[[5.0, 0.0], [1.0, 0.0]])
    behind = crowd([[0.0, 0.0], [-1.0, 0.0]], goal=[[5.0, 0.0], [-1.0, 0.0]])
    fa = srfm.force_components(ahead, p).pedestrians[0]
    fb = srfm.force_components(behind, p).pedestrians[0]
    assert np.linalg.norm(fb) / np.linalg.norm(fa) == pytest.approx(0.2, rel=1e-13)


def test_no_heading_is_isotropic() -> None:
    # At rest at its own goal: no heading, so ahead and behind are the same (ψ = 1).
    p = srfm.SRFMParams(lambda_ped=0.2)
    left = crowd([[0.0, 0.0], [-1.0, 0.0]])
    right = crowd([[0.0, 0.0], [1.0, 0.0]])
    fl = srfm.force_components(left, p).pedestrians[0]
    fr = srfm.force_components(right, p).pedestrians[0]
    np.testing.assert_allclose(fl, -fr, rtol=1e-15)
    assert fl[0] == pytest.approx(2.0 * math.exp(-0.4 / 0.89), rel=1e-14)


def test_wall_force_points_away_from_closest_point() -> None:
    p = srfm.SRFMParams(a_obs=3.0, b_obs=0.2)
    wall = srfm.Obstacles.create(segments=[[0.0, 0.0, 2.0, 0.0]])
    # Beside the interior of the wall, and beyond its end (closest point = endpoint).
    c = crowd([[1.0, 0.5], [3.0, 1.0]], radius=0.3)
    f = srfm.force_components(c, p, obstacles=wall).obstacles
    np.testing.assert_allclose(f[0], [0.0, 3.0 * math.exp((0.3 - 0.5) / 0.2)], rtol=1e-14)
    d = math.sqrt(2.0)
    mag = 3.0 * math.exp((0.3 - d) / 0.2)
    np.testing.assert_allclose(f[1], [mag / d, mag / d], rtol=1e-14)


def test_pillar_force_uses_distance_to_surface() -> None:
    p = srfm.SRFMParams(a_obs=3.0, b_obs=0.2)
    pillar = srfm.Obstacles.create(circles=[[0.0, 0.0, 0.5]])
    c = crowd([[0.0, 1.0], [0.3, 0.0]], radius=0.3)  # outside, and inside the pillar
    f = srfm.force_components(c, p, obstacles=pillar).obstacles
    np.testing.assert_allclose(f[0], [0.0, 3.0 * math.exp((0.3 - 0.5) / 0.2)], rtol=1e-14)
    np.testing.assert_allclose(f[1], [3.0 * math.exp((0.3 + 0.2) / 0.2), 0.0], rtol=1e-14)


def test_zero_strengths_switch_components_off() -> None:
    scene = _fixed_scene()
    p = scene.params.replace(a_ped=0.0, a_robot=0.0, a_obs=0.0)
    f = srfm.force_components(scene.crowd, p, scene.robot, scene.obstacles)
    for name in ("pedestrians", "robot", "obstacles"):
        np.testing.assert_array_equal(getattr(f, name), 0.0)


# --------------------------------------------------------------------------------------
# No NaN at zero distance or zero velocity.


def _assert_finite(f: srfm.ForceComponents) -> None:
    for name in COMPONENTS:
        assert np.all(np.isfinite(getattr(f, name))), name


def test_coincident_pedestrians_exert_no_force_on_each_other() -> None:
    c = crowd([[1.0, 1.0], [1.0, 1.0], [2.0, 1.0]], vel=[[0.5, 0.0], [0.0, 0.0], [0.0, 0.0]])
    f = srfm.force_components(c)
    _assert_finite(f)
    only_third = crowd([[1.0, 1.0], [2.0, 1.0]], vel=[[0.5, 0.0], [0.0, 0.0]])
    g = srfm.force_components(only_third)
    np.testing.assert_array_equal(f.pedestrians[0], g.pedestrians[0])


def test_pedestrian_at_robot_centre() -> None:
    c = crowd([[1.0, 1.0], [3.0, 1.0]], goal=[[4.0, 4.0], [3.0, 1.0]])
    f = srfm.force_components(c, robot=srfm.RobotBody(x=1.0, y=1.0))
    _assert_finite(f)
    np.testing.assert_array_equal(f.robot[0], 0.0)
    assert np.linalg.norm(f.robot[1]) > 0.0


@pytest.mark.parametrize(
    "where",
    [[1.0, 0.0], [0.0, 0.0], [2.0, 0.0], [0.5, 0.5]],
    ids=["on-wall", "on-wall-end", "on-other-end", "on-point-wall"],
)
def test_pedestrian_on_a_wall(where) -> None:
    walls = srfm.Obstacles.create(segments=[[0.0, 0.0, 2.0, 0.0], [0.5, 0.5, 0.5, 0.5]])
    c = crowd([where], goal=[[3.0, 3.0]])
    f = srfm.force_components(c, obstacles=walls)
    _assert_finite(f)


def test_pedestrian_on_a_pillar_centre() -> None:
    pillars = srfm.Obstacles.create(circles=[[1.0, 1.0, 0.4], [2.0, 2.0, 0.0]])
    c = crowd([[1.0, 1.0], [2.0, 2.0]])
    f = srfm.force_components(c, obstacles=pillars)
    _assert_finite(f)
    # Each feels only the other pillar, from its own centre's direction.
    want = ref.forces(c, srfm.SRFMParams(), obstacles=pillars)
    assert_component(f.obstacles, want.obstacles, want.obstacles_scale)


@pytest.mark.parametrize("v0", [0.0, 1.25])
def test_at_rest_and_at_goal(v0) -> None:
    c = crowd([[1.0, 1.0], [3.0, 1.0]], v0=v0)
    f = srfm.force_components(c, robot=srfm.RobotBody(x=2.0, y=2.0))
    _assert_finite(f)
    np.testing.assert_array_equal(f.goal, 0.0)


def test_zero_radius_and_zero_speed_everywhere() -> None:
    c = crowd([[1.0, 1.0], [1.0, 1.0]], radius=0.0, v0=0.0)
    walls = srfm.Obstacles.create(segments=[[1.0, 1.0, 1.0, 1.0]], circles=[[1.0, 1.0, 0.0]])
    f = srfm.force_components(c, robot=srfm.RobotBody(x=1.0, y=1.0, radius=0.0), obstacles=walls)
    _assert_finite(f)
    np.testing.assert_array_equal(f.total, 0.0)


def test_empty_crowd() -> None:
    c = srfm.CrowdState.create(pos=np.zeros((0, 2)), goal=np.zeros((0, 2)))
    f = srfm.force_components(c, robot=srfm.RobotBody(x=0.0, y=0.0))
    assert f.total.shape == (0, 2)


# --------------------------------------------------------------------------------------
# Agent order.


@settings(deadline=None, max_examples=80)
@given(scene=ref.scenes(min_n=2), data=st.data())
def test_permuting_agents_permutes_forces(scene: ref.Scene, data: st.DataObject) -> None:
    n = scene.crowd.n
    perm = np.array(data.draw(st.permutations(range(n))))
    c = scene.crowd
    permuted = srfm.CrowdState.create(
        pos=c.pos[perm],
        goal=c.goal[perm],
        vel=c.vel[perm],
        radius=c.radius[perm],
        v0=c.v0[perm],
        vmax=c.vmax[perm],
    )
    f = srfm.force_components(c, scene.params, scene.robot, scene.obstacles)
    g = srfm.force_components(permuted, scene.params, scene.robot, scene.obstacles)
    scale = ref.forces(c, scene.params, scene.robot, scene.obstacles).total_scale
    for name in COMPONENTS:
        np.testing.assert_allclose(
            getattr(g, name),
            getattr(f, name)[perm],
            rtol=1e-13,
            atol=1e-13 * max(float(scale.max()), 1e-300),
        )
