"""Replay kernel, windows, parameter learning (identifiability) and ADE evaluation."""

from __future__ import annotations

import math
from pathlib import Path

import attrs
import numpy as np
import pytest

import srfm
from srfm.datasets import PEDESTRIAN, ROBOT, Trajectories, navwareset
from srfm.errors import DatasetError
from srfm.fitting import (
    WindowConfig,
    build_windows,
    evaluate_ade,
    fit_params,
    predict,
    window_errors,
)
from tests.datasets._synthetic import simulate_scene

# The parameters the synthetic pedestrians walk with (none of them a preset value).
TRUE = srfm.SRFMParams(a_ped=2.0, b_ped=0.5, lambda_ped=0.4, tau=0.6, a_robot=6.0, b_robot=0.8)


@pytest.fixture(scope="module")
def clean_scenes() -> tuple[list[Trajectories], list[dict[str, np.ndarray]]]:
    truths: list[dict[str, np.ndarray]] = [{} for _ in range(6)]
    scenes = [simulate_scene(TRUE, s, name=f"peds{s}", truth=truths[s]) for s in range(3)] + [
        simulate_scene(TRUE, 10 + s, name=f"robot{s}", robot=True, truth=truths[3 + s])
        for s in range(3)
    ]
    return scenes, truths


def _reference_replay(
    scene: Trajectories,
    ped: str,
    k0: int,
    steps: int,
    goal: np.ndarray,
    v0: float,
    vel0: np.ndarray,
    params: srfm.SRFMParams,
    robot_on: bool,
    max_substep: float = 1 / 15,
) -> np.ndarray:
    """The replay through the public API: step_crowd on [pedestrian, neighbours...]."""
    frames, times = scene.frames()
    ped_idx = scene.agent_ids.index(ped)
    pos = scene.track(ped)[2][np.searchsorted(scene.track(ped)[0], frames[k0])].copy()
    vel = vel0.copy()
    out = []
    for k in range(k0, k0 + steps):
        dt = (times[k + 1] - times[k]) * 1e-9
        n_sub = max(1, math.ceil(dt / max_substep - 1e-6))
        here = scene.frame == frames[k]
        there = scene.frame == frames[k + 1]
        for u in range(n_sub):
            alpha = u / n_sub
            others, robot = [], None
            for a in scene.agent[here]:
                p_a = scene.xy[here][scene.agent[here] == a][0]
                nxt = scene.xy[there][scene.agent[there] == a]
                p_b = nxt[0] if nxt.size else p_a
                p = p_a + alpha * (p_b - p_a)
                if scene.kinds[a] == ROBOT:
                    robot = srfm.RobotBody(x=float(p[0]), y=float(p[1]))
                elif a != ped_idx:
                    others.append(p)
            n = 1 + len(others)
            crowd = srfm.CrowdState.create(
                pos=np.vstack([pos, *others]) if others else pos[None],
                goal=np.vstack([goal] * n),
                vel=np.vstack([vel] + [np.zeros(2)] * (n - 1)),
                v0=np.array([v0] * n),
                vmax=np.array([1.3 * v0] * n),
            )
            srfm.step_crowd(crowd, dt / n_sub, params, robot=robot if robot_on else None)
            pos, vel = crowd.pos[0].copy(), crowd.vel[0].copy()
        out.append(pos)
    return np.array(out)


@pytest.mark.parametrize("every", [1, 2])  # 15 Hz (one substep) and 7.5 Hz (two)
def test_replay_kernel_matches_step_crowd(
    clean_scenes: tuple[list[Trajectories], list[dict[str, np.ndarray]]], every: int
) -> None:
    full = clean_scenes[0][3]  # a scene with a robot
    keep = np.isin(full.frame, np.arange(0, 60, every))
    scene = Trajectories.from_samples(
        scene="sub",
        agent_ids=full.agent_ids,
        kinds=full.kinds,
        agent=full.agent[keep],
        frame=full.frame[keep],
        t_ns=full.t_ns[keep],
        xy=full.xy[keep],
    )
    windows = build_windows([scene], WindowConfig(horizon_s=1.6, stride_s=0.8))
    assert windows.n_windows > 5
    params = srfm.SRFMParams.preset("ferrer2013").replace(a_ped=3.0, b_ped=0.6)
    frames = scene.frames()[0]
    for mode in ("sfm", "srfm"):
        pred = predict(windows, params, windows.select(None), mode)  # type: ignore[arg-type]
        rows = 0
        for w in range(windows.n_windows):
            ped = scene.agent_ids[int(windows.agent[w])]
            k0 = int(np.searchsorted(frames, scene.frames()[0][windows.frame0[w]]))
            ref = _reference_replay(
                scene,
                ped,
                k0,
                int(windows.steps[w]),
                windows.goal[w],
                float(windows.v0[w]),
                windows.vel[w],
                params,
                robot_on=mode == "srfm",
            )
            got = pred[rows : rows + windows.steps[w]]
            rows += int(windows.steps[w])
            assert np.abs(got - ref).max() < 1e-9, (mode, w)
    # The robot force changes the prediction near the robot (so the check above bites).
    inter = windows.select(True)
    assert inter.size
    assert not np.allclose(
        predict(windows, params, inter, "srfm"), predict(windows, params, inter, "sfm")
    )


