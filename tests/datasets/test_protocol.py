"""The NavWareSet robot-force protocol (srfm.fitting._protocol): identifiability on
pedestrians re-simulated around the recorded robots, scene-level hold-out and bootstrap,
the paired test, and bad input."""

from __future__ import annotations

import functools
import math
from pathlib import Path

import attrs
import numpy as np
import pytest

import srfm
from srfm.datasets import Trajectories, navwareset
from srfm.errors import ParameterError
from srfm.fitting import (
    FIT_WINDOWS,
    TABLE2_MODES,
    WindowConfig,
    bootstrap_robot_part,
    build_windows,
    fit_params,
    fit_robot_part,
    heldout_errors,
    heldout_metrics,
    leave_one_scene_out,
    paired_test,
    pass_errors,
    predict,
    replay_encounter,
    scene_groups,
    window_metrics,
)
from srfm.metrics.frechet import frechet_distance
from tests.datasets._synthetic import resimulate_pedestrian, simulate_scene

# A pedestrian part that reaches its goal (short τ) and a robot part that is none of the
# presets, anisotropic.
TRUE = srfm.SRFMParams(
    a_ped=2.0, b_ped=0.5, lambda_ped=0.4, tau=0.8, a_robot=3.0, b_robot=0.6, lambda_robot=0.4
)


@pytest.fixture(scope="module")
def excerpt() -> list[Trajectories]:
    from tests.datasets.conftest import data_dir

    root = data_dir() / "navwareset"
    if not root.is_dir():
        pytest.skip(
            f"NavWareSet excerpt not found at {root}; set SRFM_DATA_DIR to the shared data "
            "folder to run this test"
        )
    return navwareset.read_navwareset(root)


def test_fit_recovers_robot_part_around_recorded_robots(excerpt: list[Trajectories]) -> None:
    # The 12 recorded robot trajectories (scenes 21, 34, 47), each pedestrian replaced by
    # an SRFM pedestrian with known parameters; the protocol's windows; fitted from the
    # paper's robot part with the pedestrian part known.
    # The goal and desired speed of the simulation are given to the windows: the
    # re-simulated pedestrians are deflected and do not all reach their goal within the
    # recording, so the estimated ones would not be the simulation's (a goal-estimation
    # error, not a question of identifiability).
    truth: dict[str, list[object]] = {}
    scenes = [resimulate_pedestrian(s, TRUE, truth) for s in excerpt]
    windows = build_windows(scenes, WindowConfig(stride_s=0.4, min_start_speed_mps=0.3))
    goal = np.array(truth["goal"], dtype=np.float64)[windows.scene]
    v0 = np.array(truth["v0"], dtype=np.float64)[windows.scene]
    windows = attrs.evolve(windows, goal=np.ascontiguousarray(goal), v0=v0, vmax=1.3 * v0)
    assert int(windows.interaction.sum()) >= 50
    start = TRUE.replace(**{f: getattr(srfm.SRFMParams(), f) for f in ("a_robot", "b_robot")})
    start = start.replace(lambda_robot=1.0)
    fitted = fit_robot_part(windows, start, multi_start=False)
    assert fitted.a_robot == pytest.approx(TRUE.a_robot, rel=0.3)
    assert fitted.b_robot == pytest.approx(TRUE.b_robot, rel=0.15)
    assert fitted.lambda_robot == pytest.approx(TRUE.lambda_robot, abs=0.2)
    # The pedestrian part is untouched.
    assert (fitted.a_ped, fitted.tau) == (TRUE.a_ped, TRUE.tau)


def test_resimulated_tracks_follow_the_force(excerpt: list[Trajectories]) -> None:
    # Without the robot force the same re-simulation differs: the recorded robot
    # matters, so the test above can fail.
    scene = excerpt[0]
    with_force = resimulate_pedestrian(scene, TRUE)
    without = resimulate_pedestrian(scene, TRUE.replace(a_robot=0.0))
    assert np.max(np.linalg.norm(with_force.xy - without.xy, axis=1)) > 0.05


@functools.cache
def _scenes() -> tuple[Trajectories, ...]:
    out = []
    for i, seed in enumerate((40, 41, 42)):
        s = simulate_scene(TRUE, seed, name=f"s{seed}", robot=True, n_per_side=2)
        src = {
            **s.source,
            "navwareset_scene": str(i + 1),
            "scenario": "frontal_approach",
            "robot": "hsr" if i else "jackal",
            "compliant": "true" if i == 1 else "false",
        }
        out.append(
            Trajectories.from_samples(
                scene=s.scene,
                agent_ids=s.agent_ids,
                kinds=s.kinds,
                agent=s.agent,
                frame=s.frame,
                t_ns=s.t_ns,
                xy=s.xy,
                source=src,
            )
        )
    return tuple(out)


