"""The environment's simulation core, free of gymnasium: one episode engine, the reward
and the observation.

:class:`EnvCore` drives an :class:`srfm.sim.engine.EpisodeEngine`, the episode of
:class:`srfm.TwinSimulator`, with one call of :func:`srfm.rl._kernels.env_step` per
simulation step (the engine's step kernel followed by the reward and the observation)
and the engine's Python rules after it. The observation is built by the kernel that
:class:`srfm.planners._observation.ObservationBuilder` also calls, so a policy sees
identical inputs in training (the environment) and in evaluation (a planner in
:func:`srfm.run_episode`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any, Final

import attrs
import numpy as np

from srfm._jit import specialize_once
from srfm.errors import ScenarioError
from srfm.models import _robot_kernels as _rk
from srfm.models.params import SRFMParams
from srfm.models.robot import RobotState
from srfm.planners._observation import EnvConfig
from srfm.rl import _kernels as _k
from srfm.scenarios import Scenario, episode_setup
from srfm.sim.engine import EpisodeEngine

__all__ = ["REWARD_TERMS", "EnvCore", "resolve_scenario"]

REWARD_TERMS: Final = (_k.OUT_REWARD, _k.OUT_R_DIST, _k.OUT_R_DIV, _k.OUT_R_TERM, _k.OUT_R_PROGRESS)
"""The entries of the kernel's ``out`` that an action sums over its simulation steps
(:attr:`EnvCore.total` holds them in this order)."""


def resolve_scenario(scenario: Scenario, config: EnvConfig) -> Scenario:
    """The scenario with the robot kinematics the configuration asks for."""
    if config.kinematics is None or config.kinematics == scenario.robot.kinematics:
        return scenario
    robot = attrs.evolve(scenario.robot, kinematics=config.kinematics)
    return attrs.evolve(scenario, robot=robot)


class EnvCore:
    """The environment's episodes: an episode engine per reset, the reward, the observation.

    Args:
        scenario: the scenario (its kinematics already resolved).
        config: reward and observation options.
        params: SRFM parameters.
    """

    def __init__(self, scenario: Scenario, config: EnvConfig, params: SRFMParams) -> None:
        self.scenario = scenario
        self.config = config
        self.params = params
        n = scenario.n_pedestrians
        self.n = n
        self.repeat = int(config.action_repeat)
        self.regoal = scenario.random is not None and scenario.random.regoal
        self.total = [0.0] * len(REWARD_TERMS)  # one action's reward terms (see step)
        reward = _k.RewardParams(
            k1=float(config.k1),
            k2=float(config.k2),
            success_reward=float(config.success_reward),
            timeout_penalty=float(config.timeout_penalty),
            collision_penalty=float(config.collision_penalty),
            goal_distance_m=1.0,
            k_progress=float(config.k_progress),
            gamma=float(config.progress_gamma),
        )
        self.arrays = _k.EnvArrays(
            action=np.zeros(2),
            obs=np.zeros(config.obs_size, dtype=np.float32),
            out=np.zeros(_k.OUT_SIZE),  # one simulation step's results (the kernel's)
            zone_body=np.array([0.0, 0.0, scenario.robot.radius_m, 0.0, 0.0]),
            dist_buf=np.zeros(max(n, 1)),
            idx_buf=np.zeros(max(n, 1), dtype=np.int64),
            steer=_rk.robot_task(np.zeros(2), scenario.world, scenario.horizon_steps),
            observation=config.observation_params(scenario.world),
            reward=reward,
            regoal=self.regoal,
        )
        self.engine: EpisodeEngine | None = None
        self._held = self.arrays

    @property
    def obs(self) -> np.ndarray:
        """The observation after the last step or reset (float32)."""
        return self.arrays.obs

    @property
    def step_index(self) -> int:
        """Simulation steps taken in the current episode."""
        return 0 if self.engine is None else self.engine.step_index

    def use_layout(self, scenario: Scenario) -> None:
        """Run the next episodes on ``scenario``, a layout with this core's pedestrian
        count, re-goaling, world, time step, horizon and robot (the mixed training
        layouts, :mod:`srfm.scenarios.training`)."""
        current = self.scenario
        regoal = scenario.random is not None and scenario.random.regoal
        if (
            scenario.n_pedestrians != self.n
            or regoal != self.regoal
            or scenario.world != current.world
            or scenario.dt_s != current.dt_s
            or scenario.horizon_steps != current.horizon_steps
            or scenario.robot != current.robot
            or scenario.ped_goal_radius_m != current.ped_goal_radius_m
            or not scenario.obstacles.empty
        ):
            raise ScenarioError(f"{scenario.source}: does not fit this environment core")
        self.scenario = scenario

    def set_k2(self, k2: float) -> None:
        """The deviation weight k2 (1/m) from the next step on."""
        if self.arrays.reward.k2 != k2:
            self._set(reward=self.arrays.reward._replace(k2=k2))

    def _set(self, **fields: Any) -> None:
        """Change fields of the environment's arrays (parameters, steer); the held
        version for the steps of an action before its last one has progress γ = 1
        (see :meth:`step`)."""
        self.arrays = self.arrays._replace(**fields)
        self._held = self.arrays._replace(reward=self.arrays.reward._replace(gamma=1.0))

    def _specialize(self, engine: EpisodeEngine) -> tuple[Callable[..., Any], ...]:
        """The kernels, their argument types resolved once (:func:`srfm._jit.specialize_once`)."""
        ep, env = engine.arrays, self.arrays
        return (
            specialize_once(_k.env_step, ep, env, 0),
            specialize_once(_k.reward_and_observation, ep, env, _rk.EVENT_NONE),
            specialize_once(_k.observe, ep, env, _rk.EVENT_NONE),
        )

    def reset(self, episode_seed: int) -> None:
        """Start episode ``episode_seed`` (the scenario's set-up for that seed)."""
        setup = episode_setup(self.scenario, episode_seed)
        engine = self.engine
        if engine is None:
            engine = EpisodeEngine(
                setup,
                self.params,
                cutoff="exact",
                counterfactual=self.config.counterfactual_twin,
                records=False,
            )
        else:
            engine.reset(setup)
        if engine.outcome is not None:
            raise ScenarioError(
                f"{self.scenario.source}: seed {setup.seed}: the robot's episode ends at "
                f"sample 0 ({engine.outcome}); the environment needs a robot that "
                "starts free, inside the world and away from its goal"
            )
        self.engine = engine
        robot = engine.robot
        task = engine.task
        self.arrays.action[:] = 0.0
        self._set(
            steer=self._steer(engine),
            reward=self.arrays.reward._replace(
                goal_distance_m=math.hypot(task.goal_x - robot[_rk.X], task.goal_y - robot[_rk.Y])
            ),
        )
        observe = self._specialize(engine)[2]
        observe(engine.arrays, self.arrays, _rk.EVENT_NONE)

    @staticmethod
    def _steer(engine: EpisodeEngine) -> _rk.RobotTask:
        point = engine.steering_goal()
        return engine.task._replace(goal_x=float(point[0]), goal_y=float(point[1]))

    def step(self, a0: float, a1: float) -> int:
        """Apply the action (a0, a1) for ``config.action_repeat`` simulation steps, or
        until the episode ends; return the event code.

        The reward terms summed over those steps are in ``self.total`` (the entries
        :data:`REWARD_TERMS` of :mod:`srfm.rl._kernels`' ``out``, in that order, as
        floats) and the observation
        in ``self.obs``. The progress term uses γ = 1 on every step of the action but
        its last one (the horizon's step is a last one), so that its sum telescopes
        to γ Φ(s_{t+k}) − Φ(s_t): potential-based per action.

        The reward of a step is computed on the crowd after it, with the pedestrians
        that entered and the new goals of those that arrived in a re-goaling scenario,
        before the pedestrians' routes move on to their next waypoints.
        """
        engine = self.engine
        assert engine is not None
        env_step, reward_and_observation, observe = self._specialize(engine)
        rules = engine.has_routes or self.regoal  # Python work after a quiet step
        action = self.arrays.action
        action[0] = a0
        action[1] = a1
        out = self.arrays.out
        total = [0.0] * len(REWARD_TERMS)
        last_step = self.scenario.horizon_steps - 1
        event = _rk.EVENT_NONE
        for k in range(self.repeat):
            last = k == self.repeat - 1 or engine.step_index >= last_step
            env = self.arrays if last else self._held
            n_new, event, nearest = env_step(engine.arrays, env, engine.step_index)
            present = engine.n_present
            event, nearest = engine.enter_sample(event, nearest)
            if engine.n_present != present:  # the reward and observation with them
                reward_and_observation(engine.arrays, env, event)
            if rules or n_new or event != _rk.EVENT_NONE:
                route = engine.robot_route
                waypoint = -1 if route is None else route.index
                engine.apply_events(n_new, event, nearest)
                if self.regoal and n_new:  # with the new goals
                    reward_and_observation(engine.arrays, env, event)
                if route is not None and event == _rk.EVENT_NONE and route.index != waypoint:
                    self._set(steer=self._steer(engine))
                    if last:
                        observe(engine.arrays, self.arrays, event)
            terms = out.tolist()
            total = [t + terms[i] for t, i in zip(total, REWARD_TERMS, strict=True)]
            if event != _rk.EVENT_NONE:
                break
        self.total = total
        return event

    def robot_state(self) -> RobotState:
        """The robot as a :class:`srfm.RobotState`."""
        assert self.engine is not None
        return self.engine.robot_state
