"""The environment's simulation core, free of gymnasium: arrays, reset, one fused step.

:class:`EnvCore` holds one episode in flat arrays and advances it with one call of
:func:`srfm.rl._kernels.env_step` per step. The observation is built by the kernel
that :class:`srfm.planners._observation.ObservationBuilder` also calls, so a policy
sees identical inputs in training (the environment) and in evaluation (a planner in
:func:`srfm.run_episode`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any, Final

import attrs
import numpy as np
from numpy.typing import NDArray

from srfm._jit import specialize
from srfm.errors import ScenarioError
from srfm.models import _robot_kernels as _rk
from srfm.models.params import SRFMParams
from srfm.models.robot import RobotState
from srfm.planners._observation import EnvConfig, build_observation, obs_size
from srfm.rl import _kernels as _k
from srfm.scenarios import EpisodeSetup, Scenario, episode_setup, next_goal
from srfm.sim.routes import PedestrianRoutes, RobotRoute
from srfm.sim.simulator import EVENT_OUTCOMES

__all__ = ["REWARD_TERMS", "EnvCore", "resolve_scenario"]

REWARD_TERMS: Final = (_k.OUT_REWARD, _k.OUT_R_DIST, _k.OUT_R_DIV, _k.OUT_R_TERM, _k.OUT_R_PROGRESS)
"""The entries of the kernel's ``out`` that an action sums over its simulation steps."""

FloatArray = NDArray[np.float64]


def resolve_scenario(scenario: Scenario, config: EnvConfig) -> Scenario:
    """The scenario with the robot kinematics the configuration asks for."""
    if config.kinematics is None or config.kinematics == scenario.robot.kinematics:
        return scenario
    robot = attrs.evolve(scenario.robot, kinematics=config.kinematics)
    return attrs.evolve(scenario, robot=robot)


