"""Twin counterfactual simulation: invariants, events, the robot as a body, determinism."""

from __future__ import annotations

import json
import math
import subprocess
import sys
import tomllib
from pathlib import Path
from typing import Any

import attrs
import numpy as np
import pytest

import srfm
from srfm.models.state import Obstacles
from srfm.planners import Observation, PlannerContext
from srfm.scenarios import BUILTIN_SCENARIOS, episode_setup, load_scenario
from srfm.sim.engine import EpisodeEngine
from srfm.sim.record import Event
from srfm.sim.simulator import TwinSimulator
from tests.conftest import REPO, record_digest, write_scenario

NO_ROBOT = srfm.SRFMParams(a_robot=0.0)


class StandStill:
    """A planner that never moves: the robot stays active until the horizon."""

    name = "stand-still"
    detection_range_m: float | None = None

    def reset(self, context: PlannerContext, rng: np.random.Generator) -> None:
        self.context = context

    def act(self, observation: Observation) -> np.ndarray:
        return np.zeros(2)


def _scenario(
    tmp_path: Path, robot: str, peds: str, extra: str = "", horizon: int = 300
) -> srfm.Scenario:
    body = f"""
schema_version = 1
name = "t"
description = "test"
[simulation]
horizon_steps = {horizon}
[robot]
{robot}
[pedestrians]
noise_m = 0.0
{peds}
{extra}
"""
    return load_scenario(write_scenario(tmp_path / "t.toml", body))


def _unchecked(
    tmp_path: Path, robot: str, peds: str, extra: str = "", horizon: int = 300
) -> srfm.Scenario:
    """:func:`_scenario` of a scene a scenario file may not hold since issue 33 (a goal
    walled off, a robot starting on a pedestrian): the same scenario, its positions and
    obstacles put in after the file's checks."""
    doc = tomllib.loads(f"[robot]\n{robot}\n[pedestrians]\n{peds}\n{extra}\n")
    free = _scenario(
        tmp_path,
        "start = [1.0, 14.0]\ngoal = [14.0, 14.0]",
        "starts = [[14.0, 1.0]]\ngoals = [[13.0, 1.0]]",
        horizon=horizon,
    )

    def points(value: object) -> np.ndarray:
        out = np.array(value, dtype=np.float64)
        out.setflags(write=False)
        return out

    walls = doc.get("obstacles", {})
    return attrs.evolve(
        free,
        robot_start=points(doc["robot"]["start"]),
        robot_goal=points(doc["robot"]["goal"]),
        robot_heading_rad=None,
        ped_starts=points(doc["pedestrians"]["starts"]),
        ped_goals=points(doc["pedestrians"]["goals"]),
        obstacles=Obstacles.create(
            segments=walls.get("walls", ()), circles=walls.get("pillars", ())
        ),
    )


@pytest.mark.parametrize("name", BUILTIN_SCENARIOS)
def test_twins_are_bit_identical_without_robot_force(name: str) -> None:
    record = srfm.run_episode(name, seed=11, params=NO_ROBOT)
    assert np.array_equal(record.factual_pos, record.counterfactual_pos)
    assert np.array_equal(record.factual_vel, record.counterfactual_vel)
    assert np.array_equal(record.factual_goal, record.counterfactual_goal)
    assert np.all(record.twin_separation_m() == 0.0)
    arrivals = {
        twin: [
            (e.step, e.agent) for e in record.events if e.kind == "ped_arrival" and e.twin == twin
        ]
        for twin in ("factual", "counterfactual")
    }
    assert arrivals["factual"] == arrivals["counterfactual"]


@pytest.mark.parametrize("name", BUILTIN_SCENARIOS)
def test_robot_force_makes_the_twins_differ(name: str) -> None:
    record = srfm.run_episode(name, seed=11)
    assert record.twin_separation_m().max() > 0.05
    np.testing.assert_array_equal(record.factual_pos[0], record.counterfactual_pos[0])


def test_record_shapes_and_times() -> None:
    record = srfm.run_episode("crosswalk", seed=0)
    T, n = 750, 10
    assert record.time_s.shape == (T + 1,)
    assert record.time_s[0] == 0.0
    assert record.time_s[-1] == pytest.approx(50.0)
    for arr in (record.factual_pos, record.factual_vel, record.counterfactual_pos):
        assert arr.shape == (T + 1, n, 2)
    assert record.robot_pose.shape == (T + 1, 3)
    assert record.robot_cmd.shape == (T, 2)
    assert record.robot_active.shape == (T + 1,)
    assert record.outcome == "goal_reached"
    end = record.end_step
    assert record.robot_active[:end].all()
    assert not record.robot_active[end:].any()
    assert np.all(np.isfinite(record.robot_cmd[:end]))
    assert np.all(np.isnan(record.robot_cmd[end:]))
    goal_events = [e for e in record.events if e.kind == "robot_goal_reached"]
    assert len(goal_events) == 1
    assert goal_events[0].step == end
    assert math.dist(record.robot_pose[end, :2], record.robot_goal) < 0.5
    assert math.dist(record.robot_pose[end - 1, :2], record.robot_goal) >= 0.5
    steps = [e.step for e in record.events]
    assert steps == sorted(steps)


