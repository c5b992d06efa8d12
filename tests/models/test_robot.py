"""Robot kinematics and limits."""

from __future__ import annotations

import math

import attrs
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import srfm
from srfm.models import _robot_kernels as rk
from srfm.models.robot import RobotConfig, RobotState, apply_command
from srfm.models.state import CrowdState, Obstacles
from srfm.scenarios import WorldBounds

DT = 1.0 / 15.0
UNI = RobotConfig()
HOLO = RobotConfig(kinematics="holonomic")
finite = st.floats(-10.0, 10.0, allow_nan=False)


@settings(deadline=None, max_examples=200)
@given(v0=st.floats(-0.5, 0.5), w0=st.floats(-math.pi, math.pi), cv=finite, cw=finite)
def test_unicycle_respects_speed_and_acceleration_limits(
    v0: float, w0: float, cv: float, cw: float
) -> None:
    state = RobotState(x=1.0, y=2.0, theta=0.3, v=v0, omega=w0)
    nxt = apply_command(state, [cv, cw], UNI, DT)
    assert abs(nxt.v) <= UNI.max_speed_mps
    assert abs(nxt.omega) <= UNI.max_angular_speed_radps
    assert abs(nxt.v - v0) <= UNI.max_accel_mps2 * DT + 1e-12
    assert abs(nxt.omega - w0) <= UNI.max_angular_accel_radps2 * DT + 1e-12
    assert math.hypot(nxt.x - 1.0, nxt.y - 2.0) == pytest.approx(abs(nxt.v) * DT)
    assert -math.pi < nxt.theta <= math.pi


@settings(deadline=None, max_examples=200)
@given(vx=st.floats(-0.5, 0.5), vy=st.floats(-0.5, 0.5), cx=finite, cy=finite)
def test_holonomic_respects_speed_and_acceleration_limits(
    vx: float, vy: float, cx: float, cy: float
) -> None:
    if math.hypot(vx, vy) > 0.5:
        vx, vy = vx / 2, vy / 2
    state = RobotState(x=0.0, y=0.0, theta=0.0, vx=vx, vy=vy)
    nxt = apply_command(state, (cx, cy), HOLO, DT)
    assert math.hypot(nxt.vx, nxt.vy) <= HOLO.max_speed_mps + 1e-12
    assert math.hypot(nxt.vx - vx, nxt.vy - vy) <= HOLO.max_accel_mps2 * DT + 1e-12
    assert nxt.x == pytest.approx(nxt.vx * DT)
    assert nxt.y == pytest.approx(nxt.vy * DT)


def test_unicycle_drives_along_its_heading_and_turns() -> None:
    state = RobotState(x=0.0, y=0.0, theta=math.pi / 2, v=0.5)
    nxt = apply_command(state, [0.5, 0.0], UNI, DT)
    assert nxt.x == pytest.approx(0.0, abs=1e-15)
    assert nxt.y == pytest.approx(0.5 * DT)
    turning = RobotState(x=0.0, y=0.0, theta=0.0, omega=1.0)
    nxt = apply_command(turning, [0.0, 1.0], UNI, DT)
    assert nxt.theta == pytest.approx(DT)
    assert (nxt.x, nxt.y) == (0.0, 0.0)


def test_heading_wraps_into_minus_pi_pi() -> None:
    state = RobotState(x=0.0, y=0.0, theta=math.pi - 0.01, omega=math.pi)
    nxt = apply_command(state, [0.0, math.pi], UNI, DT)
    assert -math.pi < nxt.theta < 0.0


@pytest.mark.parametrize(
    "command",
    [[math.nan, 0.0], [0.0, math.inf], [1.0], [1.0, 2.0, 3.0], "ab", "12", b"12", None, 3.0],
)
def test_bad_commands_raise_planner_error(command: object) -> None:
    with pytest.raises(srfm.PlannerError, match="command"):
        apply_command(RobotState(x=0.0, y=0.0, theta=0.0), command, UNI, DT)


@pytest.mark.parametrize(
    ("field", "value"),
    [
        ("radius_m", -0.2),
        ("max_speed_mps", 0.0),
        ("max_accel_mps2", math.nan),
        ("kinematics", "tank"),
    ],
)
def test_config_validation(field: str, value: object) -> None:
    with pytest.raises(srfm.ParameterError, match=field.split("_")[0]):
        RobotConfig(**{field: value})  # type: ignore[arg-type]


def _remainder_wrap(angle: float) -> float:
    """The reference: CPython's math.remainder(angle, 2π), −π mapped to π."""
    wrapped = math.remainder(angle, 2.0 * math.pi)
    return math.pi if wrapped == -math.pi else wrapped


