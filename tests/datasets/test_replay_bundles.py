"""The replay kernel takes bundles (issue 39, part 5) and predicts byte for byte what its
24-argument form did, on the shared data, in every mode and robot form."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import srfm
from srfm.datasets.navwareset import drop_supersets, read_navwareset
from srfm.fitting import WindowConfig, build_windows, predict
from srfm.fitting._kernels import ReplayBodies, ReplayScenes, ReplayWindows
from srfm.models.params import ROBOT_FORMS
from tests.datasets._replay_reference import replay_windows_24

ENCOUNTERS = WindowConfig(align="encounter", lead_s=3.0, goal="heading", min_start_speed_mps=0.3)


def _old(windows: srfm.fitting.Windows, params: srfm.SRFMParams, use_robot: bool) -> np.ndarray:
    out = np.zeros_like(windows.observed)
    sel = np.arange(windows.n_windows, dtype=np.int64)
    replay_windows_24(
        sel,
        windows.agent,
        windows.frame0,
        windows.steps,
        windows.out_row,
        windows.pos,
        windows.vel,
        windows.goal,
        windows.v0,
        windows.vmax,
        windows.fr_off,
        windows.e_agent,
        windows.e_a,
        windows.e_b,
        windows.rb_on,
        windows.rb_a,
        windows.rb_b,
        windows.dt,
        float(windows.config.ped_radius_m),
        float(windows.config.robot_radius_m),
        float(windows.config.max_substep_s),
        params.for_kernels(),
        use_robot,
        out,
    )
    return out


def test_bundles_hold_the_windows_arrays_themselves() -> None:
    scene = srfm.datasets.Trajectories.from_samples(
        scene="s",
        agent_ids=("p",),
        kinds=(srfm.datasets.PEDESTRIAN,),
        agent=np.zeros(20, dtype=np.int64),
        frame=np.arange(20),
        t_ns=np.arange(20) * 100_000_000,
        xy=np.column_stack([np.linspace(0, 2, 20), np.zeros(20)]),
    )
    w = build_windows([scene], WindowConfig(stride_s=0.4, horizon_s=0.8))
    win, scenes, bodies = w.replay_bundles()
    assert isinstance(win, ReplayWindows)
    assert win.pos is w.pos
    assert win.vmax is w.vmax
    assert isinstance(scenes, ReplayScenes)
    assert scenes.fr_off is w.fr_off
    assert scenes.dt is w.dt
    assert bodies == ReplayBodies(
        w.config.ped_radius_m, w.config.robot_radius_m, w.config.max_substep_s
    )


def test_bundled_kernel_is_byte_identical_on_the_shared_data(real_data: Path) -> None:
    quant = real_data / "navwareset_quant"
    if not quant.is_dir():
        pytest.skip(f"{quant} not found; set SRFM_DATA_DIR to the shared data folder")
    scenes, _ = drop_supersets(read_navwareset(quant))
    windows = build_windows(scenes, ENCOUNTERS)
    sel = np.arange(windows.n_windows, dtype=np.int64)
    base = srfm.SRFMParams.preset("navwareset2026_ttc")
    cases = [(srfm.SRFMParams.preset("agrawal2024"), "srfm"), (base, "sfm")]
    cases += [(base.replace(robot_form=form), "srfm") for form in ROBOT_FORMS]
    for params, mode in cases:
        new = predict(windows, params, sel, mode)  # all windows: rows in window order
        old = _old(windows, params, mode != "sfm")
        assert new.tobytes() == old.tobytes(), (params.robot_form, mode)
