"""numba kernels of the gymnasium environment: one fused call per simulation step.

Nothing of the simulation is written here: :func:`env_step` turns the agent's action
into a command and runs the episode engine's step kernel
(:func:`srfm.sim._kernels.advance_exact`, the one :class:`srfm.TwinSimulator` runs),
then computes what is the environment's own: the reward and the observation (the
observation kernel of :mod:`srfm.planners._observation`, which a policy planner also
calls). An environment episode is therefore bit-identical to a simulator episode under
the same commands (tested in ``tests/rl/test_equivalence.py``).

Arrays and parameters: the engine's :class:`~srfm.sim._kernels.EpisodeArrays` and the
environment's :class:`EnvArrays` (the last action, the observation, the step's results
``out`` with its ``OUT_*`` entries, scratch, and the parameter tuples
:class:`~srfm.models._robot_kernels.RobotTask` (``steer``),
:class:`~srfm.planners._observation.ObservationParams` and :class:`RewardParams`).
"""

from __future__ import annotations

import math
from typing import Final, NamedTuple

import numpy as np
from numba import njit

from srfm.models._arrays import CrowdArrays, ForceContext
from srfm.models._kernels import _agent_forces, euler_velocity, exact_cut
from srfm.models._robot_kernels import (
    EVENT_GOAL,
    EVENT_NONE,
    EVENT_TIMEOUT,
    THETA,
    VX,
    VY,
    RobotTask,
    X,
    Y,
)
from srfm.planners._observation import ObservationParams, action_to_command, build_observation
from srfm.sim._kernels import EpisodeArrays, advance_exact

# step results (``out``): reward and its terms
OUT_REWARD, OUT_R_DIST, OUT_R_DIV, OUT_R_TERM = 0, 1, 2, 3
# the progress term, and the robot's goal distance before the step (m)
OUT_R_PROGRESS, OUT_GOAL_DIST_BEFORE = 4, 5
OUT_SIZE: Final = 6


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


class EnvArrays(NamedTuple):
    """The environment's own arrays and parameters (see the module docstring).

    Attributes:
        action: (2,) float64, the agent's action, clipped to [−1, 1] by the step (the
            observation's last action).
        obs: (9 + 6K + B,) float32, the observation (:mod:`srfm.planners._observation`).
        out: (``OUT_SIZE``,) float64, the step's reward terms (``OUT_*``).
        zone_body: (5,) the robot's body (x, y, radius, vx, vy) at its new state (the
            r_div input).
        dist_buf: (≥ N,) float64 scratch of the observation.
        idx_buf: (≥ N,) int64 scratch of the observation.
        steer: the point the observation's goal entries describe (the goal, or the
            route's current waypoint in a scenario with walls), with the task's world.
        observation: the observation's options.
        reward: the reward's weights.
        regoal: arrivals get new goals (drawn in Python after the step, so the reward
            of a step with arrivals is computed after them, by the caller).
    """

    action: np.ndarray
    obs: np.ndarray
    out: np.ndarray
    zone_body: np.ndarray
    dist_buf: np.ndarray
    idx_buf: np.ndarray
    steer: RobotTask
    observation: ObservationParams
    reward: RewardParams
    regoal: bool


@njit(cache=True, inline="always")
def one_step_deviation(crowd: CrowdArrays, felt: ForceContext, dt: float, zone: float) -> float:
    """r_div: the one-step counterfactual deviation summed over the social zone (m).

    From the current factual state and the robot ``felt.robot`` (5,) = (x, y, radius, vx,
    vy), each pedestrian i closer than ``zone`` to the robot centre is stepped twice, with and
    without the robot force (all other forces from the same snapshot, the crowd step's
    own velocity update :func:`~srfm.models._kernels.euler_velocity`); r_div = Σ_i
    |x̂_i(with robot) − x̂_i(without robot)|. Exactly 0 when the robot form's strength is 0.
    """
    pos = crowd.pos
    vel = crowd.vel
    vmax = crowd.vmax
    cut, ped = exact_cut()
    exact = ForceContext(felt.params, felt.robot, True, felt.obstacles, cut)
    body = felt.robot
    z2 = zone * zone
    total = np.empty((1, 2))  # (each agent's step force, not read here)
    deviation = 0.0
    for i in range(pos.shape[0]):
        dx = pos[i, 0] - body[0]
        dy = pos[i, 1] - body[1]
        if not dx * dx + dy * dy < z2:
            continue
        g0, g1, p0, p1, r0, r1, o0, o1 = _agent_forces(i, i + 1, crowd, exact, ped, total)
        px = pos[i, 0]
        py = pos[i, 1]
        # With the robot (the sum in the crowd step's order) ...
        vx, vy = euler_velocity(
            vel[i, 0], vel[i, 1], g0 + p0 + r0 + o0, g1 + p1 + r1 + o1, vmax[i], dt
        )
        # ... and without it (as the counterfactual twin adds a zero robot term).
        ux, uy = euler_velocity(
            vel[i, 0], vel[i, 1], g0 + p0 + 0.0 + o0, g1 + p1 + 0.0 + o1, vmax[i], dt
        )
        ex = (px + vx * dt) - (px + ux * dt)
        ey = (py + vy * dt) - (py + uy * dt)
        deviation += math.sqrt(ex * ex + ey * ey)
    return deviation


