"""The RL policy's observation and action: one definition for training and evaluation.

A policy sees the same 9 + 6K + B numbers whether it is trained in the environment
``srfm/SocialNav-v0`` (:mod:`srfm.rl`, which builds the vector inside its fused step
kernel) or runs as a planner in :func:`srfm.run_episode` (:class:`ObservationBuilder`,
used by :mod:`srfm.planners.td3`): both call :func:`build_observation`, and both turn
actions into commands with :func:`action_to_command`.

:class:`EnvConfig`, the environment's configuration, lives here because a policy file
records it (``srfm train`` writes it) and the policy planner reads it back to build
the observation the policy was trained on. This module needs neither gymnasium nor
anything of :mod:`srfm.rl` or :mod:`srfm.sim`.

Observation layout (float32, every entry in [−1, 1]; robot frame: x forward along the
heading, y to the left):

==============  ==========================================================
index           entry
==============  ==========================================================
0               goal distance / goal scale (the world diagonal), capped at 1
1, 2            cos, sin of the goal bearing
3, 4            unicycle: v / v_max, ω / ω_max; holonomic: robot-frame
                (vx, vy) / v_max; clipped to [−1, 1]
5, 6            the last action (clipped to [−1, 1]; zeros after reset)
7               success flag (1.0 when the goal was reached at this step)
8               terminated flag (1.0 when the episode ended at this step)
9 + 6m … 14+6m  slot m = 0 … K−1, closest pedestrian first: present (1.0),
                distance / social zone, cos and sin of the bearing, relative
                velocity (pedestrian − robot) / velocity scale (x, y), clipped
9 + 6K + j      range beam j = 0 … B−1 (B = ``range_beams``, 0 by default):
                the distance from the robot centre to the nearest wall or
                pillar along the direction heading + 2πj/B (counter-clockwise,
                beam 0 straight ahead) / ``range_max_m``, capped at 1 (1: nothing
                within range)
==============  ==========================================================

Slots hold the pedestrians whose centre is closer than the social zone to the robot
centre, nearest first (ties by index); empty slots are zeros. The range beams model a
planar range sensor (a 2-D lidar) that sees the scenario's walls and pillars, not
pedestrians (they are in the slots) and not the world's bounds (no physical surface).
"""

from __future__ import annotations

import math
import operator
from collections.abc import Callable
from typing import Any, Final, NamedTuple

import attrs
import numpy as np
from numba import njit
from numpy.typing import NDArray

from srfm._jit import specialize
from srfm._text import plain
from srfm._validate import keyword_options, non_negative, positive
from srfm.errors import ParameterError
from srfm.models._primitives import EPS
from srfm.models._robot_kernels import (
    OMEGA,
    ROBOT_SIZE,
    THETA,
    VX,
    VY,
    RobotLimits,
    RobotTask,
    V,
    X,
    Y,
    robot_task,
)
from srfm.models.robot import KINEMATICS, Kinematics
from srfm.planners._base import Observation, PlannerContext

__all__ = [
    "DEFAULT_K_DIV",
    "MAX_RANGE_BEAMS",
    "OBS_ACTION",
    "OBS_FLAGS",
    "OBS_GOAL",
    "OBS_PEDS",
    "OBS_VEL",
    "PED_FEATURES",
    "EnvConfig",
    "ObservationBuilder",
    "ObservationParams",
    "action_to_command",
    "beam_range",
    "build_observation",
    "obs_size",
]

FloatArray = NDArray[np.float64]

# Default weight of the one-step deviation penalty (per metre of summed deviation).
DEFAULT_K_DIV: Final = 2.0

# Offsets in the observation vector (see the table in the module docstring).
OBS_GOAL: Final = 0  # goal distance / goal scale, cos, sin of the goal bearing
OBS_VEL: Final = 3  # the robot's velocity, normalised
OBS_ACTION: Final = 5  # the last action, in [-1, 1]
OBS_FLAGS: Final = 7  # success, terminated
OBS_PEDS: Final = 9  # K slots of PED_FEATURES, then B range beams
PED_FEATURES: Final = 6  # present, distance / zone, cos, sin, relative vx, vy
MAX_RANGE_BEAMS: Final = 360


