"""The recorded-robot planner and the scenario of a recorded scene (issue 15, item 4)."""

from __future__ import annotations

import attrs
import numpy as np
import pytest

import srfm
from srfm.errors import PlannerError, ScenarioError
from srfm.planners.recorded import RecordedRobotPlanner, recorded_encounter
from tests.datasets._synthetic import simulate_scene

TRUE = srfm.SRFMParams(tau=0.6, a_robot=4.0, b_robot=0.6)


def test_replays_the_recorded_robot_in_the_twin_episode() -> None:
    scene = simulate_scene(TRUE, 7, name="rec", robot=True, n_per_side=2)
    scenario, planner = recorded_encounter(scene)
    assert scenario.n_pedestrians == 4
    assert scenario.robot.kinematics == "holonomic"
    rec = srfm.run_episode(scenario, 0, planner)
    end = rec.end_step
    assert end > 10
    robot = rec.robot_pose[: end + 1, :2]
    wanted = np.array([planner.position_at(t) for t in rec.time_s[: end + 1]])
    np.testing.assert_allclose(robot, wanted, atol=1e-9)
    # the recorded robot drives at 0.5 m/s along y = 7 from x = 16
    assert robot[0].tolist() == pytest.approx([16.0, 7.0])
    assert np.allclose(robot[:, 1], 7.0)
    # the twins: the factual crowd feels the recorded robot, the counterfactual does not
    assert not np.array_equal(rec.factual_pos, rec.counterfactual_pos)
    # the pedestrians start where they were first observed
    first = np.array([scene.track(a)[2][0] for a in scene.agent_ids[:4]])
    np.testing.assert_allclose(rec.factual_pos[0], first)


def test_bad_input_is_refused() -> None:
    with pytest.raises(PlannerError, match="n >= 2"):
        RecordedRobotPlanner([0.0], [[0.0, 0.0]])
    with pytest.raises(PlannerError, match="finite"):
        RecordedRobotPlanner([0.0, 1.0], [[0.0, 0.0], [np.nan, 0.0]])
    with pytest.raises(PlannerError, match="increase strictly"):
        RecordedRobotPlanner([0.0, 0.0], [[0.0, 0.0], [1.0, 0.0]])
    with pytest.raises(PlannerError, match="start at 0"):
        RecordedRobotPlanner([1.0, 2.0], [[0.0, 0.0], [1.0, 0.0]])
    scene = simulate_scene(TRUE, 7, name="rec", robot=True, n_per_side=1)
    scenario, planner = recorded_encounter(scene)
    unicycle = attrs.evolve(scenario, robot=attrs.evolve(scenario.robot, kinematics="unicycle"))
    with pytest.raises(PlannerError, match="holonomic"):
        srfm.run_episode(unicycle, 0, planner)
    with pytest.raises(ScenarioError, match="no robot"):
        recorded_encounter(simulate_scene(TRUE, 7, name="x", n_per_side=1))


def test_real_recording() -> None:
    from srfm.datasets import navwareset
    from tests.datasets.conftest import data_dir

    folder = data_dir() / "navwareset"
    if not folder.is_dir():
        pytest.skip(f"{folder} not found; set SRFM_DATA_DIR to the shared data folder")
    path = sorted(folder.glob("*.csv"))[0]
    scenario, planner = recorded_encounter(navwareset.read_file(path))
    rec = srfm.run_episode(scenario, 0, planner)
    assert rec.outcome == "goal_reached"
    end = rec.end_step
    wanted = np.array([planner.position_at(t) for t in rec.time_s[: end + 1]])
    np.testing.assert_allclose(rec.robot_pose[: end + 1, :2], wanted, atol=1e-9)