def test_true_parameters_reproduce_noise_free_tracks(
    clean_scenes: tuple[list[Trajectories], list[dict[str, np.ndarray]]],
) -> None:
    scenes, truths = clean_scenes
    cfg = WindowConfig(stride_s=2.4, velocity_span_s=1 / 15)
    for scene, truth in zip(scenes, truths, strict=True):
        w = build_windows([scene], cfg)
        # With the true goals and desired speeds the replay is the simulation itself.
        exact = attrs.evolve(
            w, goal=truth["goal"][w.agent], v0=truth["v0"][w.agent], vmax=1.3 * truth["v0"][w.agent]
        )
        mode = "srfm" if scene.robot_index is not None else "sfm"
        ade, _ = window_errors(exact, exact.select(None), TRUE, mode)
        assert ade.max() < 1e-6, scene.scene
        other, _ = window_errors(exact, exact.select(None), srfm.SRFMParams(), mode)
        assert other.mean() > 0.01


def _rel(got: float, want: float) -> float:
    return abs(got - want) / want


def test_identifiability_noise_free(
    clean_scenes: tuple[list[Trajectories], list[dict[str, np.ndarray]]],
) -> None:
    """Stated tolerance (docs/fitting.md): A, B, τ within 15 %, λ within 0.1."""
    windows = build_windows(clean_scenes[0], WindowConfig(stride_s=1.2, velocity_span_s=1 / 15))
    assert windows.select(True).size > 50
    assert windows.select(False).size > 300
    start = srfm.SRFMParams.preset("ferrer2013")
    result = fit_params(windows, start=start, multi_start=False)
    p = result.params
    assert [s.stage for s in result.stages] == ["pedestrian", "robot"]
    for field in ("a_ped", "b_ped", "tau", "a_robot", "b_robot"):
        assert _rel(getattr(p, field), getattr(TRUE, field)) < 0.15, field
    assert abs(p.lambda_ped - TRUE.lambda_ped) < 0.1
    assert (p.lambda_robot, p.a_obs, p.b_obs) == (1.0, start.a_obs, start.b_obs)
    for stage in result.stages:
        assert stage.ade_m < 0.5 * stage.ade_start_m


def test_identifiability_with_noise() -> None:
    """Tracks at 15 Hz with 2 cm Gaussian position noise, the default protocol.

    Stated tolerance (docs/fitting.md): A and τ within 30 %, B within 10 %, λ within
    0.15. Noisy initial velocities bias A up and τ down (errors in variables); the docs
    tabulate the bias against the noise level.
    """
    scenes = [simulate_scene(TRUE, s, name=f"p{s}", noise_m=0.02) for s in range(20, 23)] + [
        simulate_scene(TRUE, s, name=f"r{s}", robot=True, noise_m=0.02) for s in range(30, 33)
    ]
    windows = build_windows(scenes, WindowConfig(stride_s=1.2))
    p = fit_params(windows, start=srfm.SRFMParams.preset("ferrer2013"), multi_start=False).params
    for field in ("a_ped", "a_robot", "tau"):
        assert _rel(getattr(p, field), getattr(TRUE, field)) < 0.3, field
    for field in ("b_ped", "b_robot"):
        assert _rel(getattr(p, field), getattr(TRUE, field)) < 0.1, field
    assert abs(p.lambda_ped - TRUE.lambda_ped) < 0.15


def test_stage_without_windows_is_skipped(
    clean_scenes: tuple[list[Trajectories], list[dict[str, np.ndarray]]],
) -> None:
    windows = build_windows(clean_scenes[0][:1], WindowConfig(stride_s=4.8))
    assert windows.select(True).size == 0
    result = fit_params(windows, stages=["robot"])
    (stage,) = result.stages
    assert stage.skipped
    assert "no interaction windows" in stage.message
    assert result.params == srfm.SRFMParams()