def test_scene_groups_and_holdout() -> None:
    scenes = _scenes()
    windows = build_windows(scenes, WindowConfig(stride_s=2.4))
    groups = scene_groups(windows, scenes)
    assert groups.keys == ("1", "2", "3")
    assert groups.robot == ("jackal", "hsr", "hsr")
    assert groups.compliant == (False, True, False)
    assert groups.where(lambda s, r, c: r == "hsr") == [1, 2]
    np.testing.assert_array_equal(
        np.sort(groups.windows_of([0, 1, 2])), np.arange(windows.n_windows)
    )
    twice = groups.windows_of([1, 1])
    assert twice.size == 2 * groups.windows_of([1]).size
    base = TRUE.replace(a_robot=1.0, b_robot=1.0, lambda_robot=1.0)
    per_group = leave_one_scene_out(windows, groups, base, n_folds=3, tolerance=1e-4)
    assert len(per_group) == 3
    # Scene g's parameters are those fitted on the other two scenes.
    for g in range(3):
        others = groups.windows_of([h for h in range(3) if h != g])
        alone = fit_robot_part(windows, base, others, tolerance=1e-4)
        assert alone == per_group[g]
    err = heldout_errors(windows, groups, base, per_group)
    assert tuple(err) == TABLE2_MODES
    for ade, fde in err.values():
        assert ade.shape == (windows.n_windows,)
        assert np.all(np.isfinite(ade))
        assert np.all(fde >= 0)
    # The protocol's evaluation with the pass-distance and path-offset errors: the same
    # ADE and FDE, and the pass errors of each window as pass_errors gives them.
    metrics = heldout_metrics(windows, groups, base, per_group)
    assert tuple(metrics) == TABLE2_MODES
    for mode, m in metrics.items():
        np.testing.assert_array_equal(m.ade, err[mode][0])
        np.testing.assert_array_equal(m.fde, err[mode][1])
        assert np.all(np.isfinite(m.pass_distance))
        assert np.all(np.isfinite(m.path_offset))
    for g in range(3):
        sel = groups.windows_of([g])
        params = base.replace(
            **{f: getattr(per_group[g], f) for f in ("a_robot", "b_robot", "lambda_robot")}
        )
        dist, off = pass_errors(windows, sel, predict(windows, params, sel, "srfm"))
        np.testing.assert_array_equal(metrics["srfm"].pass_distance[sel], dist)
        np.testing.assert_array_equal(metrics["srfm"].path_offset[sel], off)
        one = window_metrics(windows, sel, params, "srfm")
        np.testing.assert_array_equal(one.pass_distance, dist)
        np.testing.assert_array_equal(one.ade, metrics["srfm"].ade[sel])
        np.testing.assert_array_equal(one.fde, metrics["srfm"].fde[sel])
    empty = window_metrics(windows, np.zeros(0, dtype=np.int64), base, "sfm")
    assert empty.ade.shape == empty.path_offset.shape == (0,)
    # the robot force moves the pass: its pass-distance errors differ from the SFM's
    assert not np.array_equal(metrics["srfm"].pass_distance, metrics["sfm"].pass_distance)


def test_bootstrap_is_deterministic_and_resamples() -> None:
    scenes = _scenes()
    windows = build_windows(scenes, WindowConfig(stride_s=2.4))
    groups = scene_groups(windows, scenes)
    a = bootstrap_robot_part(windows, groups, TRUE, TRUE, n_boot=2, seed=3, tolerance=1e-3)
    b = bootstrap_robot_part(windows, groups, TRUE, TRUE, n_boot=2, seed=3, tolerance=1e-3)
    np.testing.assert_array_equal(a, b)
    assert a.shape == (2, 3)
    with pytest.raises(ParameterError, match="n_boot"):
        bootstrap_robot_part(windows, groups, TRUE, TRUE, n_boot=0, seed=0)
    with pytest.raises(ParameterError, match="no scenes"):
        bootstrap_robot_part(windows, groups, TRUE, TRUE, n_boot=1, seed=0, among=[])
    with pytest.raises(ParameterError, match="n_folds"):
        leave_one_scene_out(windows, groups, TRUE, n_folds=7)
    with pytest.raises(ParameterError, match="one parameter set per scene"):
        heldout_errors(windows, groups, TRUE, [TRUE])
    with pytest.raises(ParameterError, match="2 scenes given"):
        scene_groups(windows, list(scenes[:2]))


