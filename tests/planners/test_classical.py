"""The classical planners in episodes: registry, finishing, kinematics, determinism,
configuration errors."""

from __future__ import annotations

import math
import typing
from pathlib import Path
from typing import Any

import attrs
import numpy as np
import pytest

import srfm
from srfm.planners import (
    DWAConfig,
    DWAPlanner,
    ORCAConfig,
    Planner,
    SocialForceConfig,
    VOConfig,
    available_planners,
    make_planner,
)
from srfm.sim.routes import RobotRoute
from tests.conftest import record_digest, write_scenario

CLASSICAL = ("dwa", "vo", "orca", "social-force")


def with_kinematics(name: str, kinematics: str) -> srfm.Scenario:
    scenario = srfm.load_scenario(name)
    return attrs.evolve(scenario, robot=attrs.evolve(scenario.robot, kinematics=kinematics))


def test_registered_with_their_names() -> None:
    names = {p.name for p in available_planners()}
    assert set(CLASSICAL) <= names
    for name in CLASSICAL:
        a, b = make_planner(name), make_planner(name)
        assert a is not b
        assert isinstance(a, Planner)
        assert a.name == name
        assert a.detection_range_m == 2.0


@pytest.mark.parametrize("planner", CLASSICAL)
@pytest.mark.parametrize("scenario", srfm.EVALUATION_SCENARIOS)
def test_every_planner_finishes_every_evaluation_scenario(planner: str, scenario: str) -> None:
    for seed in (0, 1):
        record = srfm.run_episode(scenario, seed, planner, parallel=False)
        assert record.outcome == "goal_reached", (seed, record.outcome, record.end_step)
        assert record.end_step < record.horizon_steps
        assert record.min_robot_distance_m() >= 0.5
        active = record.robot_cmd[: record.end_step]
        assert np.all(np.isfinite(active))
        assert np.all(np.abs(active[:, 0]) <= 0.5 + 1e-12)  # v within its limits
        assert np.all(np.abs(active[:, 1]) <= math.pi + 1e-12)  # ω within its limits
        speeds = np.linalg.norm(record.robot_vel[1 : record.end_step + 1], axis=1)
        assert speeds.mean() > 0.4  # comparable to the 0.5 m/s top speed


@pytest.mark.parametrize("planner", CLASSICAL)
def test_holonomic_robots_get_velocity_commands(planner: str) -> None:
    scenario = with_kinematics("crosswalk", "holonomic")
    record = srfm.run_episode(scenario, 2, planner, parallel=False)
    assert record.robot_kinematics == "holonomic"
    assert record.outcome == "goal_reached"
    active = record.robot_cmd[: record.end_step]
    assert np.all(np.linalg.norm(active, axis=1) <= 0.5 + 1e-9)
    # World-frame velocities toward the goal (+y here), not (v, ω) pairs.
    assert np.median(active[:, 1]) > 0.4


@pytest.mark.parametrize("planner", CLASSICAL)
def test_same_seed_same_record_whatever_ran_before(planner: str) -> None:
    fresh = srfm.run_episode("concert", 3, planner, parallel=False)
    again = srfm.run_episode("concert", 3, make_planner(planner), parallel=False)
    reused = make_planner(planner)
    srfm.run_episode("circle", 0, reused, parallel=False)
    srfm.run_episode(with_kinematics("footpath", "holonomic"), 1, reused, parallel=False)
    after = srfm.run_episode("concert", 3, reused, parallel=False)
    assert record_digest(fresh) == record_digest(again) == record_digest(after)


SWAP = """
schema_version = 1
name = "swap"
description = "The robot and one pedestrian swap places along a corridor."
kind = "fixed"
[simulation]
horizon_steps = 600
[world]
x_max = 12.0
y_max = 6.0
[robot]
start = [1.0, 3.0]
goal = [11.0, 3.0]
kinematics = "{kinematics}"
[pedestrians]
starts = [[11.0, 3.05]]
goals = [[1.0, 3.05]]
desired_speed_mps = 0.6
max_speed_mps = 0.6
noise_m = 0.0
"""


@pytest.mark.parametrize("kinematics", ["unicycle", "holonomic"])
@pytest.mark.parametrize("planner", CLASSICAL)
def test_swap_with_one_pedestrian_without_collision(
    tmp_path: Path, planner: str, kinematics: str
) -> None:
    path = write_scenario(tmp_path / "swap.toml", SWAP.format(kinematics=kinematics))
    record = srfm.run_episode(path, 0, planner, parallel=False)
    assert record.outcome == "goal_reached"
    assert record.min_robot_distance_m() >= 0.5
    # The pedestrian reached its goal too.
    assert np.linalg.norm(record.factual_pos[-1, 0] - [1.0, 3.05]) < 0.5


@pytest.mark.parametrize("kinematics", ["unicycle", "holonomic"])
@pytest.mark.parametrize("planner", ["dwa", "vo", "orca"])
def test_swap_with_a_pedestrian_who_ignores_the_robot(
    tmp_path: Path, planner: str, kinematics: str
) -> None:
    """With A_r = 0 the pedestrian walks straight at the robot; the robot alone avoids.
    (The social-force robot, like two social-force pedestrians head-on, does not.)"""
    path = write_scenario(tmp_path / "swap.toml", SWAP.format(kinematics=kinematics))
    params = srfm.SRFMParams(a_robot=0.0)
    record = srfm.run_episode(path, 0, planner, params, parallel=False)
    assert record.outcome == "goal_reached"
    assert record.min_robot_distance_m() >= 0.5
    # The pedestrian kept its line: the robot did the avoiding.
    assert np.abs(record.factual_pos[:, 0, 1] - 3.05).max() < 1e-9


