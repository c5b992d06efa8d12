"""A planner's command and an agent's action are exactly two finite real
numbers; anything else is refused with a PlannerError naming the value, before
anything moves (one rule: srfm.models.robot.command_pair)."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

import srfm
from srfm.errors import ParameterError, PlannerError
from srfm.models.robot import command_pair
from srfm.rl.env import SocialNavEnv

BAD: list[Any] = [
    [0.1, 0.2, 0.3],
    "12",
    b"12",
    {"v": 1.0},
    {0: 0.1, 1: 0.2},
    [1j, 0.0],
    np.array([1 + 0j, 0j]),
    None,
    5.0,
    [[0.1], [0.2]],
    ["0.1", "0.2"],
    np.array(["0.1", "0.2"]),
    [True, 0.0],
    np.array([True, False]),
    [0.1],
    [],
    [float("nan"), 0.0],
    [0.0, float("inf")],
]


@pytest.mark.parametrize("value", BAD, ids=repr)
def test_command_pair_refuses(value: Any) -> None:
    with pytest.raises(PlannerError, match="a command must be"):
        command_pair(value)


@pytest.mark.parametrize(
    "value", [(0.1, 0.2), [1, 2], np.array([0.1, 0.2], dtype=np.float32), np.array([1, 2])]
)
def test_command_pair_accepts_numbers(value: Any) -> None:
    assert command_pair(value) == (float(value[0]), float(value[1]))


@pytest.mark.parametrize("value", BAD, ids=repr)
def test_environment_refuses_bad_actions_and_keeps_its_state(value: Any) -> None:
    env = SocialNavEnv("crosswalk")
    env.reset(seed=1)
    before = env.robot_state
    with pytest.raises(PlannerError, match="an action must be"):
        env.step(value)
    assert env.step_index == 0
    assert env.robot_state == before
    env.step(np.zeros(2, dtype=np.float32))  # the episode goes on
    assert env.step_index == 1


@pytest.mark.parametrize("options", [5, "episode_seed=3", [("episode_seed", 3)]], ids=repr)
def test_environment_reset_options_must_be_a_dict(options: Any) -> None:
    env = SocialNavEnv("crosswalk")
    with pytest.raises(ParameterError, match="reset options must be a dict"):
        env.reset(options=options)


@pytest.mark.parametrize("value", BAD, ids=repr)
def test_simulator_refuses_bad_commands(value: Any) -> None:
    sim = srfm.TwinSimulator(srfm.episode_setup(srfm.load_scenario("crosswalk"), 0))
    with pytest.raises(PlannerError, match="a command must be"):
        sim.step(value if value is not None else "x")
    sim.step((0.1, 0.0))  # nothing moved before the refusal: the run continues
