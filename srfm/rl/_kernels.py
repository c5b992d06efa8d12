"""numba kernels of the gymnasium environment: one fused call per environment step.

Nothing of the simulation is re-implemented here: :func:`env_step` calls the crowd
kernels of :mod:`srfm.models._kernels` (the same ``twin_step_exact`` / ``step_exact``
and ``mark_arrivals`` that :class:`srfm.TwinSimulator` calls), the robot kernels of
:mod:`srfm.models._robot_kernels` (``move_robot``, ``robot_event``, which the simulator
calls too) and the observation kernels of :mod:`srfm.planners._observation`, so that
an environment episode is bit-identical to a :class:`~srfm.TwinSimulator` episode under
the same commands (tested in ``tests/rl/test_equivalence.py``). Only the reward is
computed here.

Arrays (all C-contiguous):

- ``crowd`` (6, N, 2) float64: factual pos, vel, goal, counterfactual pos, vel, goal
  (rows ``FACTUAL_POS`` … ``COUNTERFACTUAL_GOAL``);
- ``agent`` (3, N) float64: radius, desired speed v0, speed cap vmax (rows ``AGENT_*``);
- ``robot`` (7,) float64: the robot kernels' state, x, y, theta, vx, vy, v, omega;
- ``flags`` (4, N) bool: factual arrived, counterfactual arrived, factual new,
  counterfactual new (as the simulator's arrival bookkeeping);
- ``obs`` (9 + 6K,) float32, see :mod:`srfm.planners._observation`;
- ``out`` (``OUT_SIZE``,) float64: the step's results (``OUT_*`` entries).

Parameters are NamedTuples: :class:`~srfm.models.params.SRFMKernelParams`,
:class:`~srfm.models._robot_kernels.RobotLimits`,
:class:`~srfm.models._robot_kernels.RobotTask`,
:class:`~srfm.planners._observation.ObservationParams`, and below
:class:`RewardParams` and :class:`StepOptions`.
"""

from __future__ import annotations

import math
from typing import Final, NamedTuple

import numpy as np
from numba import njit

from srfm.models._kernels import (
    _agent_forces,
    exact_cut,
    mark_arrivals,
    step_exact,
    twin_step_exact,
)
from srfm.models._primitives import TRUE
from srfm.models._robot_kernels import (
    EVENT_GOAL,
    EVENT_NONE,
    EVENT_TIMEOUT,
    THETA,
    RobotLimits,
    RobotTask,
    X,
    Y,
    move_robot,
    robot_event,
)
from srfm.models.params import SRFMKernelParams
from srfm.planners._observation import ObservationParams, action_to_command, build_observation

# crowd rows
FACTUAL_POS, FACTUAL_VEL, FACTUAL_GOAL = 0, 1, 2
COUNTERFACTUAL_POS, COUNTERFACTUAL_VEL, COUNTERFACTUAL_GOAL = 3, 4, 5
# agent rows
AGENT_RADIUS, AGENT_V0, AGENT_VMAX = 0, 1, 2
# flags rows
ARRIVED_F, ARRIVED_C, NEW_F, NEW_C = 0, 1, 2, 3

# step results (``out``): reward and its terms, new arrivals of each twin
OUT_REWARD, OUT_R_DIST, OUT_R_DIV, OUT_R_TERM, OUT_NEW_F, OUT_NEW_C = 0, 1, 2, 3, 4, 5
# the progress term, and the robot's goal distance before the step (m)
OUT_R_PROGRESS, OUT_GOAL_DIST_BEFORE = 6, 7
OUT_SIZE: Final = 8