def obs_size(max_peds: int, range_beams: int = 0) -> int:
    """Length of the observation vector with ``max_peds`` pedestrian slots and
    ``range_beams`` range beams (9 + 6K + B)."""
    return OBS_PEDS + PED_FEATURES * max_peds + range_beams


def _non_negative(inst: Any, attribute: attrs.Attribute[float], value: Any) -> None:
    non_negative(value, f"env.{attribute.name}", ParameterError)


def _positive(inst: Any, attribute: attrs.Attribute[float], value: Any) -> None:
    positive(value, f"env.{attribute.name}", ParameterError)


def _max_peds(inst: Any, attribute: attrs.Attribute[int], value: Any) -> None:
    try:
        count = operator.index(value)
    except TypeError:
        count = -1
    if isinstance(value, bool) or not 1 <= count <= 1000:  # 0 slots: a robot blind to people
        raise ParameterError(
            f"env.max_pedestrians must be an integer in [1, 1000], got {plain(value)}"
        )


MAX_ACTION_REPEAT: Final = 100


def _action_repeat(inst: Any, attribute: attrs.Attribute[int], value: Any) -> None:
    try:
        count = operator.index(value)
    except TypeError:
        count = 0
    if isinstance(value, bool) or not 1 <= count <= MAX_ACTION_REPEAT:
        raise ParameterError(
            f"env.action_repeat must be an integer in [1, {MAX_ACTION_REPEAT}], got {plain(value)}"
        )


def _range_beams(inst: Any, attribute: attrs.Attribute[int], value: Any) -> None:
    try:
        count = operator.index(value)
    except TypeError:
        count = -1
    if isinstance(value, bool) or not 0 <= count <= MAX_RANGE_BEAMS:
        raise ParameterError(
            f"env.range_beams must be an integer in [0, {MAX_RANGE_BEAMS}], got {plain(value)}"
        )


def _kinematics(inst: Any, attribute: attrs.Attribute[str | None], value: Any) -> None:
    if value is not None and (not isinstance(value, str) or value not in KINEMATICS):
        raise ParameterError(
            f"env.kinematics must be None or one of {KINEMATICS}, got {plain(value)}"
        )


def _unit_interval(inst: Any, attribute: attrs.Attribute[float], value: Any) -> None:
    non_negative(value, f"env.{attribute.name}", ParameterError)
    if value > 1.0:
        raise ParameterError(f"env.{attribute.name} must be in [0, 1], got {plain(value)}")


def _flag(inst: Any, attribute: attrs.Attribute[bool], value: Any) -> None:
    if not isinstance(value, bool):
        raise ParameterError(f"env.{attribute.name} must be True or False, got {plain(value)}")


class ObservationParams(NamedTuple):
    """The observation options as :func:`build_observation` takes them.

    Built by :meth:`EnvConfig.observation_params`.

    Attributes:
        goal_scale_m: the goal distance is divided by this (m): the world diagonal.
        social_zone_m: pedestrians closer than this to the robot centre are observed,
            and their distance is divided by it (m).
        velocity_scale_mps: relative velocities are divided by this (m/s).
        max_pedestrians: K, the number of pedestrian slots.
        range_beams: B, the number of range beams (0: none).
        range_max_m: the beams' range (m); a beam's distance is divided by it.
    """

    goal_scale_m: float
    social_zone_m: float
    velocity_scale_mps: float
    max_pedestrians: int
    range_beams: int
    range_max_m: float