def test_robot_stays_as_a_body_after_its_episode(tmp_path: Path) -> None:
    # The robot parks at (5.3, 5) within a few steps; a pedestrian walks through that spot.
    s = _scenario(
        tmp_path,
        "start = [5.0, 5.0]\ngoal = [5.6, 5.0]",
        "starts = [[0.5, 5.05]]\ngoals = [[10.0, 5.05]]",
    )
    record = srfm.run_episode(s, 0)
    assert record.outcome == "goal_reached"
    end = record.end_step
    assert end < 40
    parked = record.robot_pose[end:]
    assert np.all(parked == parked[0])
    assert np.all(record.robot_vel[end + 1 :] == 0.0)
    # The counterfactual pedestrian walks straight through; the factual one goes around.
    cf_y = record.counterfactual_pos[:, 0, 1]
    f_y = record.factual_pos[:, 0, 1]
    assert np.max(np.abs(cf_y - 5.05)) < 1e-9
    passing = np.abs(record.factual_pos[:, 0, 0] - parked[0, 0]) < 0.3
    assert passing.any()
    assert np.min(np.abs(f_y[passing] - parked[0, 1])) > 0.5


def test_collision_ends_the_robot_episode(tmp_path: Path) -> None:
    s = _scenario(
        tmp_path,
        "start = [2.0, 5.0]\ngoal = [12.0, 5.0]",
        "starts = [[8.0, 5.0]]\ngoals = [[0.5, 5.0]]",
    )
    record = srfm.run_episode(s, 0, params=NO_ROBOT)
    assert record.outcome == "collision"
    (event,) = [e for e in record.events if e.kind == "robot_collision"]
    assert event.agent == 0
    assert event.step == record.end_step
    k = record.end_step
    d = np.linalg.norm(record.factual_pos[k, 0] - record.robot_pose[k, :2])
    assert d < 0.5
    d_before = np.linalg.norm(record.factual_pos[k - 1, 0] - record.robot_pose[k - 1, :2])
    assert d_before >= 0.5


def test_obstacle_collision_and_pedestrian_wall(tmp_path: Path) -> None:
    s = _unchecked(
        tmp_path,
        "start = [2.0, 2.0]\ngoal = [2.0, 12.0]",
        "starts = [[8.0, 2.0]]\ngoals = [[8.0, 12.0]]",
        "[obstacles]\nwalls = [[0.0, 6.0, 15.0, 6.0]]",
    )
    record = srfm.run_episode(s, 0)
    assert record.outcome == "collision"
    (event,) = [e for e in record.events if e.kind == "robot_collision"]
    assert event.agent == -1
    assert record.robot_pose[record.end_step, 1] > 6.0 - 0.2 - 0.04
    # the pedestrian is held back by the wall in both twins
    for pos in (record.factual_pos, record.counterfactual_pos):
        assert pos[:, 0, 1].max() < 6.0 - 0.1


def test_kernel_types_do_not_depend_on_the_obstacles_arrays(tmp_path: Path) -> None:
    # issue 19: numba compiles a kernel once per argument type and read-only is part of
    # an array's type. Walls only, walls and pillars, and an unpickled scenario (as in a
    # benchmark worker) must all run the same compiled twin step and robot events.
    import pickle

    from srfm.models import _robot_kernels
    from srfm.sim import _kernels as _sim_kernels

    walls = _unchecked(
        tmp_path,
        "start = [2.0, 2.0]\ngoal = [2.0, 12.0]",
        "starts = [[8.0, 2.0]]\ngoals = [[8.0, 12.0]]",
        "[obstacles]\nwalls = [[0.0, 6.0, 15.0, 6.0]]",
    )
    pillars = _scenario(
        tmp_path,
        "start = [2.0, 2.0]\ngoal = [2.0, 12.0]",
        "starts = [[8.0, 2.0]]\ngoals = [[8.0, 12.0]]",
        "[obstacles]\nwalls = [[0.0, 6.0, 1.0, 6.0]]\npillars = [[12.0, 8.0, 0.5]]",
    )
    srfm.run_episode(walls, 0)
    kernels = (_sim_kernels.advance_exact, _robot_kernels.robot_event)
    compiled = [len(k.signatures) for k in kernels]
    srfm.run_episode(pillars, 0)
    srfm.run_episode(pickle.loads(pickle.dumps(walls)), 0)
    assert [len(k.signatures) for k in kernels] == compiled