def test_windows_split_by_distance_to_robot(
    clean_scenes: tuple[list[Trajectories], list[dict[str, np.ndarray]]],
) -> None:
    scene = clean_scenes[0][3]
    w = build_windows([scene], WindowConfig(interaction_radius_m=3.0))
    assert np.all(w.interaction == (w.min_robot_distance <= 3.0))
    assert w.interaction.any()
    assert (~w.interaction).any()
    # Every window has H = 4.8 s * 15 Hz = 72 steps, observed positions are the track's.
    assert set(w.steps.tolist()) == {72}
    ped = scene.agent_ids[int(w.agent[0])]
    track = scene.track(ped)[2]
    k = int(np.flatnonzero((track == w.pos[0]).all(axis=1))[0])
    assert np.array_equal(w.observed[:72], track[k + 1 : k + 73])
    assert np.array_equal(w.goal[0], track[-1])
    no_robot = build_windows(clean_scenes[0][:1])
    assert not no_robot.interaction.any()
    assert np.all(np.isinf(no_robot.min_robot_distance))


def test_robot_frame_scenes_are_refused() -> None:
    scene = Trajectories.from_samples(
        scene="rf",
        agent_ids=["p", "robot"],
        kinds=[PEDESTRIAN, ROBOT],
        agent=[0, 1, 0, 1],
        frame=[0, 0, 1, 1],
        t_ns=[0, 0, 10**8, 10**8],
        xy=np.zeros((4, 2)),
        frame_of_reference="robot",
    )
    with pytest.raises(DatasetError, match="robot's moving frame"):
        build_windows([scene])


def test_ade_rows(clean_scenes: tuple[list[Trajectories], list[dict[str, np.ndarray]]]) -> None:
    windows = build_windows(clean_scenes[0], WindowConfig(stride_s=2.4))
    rows = evaluate_ade(windows, TRUE)
    assert [(r.model, r.tracks) for r in rows] == [
        ("CV", "non-interaction"),
        ("SFM", "non-interaction"),
        ("CV", "interaction"),
        ("SFM, robot ignored", "interaction"),
        ("SFM, robot as pedestrian", "interaction"),
        ("SRFM", "interaction"),
    ]
    assert [r.paper_ade_m for r in rows] == [None, 0.70, None, None, 0.75, 0.59]
    by = {(r.model, r.tracks): r for r in rows}
    # On data simulated with the SRFM, the SRFM beats every other row on its windows.
    srfm_row = by[("SRFM", "interaction")]
    for name in ("CV", "SFM, robot ignored", "SFM, robot as pedestrian"):
        assert srfm_row.ade_m < by[(name, "interaction")].ade_m
    assert by[("SFM", "non-interaction")].ade_m < by[("CV", "non-interaction")].ade_m
    for r in rows:
        assert r.n_windows > 0
        assert 0.0 < r.ade_m < r.fde_m
    # ADE is the mean over windows of each window's mean displacement.
    sel = windows.select(True)
    ade, fde = window_errors(windows, sel, TRUE, "srfm")
    assert srfm_row.ade_m == pytest.approx(ade.mean())
    assert srfm_row.fde_m == pytest.approx(fde.mean())


def test_real_navwareset_robot_stage(real_data: Path) -> None:
    scenes = navwareset.read_navwareset(real_data / "navwareset")
    windows = build_windows(scenes)
    # Every NavWareSet window comes within 3 m of the robot: all are interaction windows.
    assert windows.n_windows > 40
    assert windows.interaction.all()
    assert np.unique(windows.track).size == 12
    assert set(windows.steps.tolist()) == {48}  # 4.8 s at 10 Hz
    result = fit_params(windows, stages=["robot"], multi_start=False, max_nfev=40)
    (stage,) = result.stages
    assert stage.n_windows == windows.n_windows
    # The paper's robot force over-predicts the push on these tracks; fitting reduces it.
    assert stage.ade_m < stage.ade_start_m
    assert result.params.a_robot < srfm.SRFMParams().a_robot
    rows = {(r.model, r.tracks): r for r in evaluate_ade(windows, result.params)}
    assert rows[("SFM", "non-interaction")].n_windows == 0
    assert math.isnan(rows[("SFM", "non-interaction")].ade_m)
    assert rows[("SRFM", "interaction")].ade_m < rows[("CV", "interaction")].ade_m
