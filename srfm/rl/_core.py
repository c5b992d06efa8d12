"""The environment's simulation core, free of gymnasium: arrays, reset, one fused step.

:class:`EnvCore` holds one episode in flat arrays and advances it with one call of
:func:`srfm.rl._kernels.env_step` per step. :class:`ObservationBuilder` builds the
same observation from a planner's :class:`~srfm.planners.Observation`, so a policy
sees identical inputs in training (the environment) and in evaluation (a planner in
:func:`srfm.run_episode`).
"""

from __future__ import annotations

import math
from typing import Final

import attrs
import numpy as np
from numpy.typing import NDArray

from srfm.errors import ScenarioError
from srfm.models.params import SRFMParams
from srfm.models.robot import RobotConfig, RobotState
from srfm.planners._base import Observation, PlannerContext
from srfm.rl import _kernels as _k
from srfm.rl._config import EnvConfig
from srfm.scenarios import EpisodeSetup, Scenario, WorldBounds, episode_setup, next_goal

__all__ = ["EVENT_OUTCOMES", "EnvCore", "ObservationBuilder", "make_cfg"]

FloatArray = NDArray[np.float64]

# The outcome of the robot's episode for each event code.
EVENT_OUTCOMES: Final[dict[int, str]] = {
    _k.EV_COLLISION: "collision",
    _k.EV_OBSTACLE: "collision",
    _k.EV_OUT_OF_BOUNDS: "out_of_bounds",
    _k.EV_GOAL: "goal_reached",
    _k.EV_TIMEOUT: "timeout",
}


def make_cfg(
    *,
    robot: RobotConfig,
    world: WorldBounds,
    goal: FloatArray,
    dt_s: float,
    horizon_steps: int,
    config: EnvConfig,
) -> FloatArray:
    """The kernels' configuration vector (``_kernels.C_*`` entries).

    Entries that depend on the episode (goal distance at reset) or on the crowd are
    filled in by :class:`EnvCore`.
    """
    cfg = np.zeros(_k.CFG_SIZE)
    cfg[_k.C_DT] = dt_s
    cfg[_k.C_ROBOT_RADIUS] = robot.radius_m
    cfg[_k.C_VMAX] = robot.max_speed_mps
    cfg[_k.C_WMAX] = robot.max_angular_speed_radps
    cfg[_k.C_ACCEL] = robot.max_accel_mps2
    cfg[_k.C_ANG_ACCEL] = robot.max_angular_accel_radps2
    cfg[_k.C_GOAL_RADIUS] = robot.goal_radius_m
    cfg[_k.C_HOLONOMIC] = 1.0 if robot.kinematics == "holonomic" else 0.0
    cfg[_k.C_X_MIN] = world.x_min
    cfg[_k.C_X_MAX] = world.x_max
    cfg[_k.C_Y_MIN] = world.y_min
    cfg[_k.C_Y_MAX] = world.y_max
    cfg[_k.C_GOAL_X] = goal[0]
    cfg[_k.C_GOAL_Y] = goal[1]
    cfg[_k.C_ZONE] = config.social_zone_m
    cfg[_k.C_K1] = config.k1
    cfg[_k.C_K2] = config.k2
    cfg[_k.C_SUCCESS] = config.success_reward
    cfg[_k.C_TIMEOUT_PEN] = config.timeout_penalty
    cfg[_k.C_COLLISION_PEN] = config.collision_penalty
    cfg[_k.C_GOAL_DIST0] = 1.0
    cfg[_k.C_GOAL_SCALE] = math.hypot(world.x_max - world.x_min, world.y_max - world.y_min)
    cfg[_k.C_VEL_SCALE] = config.velocity_scale_mps
    cfg[_k.C_TWIN] = 1.0 if config.counterfactual_twin else 0.0
    cfg[_k.C_HORIZON] = horizon_steps
    cfg[_k.C_MAX_PEDS] = config.max_pedestrians
    return cfg