@given(st.floats(allow_nan=False, allow_infinity=False))
@settings(deadline=None, max_examples=500)
def test_wrap_angle_is_the_exact_remainder(angle: float) -> None:
    assert rk.wrap_angle(angle) == _remainder_wrap(angle)


@pytest.mark.parametrize(
    "angle",
    [
        math.pi,
        -math.pi,
        3 * math.pi,
        -3 * math.pi,
        0.0,
        -0.0,
        2 * math.pi,
        5 * math.pi,
        math.nextafter(math.pi, 4.0),
        math.nextafter(-math.pi, -4.0),
        1e300,
    ],
)
def test_wrap_angle_edges(angle: float) -> None:
    wrapped = rk.wrap_angle(angle)
    assert wrapped == _remainder_wrap(angle)
    assert -math.pi < wrapped <= math.pi


@pytest.mark.parametrize("kinematics", ["unicycle", "holonomic"])
def test_move_robot_equals_its_python_function(kinematics: str) -> None:
    """The kernel against its own code run by CPython (math.hypot there is CPython's:
    the holonomic update may differ in the last bits)."""
    config = RobotConfig(kinematics=kinematics)  # type: ignore[arg-type]
    limits = config.for_kernels()
    rng = np.random.default_rng(3)
    jit = np.array([1.0, 2.0, 3.0, 0.0, 0.0, 0.0, 0.0])
    ref = jit.copy()
    for _ in range(3000):
        c = rng.uniform(-4.0, 4.0, 2)
        rk.move_robot(jit, float(c[0]), float(c[1]), limits, DT)
        rk.move_robot.py_func(ref, float(c[0]), float(c[1]), limits, DT)
        if kinematics == "unicycle":
            assert jit.tobytes() == ref.tobytes()
        else:
            np.testing.assert_allclose(jit, ref, rtol=1e-12, atol=1e-12)
            ref[:] = jit  # compare single steps, not the drift


def test_apply_command_is_the_kernel() -> None:
    state = RobotState(x=1.0, y=2.0, theta=3.0, v=0.2, omega=-0.5)
    arr = state.as_array()
    rk.move_robot(arr, 0.4, 1.0, UNI.for_kernels(), DT)
    assert apply_command(state, (0.4, 1.0), UNI, DT) == RobotState.from_array(arr)
    assert RobotState.from_array(state.as_array()) == state


def test_robot_limits_mirror_the_config() -> None:
    limits = HOLO.for_kernels()
    assert limits.holonomic is True
    assert UNI.for_kernels().holonomic is False
    for field in attrs.fields(RobotConfig):
        if field.name != "kinematics":
            assert getattr(limits, field.name) == getattr(HOLO, field.name)


def _event(
    x: float, y: float, step: int = 1, obstacles: Obstacles | None = None
) -> tuple[int, int]:
    obstacles = obstacles if obstacles is not None else Obstacles.create()
    crowd = CrowdState.create(pos=[[3.0, 3.0], [6.0, 6.0]], goal=[[0.0, 0.0], [0.0, 0.0]])
    task = rk.robot_task(np.array([9.0, 9.0]), WorldBounds(), 750)
    return rk.robot_event(
        np.array([x, y, 0.0, 0.0, 0.0, 0.0, 0.0]),
        crowd.for_kernels(),
        obstacles.for_kernels(),
        UNI.for_kernels(),
        task,
        step,
    )


def test_robot_events_in_order() -> None:
    assert _event(6.0, 6.45) == (rk.EVENT_COLLISION, 1)  # clearance 0.15 < 0.2
    assert _event(6.0, 6.55) == (rk.EVENT_NONE, -1)  # clearance 0.25
    pillar = Obstacles.create(circles=[[12.0, 3.0, 1.0]])
    assert _event(12.0, 4.1, obstacles=pillar) == (rk.EVENT_OBSTACLE, -1)
    wall = Obstacles.create(segments=[[0.0, 12.0, 15.0, 12.0]])
    assert _event(5.0, 11.85, obstacles=wall) == (rk.EVENT_OBSTACLE, -1)
    assert _event(-0.01, 5.0) == (rk.EVENT_OUT_OF_BOUNDS, -1)
    assert _event(0.0, 5.0) == (rk.EVENT_NONE, -1)  # edges are inside
    assert _event(9.3, 9.3) == (rk.EVENT_GOAL, -1)  # 0.42 m < 0.5 m
    assert _event(9.0, 9.5) == (rk.EVENT_NONE, -1)  # exactly 0.5 m: not yet
    assert _event(5.0, 5.0, step=750) == (rk.EVENT_TIMEOUT, -1)
    # the first check that holds wins: a collision at the goal at the horizon
    assert _event(3.0, 3.4, step=750) == (rk.EVENT_COLLISION, 0)
