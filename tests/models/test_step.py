"""The crowd step: compute-then-apply, semi-implicit Euler, speed cap, kernel variants."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import srfm
from srfm.models import _kernels
from srfm.models._arrays import ForceContext
from tests.models import _reference as ref

DT = 1.0 / 15.0

dts = st.sampled_from([DT, 0.01, 0.1, 0.5])


def stepped(
    crowd: srfm.CrowdState,
    dt: float = DT,
    params: srfm.SRFMParams | None = None,
    robot: srfm.RobotBody | None = None,
    obstacles: srfm.Obstacles | None = None,
    *,
    parallel: bool | None = None,
    steps: int = 1,
) -> srfm.CrowdState:
    """A stepped copy; ``crowd`` is left as it was."""
    out = crowd.copy()
    for _ in range(steps):
        srfm.step_crowd(out, dt, params, robot, obstacles, parallel=parallel)
    return out


def permuted(crowd: srfm.CrowdState, perm: np.ndarray) -> srfm.CrowdState:
    return srfm.CrowdState.create(
        pos=crowd.pos[perm],
        goal=crowd.goal[perm],
        vel=crowd.vel[perm],
        radius=crowd.radius[perm],
        v0=crowd.v0[perm],
        vmax=crowd.vmax[perm],
    )


def random_crowd(n: int, seed: int, size: float = 6.0) -> srfm.CrowdState:
    rng = np.random.default_rng(seed)
    return srfm.CrowdState.create(
        pos=rng.uniform(0, size, (n, 2)),
        goal=rng.uniform(0, size, (n, 2)),
        vel=rng.uniform(-1, 1, (n, 2)),
        radius=rng.uniform(0.2, 0.35, n),
        v0=rng.uniform(0.8, 1.4, n),
    )


WALLS = srfm.Obstacles.create(
    segments=[[0.0, 0.0, 6.0, 0.0], [0.0, 6.0, 6.0, 6.0], [3.0, 2.0, 3.0, 4.0]],
    circles=[[1.5, 3.0, 0.3], [4.5, 3.0, 0.4]],
)


# --------------------------------------------------------------------------------------
# Semi-implicit Euler from one snapshot.


@settings(deadline=None, max_examples=120)
@given(scene=ref.scenes(), dt=dts)
def test_step_is_semi_implicit_euler_on_snapshot_forces(scene: ref.Scene, dt: float) -> None:
    c = scene.crowd
    force = srfm.force_components(c, scene.params, scene.robot, scene.obstacles).total
    new = stepped(c, dt, scene.params, scene.robot, scene.obstacles)

    v = c.vel + force * dt
    speed = np.linalg.norm(v, axis=1)
    capped = speed > c.vmax
    v[capped] *= (c.vmax[capped] / speed[capped])[:, None]
    np.testing.assert_allclose(new.vel, v, rtol=1e-14, atol=1e-300)
    # Positions advance with the new (capped) velocity, not the old one.
    np.testing.assert_allclose(new.pos, c.pos + new.vel * dt, rtol=1e-14, atol=1e-15)
    # Goals and per-agent values are not touched.
    for name in ("goal", "radius", "v0", "vmax"):
        np.testing.assert_array_equal(getattr(new, name), getattr(c, name))


@settings(deadline=None, max_examples=120)
@given(scene=ref.scenes(), dt=dts)
def test_step_matches_reference(scene: ref.Scene, dt: float) -> None:
    want_pos, want_vel = ref.step(scene.crowd, dt, scene.params, scene.robot, scene.obstacles)
    new = stepped(scene.crowd, dt, scene.params, scene.robot, scene.obstacles)
    scale = ref.forces(scene.crowd, scene.params, scene.robot, scene.obstacles).total_scale
    atol = 1e-12 * max(float(scale.max()) * dt, 1.0)
    np.testing.assert_allclose(new.vel, want_vel, rtol=1e-11, atol=atol)
    np.testing.assert_allclose(new.pos, want_pos, rtol=1e-11, atol=atol)


def test_uncapped_step_is_exactly_v_plus_f_dt() -> None:
    c = random_crowd(12, seed=1)
    c.vmax[:] = 1e3
    force = srfm.force_components(c, robot=srfm.RobotBody(x=3, y=3), obstacles=WALLS).total
    new = stepped(c, robot=srfm.RobotBody(x=3, y=3), obstacles=WALLS)
    np.testing.assert_allclose(new.vel, c.vel + force * DT, rtol=1e-15)
    np.testing.assert_allclose(new.pos, c.pos + (c.vel + force * DT) * DT, rtol=1e-15)


def test_step_uses_the_snapshot_not_updated_neighbours() -> None:
    # Two pedestrians walking head-on: a one-after-another update would let the second
    # feel the first at its new position. The forces must be the same as at t = 0.
    c = srfm.CrowdState.create(
        pos=[[0.0, 0.0], [0.8, 0.0]], goal=[[5.0, 0.0], [-5.0, 0.0]], vel=[[1, 0], [-1, 0]]
    )
    p = srfm.SRFMParams(a_ped=50.0)
    force = srfm.force_components(c, p).total
    new = stepped(c, 0.2, p)
    sequential = c.copy()
    _kernels.integrate(sequential.pos[:1], sequential.vel[:1], force[:1], c.vmax[:1], 0.2)
    second = srfm.force_components(sequential, p).total[1]
    assert not np.allclose(second, force[1])  # the order would matter ...
    expected = stepped(permuted(c, np.array([1, 0])), 0.2, p)
    np.testing.assert_array_equal(new.pos, expected.pos[[1, 0]])  # ... and does not.


# --------------------------------------------------------------------------------------
# Agent order.


@settings(deadline=None, max_examples=80)
@given(scene=ref.scenes(min_n=2), dt=dts, data=st.data())
def test_permuted_crowd_steps_to_permuted_result(
    scene: ref.Scene, dt: float, data: st.DataObject
) -> None:
    perm = np.array(data.draw(st.permutations(range(scene.crowd.n))))
    new = stepped(scene.crowd, dt, scene.params, scene.robot, scene.obstacles)
    new_p = stepped(permuted(scene.crowd, perm), dt, scene.params, scene.robot, scene.obstacles)
    scale = ref.forces(scene.crowd, scene.params, scene.robot, scene.obstacles).total_scale
    atol = 1e-13 * max(float(scale.max()) * dt, 1.0)
    np.testing.assert_allclose(new_p.vel, new.vel[perm], rtol=1e-13, atol=atol)
    np.testing.assert_allclose(new_p.pos, new.pos[perm], rtol=1e-13, atol=atol * dt)


def test_permuted_crowd_over_many_steps() -> None:
    c = random_crowd(20, seed=3)
    perm = np.random.default_rng(4).permutation(20)
    robot = srfm.RobotBody(x=3.0, y=3.0)
    a = stepped(c, robot=robot, obstacles=WALLS, steps=30)
    b = stepped(permuted(c, perm), robot=robot, obstacles=WALLS, steps=30)
    np.testing.assert_allclose(b.pos, a.pos[perm], rtol=1e-9, atol=1e-9)


# --------------------------------------------------------------------------------------
# Speed cap.


@settings(deadline=None, max_examples=80)
@given(crowd=ref.crowd_states(), dt=dts, strength=st.floats(1e3, 1e6))
def test_speed_is_capped_under_huge_forces(crowd: srfm.CrowdState, dt, strength) -> None:
    p = srfm.SRFMParams(a_ped=strength, a_robot=strength, a_obs=strength, tau=1e-3)
    robot = srfm.RobotBody(x=2.0, y=2.0)
    obstacles = srfm.Obstacles.create(segments=[[0, 1, 4, 1]], circles=[[3, 3, 0.5]])
    force = srfm.force_components(crowd, p, robot, obstacles).total
    new = stepped(crowd, dt, p, robot, obstacles)
    speed = np.linalg.norm(new.vel, axis=1)
    assert np.all(np.isfinite(new.vel))
    assert np.all(np.isfinite(new.pos))
    assert np.all(speed <= crowd.vmax * (1 + 1e-15))
    # Where the cap binds, the speed is exactly vmax and the direction is that of v + F dt.
    free = crowd.vel + force * dt
    free_speed = np.linalg.norm(free, axis=1)
    bound = free_speed > crowd.vmax
    np.testing.assert_allclose(speed[bound], crowd.vmax[bound], rtol=1e-15)
    cos = np.sum(new.vel[bound] * free[bound], axis=1)
    np.testing.assert_allclose(cos, speed[bound] * free_speed[bound], rtol=1e-12)


def test_speed_cap_per_agent() -> None:
    c = srfm.CrowdState.create(
        pos=[[0.0, 0.0], [0.0, 3.0], [0.0, 6.0]],
        goal=[[100.0, 0.0], [100.0, 3.0], [100.0, 6.0]],
        v0=1.25,
        vmax=[0.0, 0.5, 2.0],
    )
    new = stepped(c, 1.0, srfm.SRFMParams(tau=1e-3))
    np.testing.assert_allclose(np.linalg.norm(new.vel, axis=1), [0.0, 0.5, 2.0], rtol=1e-15)
    np.testing.assert_array_equal(new.pos[0], c.pos[0])  # vmax = 0 never moves


# --------------------------------------------------------------------------------------
# Serial and parallel kernels.


@settings(deadline=None, max_examples=40)
@given(scene=ref.scenes(), dt=dts)
def test_serial_and_parallel_steps_are_bit_identical(scene: ref.Scene, dt: float) -> None:
    args = (dt, scene.params, scene.robot, scene.obstacles)
    serial = stepped(scene.crowd, *args, parallel=False, steps=3)
    parallel = stepped(scene.crowd, *args, parallel=True, steps=3)
    np.testing.assert_array_equal(parallel.pos, serial.pos)
    np.testing.assert_array_equal(parallel.vel, serial.vel)


@pytest.mark.parametrize("n", [49, 107])
def test_serial_and_parallel_are_bit_identical_for_large_crowds(n: int) -> None:
    c = random_crowd(n, seed=n, size=20.0)
    robot = srfm.RobotBody(x=10.0, y=10.0)
    serial = stepped(c, robot=robot, obstacles=WALLS, parallel=False, steps=10)
    parallel = stepped(c, robot=robot, obstacles=WALLS, parallel=True, steps=10)
    default = stepped(c, robot=robot, obstacles=WALLS, steps=10)
    np.testing.assert_array_equal(parallel.pos, serial.pos)
    np.testing.assert_array_equal(parallel.vel, serial.vel)
    np.testing.assert_array_equal(default.pos, serial.pos)
    assert not np.array_equal(serial.pos, c.pos)


def test_jitted_and_python_step_kernels_agree() -> None:
    c = random_crowd(15, seed=5)
    robot = srfm.RobotBody(x=3.0, y=3.0).as_array()
    p = srfm.SRFMParams().for_kernels()
    results = []
    for kernel in (_kernels.step_serial, _kernels.step_serial.py_func):
        s = c.copy()
        buf = np.empty((s.n, 2))
        context = ForceContext(p, robot, True, WALLS.for_kernels(), np.full(2, np.inf))
        kernel(s.for_kernels(), context, DT, buf)
        results.append(s)
    np.testing.assert_allclose(results[1].pos, results[0].pos, rtol=1e-14)
    np.testing.assert_allclose(results[1].vel, results[0].vel, rtol=1e-13)
    s = c.copy()
    buf = np.array(srfm.force_components(c, robot=srfm.RobotBody(x=3, y=3), obstacles=WALLS).total)
    _kernels.integrate.py_func(s.pos, s.vel, buf, s.vmax, DT)
    np.testing.assert_allclose(s.vel, results[0].vel, rtol=1e-14)


# --------------------------------------------------------------------------------------
# The robot switched off.


@settings(deadline=None, max_examples=40)
@given(scene=ref.scenes(), robot=ref.robots, dt=dts)
def test_zero_robot_strength_equals_no_robot(scene: ref.Scene, robot, dt: float) -> None:
    p = scene.params.replace(a_robot=0.0)
    off = stepped(scene.crowd, dt, p, robot, scene.obstacles, steps=5)
    none = stepped(scene.crowd, dt, p, None, scene.obstacles, steps=5)
    np.testing.assert_array_equal(off.pos, none.pos)
    np.testing.assert_array_equal(off.vel, none.vel)


def test_robot_changes_the_step_when_switched_on() -> None:
    # The counterpart of the test above: with A_r > 0 a nearby robot does matter.
    c = random_crowd(10, seed=11)
    robot = srfm.RobotBody(x=3.0, y=3.0)
    on = stepped(c, robot=robot, steps=5)
    none = stepped(c, steps=5)
    assert not np.array_equal(on.pos, none.pos)


def test_twin_crowds_stay_bit_identical_with_zero_robot_strength() -> None:
    c = random_crowd(25, seed=12)
    p = srfm.SRFMParams(a_robot=0.0)
    factual, counterfactual = c.copy(), c.copy()
    for k in range(100):
        robot = srfm.RobotBody(x=0.5 + 0.05 * k, y=3.0)
        srfm.step_crowd(factual, DT, p, robot, WALLS)
        srfm.step_crowd(counterfactual, DT, p, None, WALLS)
    np.testing.assert_array_equal(factual.pos, counterfactual.pos)
    np.testing.assert_array_equal(factual.vel, counterfactual.vel)


# --------------------------------------------------------------------------------------
# Degenerate states and inputs.


def test_degenerate_states_step_without_nan() -> None:
    c = srfm.CrowdState.create(
        pos=[[1.0, 1.0], [1.0, 1.0], [2.0, 0.0], [3.0, 3.0], [4.0, 4.0]],
        goal=[[1.0, 1.0], [5.0, 1.0], [2.0, 0.0], [3.0, 3.0], [4.0, 4.0]],
        v0=[1.25, 1.25, 1.25, 1.25, 0.0],
    )
    obstacles = srfm.Obstacles.create(
        segments=[[0.0, 0.0, 4.0, 0.0], [4.0, 4.0, 4.0, 4.0]], circles=[[3.0, 3.0, 0.3]]
    )
    robot = srfm.RobotBody(x=1.0, y=1.0)
    new = stepped(c, DT, None, robot, obstacles, steps=20)
    assert np.all(np.isfinite(new.pos))
    assert np.all(np.isfinite(new.vel))


@pytest.mark.parametrize("v0", [0.0, 1.25])
def test_at_rest_at_goal_stays_put(v0: float) -> None:
    c = srfm.CrowdState.create(pos=[[1.0, 1.0]], goal=[[1.0, 1.0]], v0=v0)
    new = stepped(c, steps=50)
    np.testing.assert_array_equal(new.pos, c.pos)
    np.testing.assert_array_equal(new.vel, 0.0)


def test_empty_crowd_steps() -> None:
    c = srfm.CrowdState.create(pos=np.zeros((0, 2)), goal=np.zeros((0, 2)))
    for parallel in (False, True):
        srfm.step_crowd(c, DT, parallel=parallel)
    assert c.pos.shape == (0, 2)


def test_step_is_deterministic() -> None:
    c = random_crowd(30, seed=13)
    a = stepped(c, obstacles=WALLS, robot=srfm.RobotBody(x=2, y=2), steps=20)
    b = stepped(c, obstacles=WALLS, robot=srfm.RobotBody(x=2, y=2), steps=20)
    np.testing.assert_array_equal(a.pos, b.pos)


@pytest.mark.parametrize("dt", [0.0, -0.1, float("nan"), float("inf"), 1.5])
def test_invalid_dt_raises(dt: float) -> None:
    c = random_crowd(3, seed=0)
    before = c.copy()
    with pytest.raises(srfm.SimulationError, match=rf"dt .*{dt!r}"):
        srfm.step_crowd(c, dt)
    np.testing.assert_array_equal(c.pos, before.pos)


@pytest.mark.parametrize(
    ("robot", "text"),
    [
        (srfm.RobotBody(x=0.0, y=0.0, radius=-0.2), "-0.2"),
        (srfm.RobotBody(x=float("nan"), y=0.0), "nan"),
        (srfm.RobotBody(x=0.0, y=float("inf")), "inf"),
    ],
)
def test_invalid_robot_body_raises(robot: srfm.RobotBody, text: str) -> None:
    c = random_crowd(3, seed=0)
    with pytest.raises(srfm.SimulationError, match=f"robot.*{text}"):
        srfm.step_crowd(c, DT, robot=robot)
    with pytest.raises(srfm.SimulationError, match=f"robot.*{text}"):
        srfm.force_components(c, robot=robot)
