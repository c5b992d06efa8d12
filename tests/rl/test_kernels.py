"""The environment kernels' exact re-implementations of Python's math and robot code."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from srfm.models.robot import RobotConfig, RobotState, _wrap, apply_command
from srfm.rl import _kernels as kern

finite = st.floats(min_value=-1e6, max_value=1e6, allow_nan=False, allow_infinity=False)
tiny_or_large = st.floats(allow_nan=False, allow_infinity=False)


@given(tiny_or_large, tiny_or_large)
@settings(deadline=None, max_examples=400)
def test_py_hypot_is_cpython_hypot(x: float, y: float) -> None:
    expected = math.hypot(x, y)
    if math.isinf(expected):
        return  # overflow: not reachable from the simulation
    assert kern.py_hypot(x, y) == expected


def test_py_hypot_bulk_random() -> None:
    rng = np.random.default_rng(7)
    xs = rng.normal(size=20_000) * 10.0 ** rng.integers(-6, 6, size=20_000)
    ys = rng.normal(size=20_000) * 10.0 ** rng.integers(-6, 6, size=20_000)
    bad = [(x, y) for x, y in zip(xs, ys, strict=True) if kern.py_hypot(x, y) != math.hypot(x, y)]
    assert bad == []


@given(finite)
@settings(deadline=None, max_examples=400)
def test_wrap_is_robot_wrap(angle: float) -> None:
    assert kern._wrap(angle) == _wrap(angle)


@pytest.mark.parametrize(
    "angle", [math.pi, -math.pi, 3 * math.pi, -3 * math.pi, 0.0, 2 * math.pi, 5 * math.pi]
)
def test_wrap_edges(angle: float) -> None:
    assert kern._wrap(angle) == _wrap(angle)


@pytest.mark.parametrize("kinematics", ["unicycle", "holonomic"])
def test_apply_command_kernel_matches_python(kinematics: str) -> None:
    config = RobotConfig(kinematics=kinematics)  # type: ignore[arg-type]
    cfg = np.zeros(kern.CFG_SIZE)
    cfg[kern.C_DT] = 1 / 15
    cfg[kern.C_VMAX] = config.max_speed_mps
    cfg[kern.C_WMAX] = config.max_angular_speed_radps
    cfg[kern.C_ACCEL] = config.max_accel_mps2
    cfg[kern.C_ANG_ACCEL] = config.max_angular_accel_radps2
    cfg[kern.C_HOLONOMIC] = 1.0 if kinematics == "holonomic" else 0.0
    rng = np.random.default_rng(3)
    state = RobotState(x=1.0, y=2.0, theta=3.0)
    arr = np.array([1.0, 2.0, 3.0, 0.0, 0.0, 0.0, 0.0])
    for _ in range(3000):
        c = rng.uniform(-4.0, 4.0, 2)
        state = apply_command(state, c, config, 1 / 15)
        kern.apply_command_kernel(arr, float(c[0]), float(c[1]), cfg)
        got = RobotState(
            x=arr[0], y=arr[1], theta=arr[2], vx=arr[3], vy=arr[4], v=arr[5], omega=arr[6]
        )
        assert got == state
