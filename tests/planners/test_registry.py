"""The planner registry and the straight baseline."""

from __future__ import annotations

import numpy as np
import pytest

import srfm
from srfm.planners import (
    Planner,
    StraightPlanner,
    available_planners,
    make_planner,
    register_planner,
)
from srfm.planners._registry import _REGISTRY


def test_straight_is_registered_and_fresh_each_time() -> None:
    names = [p.name for p in available_planners()]
    assert "straight" in names
    a, b = make_planner("straight"), make_planner("straight")
    assert a is not b
    assert isinstance(a, Planner)


def test_unknown_and_duplicate_names() -> None:
    with pytest.raises(srfm.PlannerError, match=r"unknown planner 'nope'; known: .*straight"):
        make_planner("nope")
    with pytest.raises(srfm.PlannerError, match="already registered"):
        register_planner("straight", StraightPlanner, "again")
    with pytest.raises(srfm.PlannerError, match="planner name must be"):
        register_planner("bad name", StraightPlanner, "spaces")


def test_register_a_user_planner() -> None:
    register_planner("test-straight-copy", StraightPlanner, "a copy for this test")
    try:
        record = srfm.run_episode("footpath", 0, planner="test-straight-copy")
        assert record.outcome == "goal_reached"
    finally:
        del _REGISTRY["test-straight-copy"]


@pytest.mark.parametrize("name", srfm.EVALUATION_SCENARIOS)
def test_straight_reaches_the_goal_at_top_speed(name: str) -> None:
    record = srfm.run_episode(name, 0, planner="straight")
    assert record.outcome == "goal_reached"
    speeds = np.linalg.norm(record.robot_vel[1 : record.end_step + 1], axis=1)
    assert np.median(speeds) == pytest.approx(0.5)
    straight_line = np.linalg.norm(record.robot_goal - record.robot_pose[0, :2])
    assert record.robot_path_length_m() < straight_line