class EnvCore:
    """One episode of the environment in flat arrays (see :mod:`srfm.rl._kernels`).

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
        # The kernels' arrays hold the m pedestrians there (the first m of the episode's
        # order, srfm.scenarios.EpisodeSetup.n_present; m = n without entries): fresh
        # C-contiguous arrays of m rows whenever m grows (_resize), so that the kernels
        # keep their argument types. Every pedestrian's state at its entry (its start,
        # at rest, its first goal or waypoint) is kept in entry_crowd / entry_agent.
        self.m = n
        self.crowd = np.zeros((6, n, 2))
        self.agent = np.zeros((3, n))
        self.flags = np.zeros((4, n), dtype=np.bool_)
        self.entry_crowd = self.crowd.copy()
        self.entry_agent = self.agent.copy()
        self.kernel_params = params.for_kernels()
        self.robot = np.zeros(_rk.ROBOT_SIZE)
        self.body = np.array([0.0, 0.0, scenario.robot.radius_m])
        obstacles = scenario.obstacles
        self.segments = obstacles.segments
        self.circles = obstacles.circles
        self.pillar_xy = np.ascontiguousarray(obstacles.circles[:, :2])
        self.pillar_r = np.ascontiguousarray(obstacles.circles[:, 2])
        self.force_buf = np.zeros((n, 2))
        self.dist_buf = np.zeros(max(n, 1))
        self.idx_buf = np.zeros(max(n, 1), dtype=np.int64)
        self.obs = np.zeros(obs_size(config.max_pedestrians), dtype=np.float32)
        self.out = np.zeros(_k.OUT_SIZE)  # one simulation step's results (the kernel's)
        self.total = np.zeros(_k.OUT_SIZE)  # one action's reward terms (see step)
        self.repeat = int(config.action_repeat)
        self.action = np.zeros(2)
        self.regoal = scenario.random is not None and scenario.random.regoal
        self.limits = scenario.robot.for_kernels()
        # The goal (task) and the goal distance at reset (reward) are set per episode.
        self.task = _rk.robot_task(np.zeros(2), scenario.world, scenario.horizon_steps)
        # What the observation's goal entries describe: the goal, or the route's waypoint
        # in a scenario with obstacles (srfm.sim.routes, as in the simulator).
        self.steer = self.task
        self._robot_route: RobotRoute | None = None
        self._ped_routes: list[PedestrianRoutes] = []
        self.observation = config.observation_params(scenario.world)
        self.reward = _k.RewardParams(
            k1=float(config.k1),
            k2=float(config.k2),
            success_reward=float(config.success_reward),
            timeout_penalty=float(config.timeout_penalty),
            collision_penalty=float(config.collision_penalty),
            goal_distance_m=1.0,
            k_progress=float(config.k_progress),
            gamma=float(config.progress_gamma),
        )
        self.options = _k.StepOptions(
            dt_s=float(scenario.dt_s),
            ped_goal_radius_m=float(scenario.ped_goal_radius_m),
            counterfactual_twin=config.counterfactual_twin,
            regoal=self.regoal,
        )
        self.goal_count = np.zeros((2, n), dtype=np.int64)
        self._goal_cache: dict[tuple[int, int], FloatArray] = {}
        self.setup: EpisodeSetup | None = None
        self.step_index = 0
        self.event = _rk.EVENT_NONE
        self._pack()
        self._specialize()

    def _pack(self) -> None:
        """The kernels' arguments: the same arrays (updated in place) at every step; the
        task (goal) and the reward (goal distance at reset) change per episode."""
        arrays = (
            self.crowd,
            self.agent,
            self.robot,
            self.body,
            self.action,
            self.segments,
            self.circles,
        )
        scratch = (self.dist_buf, self.idx_buf, self.obs, self.out)
        config = (
            self.kernel_params,
            self.limits,
            self.task,
            self.steer,
            self.observation,
            self.reward,
            self.options,
        )
        # env_step's arguments but the step index: for the last simulation step of an
        # action, and (progress γ = 1, see step) for the steps before it
        held = (*config[:5], self.reward._replace(gamma=1.0), config[6])
        self._step_args = (
            self.flags,
            *arrays,
            self.pillar_xy,
            self.pillar_r,
            self.force_buf,
            *scratch,
            *config,
        )
        self._held_step_args = (*self._step_args[: -len(config)], *held)
        # reward_and_observation's arguments but the event (the same two kinds)
        self._reward_args = (*arrays, *scratch, *config)
        self._held_reward_args = (*arrays, *scratch, *held)
        factual_pos = self.crowd[_k.FACTUAL_POS]
        # robot_event's arguments but the sample index
        self._event_args = (
            self.robot,
            factual_pos,
            self.agent[_k.AGENT_RADIUS],
            self.segments,
            self.pillar_xy,
            self.pillar_r,
            self.limits,
            self.task,
        )
        self._observation_args = (
            factual_pos,
            self.crowd[_k.FACTUAL_VEL],
            self.robot,
            self.action,
            False,
            False,
            self.limits,
            self.steer,
            self.observation,
            self.dist_buf,
            self.idx_buf,
            self.obs,
        )

    def _specialize(self) -> None:
        """Resolve the kernels' argument types once (see :func:`srfm._jit.specialize`)."""
        self._env_step: Callable[..., int] = specialize(_k.env_step, *self._step_args, 0)
        self._reward_and_observation: Callable[..., None] = specialize(
            _k.reward_and_observation, *self._reward_args, _rk.EVENT_NONE
        )
        self._robot_event: Callable[..., tuple[int, int]] = specialize(
            _rk.robot_event, *self._event_args, 0
        )
        self._build_observation: Callable[..., int] = specialize(
            build_observation, *self._observation_args
        )

    def __getstate__(self) -> dict[str, Any]:
        state = self.__dict__.copy()
        for name in ("_env_step", "_reward_and_observation", "_robot_event", "_build_observation"):
            del state[name]  # compiled functions do not pickle; made again on unpickling
        return state

    def __setstate__(self, state: dict[str, Any]) -> None:
        self.__dict__.update(state)
        self._pack()
        self._specialize()

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
        if self.reward.k2 != k2:
            self.reward = self.reward._replace(k2=k2)
            self._pack()

    def reset(self, episode_seed: int) -> None:
        """Start episode ``episode_seed`` (the scenario's set-up for that seed)."""
        setup = episode_setup(self.scenario, episode_seed)
        crowd = setup.crowd
        c = self.entry_crowd
        c[_k.FACTUAL_POS] = crowd.pos
        c[_k.FACTUAL_VEL] = crowd.vel
        c[_k.FACTUAL_GOAL] = crowd.goal
        c[_k.COUNTERFACTUAL_POS] = crowd.pos
        c[_k.COUNTERFACTUAL_VEL] = crowd.vel
        c[_k.COUNTERFACTUAL_GOAL] = crowd.goal
        self.entry_agent[_k.AGENT_RADIUS] = crowd.radius
        self.entry_agent[_k.AGENT_V0] = crowd.v0
        self.entry_agent[_k.AGENT_VMAX] = crowd.vmax
        self.goal_count[:] = 0
        self._goal_cache.clear()
        r = self.robot
        r[:] = 0.0
        r[_rk.X] = setup.robot_start[0]
        r[_rk.Y] = setup.robot_start[1]
        r[_rk.THETA] = setup.robot_heading_rad
        goal = setup.robot_goal
        self.task = self.task._replace(goal_x=float(goal[0]), goal_y=float(goal[1]))
        self.steer = self.task
        self._robot_route = None
        self._ped_routes = []
        scenario = self.scenario
        if not scenario.obstacles.empty:
            self._robot_route = RobotRoute(scenario, setup.robot_start, goal)
            self.steer = self._steer_task(self._robot_route.update(r[_rk.X], r[_rk.Y]))
        if not scenario.obstacles.empty or setup.ped_routes is not None:
            twins = PedestrianRoutes.twins(setup)
            for row, routes in zip((_k.FACTUAL_GOAL, _k.COUNTERFACTUAL_GOAL), twins, strict=True):
                if routes.any:
                    c[row] = routes.targets()
                    self._ped_routes.append(routes)
        self.reward = self.reward._replace(
            goal_distance_m=math.hypot(goal[0] - r[_rk.X], goal[1] - r[_rk.Y])
        )
        self.setup = setup
        self.m = 0
        self._resize(setup.n_present(0))  # and _pack, with the episode's task and reward
        self.step_index = 0
        self.action[:] = 0.0
        event, _ = self._robot_event(*self._event_args, 0)
        if event != _rk.EVENT_NONE:
            raise ScenarioError(
                f"{self.scenario.source}: seed {setup.seed}: the robot's episode ends at "
                f"sample 0 ({EVENT_OUTCOMES[event]}); the environment needs a robot that "
                "starts free, inside the world and away from its goal"
            )
        self.event = _rk.EVENT_NONE
        self.body[0] = r[_rk.X]
        self.body[1] = r[_rk.Y]
        self._build_observation(*self._observation_args)

    def step(self, a0: float, a1: float) -> int:
        """Apply the action (a0, a1) for ``config.action_repeat`` simulation steps, or
        until the episode ends; return the event code.

        The reward terms summed over those steps are in ``self.total`` (indices
        :data:`REWARD_TERMS` of :mod:`srfm.rl._kernels`' ``out``) and the observation
        in ``self.obs``. The progress term uses γ = 1 on every step of the action but
        its last one (the horizon's step is a last one), so that its sum telescopes
        to γ Φ(s_{t+k}) − Φ(s_t): potential-based per action.
        """
        action = self.action
        action[0] = a0
        action[1] = a1
        out = self.out
        total = self.total
        total[:] = 0.0
        last_step = self.scenario.horizon_steps - 1
        event = _rk.EVENT_NONE
        for k in range(self.repeat):
            last = k == self.repeat - 1 or self.step_index >= last_step
            step_args = self._step_args if last else self._held_step_args
            event = self._env_step(*step_args, self.step_index)
            self.step_index += 1
            if self.m < self.n and self._entered():
                # The sample k + 1 has new pedestrians (at their starts): the robot's event
                # and the reward terms and observation at k + 1 again, with them there.
                event, _ = self._robot_event(*self._event_args, self.step_index)
                reward_args = self._reward_args if last else self._held_reward_args
                self._reward_and_observation(*reward_args, event)
            if self._ped_routes or self._robot_route is not None:
                self._follow_routes(event, last)
            if self.regoal and (out[_k.OUT_NEW_F] or out[_k.OUT_NEW_C]):
                self._regoal()
                if out[_k.OUT_NEW_F]:
                    reward_args = self._reward_args if last else self._held_reward_args
                    self._reward_and_observation(*reward_args, event)
            for term in REWARD_TERMS:
                total[term] += out[term]
            if event != _rk.EVENT_NONE:
                break
        self.event = event
        return event

    def _entered(self) -> bool:
        """Grow the kernels' arrays to the pedestrians there at the current sample;
        whether any entered."""
        assert self.setup is not None
        m = self.setup.n_present(self.step_index)
        if m == self.m:
            return False
        self._resize(m)
        return True

    def _resize(self, m: int) -> None:
        """The kernels' arrays for the first ``m`` pedestrians: those there keep their
        state, the ones entering come in at their entry state; then :meth:`_pack`."""
        old = self.m
        crowd = np.empty((6, m, 2))
        crowd[:, :old] = self.crowd[:, :old]
        crowd[:, old:] = self.entry_crowd[:, old:m]
        agent = np.empty((3, m))
        agent[:, :old] = self.agent[:, :old]
        agent[:, old:] = self.entry_agent[:, old:m]
        flags = np.zeros((4, m), dtype=np.bool_)
        flags[:, :old] = self.flags[:, :old]
        self.crowd, self.agent, self.flags = crowd, agent, flags
        self.force_buf = np.zeros((m, 2))
        self.dist_buf = np.zeros(max(m, 1))
        self.idx_buf = np.zeros(max(m, 1), dtype=np.int64)
        self.m = m
        self._pack()

    def full(self, row: int) -> FloatArray:
        """(N, 2) row ``row`` of the crowd array (``_k.FACTUAL_POS``, ...) for every
        pedestrian, a copy: those not there yet at their entry state, as the
        simulator's arrays hold them."""
        out: FloatArray = self.entry_crowd[row].copy()
        out[: self.m] = self.crowd[row]
        return out

    def _steer_task(self, point: FloatArray) -> _rk.RobotTask:
        return self.task._replace(goal_x=float(point[0]), goal_y=float(point[1]))

    def _follow_routes(self, event: int, last: bool) -> None:
        """Advance the pedestrians' and the robot's routes after a simulation step (the
        simulator's rules, srfm.sim.routes); a new robot waypoint re-packs the kernels'
        arguments and, at an action's last step, rebuilds the observation."""
        rows = (
            (_k.FACTUAL_POS, _k.FACTUAL_GOAL, _k.ARRIVED_F),
            (_k.COUNTERFACTUAL_POS, _k.COUNTERFACTUAL_GOAL, _k.ARRIVED_C),
        )
        m = self.m
        for routes, (pos_row, goal_row, arrived_row) in zip(self._ped_routes, rows, strict=False):
            before = routes.index.copy()
            routes.advance(self.crowd[pos_row], self.crowd[goal_row], m)
            # a pedestrian near a waypoint is not at its goal: forget such arrivals
            self.flags[arrived_row, np.flatnonzero(routes.index[:m] != before[:m])] = False
            self.flags[arrived_row, [i for i in routes.active if i < m]] = False
        route = self._robot_route
        if route is None or event != _rk.EVENT_NONE:
            return
        index = route.index
        point = route.update(self.robot[_rk.X], self.robot[_rk.Y])
        if route.index != index:
            self.steer = self._steer_task(point)
            self._pack()
            if last:
                self._build_observation(*self._observation_args)

    def _regoal(self) -> None:
        """New goals for the pedestrians that arrived (the simulator's draws)."""
        assert self.setup is not None
        for twin, new_row, goal_row in (
            (0, _k.NEW_F, _k.FACTUAL_GOAL),
            (1, _k.NEW_C, _k.COUNTERFACTUAL_GOAL),
        ):
            for idx in np.flatnonzero(self.flags[new_row]):
                i = int(idx)
                count = self.goal_count[twin]
                count[i] += 1
                k = int(count[i])
                key = (i, k)
                goal = self._goal_cache.get(key)
                if goal is None:
                    goal = next_goal(self.setup, i, k, self.crowd[goal_row, i].copy())
                    self._goal_cache[key] = goal
                self.crowd[goal_row, i] = goal

    def robot_state(self) -> RobotState:
        """The robot as a :class:`srfm.RobotState`."""
        return RobotState.from_array(self.robot)