class Forward(StandStill):
    """Drives straight ahead at top speed, whatever the goal."""

    name = "forward"

    def act(self, observation: Observation) -> np.ndarray:
        return np.array([0.5, 0.0])


def test_out_of_bounds(tmp_path: Path) -> None:
    s = _scenario(
        tmp_path,
        "start = [14.0, 7.0]\ngoal = [2.0, 7.0]\nheading_rad = 0.0",
        "starts = [[2.0, 2.0]]\ngoals = [[3.0, 3.0]]",
    )
    record = srfm.run_episode(s, 0, planner=Forward())
    assert record.outcome == "out_of_bounds"
    assert record.robot_pose[record.end_step, 0] > 15.0
    assert record.robot_pose[record.end_step - 1, 0] <= 15.0


def test_timeout_is_reported_at_the_horizon() -> None:
    record = srfm.run_episode("footpath", 0, planner=StandStill())
    assert record.outcome == "timeout"
    assert record.end_step == 750
    assert record.events[-1].kind == "robot_timeout"
    assert record.robot_active[:750].all()
    assert not record.robot_active[750]


def test_holonomic_robot_reaches_its_goal(tmp_path: Path) -> None:
    s = _scenario(
        tmp_path,
        'start = [2.0, 2.0]\ngoal = [10.0, 9.0]\nkinematics = "holonomic"',
        "starts = [[13.0, 1.0]]\ngoals = [[14.0, 1.0]]",
        horizon=750,
    )
    record = srfm.run_episode(s, 0)
    assert record.outcome == "goal_reached"
    speeds = np.linalg.norm(record.robot_vel, axis=1)
    assert speeds.max() <= 0.5 + 1e-12


def test_step_cap_and_stepping_past_the_end() -> None:
    setup = episode_setup(load_scenario("concert"), 0)
    sim = TwinSimulator(setup)
    with pytest.raises(srfm.PlannerError, match="needs a command"):
        sim.step(None)
    for _ in range(750):
        sim.step(np.zeros(2))
    assert sim.done
    assert sim.outcome == "timeout"
    with pytest.raises(srfm.SimulationError, match="horizon of 750 steps reached"):
        sim.step(np.zeros(2))


@pytest.mark.parametrize("bad", [np.array([np.nan, 0.0]), np.zeros(3), "go", None])
def test_unusable_planner_commands(bad: object) -> None:
    class Bad(StandStill):
        name = "bad"

        def act(self, observation: Observation) -> np.ndarray:
            return bad  # type: ignore[return-value]

    with pytest.raises(srfm.PlannerError):
        srfm.run_episode("footpath", 0, planner=Bad())


def test_observation_holds_factual_pedestrians_in_range() -> None:
    setup = episode_setup(load_scenario("concert"), 0)
    sim = TwinSimulator(setup)
    obs = sim.observe(3.0)
    d = np.linalg.norm(sim.factual.pos - [sim.robot.x, sim.robot.y], axis=1)
    np.testing.assert_array_equal(obs.ped_ids, np.flatnonzero(d <= 3.0))
    np.testing.assert_array_equal(obs.ped_pos, sim.factual.pos[obs.ped_ids])
    assert sim.observe(None).ped_ids.tolist() == list(range(10))
    assert sim.observe(0.0).ped_ids.size == 0
    obs.ped_pos[:] = 0.0  # a planner cannot change the simulation through its view
    assert not np.any(sim.factual.pos == 0.0)


def test_parallel_and_serial_kernels_give_identical_episodes() -> None:
    a = srfm.run_episode("circle", 5, parallel=False)
    b = srfm.run_episode("circle", 5, parallel=True)
    assert record_digest(a) == record_digest(b)


def test_same_seed_same_record_after_other_episodes() -> None:
    first = record_digest(srfm.run_episode("cross_footpath", 4))
    for name in ("random", "circle", "concert"):
        srfm.run_episode(name, 99)
    assert record_digest(srfm.run_episode("cross_footpath", 4)) == first
    assert record_digest(srfm.run_episode("cross_footpath", 5)) != first


def test_same_seed_same_record_in_another_process() -> None:
    here = {name: record_digest(srfm.run_episode(name, 2)) for name in ("crosswalk", "random")}
    code = (
        "import json, srfm\n"
        "from tests.conftest import record_digest\n"
        "names = ('random', 'crosswalk')\n"
        "print(json.dumps({n: record_digest(srfm.run_episode(n, 2)) for n in names}))\n"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], cwd=REPO, capture_output=True, text=True, check=True
    )
    assert json.loads(out.stdout.strip().splitlines()[-1]) == here