OBSTACLES = """
schema_version = 1
name = "pillar"
description = "A pillar and a slanted wall between the robot and its goal."
kind = "fixed"
[world]
x_max = 12.0
y_max = 8.0
[robot]
start = [1.0, 4.0]
goal = [11.0, 4.0]
kinematics = "{kinematics}"
[pedestrians]
starts = [[6.0, 7.5]]
goals = [[6.0, 7.5]]
noise_m = 0.0
[obstacles]
pillars = [[4.0, 4.1, 0.5]]
walls = [[7.5, 2.8, 8.5, 4.8]]
"""


@pytest.mark.parametrize("kinematics", ["unicycle", "holonomic"])
@pytest.mark.parametrize("planner", CLASSICAL)
def test_avoids_walls_and_pillars(tmp_path: Path, planner: str, kinematics: str) -> None:
    path = write_scenario(tmp_path / "pillar.toml", OBSTACLES.format(kinematics=kinematics))
    record = srfm.run_episode(path, 0, planner, parallel=False)
    assert record.outcome == "goal_reached"
    # The obstacles are in the way: the global route (srfm.sim.routes, issue 17) bends
    # round them, and even the straight planner, which avoids nothing, gets through.
    scenario = srfm.load_scenario(path)
    route = RobotRoute(scenario, scenario.robot_start, scenario.robot_goal).waypoints
    assert len(route) > 1
    straight = srfm.run_episode(path, 0, "straight", parallel=False)
    assert straight.outcome == "goal_reached"


@pytest.mark.parametrize(
    ("factory", "match"),
    [
        (lambda: DWAConfig(horizon_s=-1.0), r"DWAConfig.horizon_s must be > 0, got -1.0"),
        (lambda: DWAConfig(v_samples=0), r"DWAConfig.v_samples must be in \[1, 10000\], got 0"),
        (lambda: DWAConfig(omega_samples=2.5), r"omega_samples must be an integer, got 2.5"),
        (lambda: DWAConfig(predict_pedestrians=1), r"must be True or False, got 1"),
        (lambda: DWAConfig(rollout_step_s=3.0), r"rollout_step_s must be <= horizon_s"),
        (lambda: DWAConfig(detection_range_m=-2.0), r"detection_range_m must be >= 0, got -2.0"),
        (lambda: VOConfig(time_horizon_s=0.0), r"VOConfig.time_horizon_s must be > 0, got 0.0"),
        (lambda: VOConfig(heading_samples=True), r"must be an integer, got True"),
        (lambda: ORCAConfig(responsibility=1.5), r"responsibility must be in \(0, 1\], got 1.5"),
        (lambda: ORCAConfig(time_horizon_s=math.nan), r"time_horizon_s must be finite, got nan"),
        (lambda: SocialForceConfig(anisotropy=2.0), r"anisotropy must be in \[0, 1\], got 2.0"),
        (lambda: SocialForceConfig(tau_s="1"), r"tau_s must be a number, got '1'"),
    ],
)
def test_bad_config_values_are_named(factory: object, match: str) -> None:
    with pytest.raises(srfm.PlannerError, match=match):
        factory()  # type: ignore[operator]


def test_dwa_min_speed_must_fit_the_robot() -> None:
    with pytest.raises(srfm.PlannerError, match=r"min_speed_mps must lie in .*got 0.8"):
        DWAPlanner(DWAConfig(min_speed_mps=0.8))
    scenario = srfm.load_scenario("footpath")
    slow = attrs.evolve(scenario, robot=attrs.evolve(scenario.robot, max_speed_mps=0.3))
    planner = DWAPlanner(DWAConfig(min_speed_mps=0.4))
    with pytest.raises(srfm.PlannerError, match=r"\[-0.3, 0.3\], got 0.4"):
        srfm.run_episode(slow, 0, planner)


@pytest.mark.parametrize("kinematics", ["unicycle", "holonomic"])
@pytest.mark.parametrize("planner", CLASSICAL)
def test_kernel_parameters_have_their_declared_types(planner: str, kinematics: str) -> None:
    """The NamedTuples a planner builds at reset hold every field in its declared type
    (floats as float, flags as bool, counts as int): numba compiles a kernel per
    argument type, and the kernels get the same fields as plain tuples."""
    p: Any = make_planner(planner)
    srfm.run_episode(with_kinematics("footpath", kinematics), 0, p)
    for params, fields in ((p.common, p._common_fields), (p.params, p._params_fields)):
        declared = typing.get_type_hints(type(params))
        assert [type(v) for v in params] == [declared[f] for f in params._fields]
        assert fields == tuple(params)
    assert p.common.unicycle is (kinematics == "unicycle")


def test_configs_are_frozen_and_keyword_only() -> None:
    config = DWAConfig()
    with pytest.raises(attrs.exceptions.FrozenInstanceError):
        config.horizon_s = 3.0  # type: ignore[misc]
    with pytest.raises(TypeError):
        DWAConfig(2.0)  # type: ignore[misc]
