"""The robot, social and pedestrian-side metrics against hand-computed cases.

Each case is a small episode record built by hand (a few samples, one or two
pedestrians, dt = 0.5 s or 1 s), whose metric values are worked out on paper in the
comments; the kernels are also checked against their plain-Python versions and the
force exposure against the simulator's own force kernel on a real episode.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

from srfm import CrowdState, RobotBody, SRFMParams, force_components, run_episode
from srfm.errors import MetricError
from srfm.metrics import MetricParams, episode_metrics
from srfm.metrics import _social_kernels as kernels
from srfm.sim.record import EpisodeRecord, Event


def _record(
    ped: list[list[tuple[float, float]]],
    robot: list[tuple[float, float]],
    *,
    dt: float = 1.0,
    counterfactual: list[list[tuple[float, float]]] | None = None,
    goal: tuple[float, float] = (100.0, 0.0),
    ped_goal: list[tuple[float, float]] | None = None,
    end_step: int | None = None,
    outcome: str = "goal_reached",
    events: tuple[Event, ...] = (),
    params: SRFMParams | None = None,
    goal_radius: float = 0.5,
) -> EpisodeRecord:
    """A record from hand-written paths: ``ped[i][k]`` is pedestrian i at sample k."""
    f_pos = np.array(ped, dtype=np.float64).transpose(1, 0, 2).copy()  # (T + 1, N, 2)
    c_pos = (
        f_pos.copy()
        if counterfactual is None
        else np.array(counterfactual, dtype=np.float64).transpose(1, 0, 2).copy()
    )
    samples, n, _ = f_pos.shape
    horizon = samples - 1
    if ped_goal is None:
        goals = np.broadcast_to(f_pos[-1], f_pos.shape).copy()
    else:
        goals = np.broadcast_to(np.array(ped_goal, dtype=np.float64), f_pos.shape).copy()
    pose = np.zeros((samples, 3))
    pose[:, :2] = np.array(robot, dtype=np.float64)
    end = horizon if end_step is None else end_step
    return EpisodeRecord(
        scenario="hand",
        seed=0,
        planner="hand",
        params=params or SRFMParams(),
        dt_s=dt,
        horizon_steps=horizon,
        time_s=np.arange(samples) * dt,
        ped_radius=np.full(n, 0.3),
        factual_pos=f_pos,
        factual_vel=np.zeros_like(f_pos),
        counterfactual_pos=c_pos,
        counterfactual_vel=np.zeros_like(c_pos),
        factual_goal=goals,
        counterfactual_goal=goals.copy(),
        robot_pose=pose,
        robot_vel=np.zeros((samples, 2)),
        robot_cmd=np.zeros((horizon, 2)),
        robot_active=np.arange(samples) <= end,
        robot_goal=np.array(goal, dtype=np.float64),
        robot_radius=0.2,
        robot_kinematics="holonomic",
        outcome=outcome,  # type: ignore[arg-type]
        end_step=end,
        events=events,
        robot_goal_radius_m=goal_radius,
    )


def _far(samples: int) -> list[list[tuple[float, float]]]:
    """One pedestrian standing far from everything."""
    return [[(50.0, 50.0)] * samples]


# Robot side ---------------------------------------------------------------------------


def test_speed_acceleration_jerk_and_duration() -> None:
    # Robot x = 0, 1, 3, 4, 4 (dt = 1): step speeds 1, 2, 1, 0 (min 0, max 2, mean 4/4 = 1);
    # step velocities along x: 1, 2, 1, 0 -> accelerations +1, -1, -1 (all |a| = 1);
    # jerks (-1 - 1) = -2 and (-1 + 1) = 0 -> min 0, mean 1, max 2.
    robot = [(0.0, 0.0), (1.0, 0.0), (3.0, 0.0), (4.0, 0.0), (4.0, 0.0)]
    m = episode_metrics(_record(_far(5), robot, outcome="timeout"))
    assert m["robot_duration_s"] == 4.0
    assert (m["robot_min_speed_mps"], m["robot_max_speed_mps"]) == (0.0, 2.0)
    assert m["robot_mean_speed_mps"] == 1.0
    assert m["robot_min_accel_mps2"] == m["robot_mean_accel_mps2"] == m["robot_max_accel_mps2"]
    assert m["robot_max_accel_mps2"] == 1.0
    assert (m["robot_min_jerk_mps3"], m["robot_mean_jerk_mps3"]) == (0.0, 1.0)
    assert m["robot_max_jerk_mps3"] == 2.0
    # One step below 0.05 m/s (the last): stalled for dt = 1 s.
    assert m["robot_stalled_time_s"] == 1.0


def test_motion_statistics_are_undefined_for_short_episodes() -> None:
    # A collision at sample 1: one step speed, no acceleration, no jerk.
    robot = [(0.0, 0.0), (0.5, 0.0), (0.5, 0.0)]
    m = episode_metrics(_record(_far(3), robot, end_step=1, outcome="collision"))
    assert m["robot_min_speed_mps"] == m["robot_max_speed_mps"] == 0.5
    assert math.isnan(m["robot_mean_accel_mps2"])
    assert math.isnan(m["robot_max_jerk_mps3"])
    assert m["robot_duration_s"] == 1.0
    assert math.isnan(m["robot_time_to_goal_s"])


def test_path_ratio_spl_and_irregularity() -> None:
    # Start (0, 0), goal (4, 0), goal radius 0.5: l = 4 - 0.5 = 3.5. The robot goes
    # (0,0) (2,0) (2,1) (3.6,1): length 2 + 1 + 1.6 = 4.6; turns +90° then -90°:
    # irregularity = pi / 4.6 rad/m; ratio 4.6 / 3.5; SPL 3.5 / 4.6.
    robot = [(0.0, 0.0), (2.0, 0.0), (2.0, 1.0), (3.6, 1.0)]
    m = episode_metrics(_record(_far(4), robot, goal=(4.0, 0.0)))
    assert m["robot_path_length_m"] == pytest.approx(4.6)
    assert m["robot_path_ratio"] == pytest.approx(4.6 / 3.5)
    assert m["robot_spl"] == pytest.approx(3.5 / 4.6)
    assert m["robot_path_irregularity_radpm"] == pytest.approx(math.pi / 4.6)
    failed = episode_metrics(_record(_far(4), robot, goal=(4.0, 0.0), outcome="timeout"))
    assert failed["robot_spl"] == 0.0
    assert math.isnan(failed["robot_path_ratio"])


def test_a_straight_path_has_no_irregularity_and_a_still_robot_none_defined() -> None:
    straight = [(0.0, 0.0), (0.5, 0.5), (1.0, 1.0)]
    assert episode_metrics(_record(_far(3), straight))["robot_path_irregularity_radpm"] == 0.0
    still = [(0.0, 0.0)] * 3
    m = episode_metrics(_record(_far(3), still, outcome="timeout"))
    assert math.isnan(m["robot_path_irregularity_radpm"])
    assert m["robot_stalled_time_s"] == 2.0


def test_failure_to_progress() -> None:
    # dt = 1, window 5 s = 5 samples, at least 0.5 m of progress per window.
    # Goal at (10, 0). Moving 0.2 m per step: 1.0 m per window: progress.
    moving = [(0.2 * k, 0.0) for k in range(8)]
    m = episode_metrics(_record(_far(8), moving, goal=(10.0, 0.0), outcome="timeout"))
    assert m["robot_failure_to_progress"] == 0.0
    # 0.09 m per step: 0.45 m per window < 0.5 m: a failure to progress.
    slow = [(0.09 * k, 0.0) for k in range(8)]
    m = episode_metrics(_record(_far(8), slow, goal=(10.0, 0.0), outcome="timeout"))
    assert m["robot_failure_to_progress"] == 1.0
    # An episode shorter than the window cannot fail the test.
    m = episode_metrics(_record(_far(4), slow[:4], goal=(10.0, 0.0), outcome="timeout"))
    assert m["robot_failure_to_progress"] == 0.0
    # Moving sideways (no progress) in the window fails it.
    sideways = [(0.0, 0.3 * k) for k in range(8)]
    m = episode_metrics(_record(_far(8), sideways, goal=(10.0, 0.0), outcome="timeout"))
    assert m["robot_failure_to_progress"] == 1.0


# Social -------------------------------------------------------------------------------


def test_clearance_personal_space_and_time_in_it() -> None:
    # One pedestrian standing at (2, 0); the robot at x = 0, 0.6, 0.9, 1.0, 1.2 (dt = 0.5).
    # Centre distances 2, 1.4, 1.1, 1.0, 0.8; clearance = d - 0.5: 1.5, 0.9, 0.6, 0.5, 0.3.
    # Below 1.2 m: samples 1-4 (4 of 5); below 0.45 m: sample 4 (1 of 5).
    robot = [(0.0, 0.0), (0.6, 0.0), (0.9, 0.0), (1.0, 0.0), (1.2, 0.0)]
    ped = [[(2.0, 0.0)] * 5]
    m = episode_metrics(_record(ped, robot, dt=0.5, outcome="timeout"))
    assert m["min_robot_clearance_m"] == pytest.approx(0.3)
    assert m["mean_robot_clearance_m"] == pytest.approx((1.5 + 0.9 + 0.6 + 0.5 + 0.3) / 5)
    assert m["personal_space_compliance"] == pytest.approx(1 / 5)
    assert m["intimate_space_compliance"] == pytest.approx(4 / 5)
    assert m["personal_space_time_s"] == 4 * 0.5
    assert m["intimate_space_time_s"] == 1 * 0.5
    # Only the robot's episode counts: ended at sample 2, nobody inside 0.45 m.
    m = episode_metrics(_record(ped, robot, dt=0.5, end_step=2, outcome="collision"))
    assert m["intimate_space_time_s"] == 0.0
    assert m["personal_space_compliance"] == pytest.approx(1 / 3)
    assert m["mean_robot_clearance_m"] == pytest.approx((1.5 + 0.9 + 0.6) / 3)


def test_thresholds_are_parameters() -> None:
    robot = [(0.0, 0.0), (0.6, 0.0), (0.9, 0.0), (1.0, 0.0), (1.2, 0.0)]
    ped = [[(2.0, 0.0)] * 5]
    wide = MetricParams(intimate_m=0.55, personal_m=2.0)
    m = episode_metrics(_record(ped, robot, dt=0.5, outcome="timeout"), wide)
    assert m["intimate_space_time_s"] == 2 * 0.5  # clearances 0.5 and 0.3
    assert m["personal_space_compliance"] == 0.0  # all five within 2 m
    with pytest.raises(MetricError, match=r"intimate_m \(1\.5\) must be smaller than personal_m"):
        MetricParams(intimate_m=1.5)
    with pytest.raises(MetricError, match=r"near_miss_m must be a finite number > 0, got -1\.0"):
        MetricParams(near_miss_m=-1)
    with pytest.raises(MetricError, match="progress_window_s"):
        MetricParams(progress_window_s=True)  # type: ignore[arg-type]


def test_time_to_collision_under_constant_velocity() -> None:
    # The robot stands at the origin. The pedestrian walks along x at -1 m/s (dt = 1):
    # x = 6, 5, 4. At sample 1: gap 5, closing at 1 m/s, collision at centre distance
    # 0.5 -> t = 4.5 s; at sample 2: 3.5 s. At sample 0 its step velocity is 0: none.
    ped = [[(6.0, 0.0), (5.0, 0.0), (4.0, 0.0)]]
    robot = [(0.0, 0.0)] * 3
    m = episode_metrics(_record(ped, robot, outcome="timeout"))
    assert m["min_ttc_s"] == pytest.approx(3.5)
    assert m.pedestrians["min_ttc_s"][0] == pytest.approx(3.5)
    # Offset sideways by 0.3 m: |p + w t| = 0.5 with p = (4, 0.3), w = (-1, 0) at
    # sample 2: (4 - t)^2 + 0.09 = 0.25 -> t = 4 - 0.4 = 3.6 s.
    ped = [[(6.0, 0.3), (5.0, 0.3), (4.0, 0.3)]]
    assert episode_metrics(_record(ped, robot, outcome="timeout"))["min_ttc_s"] == pytest.approx(
        3.6
    )
    # Offset by 1 m: the line misses the disc; walking away: never on a collision course.
    for path in ([(6.0, 1.0), (5.0, 1.0), (4.0, 1.0)], [(4.0, 0.0), (5.0, 0.0), (6.0, 0.0)]):
        m = episode_metrics(_record([path], robot, outcome="timeout"))
        assert math.isnan(m["min_ttc_s"])
        assert math.isnan(m.pedestrians["min_ttc_s"][0])
    # Overlapping: 0.
    m = episode_metrics(_record([[(0.4, 0.0)] * 3], robot, outcome="timeout"))
    assert m["min_ttc_s"] == 0.0


def test_time_to_collision_uses_the_robot_velocity_too() -> None:
    # Pedestrian standing at (4, 0); robot moving towards it at 1 m/s: x = 0, 1 (dt = 1).
    # At sample 1: gap 3, closing at 1 m/s -> 2.5 s.
    m = episode_metrics(_record([[(4.0, 0.0)] * 2], [(0.0, 0.0), (1.0, 0.0)], outcome="timeout"))
    assert m["min_ttc_s"] == pytest.approx(2.5)


def test_near_misses_count_entries_into_the_zone() -> None:
    # Clearance (d - 0.5) to a standing pedestrian at (1, 0) while the robot moves along
    # x: robot x = -2, 0.35, -2, 0.4, 0.4, -2 -> clearances 2.5, 0.15, 2.5, 0.1, 0.1, 2.5.
    # Below 0.2 m: samples 1, 3, 4 -> two entries (1 and 3).
    robot = [(-2.0, 0.0), (0.35, 0.0), (-2.0, 0.0), (0.4, 0.0), (0.4, 0.0), (-2.0, 0.0)]
    m = episode_metrics(_record([[(1.0, 0.0)] * 6], robot, outcome="timeout"))
    assert m["near_misses"] == 2.0
    assert m.pedestrians["near_misses"][0] == 2.0
    # A collision with that pedestrian at sample 4: its last entry ended in the
    # collision, so one near miss.
    hit = Event(step=4, time_s=4.0, kind="robot_collision", agent=0)
    m = episode_metrics(
        _record([[(1.0, 0.0)] * 6], robot, end_step=4, outcome="collision", events=(hit,))
    )
    assert m["near_misses"] == 1.0
    # A larger threshold: 0.3 m changes nothing here, 3 m sees one long entry.
    wide = MetricParams(near_miss_m=3.0, personal_m=4.0)
    assert (
        episode_metrics(_record([[(1.0, 0.0)] * 6], robot, outcome="timeout"), wide)["near_misses"]
        == 1.0
    )


# Pedestrian side ----------------------------------------------------------------------


def test_robot_force_exposure_and_social_work() -> None:
    # A_r = 2, B_r = 1, isotropic. Pedestrian at x = 2, 3, 3 (dt = 1), robot at the
    # origin; r_i + r_r = 0.5. Forces at samples 0 and 1 (the states the two steps start
    # from): 2 e^(0.5 - 2) and 2 e^(0.5 - 3). Social work: f0 * 1 m + f1 * 0 m.
    params = SRFMParams(a_robot=2.0, b_robot=1.0)
    ped = [[(2.0, 0.0), (3.0, 0.0), (3.0, 0.0)]]
    m = episode_metrics(_record(ped, [(0.0, 0.0)] * 3, params=params, outcome="timeout"))
    f0 = 2.0 * math.exp(-1.5)
    f1 = 2.0 * math.exp(-2.5)
    assert m.pedestrians["robot_force_mean_mps2"][0] == pytest.approx((f0 + f1) / 2)
    assert m.pedestrians["robot_force_max_mps2"][0] == pytest.approx(f0)
    assert m.pedestrians["robot_force_p95_mps2"][0] == pytest.approx(f1 + 0.95 * (f0 - f1))
    assert m.pedestrians["social_work_m2ps2"][0] == pytest.approx(f0 * 1.0)
    assert m["social_work_m2ps2"] == pytest.approx(f0)


def test_force_exposure_anisotropy_uses_the_step_heading() -> None:
    # lambda_r = 0: a robot straight behind exerts no force (psi = 0). The pedestrian
    # walks away from the robot along +x: at sample 1 its heading is +x and the robot
    # is behind it. At sample 0 it has no step velocity; its goal (10, 0) gives the same
    # heading: no force either.
    params = SRFMParams(a_robot=2.0, b_robot=1.0, lambda_robot=0.0)
    ped = [[(2.0, 0.0), (3.0, 0.0), (4.0, 0.0)]]
    rec = _record(ped, [(0.0, 0.0)] * 3, params=params, ped_goal=[(10.0, 0.0)], outcome="timeout")
    assert episode_metrics(rec).pedestrians["robot_force_max_mps2"][0] == 0.0
    # Walking towards the robot: psi = 1, the full force.
    ped = [[(4.0, 0.0), (3.0, 0.0), (2.0, 0.0)]]
    rec = _record(ped, [(0.0, 0.0)] * 3, params=params, ped_goal=[(-10.0, 0.0)], outcome="timeout")
    got = episode_metrics(rec).pedestrians["robot_force_max_mps2"][0]
    assert got == pytest.approx(2.0 * math.exp(0.5 - 3.0))


def test_pedestrians_brought_to_a_stop() -> None:
    # dt = 0.25 s, stop below 0.2 m/s for at least 0.5 s = 2 samples. The factual
    # pedestrian walks at 1 m/s, stands for samples 2-4 (3 samples = 0.75 s) while its
    # twin keeps walking, then walks on; it never arrives (no arrival event).
    step = 0.25
    xs = [0.0, 0.25, 0.25, 0.25, 0.25, 0.5, 0.75]
    twin = [0.25 * k for k in range(7)]
    ped = [[(x, 5.0) for x in xs]]
    cf = [[(x, 5.0) for x in twin]]
    m = episode_metrics(_record(ped, [(0.0, 0.0)] * 7, dt=step, counterfactual=cf))
    assert m.pedestrians["stopped_time_s"][0] == 3 * step
    assert m.pedestrians["stopped_by_robot"][0] == 1.0
    assert m["pedestrians_stopped"] == 1.0
    # Standing only 1 sample (0.25 s): not brought to a stop.
    xs = [0.0, 0.25, 0.25, 0.5, 0.75, 1.0, 1.25]
    m = episode_metrics(
        _record([[(x, 5.0) for x in xs]], [(0.0, 0.0)] * 7, dt=step, counterfactual=cf)
    )
    assert m.pedestrians["stopped_time_s"][0] == step
    assert m["pedestrians_stopped"] == 0.0
    # When the twin stands too, it is not the robot's doing.
    m = episode_metrics(_record(ped, [(0.0, 0.0)] * 7, dt=step, counterfactual=ped))
    assert m["pedestrians_stopped"] == 0.0
    # After the pedestrian's first arrival nothing counts (it stands at its goal).
    arrival = Event(step=1, time_s=step, kind="ped_arrival", agent=0, twin="factual")
    xs = [0.0, 0.25, 0.25, 0.25, 0.25, 0.5, 0.75]
    m = episode_metrics(
        _record(ped, [(0.0, 0.0)] * 7, dt=step, counterfactual=cf, events=(arrival,))
    )
    assert m.pedestrians["stopped_time_s"][0] == 0.0


def test_twin_baseline_lengths_times_delay_and_arrivals() -> None:
    # Two pedestrians, dt = 1 s, 5 samples. Pedestrian 0 detours: factual path
    # (0,0) (1,0) (1,1) (2,1) (2,0), length 4; its twin walks (0,0) .. (2,0) and stands,
    # length 2: extra length 2. It arrives at t = 4 s, its twin at t = 2 s: delay 2 s.
    # Pedestrian 1 arrives at t = 3 s while its twin never does (no arrival event):
    # delay undefined. Episode: time to goal mean(4, 3) = 3.5 s, delay mean over those
    # arriving in both twins = 2 s, arrived fraction 2/2. The robot left the world.
    ped = [
        [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (2.0, 1.0), (2.0, 0.0)],
        [(0.0, 9.0), (1.0, 9.0), (2.0, 9.0), (3.0, 9.0), (3.0, 9.0)],
    ]
    cf = [
        [(0.0, 0.0), (1.0, 0.0), (2.0, 0.0), (2.0, 0.0), (2.0, 0.0)],
        [(0.0, 9.0), (0.5, 9.0), (1.0, 9.0), (1.5, 9.0), (2.0, 9.0)],
    ]
    arrivals = (
        Event(step=2, time_s=2.0, kind="ped_arrival", agent=0, twin="counterfactual"),
        Event(step=3, time_s=3.0, kind="ped_arrival", agent=1, twin="factual"),
        Event(step=4, time_s=4.0, kind="ped_arrival", agent=0, twin="factual"),
    )
    robot = [(50.0, 50.0)] * 5
    rec = _record(ped, robot, counterfactual=cf, events=arrivals, outcome="out_of_bounds")
    m = episode_metrics(rec)
    p = m.pedestrians
    np.testing.assert_array_equal(p["path_length_m"], [4.0, 3.0])
    np.testing.assert_array_equal(p["counterfactual_path_length_m"], [2.0, 2.0])
    np.testing.assert_array_equal(p["extra_length_m"], [2.0, 1.0])
    np.testing.assert_array_equal(p["time_to_goal_s"], [4.0, 3.0])
    assert p["counterfactual_time_to_goal_s"][0] == 2.0
    assert math.isnan(p["counterfactual_time_to_goal_s"][1])
    assert p["delay_s"][0] == 2.0
    assert math.isnan(p["delay_s"][1])
    assert m["time_to_goal_s"] == 3.5
    assert m["delay_s"] == 2.0
    assert m["arrived_fraction"] == 1.0
    assert m["extra_length_m"] == 1.5
    assert (m["robot_out_of_bounds"], m["robot_success"], m["robot_timeout"]) == (1.0, 0.0, 0.0)
    assert math.isnan(m["robot_time_to_goal_s"])
    # Nobody arrives in either twin: every time and delay undefined, fraction 0.
    m = episode_metrics(_record(ped, robot, counterfactual=cf, outcome="timeout"))
    assert m["arrived_fraction"] == 0.0
    assert math.isnan(m["time_to_goal_s"])
    assert math.isnan(m["delay_s"])


# Kernels against their Python versions and the simulator ------------------------------


@pytest.fixture(scope="module")
def episode() -> EpisodeRecord:
    return run_episode("crosswalk", 3, planner="dwa")


def _args(record: EpisodeRecord) -> dict[str, Any]:
    return {
        "pos": np.ascontiguousarray(record.factual_pos),
        "radius": record.ped_radius,
        "robot_xy": np.ascontiguousarray(record.robot_pose[:, :2]),
    }


def test_kernels_equal_their_python_versions(episode: EpisodeRecord) -> None:
    a = _args(episode)
    n = episode.n_pedestrians
    end = episode.end_step
    out_jit, out_py = np.empty(n), np.empty(n)
    enter = episode.enter_steps()
    kernels.min_time_to_collision(
        a["pos"], a["radius"], a["robot_xy"], 0.2, end, episode.dt_s, enter, out_jit
    )
    kernels.min_time_to_collision.py_func(
        a["pos"], a["radius"], a["robot_xy"], 0.2, end, episode.dt_s, enter, out_py
    )
    np.testing.assert_array_equal(out_jit, out_py)
    kernels.near_miss_entries(a["pos"], a["radius"], a["robot_xy"], 0.2, end, 1.0, enter, out_jit)
    kernels.near_miss_entries.py_func(
        a["pos"], a["radius"], a["robot_xy"], 0.2, end, 1.0, enter, out_py
    )
    np.testing.assert_array_equal(out_jit, out_py)
    t = episode.horizon_steps
    mag_jit, mag_py = np.empty((t, n)), np.empty((t, n))
    work_jit, work_py = np.empty(n), np.empty(n)
    params = SRFMParams(lambda_robot=0.4).for_kernels()
    moving = np.ascontiguousarray(episode.robot_active)
    args = (a["pos"], episode.factual_goal, a["radius"], a["robot_xy"], 0.2, moving, params)
    kernels.force_exposure(*args, episode.dt_s, enter, mag_jit, work_jit)
    kernels.force_exposure.py_func(*args, episode.dt_s, enter, mag_py, work_py)
    np.testing.assert_array_equal(mag_jit, mag_py)
    np.testing.assert_array_equal(work_jit, work_py)
    until = np.full(n, t + 1, dtype=np.int64)
    c = np.ascontiguousarray(episode.counterfactual_pos)
    kernels.stopped_samples(a["pos"], c, until, episode.dt_s, 0.5, out_jit)
    kernels.stopped_samples.py_func(a["pos"], c, until, episode.dt_s, 0.5, out_py)
    np.testing.assert_array_equal(out_jit, out_py)


def test_force_exposure_is_the_simulators_robot_force(episode: EpisodeRecord) -> None:
    """With the default isotropic robot force the exposure is, bit for bit, the robot
    component the simulator's own kernel computes in the state of each sample."""
    m = episode_metrics(episode)
    n = episode.n_pedestrians
    mags = np.empty((episode.horizon_steps, n))
    for k in range(episode.horizon_steps):
        crowd = CrowdState.create(
            pos=episode.factual_pos[k],
            vel=episode.factual_vel[k],
            goal=episode.factual_goal[k],
            radius=episode.ped_radius,
        )
        x, y = episode.robot_pose[k, :2]
        robot = force_components(crowd, episode.params, RobotBody(x=x, y=y, radius=0.2)).robot
        mags[k] = np.sqrt(robot[:, 0] * robot[:, 0] + robot[:, 1] * robot[:, 1])
    np.testing.assert_array_equal(m.pedestrians["robot_force_max_mps2"], mags.max(axis=0))
    np.testing.assert_array_equal(m.pedestrians["robot_force_mean_mps2"], mags.mean(axis=0))
    steps = np.linalg.norm(np.diff(episode.factual_pos, axis=0), axis=2)
    np.testing.assert_allclose(
        m.pedestrians["social_work_m2ps2"], (mags * steps).sum(axis=0), rtol=1e-12
    )
    assert m["social_work_m2ps2"] > 0.0


def test_no_robot_force_means_no_exposure() -> None:
    m = episode_metrics(run_episode("circle", 4, params=SRFMParams(a_robot=0.0)))
    for name in ("robot_force_mean_mps2", "robot_force_max_mps2", "social_work_m2ps2"):
        assert m[name] == 0.0
    assert m["pedestrians_stopped"] == 0.0  # the twins are identical: nobody stopped by it