def test_planner_gets_context_and_its_own_rng() -> None:
    seen = []

    class Spy(StandStill):
        name = "spy"

        def reset(self, context: PlannerContext, rng: np.random.Generator) -> None:
            seen.append((context.scenario, context.seed, context.robot_goal.tolist(), rng.random()))

    srfm.run_episode("concert", 3, planner=Spy())
    srfm.run_episode("concert", 3, planner=Spy())
    srfm.run_episode("concert", 4, planner=Spy())
    assert seen[0] == seen[1]
    assert seen[0][:3] == ("concert", 3, [7.0, 13.5])
    assert seen[2][3] != seen[0][3]


def test_a_rejected_command_moves_nothing() -> None:
    sim = TwinSimulator(episode_setup(load_scenario("crosswalk"), 0))
    sim.step(np.array([0.5, 0.0]))
    before = (sim.factual.pos.copy(), sim.counterfactual.pos.copy(), sim.robot, sim.step_index)
    with pytest.raises(srfm.PlannerError, match="finite"):
        sim.step(np.array([np.inf, 0.0]))
    assert np.array_equal(sim.factual.pos, before[0])
    assert np.array_equal(sim.counterfactual.pos, before[1])
    assert (sim.robot, sim.step_index) == before[2:]


@pytest.mark.parametrize(
    ("robot", "outcome"),
    [
        ("start = [3.0, 3.1]\ngoal = [9.0, 9.0]", "collision"),
        ("start = [9.0, 9.0]\ngoal = [9.2, 9.0]", "goal_reached"),
    ],
)
def test_robot_events_at_the_first_sample(tmp_path: Path, robot: str, outcome: str) -> None:
    s = _unchecked(tmp_path, robot, "starts = [[3.0, 3.0]]\ngoals = [[12.0, 3.0]]")
    record = srfm.run_episode(s, 0, planner=Forward())
    assert record.outcome == outcome
    assert record.end_step == 0
    assert record.events[0].step == 0
    assert not record.robot_active.any()
    assert np.all(np.isnan(record.robot_cmd))
    assert np.all(record.robot_pose == record.robot_pose[0])


@pytest.mark.parametrize("bad", [-1.0, float("nan"), "2", True])
def test_detection_range_is_validated(bad: object) -> None:
    planner = StandStill()
    planner.detection_range_m = bad  # type: ignore[assignment]
    with pytest.raises(srfm.PlannerError, match="detection_range_m must be None or a number"):
        srfm.run_episode("footpath", 0, planner=planner)


def test_planner_from_module_and_attribute() -> None:
    record = srfm.run_episode("footpath", 0, planner="tests.sim.test_simulator:StandStill")
    assert record.outcome == "timeout"
    with pytest.raises(srfm.PlannerError, match="cannot import 'no_such_module'"):
        srfm.run_episode("footpath", 0, planner="no_such_module:X")
    with pytest.raises(srfm.PlannerError, match="has no callable 'Nope'"):
        srfm.run_episode("footpath", 0, planner="tests.sim.test_simulator:Nope")
    with pytest.raises(srfm.PlannerError, match="lacks the Planner protocol"):
        srfm.run_episode("footpath", 0, planner="tests.sim.test_simulator:NotAPlanner")


class NotAPlanner:
    pass


@pytest.mark.parametrize("name", ["circle", "random", "concert", "intersection_open"])
def test_robot_at_rest_in_one_kernel_call_gives_the_same_record(
    name: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The steps after the robot's episode ends run in one kernel call up to each
    arrival (EpisodeEngine.rest): the record is the one of a call per step, with
    arrivals (circle), new goals (random) and a robot that stopped early."""
    calls: list[int] = []
    rest = EpisodeEngine.rest

    def counted(self: EpisodeEngine, stop: int, samples: Any) -> list[Event]:
        calls.append(self.step_index)
        return rest(self, stop, samples)

    monkeypatch.setattr(EpisodeEngine, "rest", counted)
    at_rest = srfm.run_episode(name, 3, "dwa")
    monkeypatch.setattr(EpisodeEngine, "can_rest", property(lambda self: False))
    per_step = srfm.run_episode(name, 3, "dwa")
    assert calls
    assert calls[0] == at_rest.end_step
    assert record_digest(at_rest) == record_digest(per_step)


def test_rest_refuses_an_active_robot_and_a_bad_stop() -> None:
    sim = TwinSimulator(episode_setup(load_scenario("crosswalk"), 0))
    samples = None  # not reached: the checks come first
    assert not sim.engine.can_rest
    with pytest.raises(srfm.SimulationError, match="robot at rest"):
        sim.engine.rest(10, samples)  # type: ignore[arg-type]
    sim.engine.robot_active = False
    with pytest.raises(srfm.SimulationError, match="to sample 0 from sample 0"):
        sim.engine.rest(0, samples)  # type: ignore[arg-type]
