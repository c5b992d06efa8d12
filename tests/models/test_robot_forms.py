"""The robot force's forms: kernels against a plain-NumPy reference, finite numbers at
the singularities, the twin guarantee of every form, the parameter set's form."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import srfm
from srfm.metrics import episode_metrics
from srfm.models import _robot_forces as rf
from srfm.models.params import FORM_FIELDS, ROBOT_FORMS
from srfm.scenarios import BUILTIN_SCENARIOS
from tests.models import _reference as ref
from tests.models import _robot_reference as rref

ANTICIPATORY = ("ttc", "collision_prediction", "elliptical", "sidestep")
STRENGTH = {"exponential": "a_robot", "ttc": "ttc_k", "collision_prediction": "cp_a"}
STRENGTH["elliptical"] = "ell_a"
STRENGTH["sidestep"] = "ss_a"

# --------------------------------------------------------------------------------------
# Kernels against the NumPy reference.


@st.composite
def form_params(draw: st.DrawFn, form: str) -> srfm.SRFMParams:
    """Parameters of ``form`` over a plausible range (the cap sometimes binding)."""
    t_min = draw(st.floats(0.01, 1.0))
    return srfm.SRFMParams(
        robot_form=form,
        ttc_k=draw(st.floats(0.0, 5.0)),
        ttc_tau0=draw(st.floats(0.5, 6.0)),
        cp_a=draw(st.floats(0.0, 3.0)),
        cp_b=draw(st.floats(0.1, 2.0)),
        cp_t_min=t_min,
        cp_t_max=draw(st.floats(t_min, 8.0)),
        ell_a=draw(st.floats(0.0, 10.0)),
        ell_b=draw(st.floats(0.1, 2.0)),
        ell_dt=draw(st.floats(0.0, 3.0)),
        lambda_robot=draw(st.floats(0.0, 1.0)),
        robot_force_cap=draw(st.floats(1.0, 50.0)),
        ss_a=draw(st.floats(0.0, 30.0)),
        ss_miss=draw(st.floats(0.05, 3.0)),
        ss_horizon=draw(st.floats(0.1, 8.0)),
        ss_speed_gain=draw(st.floats(-3.0, 3.0)),
    )


moving_robots = st.builds(
    lambda p, r, v: srfm.RobotBody(x=p[0], y=p[1], radius=r, vx=v[0], vy=v[1]),
    ref.points,
    st.floats(0.0, 0.5),
    ref.velocities,
)


def _check_against_reference(
    crowd: srfm.CrowdState, params: srfm.SRFMParams, robot: srfm.RobotBody
) -> None:
    got = srfm.force_components(crowd, params, robot).robot
    v_des = ref.desired_velocity(crowd.pos, crowd.goal, crowd.v0)
    heading, has_heading = ref.headings(crowd.vel, v_des)
    want = rref.robot_force(crowd, params, robot, heading, has_heading)
    assert np.all(np.isfinite(got))
    assert np.all(np.linalg.norm(got, axis=1) <= params.robot_force_cap * (1 + 1e-12))
    np.testing.assert_allclose(got, want, rtol=1e-7, atol=1e-9 * params.robot_force_cap)


@pytest.mark.parametrize("form", ANTICIPATORY)
@settings(deadline=None, max_examples=150)
@given(data=st.data())
def test_kernel_matches_the_numpy_reference(form: str, data: st.DataObject) -> None:
    crowd = data.draw(ref.crowd_states())
    params = data.draw(form_params(form))
    robot = data.draw(moving_robots)
    _check_against_reference(crowd, params, robot)


def _edge_crowd() -> tuple[srfm.CrowdState, srfm.RobotBody]:
    """Pedestrians at the singular states: on the robot's centre, overlapping it,
    touching it, on an exact collision course, grazing, at rest, moving with it."""
    robot = srfm.RobotBody(x=0.0, y=0.0, radius=0.3, vx=1.0, vy=0.0)
    pos = [
        [0.0, 0.0],  # on the robot's centre
        [0.2, 0.1],  # overlapping, at the robot's velocity
        [0.6, 0.0],  # touching (r_sum = 0.6), head-on
        [3.0, 0.0],  # exact collision course, head-on
        [3.0, 0.6],  # grazing: the closest approach is the contact distance
        [3.0, 0.6 + 1e-9],  # a hair off grazing
        [2.0, 0.0],  # at rest, the robot coming
        [0.0, 2.0],  # moving with the robot (zero relative velocity)
        [1e-13, 0.0],  # closer than EPS to the centre
        [-2.0, 0.0],  # behind the robot, slower than it
    ]
    vel = [
        [0.0, 0.0],
        [1.0, 0.0],
        [-1.0, 0.0],
        [-1.0, 0.0],
        [-1.0, 0.0],
        [-1.0, 0.0],
        [0.0, 0.0],
        [1.0, 0.0],
        [0.5, 0.5],
        [0.5, 0.0],
    ]
    crowd = srfm.CrowdState.create(
        pos=np.array(pos), vel=np.array(vel), goal=np.array(pos) + np.array([5.0, 0.0]), radius=0.3
    )
    return crowd, robot


@pytest.mark.parametrize("form", ANTICIPATORY)
def test_singular_states_give_finite_capped_forces_matching_the_reference(form: str) -> None:
    crowd, robot = _edge_crowd()
    params = srfm.SRFMParams(robot_form=form)
    f = srfm.force_components(crowd, params, robot).robot
    assert np.all(np.isfinite(f))
    mag = np.linalg.norm(f, axis=1)
    assert np.all(mag <= params.robot_force_cap * (1 + 1e-12))
    assert mag[0] == 0.0  # no direction on the robot's centre
    assert mag[8] == 0.0  # nor closer than EPS
    if form != "elliptical":
        assert mag[7] == 0.0  # no relative motion: nothing to anticipate
        assert mag[9] == 0.0  # behind and falling back
    assert mag[3] > 0.0  # an exact collision course pushes
    if form == "sidestep":  # sideways, to the right of its heading (−x): +y
        assert f[3, 0] == 0.0
        assert f[3, 1] > 0.0
    else:  # back along the course
        assert f[3, 0] > 0.0
    _check_against_reference(crowd, params, robot)


@pytest.mark.parametrize("form", ANTICIPATORY)
def test_extreme_valid_inputs_stay_finite(form: str) -> None:
    # The bounds of the parameters and of the state: tiny ranges and times, huge
    # strengths and speeds, deep overlaps and tiny distances.
    params = srfm.SRFMParams(
        robot_form=form,
        ttc_k=1e6,
        ttc_tau0=1e-3,
        cp_a=1e6,
        cp_b=1e-5,
        cp_t_min=1e-3,
        cp_t_max=1e-3,
        ell_a=1e6,
        ell_b=1e-5,
        ell_dt=1e3,
        robot_force_cap=1e6,
        ss_a=1e6,
        ss_miss=1e-5,
        ss_horizon=1e3,
        ss_speed_gain=10.0,
    )
    rng = np.random.default_rng(3)
    pos = rng.uniform(-1.0, 1.0, (40, 2)) * rng.choice([1e-9, 1e-3, 1.0, 1e3], (40, 1))
    vel = rng.uniform(-1.0, 1.0, (40, 2)) * rng.choice([0.0, 1e-6, 1.0, 500.0], (40, 1))
    crowd = srfm.CrowdState.create(pos=pos, vel=vel, goal=pos + 1.0, radius=0.3, vmax=1e3)
    for robot in (
        srfm.RobotBody(x=0.0, y=0.0, radius=1e3, vx=700.0, vy=-700.0),
        srfm.RobotBody(x=1e-10, y=0.0, radius=0.0, vx=0.0, vy=0.0),
    ):
        f = srfm.force_components(crowd, params, robot).robot
        assert np.all(np.isfinite(f))
        assert np.all(np.linalg.norm(f, axis=1) <= 1e6 * (1 + 1e-12))


def test_ttc_force_is_the_energy_gradient() -> None:
    # −∇_p E(τ(p)) by central differences of the energy k τ⁻² e^(−τ/τ0), away from the
    # cap: the closed form of the kernel is the paper's gradient.
    k, tau0, r = 1.5, 3.0, 0.5

    def energy(px: float, py: float, wx: float, wy: float) -> float:
        a = wx * wx + wy * wy
        b = px * wx + py * wy
        c = px * px + py * py - r * r
        tau = (-b - math.sqrt(b * b - a * c)) / a
        return k * math.exp(-tau / tau0) / tau**2

    for px, py, wx, wy in ((3.0, 0.2, -1.2, 0.1), (-2.0, 1.0, 1.0, -0.3), (1.5, -1.0, -0.8, 0.9)):
        fx, fy = rf.ttc_force.py_func(px, py, wx, wy, 0.0, 0.0, 0.0, 0.0, r, k, tau0, 1e9)
        h = 1e-6
        gx = -(energy(px + h, py, wx, wy) - energy(px - h, py, wx, wy)) / (2 * h)
        gy = -(energy(px, py + h, wx, wy) - energy(px, py - h, wx, wy)) / (2 * h)
        np.testing.assert_allclose([fx, fy], [gx, gy], rtol=1e-6)


def test_elliptical_force_at_equal_velocities_is_the_papers_force() -> None:
    # y = 0: the ellipse is a circle and the elliptical force the exponential one.
    crowd = srfm.CrowdState.create(
        pos=np.array([[1.0, 0.5], [-0.7, 0.2]]),
        vel=np.array([[0.4, -0.2], [0.4, -0.2]]),
        goal=np.array([[5.0, 0.0], [0.0, 4.0]]),
    )
    robot = srfm.RobotBody(x=0.0, y=0.0, vx=0.4, vy=-0.2)
    paper = srfm.SRFMParams(lambda_robot=0.3)
    ell = paper.replace(robot_form="elliptical", ell_a=paper.a_robot, ell_b=paper.b_robot)
    np.testing.assert_allclose(
        srfm.force_components(crowd, ell, robot).robot,
        srfm.force_components(crowd, paper, robot).robot,
        rtol=1e-12,
    )


def test_collision_prediction_uses_the_clamped_time_of_closest_approach() -> None:
    # A pedestrian at rest... feels nothing (|v_i| = 0); walking towards a robot 10 m
    # away at 1 m/s (closest approach in 10 s), the prediction stops at t_max.
    crowd = srfm.CrowdState.create(
        pos=np.array([[10.0, 0.5], [2.0, 0.0]]),
        vel=np.array([[-1.0, 0.0], [0.0, 0.0]]),
        goal=np.array([[-5.0, 0.5], [2.0, 5.0]]),
        radius=0.3,
    )
    robot = srfm.RobotBody(x=0.0, y=0.0, radius=0.2, vx=0.5, vy=0.0)
    p = srfm.SRFMParams(robot_form="collision_prediction", cp_a=2.0, cp_b=0.5, cp_t_max=3.0)
    f = srfm.force_components(crowd, p, robot).robot
    t = 3.0  # min(10 / 1.5, 3)
    q = np.array([10.0 - 1.5 * t, 0.5])
    want = 2.0 * 1.0 / t * math.exp(-(np.linalg.norm(q) - 0.5) / 0.5) * q / np.linalg.norm(q)
    np.testing.assert_allclose(f[0], want, rtol=1e-12)
    np.testing.assert_array_equal(f[1], [0.0, 0.0])


# --------------------------------------------------------------------------------------
# The twin guarantee: a robot of zero strength, in every form, on every scenario.


@pytest.mark.parametrize("name", BUILTIN_SCENARIOS)
def test_zero_strength_twins_are_bit_identical_in_every_form(name: str) -> None:
    for form in ANTICIPATORY:
        params = srfm.SRFMParams(robot_form=form, **{STRENGTH[form]: 0.0})
        record = srfm.run_episode(name, seed=5, params=params, planner="straight")
        assert np.array_equal(record.factual_pos, record.counterfactual_pos), form
        assert np.array_equal(record.factual_vel, record.counterfactual_vel), form


@pytest.mark.parametrize("form", ANTICIPATORY)
def test_each_form_moves_the_factual_crowd(form: str) -> None:
    record = srfm.run_episode("frontal_approach", seed=5, params=srfm.SRFMParams(robot_form=form))
    assert record.twin_separation_m().max() > 0.01
    metrics = episode_metrics(record)
    assert np.nanmax(metrics.pedestrians["robot_force_max_mps2"]) > 0.0


def test_the_step_reads_the_robots_velocity() -> None:
    # The same robot position, two velocities: the anticipatory forms differ, the
    # paper's does not.
    crowd = srfm.CrowdState.create(
        pos=np.array([[3.0, 0.2]]), vel=np.array([[-1.0, 0.0]]), goal=np.array([[-5.0, 0.2]])
    )
    still = srfm.RobotBody(x=0.0, y=0.0)
    coming = srfm.RobotBody(x=0.0, y=0.0, vx=1.0)
    for form in ROBOT_FORMS:
        p = srfm.SRFMParams(robot_form=form)
        a = srfm.force_components(crowd, p, still).robot
        b = srfm.force_components(crowd, p, coming).robot
        assert np.array_equal(a, b) == (form == "exponential"), form


# --------------------------------------------------------------------------------------
# Parameters: the form, its fields, validation, files.


def test_default_form_is_the_papers_and_is_written_as_before() -> None:
    p = srfm.SRFMParams()
    assert p.robot_form == "exponential"
    assert list(p.as_dict()) == [
        "a_ped",
        "b_ped",
        "lambda_ped",
        "tau",
        "a_robot",
        "b_robot",
        "lambda_robot",
        "a_obs",
        "b_obs",
    ]
    # the built-in presets are the paper's form but for the real-data time-to-collision fit
    forms = {name: q.robot_form for name, q in srfm.PRESETS.items()}
    assert forms.pop("navwareset2026_ttc") == "ttc"
    assert set(forms.values()) == {"exponential"}


@pytest.mark.parametrize("form", ANTICIPATORY)
def test_a_form_round_trips_through_a_parameter_file(tmp_path: Path, form: str) -> None:
    p = srfm.SRFMParams(robot_form=form, robot_force_cap=12.5, lambda_robot=0.5)
    p = p.replace(**{STRENGTH[form]: 0.75})
    path = tmp_path / "p.toml"
    srfm.save_params(p, path, meta={"form": form})
    text = path.read_text(encoding="utf-8")
    assert f'robot_form = "{form}"' in text
    q = srfm.load_params(path)
    assert q.robot_form == form
    assert q.as_dict() == p.as_dict()
    assert set(FORM_FIELDS[form]) <= set(q.as_dict())


def test_a_file_names_its_form_over_a_preset(tmp_path: Path) -> None:
    path = tmp_path / "p.toml"
    path.write_text(
        'schema_version = 1\npreset = "ferrer2013"\n[params]\nrobot_form = "ttc"\nttc_k = 0.8\n',
        encoding="utf-8",
    )
    q = srfm.load_params(path)
    assert (q.robot_form, q.ttc_k, q.tau) == ("ttc", 0.8, 0.43)


@pytest.mark.parametrize(
    ("changes", "pattern"),
    [
        ({"robot_form": "powerlaw"}, r"robot_form 'powerlaw'.*exponential, ttc"),
        ({"robot_form": 1}, r"robot_form 1"),
        ({"ttc_k": -1.0}, r"ttc_k.*-1\.0"),
        ({"ttc_tau0": 0.0}, r"ttc_tau0.*0\.0"),
        ({"ttc_tau0": 1e4}, r"ttc_tau0.*10000"),
        ({"cp_b": 0.0}, r"cp_b.*0\.0"),
        ({"cp_t_min": 2.0, "cp_t_max": 1.0}, r"cp_t_max.*1\.0"),
        ({"cp_t_max": float("nan")}, r"cp_t_max.*nan"),
        ({"ell_dt": -0.5}, r"ell_dt.*-0\.5"),
        ({"ell_a": 2e6}, r"ell_a.*2000000"),
        ({"robot_force_cap": 0.0}, r"robot_force_cap.*0\.0"),
        ({"robot_force_cap": float("inf")}, r"robot_force_cap.*inf"),
        ({"ttc_horizon": 3.0}, r"'ttc_horizon'"),
        ({"ss_a": -0.1}, r"ss_a.*-0\.1"),
        ({"ss_miss": 0.0}, r"ss_miss.*0\.0"),
        ({"ss_horizon": 0.0}, r"ss_horizon.*0\.0"),
        ({"ss_speed_gain": 11.0}, r"ss_speed_gain.*\[-10, 10\] s/m, got 11\.0"),
        ({"ss_speed_gain": float("nan")}, r"ss_speed_gain.*nan"),
    ],
)
def test_bad_form_parameters_raise_naming_them(changes: dict[str, object], pattern: str) -> None:
    with pytest.raises(srfm.ParameterError, match=pattern):
        srfm.SRFMParams().replace(**changes)


def test_a_bad_form_in_a_file_names_the_file(tmp_path: Path) -> None:
    path = tmp_path / "p.toml"
    path.write_text('schema_version = 1\n[params]\nrobot_form = "social"\n', encoding="utf-8")
    with pytest.raises(srfm.ParameterError, match=r"p\.toml.*robot_form 'social'"):
        srfm.load_params(path)


def test_kernel_codes_follow_the_form_names() -> None:
    codes = (
        rf.FORM_EXPONENTIAL,
        rf.FORM_TTC,
        rf.FORM_COLLISION_PREDICTION,
        rf.FORM_ELLIPTICAL,
        rf.FORM_SIDESTEP,
    )
    assert tuple(ROBOT_FORMS[c] for c in codes) == ROBOT_FORMS
    for form in ROBOT_FORMS:
        assert srfm.SRFMParams(robot_form=form).for_kernels().robot_form == ROBOT_FORMS.index(form)


def test_robot_body_velocity_is_validated() -> None:
    crowd = srfm.CrowdState.create(pos=np.zeros((1, 2)), goal=np.ones((1, 2)))
    with pytest.raises(srfm.SimulationError, match="speed"):
        srfm.force_components(crowd, robot=srfm.RobotBody(x=1.0, y=1.0, vx=2e3))
    with pytest.raises(srfm.SimulationError, match="nan"):
        srfm.force_components(crowd, robot=srfm.RobotBody(x=1.0, y=1.0, vy=float("nan")))


# --------------------------------------------------------------------------------------
# The sidestep form (issue 40): onset, horizon, amplitude, side and robot speed.


def _sidestep(
    ped: tuple[float, float], vel: tuple[float, float], robot_v: float, **changes: float
) -> np.ndarray:
    crowd = srfm.CrowdState.create(
        pos=np.array([ped]), vel=np.array([vel]), goal=np.array([ped]) + 10 * np.array([vel])
    )
    params = srfm.SRFMParams(robot_form="sidestep").replace(**changes)
    robot = srfm.RobotBody(x=0.0, y=0.0, vx=robot_v, vy=0.0)
    return np.asarray(srfm.force_components(crowd, params, robot).robot[0])


def test_sidestep_is_the_documented_hinge_of_miss_and_time() -> None:
    # A pedestrian 4 m ahead walking at 1 m/s toward a robot at 1 m/s, 0.3 m to the
    # side: t* = 2 s, d* = 0.3 m; the force is A (1 − d*/d_on)(1 − t*/T), sideways to
    # its heading (−x), on the side of the predicted miss (+y).
    f = _sidestep((4.0, 0.3), (-1.0, 0.0), 1.0, ss_a=0.5, ss_miss=0.75, ss_horizon=3.5)
    want = 0.5 * (1 - 0.3 / 0.75) * (1 - 2.0 / 3.5)
    np.testing.assert_allclose(f, [0.0, want], rtol=1e-12, atol=1e-15)
    # mirrored miss, mirrored step
    g = _sidestep((4.0, -0.3), (-1.0, 0.0), 1.0, ss_a=0.5, ss_miss=0.75, ss_horizon=3.5)
    np.testing.assert_allclose(g, [0.0, -want], rtol=1e-12, atol=1e-15)
    # beyond the onset, beyond the horizon, after the pass: nothing
    assert not np.any(_sidestep((4.0, 0.8), (-1.0, 0.0), 1.0, ss_miss=0.75))
    assert not np.any(_sidestep((8.0, 0.3), (-1.0, 0.0), 1.0, ss_horizon=3.5))
    assert not np.any(_sidestep((-1.0, 0.3), (-1.0, 0.0), 1.0))


def test_sidestep_grows_with_the_robots_speed_by_its_gain() -> None:
    # the same relative motion (w = −2 m/s along x) with the robot at 1.5 or 0.5 m/s
    fast = _sidestep((4.0, 0.3), (-0.5, 0.0), 1.5, ss_speed_gain=1.2)
    slow = _sidestep((4.0, 0.3), (-1.5, 0.0), 0.5, ss_speed_gain=1.2)
    np.testing.assert_allclose(np.linalg.norm(fast) / np.linalg.norm(slow), math.exp(1.2))
    flat = _sidestep((4.0, 0.3), (-0.5, 0.0), 1.5, ss_speed_gain=0.0)
    np.testing.assert_allclose(np.linalg.norm(flat), np.linalg.norm(slow / math.exp(-0.6)))


def test_sidestep_amplitude_is_separate_from_the_cap() -> None:
    a = _sidestep((4.0, 0.3), (-1.0, 0.0), 1.0, ss_a=0.5, robot_force_cap=20.0)
    b = _sidestep((4.0, 0.3), (-1.0, 0.0), 1.0, ss_a=0.5, robot_force_cap=0.05)
    assert np.linalg.norm(a) > 0.05
    np.testing.assert_allclose(np.linalg.norm(b), 0.05)
    np.testing.assert_allclose(b / np.linalg.norm(b), a / np.linalg.norm(a))