def test_fit_params_bad_fields_and_subset() -> None:
    scenes = _scenes()[:1]
    windows = build_windows(scenes, WindowConfig(stride_s=2.4))
    with pytest.raises(ParameterError, match="cannot fit 'a_obs'"):
        fit_params(windows, stages=["robot"], fields={"robot": ("a_obs",)})
    with pytest.raises(ParameterError, match="unknown fitting stage 'walls'"):
        fit_params(windows, fields={"walls": ("a_robot",)})
    with pytest.raises(ParameterError, match="outside"):
        fit_params(windows, stages=["robot"], subset=np.array([windows.n_windows]))
    with pytest.raises(ParameterError, match="min_start_speed_mps"):
        WindowConfig(min_start_speed_mps=-1.0)


def test_min_start_speed_drops_standing_starts() -> None:
    scenes = _scenes()[:1]
    every = build_windows(scenes, WindowConfig(stride_s=0.4))
    walking = build_windows(scenes, WindowConfig(stride_s=0.4, min_start_speed_mps=0.5))
    speed = np.linalg.norm(every.vel, axis=1)
    assert walking.n_windows == int(np.count_nonzero(speed >= 0.5)) < every.n_windows
    np.testing.assert_array_equal(walking.pos, every.pos[speed >= 0.5])


def test_paired_test() -> None:
    a = np.array([1.0, 2.0, 3.0, 4.0, 5.0, 6.0])
    t = paired_test(a, a - np.array([0.1, 0.2, 0.3, 0.4, 0.5, 0.6]))
    assert t.n == 6
    assert t.median_diff == pytest.approx(-0.35)
    assert t.p == pytest.approx(0.03125)  # exact two-sided, all six differences one way
    assert paired_test(a, a).p == 1.0
    assert math.isnan(paired_test(a[:1], a[:1] + 1).p)
    with pytest.raises(ParameterError, match="differ in size"):
        paired_test(a, a[:3])


def test_real_navwareset_groups(real_data: Path) -> None:
    quant = real_data / "navwareset_quant"
    if not quant.is_dir():
        pytest.skip(f"{quant} not found; set SRFM_DATA_DIR to the shared data folder")
    files = (
        sorted((quant / "21_poses").glob("*.csv"))[:2]
        + sorted((quant / "13_poses").glob("*.csv"))[:1]
    )
    scenes = [navwareset.read_file(f) for f in files]
    windows = build_windows(scenes, FIT_WINDOWS)
    groups = scene_groups(windows, scenes)
    assert groups.keys == ("21", "13")
    assert groups.scenario == ("frontal_approach", "circular_crossing")
    assert groups.robot == ("jackal", "hsr")
    assert groups.compliant == (False, False)
    assert windows.n_windows > 0


def test_replay_encounter_deviation_and_observed_measures() -> None:
    scene = _scenes()[0]
    # the pedestrian that passes closest to the robot
    peds = [a for a, k in zip(scene.agent_ids, scene.kinds, strict=True) if k == "pedestrian"]
    found = [replay_encounter(scene, a, TRUE) for a in peds]
    encounters = [e for e in found if e is not None]
    enc = min(encounters, key=lambda e: e.min_distance_m)
    ped = enc.agent_id
    assert enc.min_distance_m < 3.0
    n = enc.observed.shape[0]
    assert enc.factual.shape == enc.counterfactual.shape == enc.robot.shape == (n, 2)
    # same start, and the deviation is the Fréchet distance of the two simulations
    np.testing.assert_array_equal(enc.factual[0], enc.observed[0])
    assert enc.deviation_m == pytest.approx(frechet_distance(enc.factual, enc.counterfactual))
    # the observed measures, recomputed
    d = np.linalg.norm(enc.observed - enc.robot, axis=1)
    assert enc.min_distance_m == pytest.approx(d.min())
    path = np.sum(np.linalg.norm(np.diff(enc.observed, axis=0), axis=1))
    chord = np.linalg.norm(enc.observed[-1] - enc.observed[0])
    assert enc.detour == pytest.approx(path / chord - 1.0)
    assert 0.0 <= enc.slowdown <= 1.0
    # without the robot force, factual = counterfactual: no deviation
    off = replay_encounter(scene, ped, TRUE.replace(a_robot=0.0))
    assert off is not None
    assert off.deviation_m == 0.0
    np.testing.assert_array_equal(off.counterfactual, enc.counterfactual)
    with pytest.raises(ParameterError, match="not a pedestrian"):
        replay_encounter(scene, "robot", TRUE)
    with pytest.raises(ParameterError, match="no robot"):
        replay_encounter(simulate_scene(TRUE, 1, name="x", n_per_side=1), "p0", TRUE)
