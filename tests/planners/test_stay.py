"""The ``stay`` reference planner: the robot never moves."""

from __future__ import annotations

import numpy as np

import srfm
from srfm.benchmark._request import default_planners
from srfm.planners import available_planners


def test_stay_never_moves() -> None:
    record = srfm.run_episode("crosswalk", 3, planner="stay")
    assert record.planner == "stay"
    assert record.outcome == "timeout"
    assert np.all(record.robot_active[:-1])  # to the timeout at the horizon
    assert np.array_equal(record.robot_cmd, np.zeros_like(record.robot_cmd))
    assert np.all(record.robot_pose == record.robot_pose[0])
    assert np.all(record.robot_vel == 0.0)
    # the crowd still feels it: the twins part
    assert not np.array_equal(record.factual_pos, record.counterfactual_pos)


def test_references_are_registered_but_not_default() -> None:
    info = {p.name: p for p in available_planners()}
    assert {"stay", "oracle"} <= set(info)
    assert not info["stay"].default
    assert not info["oracle"].default
    assert "stay" not in default_planners()
    assert "oracle" not in default_planners()
