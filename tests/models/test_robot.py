"""Robot kinematics and limits."""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import srfm
from srfm.models.robot import RobotConfig, RobotState, apply_command

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
