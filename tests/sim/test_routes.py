"""Routing in the simulator and the environment (issue 17, srfm.sim.routes): planners
steer to the route's next waypoint in scenarios with walls, pedestrians walk round
walls, and obstacle-free scenarios are untouched."""

from __future__ import annotations

from pathlib import Path

import numpy as np

import srfm
from srfm.planners import Observation, PlannerContext
from srfm.rl import SocialNavEnv
from srfm.scenarios import episode_setup, load_scenario
from srfm.sim.routes import RobotRoute
from srfm.sim.simulator import TwinSimulator
from tests.scenarios.test_scenarios import write_scenario

# A wall across the lower 5 m of the world, between the robot's start and its goal;
# a pedestrian walks the other way on the same side.
WALLED = """schema_version = 2
name = "walled"
description = "x"
[world]
x_max = 14.0
y_max = 8.0
[robot]
start = [2.0, 2.0]
goal = [12.0, 2.0]
[pedestrians]
noise_m = 0.0
starts = [[12.0, 1.0]]
goals = [[2.0, 1.0]]
[obstacles]
walls = [[7.0, 0.0, 7.0, 5.0]]
"""


def _walled(tmp_path: Path) -> srfm.Scenario:
    return load_scenario(write_scenario(tmp_path / "walled.toml", WALLED))


class _Spy:
    """The straight planner, remembering what it was told."""

    name = "spy"
    detection_range_m = 0.0

    def __init__(self) -> None:
        self.inner = srfm.planners.make_planner("straight")
        self.goals: list[np.ndarray] = []
        self.context_goal: np.ndarray | None = None

    def reset(self, context: PlannerContext, rng: np.random.Generator) -> None:
        self.context_goal = context.robot_goal
        self.inner.reset(context, rng)

    def act(self, observation: Observation) -> np.ndarray:
        self.goals.append(observation.robot_goal.copy())
        return self.inner.act(observation)


def test_straight_planner_goes_round_the_wall(tmp_path: Path) -> None:
    s = _walled(tmp_path)
    spy = _Spy()
    record = srfm.run_episode(s, 0, spy)
    assert record.outcome == "goal_reached"
    assert record.robot_pose[: record.end_step + 1, 1].max() > 5.0  # over the wall's end
    np.testing.assert_array_equal(spy.context_goal, [12.0, 2.0])
    route = RobotRoute(s, np.array([2.0, 2.0]), np.array([12.0, 2.0])).waypoints
    assert len(route) >= 2
    np.testing.assert_array_equal(spy.goals[0], route[0])
    np.testing.assert_array_equal(spy.goals[-1], [12.0, 2.0])
    # the waypoints come in the route's order
    seen = [tuple(g) for g in spy.goals]
    order = [next(k for k, wp in enumerate(map(tuple, route)) if wp == g) for g in seen]
    assert order == sorted(order)
    # the pedestrian walks round the wall too (a computed route), and arrives
    assert any(e.kind == "ped_arrival" and e.twin == "counterfactual" for e in record.events)
    assert record.counterfactual_pos[:, 0, 1].max() > 5.0


def test_route_is_deterministic_and_twins_identical_without_robot_force(tmp_path: Path) -> None:
    s = _walled(tmp_path)
    a = srfm.run_episode(s, 3, "dwa", srfm.SRFMParams().replace(a_robot=0.0))
    b = srfm.run_episode(s, 3, "dwa", srfm.SRFMParams().replace(a_robot=0.0))
    np.testing.assert_array_equal(a.factual_pos, b.factual_pos)
    np.testing.assert_array_equal(a.robot_pose, b.robot_pose)
    np.testing.assert_array_equal(a.factual_pos, a.counterfactual_pos)
    np.testing.assert_array_equal(a.factual_goal, a.counterfactual_goal)


def test_obstacle_free_scenarios_steer_to_the_goal() -> None:
    sim = TwinSimulator(episode_setup(load_scenario("footpath"), 0))
    for _ in range(30):
        np.testing.assert_array_equal(sim.observe(None).robot_goal, sim.setup.robot_goal)
        np.testing.assert_array_equal(sim.factual.goal, sim.setup.crowd.goal)
        sim.step(np.array([0.5, 0.0]))


def test_environment_observes_the_waypoint(tmp_path: Path) -> None:
    s = _walled(tmp_path)
    env = SocialNavEnv(s)
    obs, _ = env.reset(seed=0)
    sim = TwinSimulator(episode_setup(env.scenario, 0))
    waypoint = sim.observe(None).robot_goal
    assert not np.array_equal(waypoint, sim.setup.robot_goal)
    # goal entries of the observation: distance (scaled by the world diagonal) to the
    # waypoint, not to the goal
    diagonal = float(np.hypot(14.0, 8.0))
    assert obs[0] == np.float32(min(1.0, float(np.hypot(*(waypoint - [2.0, 2.0]))) / diagonal))
    # the environment's success is still the goal
    np.testing.assert_array_equal(env.robot_goal, [12.0, 2.0])