class RewardParams(NamedTuple):
    """The reward as the kernels take it (built from :class:`srfm.rl.EnvConfig`).

    r = r_term − k1 · r_dist − k2 · r_div (paper Eq. 7) + r_progress, with the
    potential-based progress term r_progress = γ Φ(s') − Φ(s), Φ = −k_progress ·
    d / d_0 (d the goal distance, d_0 at reset; Φ = 0 in a terminal state).

    Attributes:
        k1: weight of r_dist.
        k2: weight of r_div (1/m).
        success_reward: r_term at the goal.
        timeout_penalty: −r_term at the horizon.
        collision_penalty: −r_term on a collision or on leaving the world.
        goal_distance_m: the goal distance at reset (m), the r_dist normaliser; set
            per episode.
        k_progress: weight of the progress potential (0: the paper's reward).
        gamma: the discount γ of the progress term (the learner's).
    """

    k1: float
    k2: float
    success_reward: float
    timeout_penalty: float
    collision_penalty: float
    goal_distance_m: float
    k_progress: float
    gamma: float


class StepOptions(NamedTuple):
    """How the environment steps its crowds.

    Attributes:
        dt_s: simulation step (s).
        ped_goal_radius_m: a pedestrian arrives within this distance of its goal (m).
        counterfactual_twin: step the full counterfactual crowd too.
        regoal: arrivals get new goals (drawn in Python by the caller); otherwise
            they are marked arrived.
    """

    dt_s: float
    ped_goal_radius_m: float
    counterfactual_twin: bool
    regoal: bool


@njit(cache=True)
def one_step_deviation(
    crowd: np.ndarray,
    agent: np.ndarray,
    params: SRFMKernelParams,
    body: np.ndarray,
    segments: np.ndarray,
    circles: np.ndarray,
    dt: float,
    zone: float,
) -> float:
    """r_div: the one-step counterfactual deviation summed over the social zone (m).

    From the current factual state and the robot ``body`` (3,) = (x, y, radius), each
    pedestrian i closer than ``zone`` to the robot centre is stepped twice, with and
    without the robot force (all other forces from the same snapshot, the same
    semi-implicit Euler step and speed cap as the simulator); r_div = Σ_i
    |x̂_i(with robot) − x̂_i(without robot)|. Exactly 0 when A_r = 0.
    """
    pos = crowd[FACTUAL_POS]
    vel = crowd[FACTUAL_VEL]
    goal = crowd[FACTUAL_GOAL]
    radius = agent[AGENT_RADIUS]
    v0 = agent[AGENT_V0]
    vmax = agent[AGENT_VMAX]
    cut, ped = exact_cut()
    z2 = zone * zone
    total = 0.0
    for i in range(pos.shape[0]):
        dx = pos[i, 0] - body[0]
        dy = pos[i, 1] - body[1]
        if not dx * dx + dy * dy < z2:
            continue
        g0, g1, p0, p1, r0, r1, o0, o1 = _agent_forces(
            i,
            pos,
            vel,
            goal,
            radius,
            v0,
            params,
            body,
            True,
            segments,
            circles,
            cut,
            ped,
        )
        px = pos[i, 0]
        py = pos[i, 1]
        # With the robot (the sum in the simulator's order) ...
        vx = vel[i, 0] + (g0 + p0 + r0 + o0) * dt
        vy = vel[i, 1] + (g1 + p1 + r1 + o1) * dt
        speed = math.sqrt(vx * vx + vy * vy)
        if speed > vmax[i]:
            vx *= vmax[i] / speed
            vy *= vmax[i] / speed
        # ... and without it (as the counterfactual twin adds a zero robot term).
        ux = vel[i, 0] + (g0 + p0 + 0.0 + o0) * dt
        uy = vel[i, 1] + (g1 + p1 + 0.0 + o1) * dt
        speed = math.sqrt(ux * ux + uy * uy)
        if speed > vmax[i]:
            ux *= vmax[i] / speed
            uy *= vmax[i] / speed
        ex = (px + vx * dt) - (px + ux * dt)
        ey = (py + vy * dt) - (py + uy * dt)
        total += math.sqrt(ex * ex + ey * ey)
    return total


