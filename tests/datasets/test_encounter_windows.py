"""Windows aligned to encounters with the robot (WindowConfig(align="encounter")), the
goal that uses nothing after the window start (goal="heading"), and the pass-distance
and path-offset errors (issue 28, docs/real_encounters.md)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import srfm
from srfm.datasets import PEDESTRIAN, ROBOT, Trajectories, navwareset
from srfm.errors import ParameterError
from srfm.fitting import (
    WindowConfig,
    build_windows,
    fit_robot_part,
    pass_errors,
    predict,
)
from tests.datasets._synthetic import resimulate_pedestrian

DT = 0.1  # 10 Hz, as NavWareSet
T_PASS = 6.0  # the walker passes the robot at this time (s)


def _walker(n: int = 120, swerve_after: float | None = None) -> np.ndarray:
    """(n, 2) a pedestrian walking along +x at 1 m/s from x = 0 (10 Hz); after
    ``swerve_after`` seconds it drifts to +y at 0.5 m/s."""
    t = np.arange(n) * DT
    xy = np.stack([t, np.zeros(n)], axis=1)
    if swerve_after is not None:
        xy[:, 1] = np.where(t > swerve_after, 0.5 * (t - swerve_after), 0.0)
    return xy


def _scene(
    walker: np.ndarray, robot_xy: tuple[float, float] | None, name: str = "s"
) -> Trajectories:
    """One pedestrian and (optionally) a robot standing at ``robot_xy``."""
    n = walker.shape[0]
    frames = np.arange(n, dtype=np.int64)
    t_ns = np.rint(frames * DT * 1e9).astype(np.int64)
    if robot_xy is None:
        return Trajectories.from_samples(
            scene=name,
            agent_ids=["p"],
            kinds=[PEDESTRIAN],
            agent=np.zeros(n, dtype=np.int64),
            frame=frames,
            t_ns=t_ns,
            xy=walker,
        )
    robot = np.tile(np.asarray(robot_xy, dtype=np.float64), (n, 1))
    return Trajectories.from_samples(
        scene=name,
        agent_ids=["p", "robot"],
        kinds=[PEDESTRIAN, ROBOT],
        agent=np.tile(np.array([0, 1], dtype=np.int64), n),
        frame=np.repeat(frames, 2),
        t_ns=np.repeat(t_ns, 2),
        xy=np.stack([walker, robot], axis=1).reshape(-1, 2),
    )


@pytest.mark.parametrize("lead", [2.0, 3.0, 4.0])
def test_encounter_window_starts_lead_before_the_pass(lead: float) -> None:
    # The robot stands 0.8 m beside the walker's line at x = 6 m: the closest approach
    # is at t = 6 s (sample 60). One window, starting lead_s before it.
    scene = _scene(_walker(), (T_PASS, 0.8))
    config = WindowConfig(align="encounter", lead_s=lead)
    windows = build_windows([scene], config)
    assert windows.n_windows == 1
    k0 = round((T_PASS - lead) / DT)
    assert int(windows.frame0[0]) == k0
    np.testing.assert_allclose(windows.pos[0], [k0 * DT, 0.0], atol=1e-12)
    np.testing.assert_allclose(windows.vel[0], [1.0, 0.0], atol=1e-9)
    assert int(windows.steps[0]) == round(4.8 / DT)
    # the pass is inside the window, lead_s after its start
    rows = windows.rows(np.array([0]))
    d = np.linalg.norm(windows.observed[rows] - [T_PASS, 0.8], axis=1)
    assert windows.step_time[rows][int(np.argmin(d))] == pytest.approx(lead)
    assert windows.min_robot_distance[0] == pytest.approx(0.8)
    assert bool(windows.interaction[0])
    # the default windows of the same track are many, every stride
    assert build_windows([scene]).n_windows > 1


def test_encounter_windows_need_a_close_pass_with_room_around_it() -> None:
    far = _scene(_walker(), (T_PASS, 3.5))  # closest approach 3.5 m > 3 m
    assert build_windows([far], WindowConfig(align="encounter")).n_windows == 0
    early = _scene(_walker(), (2.0, 0.8))  # pass at 2 s: no room for a 3 s lead
    assert build_windows([early], WindowConfig(align="encounter")).n_windows == 0
    late = _scene(_walker(), (11.0, 0.8))  # pass at 11 s: the horizon runs past the track
    assert build_windows([late], WindowConfig(align="encounter")).n_windows == 0
    no_robot = _scene(_walker(), None)
    assert build_windows([no_robot], WindowConfig(align="encounter")).n_windows == 0
    # a start slower than min_start_speed_mps is left out, as with stride windows
    slow = WindowConfig(align="encounter", min_start_speed_mps=1.5)
    assert build_windows([_scene(_walker(), (T_PASS, 0.8))], slow).n_windows == 0


def test_window_options_are_checked() -> None:
    with pytest.raises(ParameterError, match="lead_s"):
        WindowConfig(align="encounter", lead_s=4.8)
    with pytest.raises(ParameterError, match="align must be one of stride, encounter"):
        WindowConfig(align="pass")
    with pytest.raises(ParameterError, match="goal must be one of track_end, heading"):
        WindowConfig(goal="end")
    with pytest.raises(ParameterError, match="goal_distance_m"):
        WindowConfig(goal="heading", goal_distance_m=0.0)
    # a lead as long as the horizon is fine for stride windows, which do not use it
    assert WindowConfig(lead_s=4.8).align == "stride"


def test_heading_goal_ignores_the_motion_after_the_window_start() -> None:
    # Two tracks identical up to t = 6.5 s (after the window start at 3 s or 2.8 s and
    # after the pass at 6 s), then one swerves: the heading goal of the window is the
    # same for both, the track-end goal is not.
    straight = _scene(_walker(), (T_PASS, 0.8), name="straight")
    swerving = _scene(_walker(swerve_after=6.5), (T_PASS, 0.8), name="swerving")
    for align, k0 in (("encounter", 30), ("stride", 28)):
        heading = WindowConfig(align=align, lead_s=3.0, goal="heading", goal_distance_m=7.0)
        goals = []
        for scene in (straight, swerving):
            windows = build_windows([scene], heading)
            at = np.flatnonzero(windows.frame0 == k0)
            assert at.size == 1
            goals.append(windows.goal[at[0]])
        np.testing.assert_array_equal(goals[0], goals[1])
        # straight ahead along the initial velocity, goal_distance_m away
        np.testing.assert_allclose(goals[0], [k0 * DT + 7.0, 0.0], atol=1e-9)
        end = WindowConfig(align=align, lead_s=3.0)
        ends = [build_windows([scene], end) for scene in (straight, swerving)]
        assert not np.array_equal(
            ends[0].goal[ends[0].frame0 == k0], ends[1].goal[ends[1].frame0 == k0]
        )
    # a pedestrian standing at the window start: the goal is where it stands
    standing = np.zeros((120, 2))
    standing[60:, 0] = np.arange(60) * DT
    windows = build_windows(
        [_scene(standing, (3.0, 0.8))], WindowConfig(goal="heading", stride_s=4.0)
    )
    still = np.flatnonzero(np.all(windows.vel == 0.0, axis=1))
    assert still.size > 0
    np.testing.assert_array_equal(windows.goal[still], windows.pos[still])


def test_pass_errors() -> None:
    scene = _scene(_walker(), (T_PASS, 0.8))
    windows = build_windows([scene], WindowConfig(align="encounter", lead_s=3.0))
    sel = np.array([0], dtype=np.int64)
    observed = windows.observed[windows.rows(sel)]
    dist, off = pass_errors(windows, sel, observed)
    assert dist[0] == 0.0
    assert off[0] == 0.0
    # predicted 0.2 m further to the left (+y, towards the robot at y = 0.8)
    shifted = observed + np.array([0.0, 0.2])
    dist, off = pass_errors(windows, sel, shifted)
    assert dist[0] == pytest.approx(-0.2)
    assert off[0] == pytest.approx(0.2)
    # a prediction that stops at the window start: its pass is its closest sample to the
    # robot (the last predicted one is the start itself, 3 m before x = 6)
    stopped = np.tile(windows.pos[0], (observed.shape[0], 1))
    dist, off = pass_errors(windows, sel, stopped)
    assert dist[0] == pytest.approx(math.hypot(3.0, 0.8) - 0.8)
    assert off[0] == pytest.approx(0.0)
    # without a robot: NaN
    alone = build_windows([_scene(_walker(), None)], WindowConfig(stride_s=4.0))
    sel = np.arange(alone.n_windows, dtype=np.int64)
    dist, off = pass_errors(alone, sel, alone.observed[alone.rows(sel)])
    assert np.all(np.isnan(dist))
    assert np.all(np.isnan(off))


# The recovery test of docs/fitting.md (tests/datasets/test_protocol.py): pedestrians
# re-simulated with a known robot response around the 12 recorded robot trajectories of
# the excerpt. There the windows had to be given the simulation's goals; encounter
# windows with the heading goal recover the response from the data alone.
TRUE = srfm.SRFMParams(
    a_ped=2.0, b_ped=0.5, lambda_ped=0.4, tau=0.8, a_robot=3.0, b_robot=0.6, lambda_robot=0.4
)


def test_encounter_windows_recover_the_robot_part_without_the_true_goals() -> None:
    from tests.datasets.conftest import data_dir

    root = data_dir() / "navwareset"
    if not root.is_dir():
        pytest.skip(
            f"NavWareSet excerpt not found at {root}; set SRFM_DATA_DIR to the shared data "
            "folder to run this test"
        )
    scenes = [resimulate_pedestrian(s, TRUE) for s in navwareset.read_navwareset(root)]
    start = TRUE.replace(a_robot=srfm.SRFMParams().a_robot, b_robot=srfm.SRFMParams().b_robot)
    start = start.replace(lambda_robot=1.0)
    config = WindowConfig(align="encounter", lead_s=3.0, goal="heading", min_start_speed_mps=0.3)
    windows = build_windows(scenes, config)
    assert int(windows.interaction.sum()) == windows.n_windows >= 8
    fitted = fit_robot_part(windows, start, multi_start=False)
    assert fitted.a_robot == pytest.approx(TRUE.a_robot, rel=0.3)
    assert fitted.b_robot == pytest.approx(TRUE.b_robot, rel=0.15)
    assert fitted.lambda_robot == pytest.approx(TRUE.lambda_robot, abs=0.2)
    sel = np.arange(windows.n_windows, dtype=np.int64)
    dist, off = pass_errors(windows, sel, predict(windows, fitted, sel, "srfm"))
    assert np.nanmean(np.abs(dist)) < 0.15
    assert np.nanmean(np.abs(off)) < 0.15
    # The same windows with the estimated track-end goal: the end of a deflected track
    # carries the avoidance, and the fit trades the force for it.
    leaky = build_windows(
        scenes, WindowConfig(align="encounter", lead_s=3.0, min_start_speed_mps=0.3)
    )
    trade = fit_robot_part(leaky, start, multi_start=False)
    assert abs(trade.b_robot / TRUE.b_robot - 1.0) > 0.15
