"""numba kernels of the episode engine: one call per simulation step.

The step of an episode, from sample k to k + 1, as the engine
(:class:`srfm.sim.engine.EpisodeEngine`) runs it for the simulator and the gymnasium
environment alike:

1. the robot's body (x, y, radius, vx, vy), as the factual crowd feels it, is set to
   the robot at sample k (its velocity the one it reached k with; 0 once its episode
   has ended, when it stays where it is at rest); the robot moves under the command
   (:func:`move_robot`);
2. the factual crowd takes one SRFM step feeling that body, and, unless the
   counterfactual twin is switched off, the counterfactual crowd one step without it
   (with ``crowd_substeps`` > 1, that many crowd steps of dt / crowd_substeps, the body
   moved along the robot's step between them: the crowd at a finer step, the robot's
   control rate unchanged);
3. pedestrians within the goal radius of their goal are flagged as new arrivals
   (:func:`mark_arrivals`; the engine decides in Python what an arrival means);
4. for a robot still active, the robot event at sample k + 1 (:func:`robot_event`).

What follows in Python (pedestrians entering, new goals, routes, the event records) is
the engine's; nothing of the crowd's or the robot's motion is.

The three variants differ only in the crowd step they run (every pair, a cut-off's row
list, or the row list with threads), which they hand to the one body :func:`_advance`;
each is its own top-level function so that numba's on-disk cache keeps them apart and
a run compiles only its own.
"""

from __future__ import annotations

from typing import Any, Final, NamedTuple

import numpy as np
from numba import njit, types
from numba.experimental import structref

from srfm._jit import specialize_once
from srfm.models._arrays import CrowdArrays, ForceContext
from srfm.models._kernels import mark_arrivals, step_exact, step_parallel, step_serial
from srfm.models._primitives import FALSE
from srfm.models._robot_kernels import (
    EVENT_NONE,
    THETA,
    VX,
    VY,
    RobotLimits,
    RobotTask,
    X,
    Y,
    move_robot,
    robot_event,
)

__all__ = [
    "ArrivalFlags",
    "EpisodeArrays",
    "Samples",
    "StepOptions",
    "advance_exact",
    "advance_parallel",
    "advance_serial",
    "rest_exact",
    "rest_serial",
]


class ArrivalFlags(NamedTuple):
    """One twin's arrival bookkeeping (bool, N).

    Attributes:
        arrived: pedestrians that have arrived at their final goal (no more arrivals).
        new: pedestrians flagged at the last step as within the goal radius.
    """

    arrived: np.ndarray
    new: np.ndarray


class StepOptions(NamedTuple):
    """Fixed settings of an episode's step.

    Attributes:
        dt_s: simulation step (s).
        ped_goal_radius_m: a pedestrian arrives within this distance of its goal (m).
        counterfactual: step the counterfactual crowd too (the environment may skip
            it in training: its reward needs only the one-step deviation).
        crowd_substeps: crowd steps of ``dt_s / crowd_substeps`` per step (1: the
            paper's scheme, one crowd step per control step); the robot moves once
            per step under its command, and each crowd substep feels its body where
            it is at that time (linear between the samples, at the new velocity after
            the first substep).
    """

    dt_s: float
    ped_goal_radius_m: float
    counterfactual: bool
    crowd_substeps: int = 1


class Samples(NamedTuple):
    """An episode record's arrays of every sample k = 0..T (:func:`srfm.run_episode`),
    for the kernels that step a robot at rest (:func:`rest_exact`) to write into.

    Attributes:
        factual_pos, factual_vel, counterfactual_pos, counterfactual_vel, factual_goal,
            counterfactual_goal: (T + 1, N, 2) each twin's positions, velocities and
            goals.
        robot_pose: (T + 1, 3) x, y, θ. robot_vel: (T + 1, 2) vx, vy.
        robot_active: (T + 1,) the robot's episode goes on.
    """

    factual_pos: np.ndarray
    factual_vel: np.ndarray
    counterfactual_pos: np.ndarray
    counterfactual_vel: np.ndarray
    factual_goal: np.ndarray
    counterfactual_goal: np.ndarray
    robot_pose: np.ndarray
    robot_vel: np.ndarray
    robot_active: np.ndarray


_EPISODE_FIELDS: Final = (
    "factual",
    "counterfactual",
    "factual_arrivals",
    "counterfactual_arrivals",
    "robot",
    "felt",
    "force_buf",
    "limits",
    "task",
    "options",
)


@structref.register
class EpisodeArraysType(types.StructRef):
    """numba's type of :class:`EpisodeArrays`."""

    def preprocess_fields(self, fields: Any) -> Any:
        return tuple((name, types.unliteral(typ)) for name, typ in fields)  # type: ignore[no-untyped-call]