@njit(cache=True)
def reward_and_observation(
    crowd: np.ndarray,
    agent: np.ndarray,
    robot: np.ndarray,
    body: np.ndarray,
    last_action: np.ndarray,
    segments: np.ndarray,
    circles: np.ndarray,
    dist_buf: np.ndarray,
    idx_buf: np.ndarray,
    obs: np.ndarray,
    out: np.ndarray,
    params: SRFMKernelParams,
    limits: RobotLimits,
    task: RobotTask,
    steer: RobotTask,
    observation: ObservationParams,
    reward: RewardParams,
    options: StepOptions,
    event: int,
) -> None:
    """Reward terms into ``out`` and the observation into ``obs`` after a step.

    r = r_term − k1 r_dist − k2 r_div, with r_dist = min(goal distance / goal distance
    at reset, 1) (the paper's range [0, 1]), r_div from :func:`one_step_deviation` at
    the robot's new position, and r_term = +success reward at the goal, −timeout
    penalty on timeout, −collision penalty on a collision with a pedestrian or an
    obstacle or on leaving the world. ``task`` holds the goal (reward, events);
    ``steer`` the point the observation's goal entries describe: the goal, or the
    route's current waypoint in a scenario with walls (:mod:`srfm.sim.routes`).
    """
    body[0] = robot[X]
    body[1] = robot[Y]
    gdx = task.goal_x - robot[X]
    gdy = task.goal_y - robot[Y]
    r_dist = min(1.0, math.sqrt(gdx * gdx + gdy * gdy) / reward.goal_distance_m)
    r_div = one_step_deviation(
        crowd, agent, params, body, segments, circles, options.dt_s, observation.social_zone_m
    )
    if event == EVENT_GOAL:
        r_term = reward.success_reward
    elif event == EVENT_TIMEOUT:
        r_term = -reward.timeout_penalty
    elif event != EVENT_NONE:
        r_term = -reward.collision_penalty
    else:
        r_term = 0.0
    r_progress = 0.0
    if reward.k_progress != 0.0:
        # Ng, Harada, Russell (1999): F = γ Φ(s') − Φ(s) leaves the optimal policy
        # unchanged; Φ of a terminal state is 0 (a timeout is a truncation, not one).
        scale = reward.k_progress / reward.goal_distance_m
        phi_before = -scale * out[OUT_GOAL_DIST_BEFORE]
        phi_after = 0.0
        if event in (EVENT_NONE, EVENT_TIMEOUT):
            phi_after = -scale * math.sqrt(gdx * gdx + gdy * gdy)
        r_progress = reward.gamma * phi_after - phi_before
    out[OUT_R_DIST] = r_dist
    out[OUT_R_DIV] = r_div
    out[OUT_R_TERM] = r_term
    out[OUT_R_PROGRESS] = r_progress
    out[OUT_REWARD] = r_term - reward.k1 * r_dist - reward.k2 * r_div + r_progress
    build_observation(
        crowd[FACTUAL_POS],
        crowd[FACTUAL_VEL],
        robot,
        last_action,
        event == EVENT_GOAL,
        event != EVENT_NONE,
        limits,
        steer,
        observation,
        dist_buf,
        idx_buf,
        obs,
    )