class ObservationBuilder:
    """The environment's observation, built from a planner's view of a sample.

    Args:
        context: the episode's planner context (robot limits, goal, world).
        config: the environment configuration the policy was trained with.

    The planner must observe the pedestrians within ``config.social_zone_m`` (its
    ``detection_range_m``), or all of them; either gives the environment's vector.
    """

    def __init__(self, context: PlannerContext, config: EnvConfig) -> None:
        self.config = config
        self.cfg = make_cfg(
            robot=context.robot,
            world=context.world,
            goal=context.robot_goal,
            dt_s=context.dt_s,
            horizon_steps=context.horizon_steps,
            config=config,
        )
        self._robot = np.zeros(_k.ROBOT_SIZE)
        self._dist = np.zeros(0)
        self._idx = np.zeros(0, dtype=np.int64)
        self.size = _k.obs_size(config.max_pedestrians)

    def build(
        self, observation: Observation, last_action: FloatArray, out: NDArray[np.float32]
    ) -> NDArray[np.float32]:
        """Write the observation vector into ``out`` (float32, (size,)) and return it."""
        r = observation.robot
        robot = self._robot
        robot[_k.R_X] = r.x
        robot[_k.R_Y] = r.y
        robot[_k.R_THETA] = r.theta
        robot[_k.R_VX] = r.vx
        robot[_k.R_VY] = r.vy
        robot[_k.R_V] = r.v
        robot[_k.R_OMEGA] = r.omega
        n = observation.ped_pos.shape[0]
        if self._dist.shape[0] < n:
            self._dist = np.zeros(n)
            self._idx = np.zeros(n, dtype=np.int64)
        _k.build_observation(
            observation.ped_pos,
            observation.ped_vel,
            robot,
            last_action,
            False,
            False,
            self.cfg,
            self._dist,
            self._idx,
            out,
        )
        return out

    def command(self, action: FloatArray, theta: float) -> FloatArray:
        """The simulator command for an action in [−1, 1]² (the environment's scaling)."""
        cfg = self.cfg
        c0, c1 = _k.action_to_command(
            float(action[0]),
            float(action[1]),
            theta,
            cfg[_k.C_HOLONOMIC] != 0.0,
            cfg[_k.C_VMAX],
            cfg[_k.C_WMAX],
        )
        return np.array([c0, c1])


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
        self.crowd = np.zeros((6, n, 2))
        self.agent = np.zeros((3, n))
        self.flags = np.zeros((4, n), dtype=np.bool_)
        self.param_vec = params.as_array()
        self.robot = np.zeros(_k.ROBOT_SIZE)
        self.body = np.array([0.0, 0.0, scenario.robot.radius_m])
        obstacles = scenario.obstacles
        self.segments = obstacles.segments
        self.circles = obstacles.circles
        self.pillar_xy = np.ascontiguousarray(obstacles.circles[:, :2])
        self.pillar_r = np.ascontiguousarray(obstacles.circles[:, 2])
        self.force_buf = np.zeros((n, 2))
        self.dist_buf = np.zeros(max(n, 1))
        self.idx_buf = np.zeros(max(n, 1), dtype=np.int64)
        self.obs = np.zeros(_k.obs_size(config.max_pedestrians), dtype=np.float32)
        self.out = np.zeros(_k.OUT_SIZE)
        self.action = np.zeros(2)
        self.cfg = make_cfg(
            robot=scenario.robot,
            world=scenario.world,
            goal=np.zeros(2),
            dt_s=scenario.dt_s,
            horizon_steps=scenario.horizon_steps,
            config=config,
        )
        self.regoal = scenario.random is not None and scenario.random.regoal
        self.cfg[_k.C_REGOAL] = 1.0 if self.regoal else 0.0
        self.cfg[_k.C_OBSTACLES] = 0.0 if obstacles.empty else 1.0
        self.cfg[_k.C_PED_GOAL_RADIUS] = scenario.ped_goal_radius_m
        self.goal_count = np.zeros((2, n), dtype=np.int64)
        self._goal_cache: dict[tuple[int, int], FloatArray] = {}
        self.setup: EpisodeSetup | None = None
        self.step_index = 0
        self.event = _k.EV_NONE

    def reset(self, episode_seed: int) -> None:
        """Start episode ``episode_seed`` (the scenario's set-up for that seed)."""
        setup = episode_setup(self.scenario, episode_seed)
        crowd = setup.crowd
        c = self.crowd
        c[_k.F_POS] = crowd.pos
        c[_k.F_VEL] = crowd.vel
        c[_k.F_GOAL] = crowd.goal
        c[_k.C_POS] = crowd.pos
        c[_k.C_VEL] = crowd.vel
        c[_k.C_GOAL] = crowd.goal
        self.agent[_k.A_RADIUS] = crowd.radius
        self.agent[_k.A_V0] = crowd.v0
        self.agent[_k.A_VMAX] = crowd.vmax
        self.flags[:] = False
        self.goal_count[:] = 0
        self._goal_cache.clear()
        r = self.robot
        r[:] = 0.0
        r[_k.R_X] = setup.robot_start[0]
        r[_k.R_Y] = setup.robot_start[1]
        r[_k.R_THETA] = setup.robot_heading_rad
        goal = setup.robot_goal
        cfg = self.cfg
        cfg[_k.C_GOAL_X] = goal[0]
        cfg[_k.C_GOAL_Y] = goal[1]
        self.setup = setup
        self.step_index = 0
        self.action[:] = 0.0
        event = _k.robot_event(
            c[_k.F_POS],
            self.agent[_k.A_RADIUS],
            r,
            cfg,
            self.segments,
            self.pillar_xy,
            self.pillar_r,
            0,
        )
        if event != _k.EV_NONE:
            raise ScenarioError(
                f"{self.scenario.source}: seed {setup.seed}: the robot's episode ends at "
                f"sample 0 ({EVENT_OUTCOMES[event]}); the environment needs a robot that "
                "starts free, inside the world and away from its goal"
            )
        cfg[_k.C_GOAL_DIST0] = math.hypot(goal[0] - r[_k.R_X], goal[1] - r[_k.R_Y])
        self.event = _k.EV_NONE
        self.body[0] = r[_k.R_X]
        self.body[1] = r[_k.R_Y]
        _k.build_observation(
            c[_k.F_POS],
            c[_k.F_VEL],
            r,
            self.action,
            False,
            False,
            cfg,
            self.dist_buf,
            self.idx_buf,
            self.obs,
        )

    def step(self, a0: float, a1: float) -> int:
        """Advance one step under the action (a0, a1); return the event code.

        The reward terms are in ``self.out`` and the observation in ``self.obs``.
        """
        action = self.action
        action[0] = a0
        action[1] = a1
        event: int = _k.env_step(
            self.crowd,
            self.agent,
            self.flags,
            self.param_vec,
            self.robot,
            self.body,
            self.cfg,
            self.segments,
            self.circles,
            self.pillar_xy,
            self.pillar_r,
            self.force_buf,
            action,
            self.step_index,
            self.dist_buf,
            self.idx_buf,
            self.obs,
            self.out,
        )
        self.step_index += 1
        self.event = event
        if self.regoal and (self.out[_k.O_N_NEW_F] or self.out[_k.O_N_NEW_C]):
            self._regoal()
            if self.out[_k.O_N_NEW_F]:
                _k.reward_and_observation(
                    self.crowd,
                    self.agent,
                    self.param_vec,
                    self.robot,
                    self.body,
                    self.cfg,
                    self.segments,
                    self.circles,
                    event,
                    action,
                    self.dist_buf,
                    self.idx_buf,
                    self.obs,
                    self.out,
                )
        return event

    def _regoal(self) -> None:
        """New goals for the pedestrians that arrived (the simulator's draws)."""
        assert self.setup is not None
        for twin, new_row, goal_row in ((0, 2, _k.F_GOAL), (1, 3, _k.C_GOAL)):
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
        r = self.robot
        return RobotState(
            x=float(r[_k.R_X]),
            y=float(r[_k.R_Y]),
            theta=float(r[_k.R_THETA]),
            vx=float(r[_k.R_VX]),
            vy=float(r[_k.R_VY]),
            v=float(r[_k.R_V]),
            omega=float(r[_k.R_OMEGA]),
        )
