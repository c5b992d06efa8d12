"""Run one twin episode with a planner and collect its :class:`EpisodeRecord`."""

from __future__ import annotations

import numpy as np

from srfm.errors import PlannerError, SimulationError
from srfm.models.params import SRFMParams
from srfm.planners import Planner, make_planner
from srfm.scenarios import Scenario, episode_setup, load_scenario
from srfm.sim.record import EpisodeRecord, Event
from srfm.sim.simulator import TwinSimulator

__all__ = ["PLANNER_STREAM", "planner_rng", "run_episode"]

# The planner's random stream is SeedSequence(seed, spawn_key=(PLANNER_STREAM,)); the
# scenario's set-up uses default_rng(seed) and re-goaling stream 2.
PLANNER_STREAM = 1


def planner_rng(seed: int) -> np.random.Generator:
    """The planner's own generator for episode ``seed``."""
    return np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(PLANNER_STREAM,)))


def _detection_range(planner: Planner) -> float | None:
    value = getattr(planner, "detection_range_m", None)
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, int | float) or not value >= 0.0:
        raise PlannerError(
            f"planner {getattr(planner, 'name', planner)!r}: detection_range_m must be None "
            f"or a number >= 0, got {value!r}"
        )
    return float(value)


def run_episode(
    scenario: Scenario | str,
    seed: int,
    planner: Planner | str = "straight",
    params: SRFMParams | None = None,
    *,
    parallel: bool | None = None,
) -> EpisodeRecord:
    """Simulate one twin episode and return its record.

    The loop is bounded by the scenario's horizon (at most ``MAX_HORIZON_STEPS``), so
    no run can hang. The same scenario, seed, planner and parameters give a
    bit-identical record in any process and after any other episodes.

    Args:
        scenario: a :class:`Scenario`, a built-in name or a TOML path.
        seed: episode seed (non-negative integer).
        planner: a planner instance or a registry name.
        params: SRFM parameters; the ``agrawal2024`` preset when omitted.
        parallel: force kernel choice, see :class:`TwinSimulator`.
    """
    if not isinstance(scenario, Scenario):
        scenario = load_scenario(scenario)
    if isinstance(planner, str):
        planner = make_planner(planner)
    detection = _detection_range(planner)
    setup = episode_setup(scenario, seed)
    sim = TwinSimulator(setup, params, parallel=parallel)
    planner.reset(sim.planner_context(), planner_rng(setup.seed))

    T = scenario.horizon_steps
    n = sim.factual.n
    try:
        f_pos = np.empty((T + 1, n, 2))
        f_vel = np.empty((T + 1, n, 2))
        c_pos = np.empty((T + 1, n, 2))
        c_vel = np.empty((T + 1, n, 2))
        f_goal = np.empty((T + 1, n, 2))
        c_goal = np.empty((T + 1, n, 2))
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

    def sample(k: int) -> None:
        f_pos[k] = sim.factual.pos
        f_vel[k] = sim.factual.vel
        c_pos[k] = sim.counterfactual.pos
        c_vel[k] = sim.counterfactual.vel
        f_goal[k] = sim.factual.goal
        c_goal[k] = sim.counterfactual.goal
        r = sim.robot
        pose[k, 0] = r.x
        pose[k, 1] = r.y
        pose[k, 2] = r.theta
        rvel[k, 0] = r.vx
        rvel[k, 1] = r.vy
        active[k] = sim.robot_active

    sample(0)
    for k in range(T):
        if sim.robot_active:
            command = planner.act(sim.observe(detection))
            events.extend(sim.step(command))  # validates the command
            cmd[k, 0] = command[0]
            cmd[k, 1] = command[1]
        else:
            events.extend(sim.step())
        sample(k + 1)

    assert sim.outcome is not None
    return EpisodeRecord(
        scenario=scenario.name,
        seed=setup.seed,
        planner=planner.name,
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
        robot_kinematics=scenario.robot.kinematics,
        outcome=sim.outcome,
        end_step=sim.end_step,
        events=tuple(events),
    )