@njit(cache=True, inline="always")
def reward_and_observation(ep: EpisodeArrays, env: EnvArrays, event: int) -> None:
    """Reward terms into ``env.out`` and the observation into ``env.obs`` after a step.

    r = r_term − k1 r_dist − k2 r_div, with r_dist = min(goal distance / goal distance
    at reset, 1) (the paper's range [0, 1]), r_div from :func:`one_step_deviation` at
    the robot's new position, and r_term = +success reward at the goal, −timeout
    penalty on timeout, −collision penalty on a collision with a pedestrian or an
    obstacle or on leaving the world. ``ep.task`` holds the goal (reward, events);
    ``env.steer`` the point the observation's goal entries describe.
    """
    robot = ep.robot
    task = ep.task
    reward = env.reward
    out = env.out
    body = env.zone_body
    body[0] = robot[X]
    body[1] = robot[Y]
    body[3] = robot[VX]
    body[4] = robot[VY]
    gdx = task.goal_x - robot[X]
    gdy = task.goal_y - robot[Y]
    r_dist = min(1.0, math.sqrt(gdx * gdx + gdy * gdy) / reward.goal_distance_m)
    felt = ep.felt
    zone = ForceContext(felt.params, body, felt.robot_on, felt.obstacles, felt.cut)
    r_div = one_step_deviation(ep.factual, zone, ep.options.dt_s, env.observation.social_zone_m)
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
    observe(ep, env, event)


@njit(cache=True, inline="always")
def observe(ep: EpisodeArrays, env: EnvArrays, event: int) -> int:
    """The observation into ``env.obs`` (:func:`build_observation`) after ``event``;
    the number of pedestrians in the social zone."""
    return build_observation(
        ep.factual.pos,
        ep.factual.vel,
        ep.robot,
        env.action,
        event == EVENT_GOAL,
        event != EVENT_NONE,
        ep.limits,
        env.steer,
        env.observation,
        ep.felt.obstacles.segments,
        ep.felt.obstacles.circles,
        env.dist_buf,
        env.idx_buf,
        env.obs,
    )


@njit(cache=True)
def env_step(ep: EpisodeArrays, env: EnvArrays, step_index: int) -> tuple[int, int, int]:
    """One environment step (sample k = ``step_index`` to k + 1).

    1. the action ``env.action`` is clipped to [−1, 1] (and kept there as the last
       action) and becomes a command (:func:`action_to_command`);
    2. the episode engine's step (:func:`srfm.sim._kernels.advance_exact`): the robot
       moves, the crowds step, arrivals are flagged, the robot event at k + 1;
    3. unless pedestrians arrived in a re-goaling scenario (their new goals are drawn
       in Python; the caller computes the reward after them), the reward terms and the
       observation (:func:`reward_and_observation`).

    Returns:
        (new arrivals, robot event code at k + 1, nearest pedestrian of a collision),
        as :func:`~srfm.sim._kernels.advance_exact`.
    """
    action = env.action
    a0 = min(1.0, max(-1.0, action[0]))
    a1 = min(1.0, max(-1.0, action[1]))
    action[0] = a0
    action[1] = a1
    robot = ep.robot
    c0, c1 = action_to_command(a0, a1, robot[THETA], ep.limits)
    task = ep.task
    env.out[OUT_GOAL_DIST_BEFORE] = math.sqrt(
        (task.goal_x - robot[X]) ** 2 + (task.goal_y - robot[Y]) ** 2
    )
    n_new, event, nearest = advance_exact(ep, c0, c1, True, step_index)
    if not (env.regoal and n_new > 0):
        reward_and_observation(ep, env, event)
    return n_new, event, nearest
