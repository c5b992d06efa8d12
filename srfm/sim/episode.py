"""Run one twin episode with a planner and collect its :class:`EpisodeRecord`.

Also the checks made before an episode starts: the planner's name (it becomes a folder
name), the memory the episode needs (:func:`check_episode_memory`), and the guard that
turns an exception raised inside a user's planner into one
:class:`~srfm.errors.UserCodeError`.
"""

from __future__ import annotations

import os
import re
import warnings
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Final

import attrs
import numpy as np

from srfm._streams import PLANNER_STREAM, planner_rng
from srfm._text import plain
from srfm._user_code import call_user_code, is_user_code, user_code_error
from srfm._validate import path_name, planner_name
from srfm.errors import (
    PlannerError,
    PlannerFailedError,
    PlannerFailureWarning,
    ResourceError,
    SimulationError,
    SrfmError,
)
from srfm.models import _robot_kernels as _rk
from srfm.models.forces import Cutoff
from srfm.models.params import SRFMParams
from srfm.planners import Planner, check_planner, make_planner
from srfm.planners._base import PRIVILEGED_HOOK
from srfm.scenarios import Scenario, episode_setup, load_scenario
from srfm.sim import _kernels as _sk
from srfm.sim.record import EpisodeRecord, Event
from srfm.sim.simulator import TwinSimulator

__all__ = [
    "MEMORY_LIMIT_ENV",
    "PLANNER_STREAM",
    "build_planner",
    "check_episode_memory",
    "estimate_episode_memory",
    "format_bytes",
    "memory_limit",
    "memory_room",
    "planner_rng",
    "run_episode",
    "run_planners",
]


def build_planner(name: str) -> Planner:
    """A fresh planner by registry name or ``module:attribute``, the name checked first
    (:func:`srfm._validate.planner_name`) and anything the user's import or factory
    raises (also ``sys.exit``) turned into a :class:`~srfm.errors.UserCodeError`.

    Raises:
        PlannerError: a malformed or unknown name, or a result that is no planner.
        UserCodeError: the user's module or factory raised.
    """
    planner_name(name, PlannerError)
    return call_user_code(name, "its factory", lambda: make_planner(name))


# Memory of one episode (bytes), measured with tracemalloc (full MCAP profile, which
# bounds the compact one): per pedestrian and recorded sample, the record's six
# (T + 1, N, 2) float64 arrays and the metrics' working arrays (160); per sample, the
# robot arrays (64). The logs add per pedestrian-sample / per sample: MCAP 1550 / 9000,
# Rerun 20 / 8000, force arrows 100 / 0.
_PER_PED_SAMPLE: Final = {"record": 160, "mcap": 1550, "rrd": 20, "forces": 100}
_PER_SAMPLE: Final = {"record": 64, "mcap": 9000, "rrd": 8000, "forces": 0}
# The robot's pose (x, y, θ) and velocity (vx, vy) in its (7,) array.
_POSE: Final = slice(_rk.X, _rk.THETA + 1)
_VELOCITY: Final = slice(_rk.VX, _rk.VY + 1)
_BASE_BYTES: Final = 64 * 2**20  # room kept for the process itself (numba, numpy)

MEMORY_LIMIT_ENV: Final = "SRFM_MEMORY_LIMIT"
"""Environment variable that sets the memory limit (bytes, or with a unit: 500M, 8G)."""
_UNITS: Final = {"": 1, "K": 2**10, "M": 2**20, "G": 2**30, "T": 2**40}


def estimate_episode_memory(
    scenario: Scenario, *, mcap: bool = False, rrd: bool = False, forces: bool = False
) -> int:
    """An estimate (bytes) of the memory one episode of ``scenario`` needs: its record,
    its metrics and, when asked, its logs (MCAP, Rerun, force arrows)."""
    parts = {"record": True, "mcap": mcap, "rrd": rrd, "forces": rrd and forces}
    per_ped = sum(_PER_PED_SAMPLE[k] for k, on in parts.items() if on)
    per_sample = sum(_PER_SAMPLE[k] for k, on in parts.items() if on)
    return (scenario.horizon_steps + 1) * (scenario.n_pedestrians * per_ped + per_sample)