@attrs.frozen(kw_only=True)
class EnvConfig:
    """Reward, observation and simulation options of ``srfm/SocialNav-v0``.

    Reward per step (paper Eq. 7): r = r_term − k1 · r_dist − k2 · r_div.

    Attributes:
        k1: weight of r_dist, the goal distance divided by the goal distance at reset,
            capped at 1 (dimensionless, 1 at the start, 0 at the goal).
        k2: weight of r_div (1/m), the summed one-step counterfactual deviation (m) of
            the pedestrians inside the social zone. 0 gives the paper's RL_base
            reward, > 0 the SRFM-aware one.
        social_zone_m: social zone radius (m): the pedestrians observed and the
            pedestrians whose deviation counts in r_div are those whose centre is
            closer than this to the robot centre (paper: 3 m).
        max_pedestrians: K, the number of observed pedestrian slots (paper: 10).
        success_reward: r_term when the robot reaches its goal.
        timeout_penalty: −r_term when the horizon is reached (a truncation). The
            defaults (25, and 50 for a collision) exceed the largest discounted sum of
            per-step penalties over TD3's horizon (about (k1 + k2 · 0.05 m) / (1 − γ)
            ≈ 35), so that ending an episode by a collision or by leaving the world
            never pays.
        velocity_scale_mps: relative pedestrian velocities in the observation are
            divided by this (m/s) and clipped to [−1, 1].
        kinematics: ``"unicycle"`` (v, ω), ``"holonomic"`` (robot-frame vx, vy), or
            None for the scenario's robot.
        counterfactual_twin: step the full counterfactual crowd as well (so an
            episode can be scored for deviation). The reward does not need it (it
            uses the one-step counterfactual); False skips it for faster training.
        k_progress: weight of the potential-based progress term added to the reward,
            r_progress = γ Φ(s') − Φ(s) with Φ = −k_progress · d / d_0 (d the goal
            distance, d_0 its value at reset, Φ = 0 in a terminal state): it leaves
            the optimal policy unchanged (Ng, Harada, Russell 1999). 0 (the
            default) gives the paper's reward.
        progress_gamma: γ of the progress term; set it to the learner's discount
            (``srfm train`` does).
        action_repeat: simulation steps per action (1, the default, is the paper's
            set-up). The environment applies each action for this many steps (fewer
            when the episode ends) and returns the sum of their rewards, with the
            progress term taken over the whole action, γ Φ(s_{t+k}) − Φ(s_t), so that
            it stays potential-based for a learner that discounts once per action. A
            policy's planner holds each action for as many steps.
        range_beams: B, the number of range beams to walls and pillars appended to
            the observation (0, the default, is the paper's observation, which has
            none). The beams are spread evenly over the full circle, beam 0 along
            the heading.
        range_max_m: the range of the beams (m): a beam reports its distance to the
            nearest wall or pillar divided by this, capped at 1.
    """

    k1: float = attrs.field(default=0.1, validator=_non_negative)
    k2: float = attrs.field(default=DEFAULT_K_DIV, validator=_non_negative)
    social_zone_m: float = attrs.field(default=3.0, validator=_positive)
    max_pedestrians: int = attrs.field(default=10, validator=_max_peds)
    success_reward: float = attrs.field(default=25.0, validator=_non_negative)
    timeout_penalty: float = attrs.field(default=25.0, validator=_non_negative)
    velocity_scale_mps: float = attrs.field(default=2.0, validator=_positive)
    kinematics: Kinematics | None = attrs.field(default=None, validator=_kinematics)
    counterfactual_twin: bool = attrs.field(default=True, validator=_flag)
    k_progress: float = attrs.field(default=0.0, validator=_non_negative)
    progress_gamma: float = attrs.field(default=0.99, validator=_unit_interval)
    action_repeat: int = attrs.field(default=1, validator=_action_repeat)
    range_beams: int = attrs.field(default=0, validator=_range_beams)
    range_max_m: float = attrs.field(default=4.0, validator=_positive)

    def __new__(cls, *args: Any, **options: Any) -> EnvConfig:
        # Before attrs' __init__: an unknown option is a ParameterError naming it.
        keyword_options(cls, args, options, ParameterError)
        return super().__new__(cls)

    @property
    def collision_penalty(self) -> float:
        """−r_term on a collision (pedestrian, wall or pillar) or on leaving the world:
        twice the timeout penalty (paper §IV-B)."""
        return 2.0 * self.timeout_penalty

    def replace(self, **changes: Any) -> EnvConfig:
        """A copy with some fields changed (validated)."""
        return attrs.evolve(self, **changes)

    @property
    def obs_size(self) -> int:
        """Length of the observation vector (9 + 6K + B)."""
        return obs_size(self.max_pedestrians, self.range_beams)

    def observation_params(self, world: Any) -> ObservationParams:
        """The observation options for the kernels, in a world of the given bounds.

        Args:
            world: the world rectangle (a :class:`srfm.scenarios.WorldBounds`); its
                diagonal (m) is the goal-distance scale.
        """
        return ObservationParams(
            goal_scale_m=math.hypot(world.x_max - world.x_min, world.y_max - world.y_min),
            social_zone_m=float(self.social_zone_m),
            velocity_scale_mps=float(self.velocity_scale_mps),
            max_pedestrians=int(self.max_pedestrians),
            range_beams=int(self.range_beams),
            range_max_m=float(self.range_max_m),
        )


