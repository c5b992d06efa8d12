"""The environment's dynamics are the core simulator's, bit for bit, and a policy sees
the same observation in the environment and as a planner in srfm.run_episode."""

from __future__ import annotations

import itertools
from pathlib import Path

import numpy as np
import pytest

import srfm
from srfm.planners.td3 import NumpyActor, PolicyPlanner
from srfm.rl import EnvConfig, SocialNavEnv
from srfm.scenarios import episode_setup
from srfm.sim.simulator import TwinSimulator
from tests.rl._helpers import command_for, fixed_scenario, seek_action


def _lockstep(
    name: str | Path,
    seed: int,
    kinematics: str,
    mode: str,
    params: srfm.SRFMParams | None = None,
) -> str:
    """Run the environment and a TwinSimulator under the same commands; compare every
    sample; return the outcome."""
    env = SocialNavEnv(name, EnvConfig(kinematics=kinematics), params)  # type: ignore[arg-type]
    env.reset(seed=seed)
    sim = TwinSimulator(episode_setup(env.scenario, seed), params)
    holonomic = kinematics == "holonomic"
    rng = np.random.default_rng(seed)
    for _ in range(env.scenario.horizon_steps):
        if mode == "seek":
            action = seek_action(sim.robot, sim.setup.robot_goal, holonomic)
        else:
            action = rng.uniform(-1.3, 1.3, 2).astype(np.float32)
            action[0] = abs(action[0])
        sim.step(command_for(action, sim.robot, holonomic))
        _, _, terminated, truncated, info = env.step(action)
        assert np.array_equal(sim.factual.pos, env.factual_pos)
        assert np.array_equal(sim.factual.vel, env.factual_vel)
        assert np.array_equal(sim.factual.goal, env.factual_goal)
        assert np.array_equal(sim.counterfactual.pos, env.counterfactual_pos)
        assert sim.robot == env.robot_state
        assert sim.robot_active == (not (terminated or truncated))
        if terminated or truncated:
            assert info["outcome"] == sim.outcome
            return str(sim.outcome)
    raise AssertionError("the episode did not end at the horizon")


# The paper's scenarios, the training one and library scenarios that cover every kind
# of route (computed, given by doors and rooms, groups, standing people, the NavWareSet
# room); all 27 built-ins would add minutes to the suite.
LOCKSTEP_SCENARIOS = (
    *srfm.EVALUATION_SCENARIOS,
    "random",
    "blind_corner",
    "entering_room",
    "robot_crowding",
    "navwareset_circular_crossing",
    "corridor_flow",  # pedestrians entering during the run
)


@pytest.mark.parametrize("name", LOCKSTEP_SCENARIOS)
@pytest.mark.parametrize("kinematics", ["unicycle", "holonomic"])
def test_env_reproduces_the_twin_simulator(name: str, kinematics: str) -> None:
    outcomes = {_lockstep(name, seed, kinematics, "seek") for seed in range(2)}
    outcomes |= {_lockstep(name, 7, kinematics, "random")}
    assert outcomes <= {"goal_reached", "collision", "out_of_bounds", "timeout"}


def test_lockstep_covers_every_outcome(tmp_path: Path) -> None:
    seen = {_lockstep("crosswalk", 0, "unicycle", "seek")}
    seen |= {_lockstep("circle", s, "unicycle", "random") for s in range(2)}
    seen |= {_lockstep("footpath", 0, "unicycle", "random")}
    # A pedestrian standing on the robot's path, blind to the robot (A_r = 0).
    path = fixed_scenario(
        tmp_path / "s.toml",
        robot_start=(2.0, 5.0),
        robot_goal=(10.0, 5.0),
        starts=[(4.0, 5.1), (9.0, 9.0)],
        goals=[(4.0, 5.1), (1.0, 9.0)],
    )
    no_force = srfm.SRFMParams().replace(a_robot=0.0)
    for kinematics in ("unicycle", "holonomic"):
        seen.add(_lockstep(path, 0, kinematics, "seek", no_force))
    assert seen == {"goal_reached", "collision", "out_of_bounds", "timeout"}


class _Recording(PolicyPlanner):
    def __init__(self, actor: NumpyActor, config: EnvConfig) -> None:
        super().__init__(actor, config, "recording")
        self.seen: list[np.ndarray] = []

    def act(self, observation: srfm.planners.Observation) -> np.ndarray:
        command = super().act(observation)
        self.seen.append(self._obs.copy())
        return command


def _random_actor(obs_size: int, seed: int) -> NumpyActor:
    rng = np.random.default_rng(seed)
    sizes = [obs_size, 32, 32, 2]
    weights = tuple(
        (rng.normal(size=(o, i)) / np.sqrt(i)).astype(np.float32)
        for i, o in itertools.pairwise(sizes)
    )
    biases = tuple((0.3 * rng.normal(size=o)).astype(np.float32) for o in sizes[1:])
    return NumpyActor(weights, biases)


@pytest.mark.parametrize(
    ("name", "kinematics", "repeat", "beams"),
    [
        ("random", "unicycle", 1, 0),
        ("crosswalk", "unicycle", 1, 0),
        ("circle", "holonomic", 1, 0),
        ("crosswalk", "unicycle", 3, 0),
        ("circle", "holonomic", 4, 24),
        ("blind_corner", "unicycle", 1, 24),
        ("narrow_doorway", "unicycle", 4, 24),
        ("crowd_navigation", "unicycle", 1, 36),  # pillars
        ("navwareset_circular_crossing", "holonomic", 3, 16),
        ("corridor_flow", "unicycle", 1, 0),
        ("corridor_flow", "holonomic", 3, 24),
    ],
)
def test_policy_sees_the_same_observation_in_env_and_episode(
    name: str, kinematics: str, repeat: int, beams: int
) -> None:
    """Also with action_repeat: the planner decides every ``repeat`` steps, on the
    observation the environment returned for that step, and holds the action; with
    range beams, in scenarios with walls and pillars."""
    config = EnvConfig(
        kinematics=kinematics,  # type: ignore[arg-type]
        action_repeat=repeat,
        range_beams=beams,
        range_max_m=8.0,
    )
    env = SocialNavEnv(name, config)
    actor = _random_actor(env.observation_space.shape[0], 4)
    obs, _ = env.reset(seed=3)
    env_obs = [obs]
    poses = []
    for _ in range(env.scenario.horizon_steps):
        obs, _, terminated, truncated, _ = env.step(actor.forward(obs))
        r = env.robot_state
        poses.append((r.x, r.y, r.theta))
        if terminated or truncated:
            break
        env_obs.append(obs)
    if beams and not env.scenario.obstacles.empty:  # the beams saw something
        assert min(o[-beams:].min() for o in env_obs) < 1.0
    planner = _Recording(actor, config)
    record = srfm.run_episode(env.scenario, 3, planner)
    decisions = planner.seen[::repeat]
    assert len(decisions) == len(env_obs)
    for a, b in zip(decisions, env_obs, strict=True):
        assert a.tobytes() == b.tobytes()
    at_decisions = record.robot_pose[repeat::repeat]
    assert np.array_equal(at_decisions[: len(poses) - 1], np.array(poses[:-1]))
    assert np.array_equal(record.robot_pose[record.end_step], np.array(poses[-1]))
    assert record.end_step == env.step_index
