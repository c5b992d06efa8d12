"""The environment's action scaling and observation kernels against plain references."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from srfm.models._robot_kernels import robot_task
from srfm.models.robot import RobotConfig
from srfm.planners._observation import (
    EnvConfig,
    action_to_command,
    build_observation,
    obs_size,
)
from srfm.scenarios import WorldBounds

action = st.floats(min_value=-3.0, max_value=3.0, allow_nan=False)
angle = st.floats(min_value=-math.pi, max_value=math.pi, allow_nan=False)


@given(action, action, angle)
@settings(deadline=None, max_examples=300)
def test_action_to_command_matches_a_reference(a0: float, a1: float, theta: float) -> None:
    uni = RobotConfig().for_kernels()
    holo = RobotConfig(kinematics="holonomic").for_kernels()
    b0 = min(1.0, max(-1.0, a0))
    b1 = min(1.0, max(-1.0, a1))
    assert action_to_command(a0, a1, theta, uni) == (b0 * 0.5, b1 * math.pi)
    cx, cy = b0 * 0.5, b1 * 0.5
    expected = (
        cx * math.cos(theta) - cy * math.sin(theta),
        cx * math.sin(theta) + cy * math.cos(theta),
    )
    assert action_to_command(a0, a1, theta, holo) == expected


@pytest.mark.parametrize("kinematics", ["unicycle", "holonomic"])
def test_build_observation_equals_its_python_function(kinematics: str) -> None:
    rng = np.random.default_rng(5)
    world = WorldBounds()
    limits = RobotConfig(kinematics=kinematics).for_kernels()  # type: ignore[arg-type]
    params = EnvConfig(max_pedestrians=4, range_beams=12).observation_params(world)
    for _ in range(50):
        n = int(rng.integers(0, 12))
        pos = rng.uniform(0.0, 15.0, (n, 2))
        vel = rng.uniform(-1.5, 1.5, (n, 2))
        robot = np.concatenate([rng.uniform(0.0, 15.0, 2), rng.uniform(-3.0, 3.0, 5)])
        task = robot_task(rng.uniform(0.0, 15.0, 2), world, 750)
        last = rng.uniform(-2.0, 2.0, 2)
        segments = rng.uniform(0.0, 15.0, (int(rng.integers(0, 5)), 4))
        circles = np.column_stack([rng.uniform(0.0, 15.0, (2, 2)), rng.uniform(0.1, 1.0, 2)])[
            : int(rng.integers(0, 3))
        ]
        outs = []
        for fn in (build_observation, build_observation.py_func):
            out = np.zeros(obs_size(4, 12), dtype=np.float32)
            k = fn(
                pos,
                vel,
                robot,
                last,
                False,
                True,
                limits,
                task,
                params,
                segments,
                circles,
                np.zeros(max(n, 1)),
                np.zeros(max(n, 1), dtype=np.int64),
                out,
            )
            outs.append((k, out.tobytes()))
        assert outs[0] == outs[1]