@njit(cache=True)
def env_step(
    flags: np.ndarray,
    crowd: np.ndarray,
    agent: np.ndarray,
    robot: np.ndarray,
    body: np.ndarray,
    action: np.ndarray,
    segments: np.ndarray,
    circles: np.ndarray,
    pillar_xy: np.ndarray,
    pillar_r: np.ndarray,
    force_buf: np.ndarray,
    dist_buf: np.ndarray,
    idx_buf: np.ndarray,
    obs: np.ndarray,
    out: np.ndarray,
    params: SRFMKernelParams,
    limits: RobotLimits,
    task: RobotTask,
    steer: RobotTask,
    observation: ObservationParams,
    reward: RewardParams,
    options: StepOptions,
    step_index: int,
) -> int:
    """One environment step (sample k = ``step_index`` to k + 1); returns the event.

    1. the action becomes a command (:func:`action_to_command`) and the robot's next
       state is computed (:func:`move_robot`);
    2. the crowds take one SRFM step with the robot where it is at sample k: the
       factual and, with ``options.counterfactual_twin``, the counterfactual crowd,
       through the core ``twin_step_exact`` / ``step_exact`` kernels; new arrivals
       are flagged;
    3. in scenarios without re-goaling new arrivals are marked arrived;
    4. the robot event at k + 1 (:func:`robot_event`, an ``EVENT_*`` code);
    5. unless factual pedestrians arrived in a re-goaling scenario (then the caller
       sets their new goals and calls :func:`reward_and_observation` itself), the
       reward terms and the observation.

    ``action`` (2,) is the agent's action; it is clipped to [−1, 1] and stored as the
    last action in ``action`` itself.
    """
    a0 = min(1.0, max(-1.0, action[0]))
    a1 = min(1.0, max(-1.0, action[1]))
    action[0] = a0
    action[1] = a1
    c0, c1 = action_to_command(a0, a1, robot[THETA], limits)
    body[0] = robot[X]
    body[1] = robot[Y]
    out[OUT_GOAL_DIST_BEFORE] = math.sqrt(
        (task.goal_x - robot[X]) ** 2 + (task.goal_y - robot[Y]) ** 2
    )
    dt = options.dt_s
    move_robot(robot, c0, c1, limits, dt)
    goal_radius = options.ped_goal_radius_m
    radius = agent[AGENT_RADIUS]
    if options.counterfactual_twin:
        twin_step_exact(
            crowd[FACTUAL_POS],
            crowd[FACTUAL_VEL],
            crowd[FACTUAL_GOAL],
            crowd[COUNTERFACTUAL_POS],
            crowd[COUNTERFACTUAL_VEL],
            crowd[COUNTERFACTUAL_GOAL],
            radius,
            agent[AGENT_V0],
            agent[AGENT_VMAX],
            params,
            body,
            segments,
            circles,
            dt,
            force_buf,
            goal_radius,
            flags[ARRIVED_F],
            flags[ARRIVED_C],
            flags[NEW_F],
            flags[NEW_C],
            exact_cut()[0],
        )
    else:
        step_exact(
            crowd[FACTUAL_POS],
            crowd[FACTUAL_VEL],
            crowd[FACTUAL_GOAL],
            radius,
            agent[AGENT_V0],
            agent[AGENT_VMAX],
            params,
            body,
            TRUE,
            segments,
            circles,
            dt,
            force_buf,
            exact_cut()[0],
        )
        mark_arrivals(
            crowd[FACTUAL_POS], crowd[FACTUAL_GOAL], goal_radius, flags[ARRIVED_F], flags[NEW_F]
        )
    n_f = 0
    n_c = 0
    n = radius.shape[0]
    for i in range(n):
        if flags[NEW_F, i]:
            n_f += 1
        if options.counterfactual_twin and flags[NEW_C, i]:
            n_c += 1
    if not options.regoal:
        for i in range(n):
            if flags[NEW_F, i]:
                flags[ARRIVED_F, i] = True
            if flags[NEW_C, i]:
                flags[ARRIVED_C, i] = True
    out[OUT_NEW_F] = n_f
    out[OUT_NEW_C] = n_c
    event, _ = robot_event(
        robot,
        crowd[FACTUAL_POS],
        radius,
        segments,
        pillar_xy,
        pillar_r,
        limits,
        task,
        step_index + 1,
    )
    if not options.regoal or n_f == 0:
        reward_and_observation(
            crowd,
            agent,
            robot,
            body,
            action,
            segments,
            circles,
            dist_buf,
            idx_buf,
            obs,
            out,
            params,
            limits,
            task,
            steer,
            observation,
            reward,
            options,
            event,
        )
    return event