def _read_int(path: str) -> int | None:
    try:
        text = Path(path).read_text(encoding="ascii").strip()
    except (OSError, UnicodeDecodeError):
        return None
    return int(text) if text.isdigit() else None


def memory_limit() -> tuple[int, str] | None:
    """The memory an episode may use (bytes) and where that number comes from.

    ``SRFM_MEMORY_LIMIT`` when set; otherwise the memory available now (``MemAvailable``
    of ``/proc/meminfo``), lowered to what the cgroup still allows when the process
    runs in a container with a limit. None where neither can be read (no check).

    Raises:
        ResourceError: ``SRFM_MEMORY_LIMIT`` is malformed.
    """
    text = os.environ.get(MEMORY_LIMIT_ENV, "").strip()
    if text:
        match = re.fullmatch(r"(\d+(?:\.\d+)?)\s*([KMGT]?)i?B?", text, re.IGNORECASE)
        if match is None:
            raise ResourceError(
                f"{MEMORY_LIMIT_ENV}={text!r} is not a size such as 8G, 500M or 1000000"
            )
        value = float(match.group(1)) * _UNITS[match.group(2).upper()]
        return int(value), f"{MEMORY_LIMIT_ENV}={text}"
    limit: tuple[int, str] | None = None
    try:
        with open("/proc/meminfo", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    limit = (int(line.split()[1]) * 1024, "available memory (MemAvailable)")
                    break
    except (OSError, ValueError, IndexError):
        limit = None
    cg_max = _read_int("/sys/fs/cgroup/memory.max")
    cg_now = _read_int("/sys/fs/cgroup/memory.current")
    if cg_max is not None and cg_now is not None:
        room = max(cg_max - cg_now, 0)
        if limit is None or room < limit[0]:
            limit = (room, "the container's memory limit (cgroup memory.max)")
    return limit


def memory_room() -> tuple[int, str] | None:
    """The memory episodes may use (bytes): :func:`memory_limit` less the room kept for
    the process itself (numba, numpy), and where the limit comes from; None where no
    limit can be read."""
    found = memory_limit()
    if found is None:
        return None
    limit, source = found
    return limit - _BASE_BYTES, source


def format_bytes(n: float) -> str:
    """A size for a message: ``1.23 GB`` from 100 MB on, ``12.3 MB`` below."""
    return f"{n / 1e9:.2f} GB" if n >= 1e8 else f"{n / 1e6:.1f} MB"


def check_episode_memory(
    scenario: Scenario,
    *,
    jobs: int = 1,
    mcap: bool = False,
    rrd: bool = False,
    forces: bool = False,
) -> int:
    """Refuse an episode that cannot fit in memory, before anything is allocated.

    Args:
        scenario: the scenario.
        jobs: episodes run at the same time (benchmark workers).
        mcap, rrd, forces: the logs written for each episode.

    Returns:
        How many of ``jobs`` episodes fit side by side (at least 1; ``jobs`` when no
        limit is known).

    Raises:
        ResourceError: one episode alone needs more than the limit; the message names
            the estimate, the limit and what to shorten.
    """
    need = estimate_episode_memory(scenario, mcap=mcap, rrd=rrd, forces=forces)
    found = memory_room()
    if found is None:
        return jobs
    room, source = found
    if need > room:
        raise ResourceError(
            f"scenario {scenario.name!r} ({scenario.source}): an episode of "
            f"{scenario.n_pedestrians} pedestrians x {scenario.horizon_steps + 1} samples "
            f"needs about {format_bytes(need)} of memory (record, metrics"
            + (", logs" if mcap or rrd else "")
            + f"), more than the {format_bytes(max(room, 0))} of {source}; shorten "
            "simulation.horizon_steps or use fewer pedestrians"
        )
    return max(1, min(jobs, room // max(need, 1)))


def _detection_range(planner: Planner) -> float | None:
    value = getattr(planner, "detection_range_m", None)
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, int | float) or not value >= 0.0:
        raise PlannerError(
            f"planner {planner.name!r}: detection_range_m must be None "
            f"or a number >= 0, got {plain(value)}"
        )
    return float(value)


@attrs.frozen
class _Start:
    """An episode before its first step: the planner reset on the twin simulator."""

    planner: Planner
    name: str  # the planner's name (it names the logs)
    detection: float | None  # the planner's detection range (None: everyone)
    sim: TwinSimulator
    user: bool  # a user's planner: its exceptions are reported as such
    where: str  # " (scenario NAME, seed K)", for messages


def _start(
    scenario: Scenario,
    seed: int,
    planner: Planner | str,
    params: SRFMParams | None,
    *,
    parallel: bool = False,
    cutoff: Cutoff = "auto",
    counterfactual: bool = True,
) -> _Start:
    """Build the planner (by name) or check it, set up the episode and the twin
    simulator (``counterfactual``: stepping the counterfactual crowd), and reset the
    planner: everything :func:`run_episode` does before its first step."""
    if isinstance(planner, str):
        planner = build_planner(planner)
    else:
        check_planner(planner)
    name = path_name(planner.name, "planner name", PlannerError)
    detection = _detection_range(planner)
    setup = episode_setup(scenario, seed)
    check_episode_memory(scenario)
    sim = TwinSimulator(
        setup, params, parallel=parallel, cutoff=cutoff, counterfactual=counterfactual
    )
    user = is_user_code(planner)
    where = f" (scenario {scenario.name}, seed {setup.seed})"
    context = sim.planner_context()
    rng = planner_rng(setup.seed)
    chosen = planner
    if user:
        call_user_code(name, "reset()", lambda: chosen.reset(context, rng), where)
    else:
        planner.reset(context, rng)
    attach = getattr(planner, PRIVILEGED_HOOK, None)
    if callable(attach):  # a reference planner that reads the episode (oracle)
        if user:
            call_user_code(name, f"{PRIVILEGED_HOOK}()", lambda: attach(sim.engine), where)
        else:
            attach(sim.engine)
    return _Start(planner=planner, name=name, detection=detection, sim=sim, user=user, where=where)


def first_command(
    scenario: Scenario, seed: int, planner: Planner | str, params: SRFMParams | None = None
) -> object:
    """The planner's command for the first observation of episode ``seed``, without
    stepping the crowd: what :func:`run_episode` asks first. It runs the planner's own
    kernels (and the observation's) but not the crowd's, so a process can compile a
    planner's kernels while another compiles the crowd step (the benchmark's warm-up,
    :func:`srfm.benchmark._runner._compile_in_parent`). The command is not checked."""
    start = _start(scenario, seed, planner, params)
    return start.planner.act(start.sim.observe(start.detection))


def run_episode(
    scenario: Scenario | str,
    seed: int,
    planner: Planner | str = "straight",
    params: SRFMParams | None = None,
    *,
    parallel: bool = False,
    cutoff: Cutoff = "auto",
) -> EpisodeRecord:
    """Simulate one twin episode and return its record.

    The loop is bounded by the scenario's horizon (at most ``MAX_HORIZON_STEPS``), so
    no run can hang. The same scenario, seed, planner and parameters give a
    bit-identical record in any process and after any other episodes.

    Args:
        scenario: a :class:`Scenario`, a built-in name or a TOML path.
        seed: episode seed (non-negative integer).
        planner: a planner instance, a registry name or ``"module:attribute"`` (see
            :func:`srfm.planners.make_planner`).
        params: SRFM parameters; the ``agrawal2024`` preset when omitted.
        parallel: force kernel choice, see :class:`TwinSimulator`.
        cutoff: interaction cut-off, see :class:`TwinSimulator`.

    Raises:
        PlannerError: the planner lacks the :class:`Planner` protocol (checked before
            the first step), its name cannot name a folder (it names the episode's
            logs and results), or it returned an unusable command.
        UserCodeError: a user's planner raised in its factory, ``reset`` or ``act``;
            one line naming the planner, the method, the step and the exception.

    An external planner's failure (:class:`~srfm.errors.PlannerFailedError`: a crash, a
    timeout, garbage, a bad command) raises nothing: the robot's episode ends there
    with the outcome ``planner_failed`` (the robot stays where it is, as after a
    collision, and both crowds go on to the horizon), and a
    :class:`~srfm.errors.PlannerFailureWarning` carries the one line saying what the
    planner did.
        ResourceError: the episode would not fit in memory
            (:func:`check_episode_memory`).
    """
    if not isinstance(scenario, Scenario):
        scenario = load_scenario(scenario)
    start = _start(scenario, seed, planner, params, parallel=parallel, cutoff=cutoff)
    return _simulate(scenario, start, None)


def run_planners(
    scenario: Scenario | str,
    seed: int,
    planners: Sequence[Planner | str],
    params: SRFMParams | None = None,
    *,
    parallel: bool = False,
    cutoff: Cutoff = "auto",
) -> Iterator[EpisodeRecord]:
    """The episodes of several planners on one scenario and seed, in order: the same
    records as :func:`run_episode` for each, bit for bit, at less cost.

    The counterfactual crowd does not perceive the robot, so it is the same in every
    planner's episode of a scenario, seed and parameter set: it is simulated with the
    first planner's episode only, and the others step the factual crowd alone and take
    the counterfactual crowd (its trajectories, goals and arrivals) from the first.
    The benchmark runs its planners this way (:mod:`srfm.benchmark._runner`).

    Records are yielded one at a time (each as soon as it is simulated), so only one
    is held beside the shared counterfactual crowd; each record has arrays of its own.

    Args:
        scenario, seed, params, parallel, cutoff: as for :func:`run_episode`.
        planners: planner instances or names, as for :func:`run_episode`.

    Raises:
        As :func:`run_episode`, for the planner whose episode raised.
    """
    if not isinstance(scenario, Scenario):
        scenario = load_scenario(scenario)
    twin: _CounterfactualCrowd | None = None
    for planner in planners:
        start = _start(
            scenario,
            seed,
            planner,
            params,
            parallel=parallel,
            cutoff=cutoff,
            counterfactual=twin is None,
        )
        record = _simulate(scenario, start, twin)
        if twin is None:
            twin = _CounterfactualCrowd.of(record)
        yield record


@attrs.frozen(eq=False)
class _CounterfactualCrowd:
    """The counterfactual crowd of one episode (:func:`run_planners`): its record
    arrays and its arrival events."""

    pos: np.ndarray
    vel: np.ndarray
    goal: np.ndarray
    events: tuple[Event, ...]

    @classmethod
    def of(cls, record: EpisodeRecord) -> _CounterfactualCrowd:
        """The counterfactual crowd of a full twin episode's record (copies)."""
        return cls(
            record.counterfactual_pos.copy(),
            record.counterfactual_vel.copy(),
            record.counterfactual_goal.copy(),
            tuple(e for e in record.events if e.twin == "counterfactual"),
        )


def _event_order(event: Event) -> tuple[int, int]:
    """Where an event stands among those of its sample (:meth:`EpisodeEngine.apply_events`):
    factual arrivals, then counterfactual arrivals, then the robot's event."""
    rank = 2 if event.kind != "ped_arrival" else 0 if event.twin == "factual" else 1
    return event.step, rank


def _simulate(
    scenario: Scenario, start: _Start, twin: _CounterfactualCrowd | None
) -> EpisodeRecord:
    """Step the started episode to the horizon and return its record; with ``twin``,
    the simulator steps the factual crowd only and the record's counterfactual crowd
    is ``twin``'s (copied)."""
    planner, name, detection = start.planner, start.name, start.detection
    sim, user, where = start.sim, start.user, start.where
    setup = sim.setup

    T = scenario.horizon_steps
    n = sim.factual.n
    try:
        f_pos = np.empty((T + 1, n, 2))
        f_vel = np.empty((T + 1, n, 2))
        f_goal = np.empty((T + 1, n, 2))
        c_pos = np.empty((T + 1, n, 2))
        # With a shared counterfactual crowd, one scratch array for the kernels to write.
        c_vel = np.empty((T + 1, n, 2)) if twin is None else c_pos
        c_goal = np.empty((T + 1, n, 2)) if twin is None else c_pos
    except MemoryError:
        raise SimulationError(
            f"{scenario.source}: an episode record of {T + 1} samples x {n} pedestrians "
            "does not fit in memory; shorten horizon_steps or use fewer pedestrians"
        ) from None
    pose = np.empty((T + 1, 3))
    rvel = np.empty((T + 1, 2))
    cmd = np.full((T, 2), np.nan)
    active = np.empty(T + 1, dtype=bool)
    events: list[Event] = list(sim.initial_events)

    # The engine's arrays, updated in place for the whole episode: read directly, not
    # through the simulator's properties and a RobotState per sample (the same values;
    # 1-2 µs of every step).
    engine = sim.engine
    factual, counterfactual, robot = engine.factual, engine.counterfactual, engine.robot
    shared = twin is not None

    def sample(k: int) -> None:
        f_pos[k] = factual.pos
        f_vel[k] = factual.vel
        f_goal[k] = factual.goal
        if not shared:
            c_pos[k] = counterfactual.pos
            c_vel[k] = counterfactual.vel
            c_goal[k] = counterfactual.goal
        pose[k] = robot[_POSE]
        rvel[k] = robot[_VELOCITY]
        active[k] = engine.robot_active

    samples = _sk.Samples(f_pos, f_vel, c_pos, c_vel, f_goal, c_goal, pose, rvel, active)
    engine.prepare_rest(samples)
    sample(0)
    k = 0
    while k < T:
        if engine.can_rest:  # the robot at rest: the steps up to the next arrival at once
            events.extend(sim.rest(T, samples))
            k = engine.step_index
            sample(k)
            continue
        if sim.robot_active:
            observation = sim.observe(detection)
            try:
                command = planner.act(observation)
            except PlannerFailedError as failure:  # an external planner: only this episode ends
                warnings.warn(str(failure), PlannerFailureWarning, stacklevel=2)
                sim.end_robot_episode("planner_failed")
                active[k] = False  # it ended at this sample, as after an event
                continue
            except (KeyboardInterrupt, SrfmError):
                raise
            except BaseException as exc:
                if not user:
                    raise
                raise user_code_error(name, "act()", exc, f" at step {k}{where}") from None
            events.extend(sim.step(command))  # validates the command
            cmd[k, 0] = command[0]
            cmd[k, 1] = command[1]
        else:
            events.extend(sim.step())
        k += 1
        sample(k)

    assert sim.outcome is not None
    if twin is not None:  # the arrays above were the kernels' scratch
        c_pos, c_vel, c_goal = twin.pos.copy(), twin.vel.copy(), twin.goal.copy()
        events = sorted([*events, *twin.events], key=_event_order)  # stable
    return EpisodeRecord(
        scenario=scenario.name,
        seed=setup.seed,
        planner=name,
        params=sim.params,
        dt_s=scenario.dt_s,
        horizon_steps=T,
        time_s=np.arange(T + 1, dtype=np.float64) * scenario.dt_s,
        ped_radius=sim.factual.radius.copy(),
        factual_pos=f_pos,
        factual_vel=f_vel,
        counterfactual_pos=c_pos,
        counterfactual_vel=c_vel,
        factual_goal=f_goal,
        counterfactual_goal=c_goal,
        robot_pose=pose,
        robot_vel=rvel,
        robot_cmd=cmd,
        robot_active=active,
        robot_goal=setup.robot_goal.copy(),
        robot_radius=scenario.robot.radius_m,
        robot_goal_radius_m=scenario.robot.goal_radius_m,
        robot_kinematics=scenario.robot.kinematics,
        outcome=sim.outcome,
        end_step=sim.end_step,
        events=tuple(events),
        ped_enter_step=None if setup.ped_enter_step is None else setup.ped_enter_step.copy(),
    )
