"""Pedestrians entering during the run, end to end (issue 17): the simulator, the
metrics, the logs and the environment."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import srfm
from srfm.errors import LogError
from srfm.logs import load_episode, write_episode_mcap, write_rrd
from srfm.logs._mcap import _enter_steps
from srfm.metrics import episode_metrics
from srfm.scenarios import load_scenario
from srfm.sim.record import EpisodeRecord
from tests.conftest import write_scenario

NO_ROBOT = srfm.SRFMParams(a_robot=0.0)
HEAD = """schema_version = 2
name = "entering"
description = "x"
[simulation]
horizon_steps = 300
[world]
x_max = 16.0
y_max = 10.0
[robot]
start = [1.0, 5.0]
goal = [15.0, 5.0]
"""


def _scenario(tmp_path: Path, peds: str, name: str = "s.toml") -> srfm.Scenario:
    return load_scenario(write_scenario(tmp_path / name, HEAD + peds))


def _run(scenario: srfm.Scenario, planner: str = "dwa", **kw: object) -> EpisodeRecord:
    return srfm.run_episode(scenario, 4, planner, **kw)  # type: ignore[arg-type]


def test_a_pedestrian_not_there_yet_is_neither_felt_nor_seen(tmp_path: Path) -> None:
    """With a second pedestrian entering at 6 s, the first pedestrian and the robot
    (DWA, which sees pedestrians) move exactly as if it did not exist until then, and
    differently after it entered."""
    one = "[pedestrians]\nnoise_m = 0.0\nstarts = [[13.0, 5.2]]\ngoals = [[2.0, 5.2]]\n"
    alone = _run(_scenario(tmp_path, one, "alone.toml"))
    two = _run(
        _scenario(
            tmp_path,
            "[pedestrians]\nnoise_m = 0.0\nstarts = [[13.0, 5.2], [9.0, 4.6]]\n"
            "goals = [[2.0, 5.2], [9.0, 0.5]]\nenter_s = [0.0, 6.0]\n",
            "two.toml",
        )
    )
    e = 90
    assert two.ped_enter_step is not None
    np.testing.assert_array_equal(two.ped_enter_step, [0, e])
    for name in ("factual_pos", "counterfactual_pos", "factual_vel"):
        a = getattr(alone, name)[: e + 1, 0]
        b = getattr(two, name)[: e + 1, 0]
        assert np.array_equal(a, b), name
    assert np.array_equal(alone.robot_pose[: e + 1], two.robot_pose[: e + 1])
    # Before its entry the second one stands at its start with no velocity ...
    np.testing.assert_array_equal(two.factual_pos[: e + 1, 1], np.tile([9.0, 4.6], (e + 1, 1)))
    assert not two.factual_vel[: e + 1, 1].any()
    # ... then walks, and changes what the others do.
    assert np.linalg.norm(two.factual_pos[e + 1, 1] - [9.0, 4.6]) > 0.0
    assert not np.array_equal(alone.factual_pos[:, 0], two.factual_pos[:, 0])


def test_the_robot_crosses_a_start_before_anyone_is_there(tmp_path: Path) -> None:
    """A pedestrian entering at 25 s starts on the straight robot's line, which the robot
    has passed by then: no collision, no contact in the metrics. Present from the start,
    the same (standing) pedestrian is passed within 2 m."""
    peds = "[pedestrians]\nnoise_m = 0.0\nstarts = [[5.0, 5.0]]\ngoals = [[5.0, 5.0]]\n"
    head = HEAD.replace("horizon_steps = 300", "horizon_steps = 600")
    path = write_scenario(tmp_path / "later.toml", head + peds + "enter_s = [15.0]\n")
    later = _run(load_scenario(path), "straight")
    assert later.outcome == "goal_reached"
    m = episode_metrics(later)
    assert later.robot_pose[225, 0] > 8.0  # the robot is past x = 5 when it appears
    assert m.pedestrians["min_robot_distance_m"][0] > 3.0
    assert m.values["min_robot_distance_m"] == m.pedestrians["min_robot_distance_m"][0]
    assert later.min_robot_distance_m() > 3.0
    assert m.values["near_misses"] == 0.0
    # the robot force it felt: from its entry only, when the robot was > 3 m away
    d = float(m.pedestrians["min_robot_distance_m"][0])
    p = later.params
    bound = p.a_robot * math.exp((0.3 + later.robot_radius - d) / p.b_robot)
    assert 0.0 < m.pedestrians["robot_force_max_mps2"][0] <= bound
    now = _run(load_scenario(write_scenario(tmp_path / "now.toml", head + peds)), "straight")
    # pushed aside by the robot force, it is still passed at well under 3 m (1.46 m)
    assert now.min_robot_distance_m() < 2.0


def test_metrics_count_from_the_entry(tmp_path: Path) -> None:
    """Alone in the world and with the robot force off, a pedestrian entering at sample
    e walks the path of one there from the start, e samples later: the same time to goal
    (from its entry), and no separation."""
    peds = "[pedestrians]\nnoise_m = 0.0\nstarts = [[8.0, 9.0]]\ngoals = [[15.0, 9.0]]\n"
    first = _run(_scenario(tmp_path, peds, "first.toml"), "straight", params=NO_ROBOT)
    later = _run(
        _scenario(tmp_path, peds + "enter_s = [4.0]\n", "later.toml"), "straight", params=NO_ROBOT
    )
    e = 60
    assert later.ped_enter_step is not None
    assert later.ped_enter_step[0] == e
    np.testing.assert_array_equal(later.factual_pos[e:, 0], first.factual_pos[: 301 - e, 0])
    a = episode_metrics(first)
    b = episode_metrics(later)
    assert b.values["time_to_goal_s"] == pytest.approx(a.values["time_to_goal_s"], rel=1e-12)
    assert b.values["mean_separation_m"] == 0.0
    assert b.values["arrived_fraction"] == 1.0


def test_the_library_scenario_runs_deterministically() -> None:
    a = srfm.run_episode("corridor_flow", 2, "orca")
    b = srfm.run_episode("corridor_flow", 2, "orca")
    for name, arr in a.arrays().items():
        assert np.array_equal(arr, b.arrays()[name], equal_nan=True), name
    assert a.ped_enter_step is not None
    # at every sample the pedestrians there are the first ones; the others stand still
    present = a.present()
    for k in (0, 100, 400):
        m = int(present[k].sum())
        assert present[k, :m].all()
        assert not present[k, m:].any()
        np.testing.assert_array_equal(a.factual_pos[k, m:], a.factual_pos[0, m:])
    assert present[-1].all()
    # the planner never observes a pedestrian before its entry
    sim = srfm.TwinSimulator(srfm.episode_setup(load_scenario("corridor_flow"), 2))
    seen = []
    for _ in range(200):
        seen.append((sim.step_index, sim.observe(None).ped_ids.size, sim.n_present))
        sim.step((0.0, 0.0))
    assert all(count == there for _, count, there in seen)
    assert seen[0][1] == 0
    assert seen[-1][1] > 0


def test_logs_keep_the_entries(tmp_path: Path) -> None:
    scenario = load_scenario("corridor_flow")
    record = srfm.run_episode(scenario, 1, "straight")
    metrics = episode_metrics(record)
    path = tmp_path / "ep.mcap"
    write_episode_mcap(path, record, scenario=scenario, metrics=metrics, profile="compact")
    logged = load_episode(path)
    assert logged.record.ped_enter_step is not None
    assert record.ped_enter_step is not None
    np.testing.assert_array_equal(logged.record.ped_enter_step, record.ped_enter_step)
    again = episode_metrics(logged.record)
    for name, value in metrics.values.items():
        assert np.float64(again.values[name]).tobytes() == np.float64(value).tobytes(), name
    rrd = tmp_path / "ep.rrd"
    assert write_rrd(rrd, record, scenario=scenario, metrics=metrics, forces=True) > 0


def test_malformed_entry_steps_in_a_log_are_named(tmp_path: Path) -> None:
    p = tmp_path / "x.mcap"
    assert _enter_steps(p, None, 3, 10) is None
    np.testing.assert_array_equal(_enter_steps(p, [0, 2, 2], 3, 10), [0, 2, 2])
    for bad in ([0, 2], [0, 3, 2], [0, 2, 11], [0, 2, 1.5], "x", [0, True, 2]):
        with pytest.raises(LogError, match=r"x\.mcap: pedestrians\.enter_step must be 3"):
            _enter_steps(p, bad, 3, 10)


def test_the_environment_lets_pedestrians_enter() -> None:
    """The gymnasium environment on corridor_flow: nobody at sample 0, the pedestrians
    there are the first ones, the others wait at their starts, at rest (bit-for-bit
    agreement with the simulator: tests/rl/test_equivalence.py)."""
    from srfm.rl import SocialNavEnv

    env = SocialNavEnv(scenario="corridor_flow")
    env.reset(seed=2)
    setup = srfm.episode_setup(env.scenario, 2)
    starts = setup.crowd.pos
    seen = set()
    for _ in range(300):
        m = setup.n_present(env.step_index)
        seen.add(m)
        pos = env.factual_pos
        assert pos.shape == starts.shape
        np.testing.assert_array_equal(pos[m:], starts[m:])
        assert not env.factual_vel[m:].any()
        _, _, terminated, truncated, _ = env.step(np.array([0.2, 0.0], dtype=np.float32))
        assert not terminated
        assert not truncated
    assert 0 in seen
    assert max(seen) > 5
    env.reset(seed=2)  # a second episode starts with nobody there again
    np.testing.assert_array_equal(env.factual_pos, starts)