@njit(cache=True)
def action_to_command(
    a0: float, a1: float, theta: float, limits: RobotLimits
) -> tuple[float, float]:
    """Scale an action in [−1, 1]² (clipped; NaN-free input assumed) to a command.

    Unicycle: (v, ω) = (a0 v_max, a1 ω_max). Holonomic: the action is a velocity in
    the robot frame, (a0, a1) v_max, rotated into the world frame by the heading
    ``theta`` (rad).
    """
    a0 = min(1.0, max(-1.0, a0))
    a1 = min(1.0, max(-1.0, a1))
    vmax = limits.max_speed_mps
    if not limits.holonomic:
        return a0 * vmax, a1 * limits.max_angular_speed_radps
    cx = a0 * vmax
    cy = a1 * vmax
    c = math.cos(theta)
    s = math.sin(theta)
    return cx * c - cy * s, cx * s + cy * c


@njit(cache=True, inline="always")
def _unit_clip(x: float) -> float:
    return min(1.0, max(-1.0, x))


@njit(cache=True, inline="always")
def _bearing(c: float, s: float, dx: float, dy: float, d: float) -> tuple[float, float]:
    """cos and sin of the bearing of the offset (dx, dy) (m) at distance d (m), in the
    robot frame of heading (cos, sin) = (c, s); (1, 0) when d is below ``EPS``."""
    if d > EPS:
        return (c * dx + s * dy) / d, (-s * dx + c * dy) / d
    return 1.0, 0.0


@njit(cache=True)
def beam_range(
    x: float, y: float, ux: float, uy: float, segments: np.ndarray, circles: np.ndarray, rmax: float
) -> float:
    """Distance (m) from (x, y) along the unit direction (ux, uy) to the first wall
    segment or pillar it meets, or ``rmax`` when none is nearer.

    Args:
        x, y: the ray's origin (m).
        ux, uy: its direction, a unit vector.
        segments: (M, 4) walls (x1, y1, x2, y2) (m).
        circles: (C, 3) pillars (cx, cy, radius) (m); from inside a pillar the ray
            meets its boundary on the way out.
        rmax: the largest distance reported (m).
    """
    best = rmax
    for m in range(segments.shape[0]):
        ex = segments[m, 2] - segments[m, 0]
        ey = segments[m, 3] - segments[m, 1]
        det = ux * ey - uy * ex  # cross(u, e); 0: the ray runs parallel to the wall
        if det == 0.0:
            continue
        wx = segments[m, 0] - x
        wy = segments[m, 1] - y
        t = (wx * ey - wy * ex) / det  # along the ray (m)
        s = (wx * uy - wy * ux) / det  # along the wall, 0 … 1
        if 0.0 <= t < best and 0.0 <= s <= 1.0:
            best = t
    for m in range(circles.shape[0]):
        fx = x - circles[m, 0]
        fy = y - circles[m, 1]
        r = circles[m, 2]
        b = fx * ux + fy * uy
        disc = b * b - (fx * fx + fy * fy - r * r)
        if disc < 0.0:
            continue
        root = math.sqrt(disc)
        t = -b - root
        if t < 0.0:
            t = -b + root  # the origin is inside the pillar
        if 0.0 <= t < best:
            best = t
    return best