class EpisodeArrays(structref.StructRefProxy):
    """Everything a step reads and writes, the pedestrians there at the current sample.

    A numba structure (``numba.experimental.structref``) rather than a NamedTuple: a
    kernel call then passes one reference instead of unpacking some thirty arrays and
    tuples, which cost 0.8 µs of a 16 µs environment step (side by side in one process,
    2026-11-27, ``crosswalk``). The engine keeps its own references to the arrays;
    reading a field from Python works but calls a compiled getter.

    Args:
        factual: the crowd that feels the robot.
        counterfactual: its twin, blind to the robot (shares radius, v0, vmax).
        factual_arrivals: the factual crowd's arrival flags.
        counterfactual_arrivals: the counterfactual crowd's.
        robot: (7,) the robot state (:mod:`srfm.models._robot_kernels` layout).
        felt: what the factual crowd feels: the parameters, the robot's body
            (``felt.robot`` (5,): x, y at the current sample, radius, vx, vy), the obstacles
            and the cut-offs (the counterfactual crowd feels the same with the robot
            switched off).
        force_buf: (N, 2) scratch for the forces.
        limits: the robot's body and limits.
        task: the robot's goal, world and horizon.
        options: the step's settings.
    """

    # The fields, for type checkers (numba.experimental.structref.define_proxy below
    # adds them as properties).
    factual: CrowdArrays
    counterfactual: CrowdArrays
    factual_arrivals: ArrivalFlags
    counterfactual_arrivals: ArrivalFlags
    robot: np.ndarray
    felt: ForceContext
    force_buf: np.ndarray
    limits: RobotLimits
    task: RobotTask
    options: StepOptions

    def __new__(
        cls,
        factual: CrowdArrays,
        counterfactual: CrowdArrays,
        factual_arrivals: ArrivalFlags,
        counterfactual_arrivals: ArrivalFlags,
        robot: np.ndarray,
        felt: ForceContext,
        force_buf: np.ndarray,
        limits: RobotLimits,
        task: RobotTask,
        options: StepOptions,
    ) -> EpisodeArrays:
        # numba's own constructor of a proxy (StructRefProxy.__new__) is compiled
        # anew in every process, 1.4 s; this one is in numba's cache.
        args = (
            factual,
            counterfactual,
            factual_arrivals,
            counterfactual_arrivals,
            robot,
            felt,
            force_buf,
            limits,
            task,
            options,
        )
        proxy: EpisodeArrays = specialize_once(_new_episode_arrays, *args)(*args)
        return proxy


structref.define_proxy(EpisodeArrays, EpisodeArraysType, list(_EPISODE_FIELDS))  # type: ignore[no-untyped-call]


@njit(cache=True)
def _new_episode_arrays(
    factual: CrowdArrays,
    counterfactual: CrowdArrays,
    factual_arrivals: ArrivalFlags,
    counterfactual_arrivals: ArrivalFlags,
    robot: np.ndarray,
    felt: ForceContext,
    force_buf: np.ndarray,
    limits: RobotLimits,
    task: RobotTask,
    options: StepOptions,
) -> EpisodeArrays:
    """An :class:`EpisodeArrays` (its constructor, compiled once and cached)."""
    return EpisodeArrays(
        factual,
        counterfactual,
        factual_arrivals,
        counterfactual_arrivals,
        robot,
        felt,
        force_buf,
        limits,
        task,
        options,
    )


@njit(cache=True, inline="always")
def _advance(
    ep: EpisodeArrays, c0: float, c1: float, active: bool, step_index: int, crowd_step: Any
) -> tuple[int, int, int]:
    """One step (see the module docstring) with the crowd step ``crowd_step`` (one of
    :func:`step_exact`, :func:`step_serial`, :func:`step_parallel`, a compile-time
    constant of each variant)."""
    robot = ep.robot
    o = ep.options
    if not active:
        robot[VX:] = 0.0  # at rest where its episode ended
    body = ep.felt.robot
    x0 = robot[X]
    y0 = robot[Y]
    body[0] = x0
    body[1] = y0
    body[3] = robot[VX]
    body[4] = robot[VY]
    if active:
        move_robot(robot, c0, c1, ep.limits, o.dt_s)
    felt = ep.felt
    blind = ForceContext(felt.params, body, FALSE, felt.obstacles, felt.cut)
    n_sub = o.crowd_substeps
    h = o.dt_s / n_sub  # dt itself for one substep
    for j in range(n_sub):
        if j > 0:  # the body where the robot is at time k dt + j h
            frac = j / n_sub
            body[0] = x0 + frac * (robot[X] - x0)
            body[1] = y0 + frac * (robot[Y] - y0)
            body[3] = robot[VX]
            body[4] = robot[VY]
        crowd_step(ep.factual, felt, h, ep.force_buf)
        if o.counterfactual:
            crowd_step(ep.counterfactual, blind, h, ep.force_buf)
    radius = o.ped_goal_radius_m
    f = ep.factual
    flags = ep.factual_arrivals
    n_new = mark_arrivals(f.pos, f.goal, radius, flags.arrived, flags.new)
    if o.counterfactual:
        c = ep.counterfactual
        flags = ep.counterfactual_arrivals
        n_new += mark_arrivals(c.pos, c.goal, radius, flags.arrived, flags.new)
    if not active:
        return n_new, EVENT_NONE, -1
    event, nearest = robot_event(robot, f, ep.felt.obstacles, ep.limits, ep.task, step_index + 1)
    return n_new, event, nearest