@njit(cache=True, inline="always")
def _write_beams(
    x: float,
    y: float,
    theta: float,
    segments: np.ndarray,
    circles: np.ndarray,
    params: ObservationParams,
    obs: np.ndarray,
) -> None:
    """The B range beams into ``obs[9 + 6K:]`` (distance / range, capped at 1)."""
    n = params.range_beams
    rmax = params.range_max_m
    base = OBS_PEDS + PED_FEATURES * params.max_pedestrians
    for j in range(n):
        angle = theta + 2.0 * math.pi * j / n
        hit = beam_range(x, y, math.cos(angle), math.sin(angle), segments, circles, rmax)
        obs[base + j] = hit / rmax


@njit(cache=True)
def build_observation(
    ped_pos: np.ndarray,
    ped_vel: np.ndarray,
    robot: np.ndarray,
    last_action: np.ndarray,
    success: bool,
    terminated: bool,
    limits: RobotLimits,
    task: RobotTask,
    params: ObservationParams,
    segments: np.ndarray,
    circles: np.ndarray,
    dist_buf: np.ndarray,
    idx_buf: np.ndarray,
    obs: np.ndarray,
) -> int:
    """Write the observation (float32, every entry in [−1, 1]) into ``obs``.

    The layout is the table of this module's docstring. Pedestrians count as in the
    zone when their centre is closer than ``params.social_zone_m`` (strictly, the same
    test as :func:`srfm.models._kernels.within_range`); they are insertion-sorted by
    squared distance (stable, so ties keep index order).

    Args:
        ped_pos: (N, 2) pedestrian positions (m): every pedestrian, or only those a
            planner observes within the zone (the result is the same).
        ped_vel: (N, 2) their velocities (m/s).
        robot: (7,) the robot state (kernel layout of :class:`srfm.RobotState`).
        last_action: (2,) the last action.
        success: the goal was reached at this step.
        terminated: the episode ended at this step.
        limits: the robot's limits (v_max, ω_max, kinematics).
        task: the robot's goal.
        params: the observation options.
        segments: (M, 4) walls (x1, y1, x2, y2) (m), for the range beams.
        circles: (C, 3) pillars (cx, cy, radius) (m), for the range beams.
        dist_buf: (≥ N,) scratch, float64.
        idx_buf: (≥ N,) scratch, int64.
        obs: (9 + 6K + B,) float32, overwritten.

    Returns:
        The number of pedestrians in the zone (which may exceed K).
    """
    x = robot[X]
    y = robot[Y]
    c = math.cos(robot[THETA])
    s = math.sin(robot[THETA])
    gdx = task.goal_x - x
    gdy = task.goal_y - y
    gd = math.sqrt(gdx * gdx + gdy * gdy)
    obs[OBS_GOAL] = min(1.0, gd / params.goal_scale_m)
    obs[OBS_GOAL + 1], obs[OBS_GOAL + 2] = _bearing(c, s, gdx, gdy, gd)
    rvx = robot[VX]
    rvy = robot[VY]
    vmax = limits.max_speed_mps
    if not limits.holonomic:
        obs[OBS_VEL] = _unit_clip(robot[V] / vmax)
        obs[OBS_VEL + 1] = _unit_clip(robot[OMEGA] / limits.max_angular_speed_radps)
    else:
        obs[OBS_VEL] = _unit_clip((c * rvx + s * rvy) / vmax)
        obs[OBS_VEL + 1] = _unit_clip((-s * rvx + c * rvy) / vmax)
    obs[OBS_ACTION] = _unit_clip(last_action[0])
    obs[OBS_ACTION + 1] = _unit_clip(last_action[1])
    obs[OBS_FLAGS] = 1.0 if success else 0.0
    obs[OBS_FLAGS + 1] = 1.0 if terminated else 0.0

    # Pedestrians in the zone, insertion-sorted by squared distance (stable).
    zone = params.social_zone_m
    z2 = zone * zone
    k = 0
    for i in range(ped_pos.shape[0]):
        dx = ped_pos[i, 0] - x
        dy = ped_pos[i, 1] - y
        d2 = dx * dx + dy * dy
        if not d2 < z2:
            continue
        j = k
        while j > 0 and dist_buf[j - 1] > d2:
            dist_buf[j] = dist_buf[j - 1]
            idx_buf[j] = idx_buf[j - 1]
            j -= 1
        dist_buf[j] = d2
        idx_buf[j] = i
        k += 1
    vscale = params.velocity_scale_mps
    for m in range(params.max_pedestrians):
        base = OBS_PEDS + PED_FEATURES * m
        if m >= k:
            for f in range(PED_FEATURES):
                obs[base + f] = 0.0
            continue
        i = idx_buf[m]
        dx = ped_pos[i, 0] - x
        dy = ped_pos[i, 1] - y
        d = math.sqrt(dist_buf[m])
        obs[base] = 1.0
        obs[base + 1] = min(1.0, d / zone)
        obs[base + 2], obs[base + 3] = _bearing(c, s, dx, dy, d)
        wx = ped_vel[i, 0] - rvx
        wy = ped_vel[i, 1] - rvy
        obs[base + 4] = _unit_clip((c * wx + s * wy) / vscale)
        obs[base + 5] = _unit_clip((-s * wx + c * wy) / vscale)
    if params.range_beams > 0:
        _write_beams(x, y, robot[THETA], segments, circles, params, obs)
    return k


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
        self.limits = context.robot.for_kernels()
        self.task = robot_task(context.robot_goal, context.world, context.horizon_steps)
        self.params = config.observation_params(context.world)
        self.size = config.obs_size
        walls = context.obstacles.for_kernels()
        self._segments = walls.segments
        self._circles = walls.circles
        self._robot = np.zeros(ROBOT_SIZE)
        self._dist = np.zeros(0)
        self._idx = np.zeros(0, dtype=np.int64)
        # The kernels, specialised for their argument types (srfm._jit.specialize).
        self._build: Callable[..., int] | None = None
        self._command = specialize(action_to_command, 0.0, 0.0, 0.0, self.limits)

    def build(
        self, observation: Observation, last_action: FloatArray, out: NDArray[np.float32]
    ) -> NDArray[np.float32]:
        """Write the observation vector into ``out`` and return it.

        Args:
            observation: the planner's view of the sample.
            last_action: (2,) the policy's last action (zeros at the first step).
            out: (size,) float32, C-contiguous, overwritten.

        Raises:
            ParameterError: ``out`` is not a C-contiguous float32 vector of ``size``.
        """
        if out.dtype != np.float32 or out.shape != (self.size,) or not out.flags.c_contiguous:
            raise ParameterError(
                f"out must be a C-contiguous float32 array of shape ({self.size},), "
                f"got {out.dtype} {out.shape}"
            )
        goal = observation.robot_goal
        task = self.task
        if task.goal_x != goal[0] or task.goal_y != goal[1]:
            # the route's next waypoint in a scenario with walls (srfm.sim.routes)
            self.task = task._replace(goal_x=float(goal[0]), goal_y=float(goal[1]))
        r = observation.robot
        robot = self._robot
        robot[X] = r.x
        robot[Y] = r.y
        robot[THETA] = r.theta
        robot[VX] = r.vx
        robot[VY] = r.vy
        robot[V] = r.v
        robot[OMEGA] = r.omega
        ped_pos = np.ascontiguousarray(observation.ped_pos, dtype=np.float64)
        ped_vel = np.ascontiguousarray(observation.ped_vel, dtype=np.float64)
        n = ped_pos.shape[0]
        if self._dist.shape[0] < n:
            self._dist = np.zeros(n)
            self._idx = np.zeros(n, dtype=np.int64)
        args = (
            ped_pos,
            ped_vel,
            robot,
            np.ascontiguousarray(last_action, dtype=np.float64),
            False,
            False,
            self.limits,
            self.task,
            self.params,
            self._segments,
            self._circles,
            self._dist,
            self._idx,
            out,
        )
        if self._build is None:
            self._build = specialize(build_observation, *args)
        self._build(*args)
        return out

    def command(self, action: FloatArray, theta: float) -> FloatArray:
        """The simulator command for an action in [−1, 1]² (the environment's scaling)."""
        c0, c1 = self._command(float(action[0]), float(action[1]), float(theta), self.limits)
        return np.array([c0, c1])