@njit(cache=True)
def advance_exact(
    ep: EpisodeArrays, c0: float, c1: float, active: bool, step_index: int
) -> tuple[int, int, int]:
    """One step with every pedestrian pair (the exact kernel).

    Args:
        ep: the episode's arrays, updated in place.
        c0, c1: the robot's command (ignored when not ``active``).
        active: the robot's episode goes on.
        step_index: k, the sample the step starts from.

    Returns:
        (new arrivals of both twins, robot event code at k + 1, nearest pedestrian of
        a collision or −1).
    """
    return _advance(ep, c0, c1, active, step_index, step_exact)


@njit(cache=True)
def advance_serial(
    ep: EpisodeArrays, c0: float, c1: float, active: bool, step_index: int
) -> tuple[int, int, int]:
    """:func:`advance_exact` with the cut-off's row list (:func:`step_serial`)."""
    return _advance(ep, c0, c1, active, step_index, step_serial)


# Not cached on disk: loaded from numba's cache, this kernel (a threaded callee inside
# a function of an EpisodeArrays structure) crashed the process (numba 0.68, seen
# 2026-11-27); compiled in each process that asks for threads, it runs as it should.
@njit(cache=False)
def advance_parallel(
    ep: EpisodeArrays, c0: float, c1: float, active: bool, step_index: int
) -> tuple[int, int, int]:
    """:func:`advance_serial` with the force pass over threads (:func:`step_parallel`);
    identical results."""
    return _advance(ep, c0, c1, active, step_index, step_parallel)


# Once the robot's episode has ended, a step is the kernel's alone: nothing of it needs
# Python (no command, no robot event) unless a pedestrian arrives, enters or follows a
# route. The engine then runs these kernels (EpisodeEngine.rest) instead of one call and
# the bookkeeping per step: in the paper's scenarios the robot is at rest for about
# 60 % of the horizon, and the Python around each step cost more than the step itself
# (docs/performance.md, "Full episodes").


@njit(cache=True, inline="always")
def _write_sample(ep: EpisodeArrays, samples: Samples, k: int) -> None:
    """Sample k of both twins and of the robot (at rest) into ``samples``."""
    # Element by element: an array slice assignment compiles numba's shape-mismatch
    # error with its message formatting, 3.4 s of a first run (profile_compile.py).
    f = ep.factual
    c = ep.counterfactual
    for i in range(f.pos.shape[0]):
        for d in range(2):
            samples.factual_pos[k, i, d] = f.pos[i, d]
            samples.factual_vel[k, i, d] = f.vel[i, d]
            samples.counterfactual_pos[k, i, d] = c.pos[i, d]
            samples.counterfactual_vel[k, i, d] = c.vel[i, d]
            samples.factual_goal[k, i, d] = f.goal[i, d]
            samples.counterfactual_goal[k, i, d] = c.goal[i, d]
    robot = ep.robot
    samples.robot_pose[k, 0] = robot[X]
    samples.robot_pose[k, 1] = robot[Y]
    samples.robot_pose[k, 2] = robot[THETA]
    samples.robot_vel[k, 0] = robot[VX]
    samples.robot_vel[k, 1] = robot[VY]
    samples.robot_active[k] = False


@njit(cache=True, inline="always")
def _rest(
    ep: EpisodeArrays, step_index: int, stop: int, samples: Samples, advance: Any
) -> tuple[int, int]:
    """Steps of a robot at rest with the step kernel ``advance`` (a compile-time constant
    of each variant), from sample ``step_index`` on, each new sample written into
    ``samples``, until sample ``stop`` or the first step with new arrivals (that
    sample is left to the engine, whose arrivals may change goals). Returns (the
    sample reached, new arrivals at it)."""
    k = step_index
    while k < stop:
        n_new, _, _ = advance(ep, 0.0, 0.0, FALSE, k)
        k += 1
        if n_new:
            return k, n_new
        _write_sample(ep, samples, k)
    return k, 0


@njit(cache=True)
def rest_exact(ep: EpisodeArrays, step_index: int, stop: int, samples: Samples) -> tuple[int, int]:
    """Steps of :func:`advance_exact` with the robot at rest (see :func:`_rest`)."""
    return _rest(ep, step_index, stop, samples, advance_exact)


@njit(cache=True)
def rest_serial(ep: EpisodeArrays, step_index: int, stop: int, samples: Samples) -> tuple[int, int]:
    """Steps of :func:`advance_serial` with the robot at rest (see :func:`_rest`)."""
    return _rest(ep, step_index, stop, samples, advance_serial)
