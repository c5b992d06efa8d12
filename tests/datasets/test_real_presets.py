"""The real-data presets (srfm/models/presets/*.toml): their [meta] states where their
numbers come from, and the numbers it records are recomputed here from the shipped
parameters on the NavWareSet selection (issue 28, docs/real_encounters.md, part 4)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import srfm
from srfm.datasets.navwareset import drop_supersets, read_navwareset
from srfm.fitting import EVAL_WINDOWS, WindowConfig, build_windows, window_errors
from srfm.models.params import _packaged_presets, preset_meta

REAL = sorted(_packaged_presets())
PROVENANCE = (
    "created_by",
    "data",
    "pedestrian_part",
    "robot_form",
    "robot_part",
    "docs",
    "reproduce",
    "heldout_ade_change_vs_robot_ignored",
    "heldout_ade_p_holm",
)


def test_every_real_data_preset_states_its_provenance() -> None:
    assert "navwareset2025" in REAL
    for name in REAL:
        meta = preset_meta(name)
        missing = [key for key in PROVENANCE if key not in meta]
        assert not missing, f"{name}: [meta] lacks {missing}"
        assert meta["name"] == name
        params = srfm.SRFMParams.preset(name)
        assert params.robot_form == meta["robot_form"]
        assert f"--robot-force {meta['robot_form']}" in meta["reproduce"]
    assert preset_meta("agrawal2024") == {}
    # issue 40: the time-to-collision preset's robot part is not fitted and says so
    ttc = preset_meta("navwareset2026_ttc")["robot_part"]
    assert ttc.startswith("not fitted: the time-to-collision force at default parameters")
    assert "chosen by a held-out test" in ttc
    with pytest.raises(srfm.ParameterError, match="unknown parameter preset 'nope'"):
        preset_meta("nope")


@pytest.mark.parametrize("name", REAL)
def test_real_data_preset_numbers_recompute(real_data: Path, name: str) -> None:
    """The ADEs in [meta] are those of the shipped parameters, and the pedestrian part
    predicts NavWareSet's non-interaction windows no worse than agrawal2024's."""
    quant = real_data / "navwareset_quant"
    if not quant.is_dir():
        pytest.skip(f"{quant} not found; set SRFM_DATA_DIR to the shared data folder")
    meta = preset_meta(name)
    params = srfm.SRFMParams.preset(name)
    scenes, _ = drop_supersets(read_navwareset(quant))
    ev = build_windows(scenes, EVAL_WINDOWS)
    non = ev.select(False)
    assert non.size == meta["check_nonint_windows"]
    ade = float(window_errors(ev, non, params, "sfm")[0].mean())
    agrawal = float(window_errors(ev, non, srfm.SRFMParams.preset("agrawal2024"), "sfm")[0].mean())
    assert ade == pytest.approx(meta["check_nonint_ade_m"], rel=1e-9)
    assert agrawal == pytest.approx(meta["check_agrawal2024_nonint_ade_m"], rel=1e-9)
    assert ade <= agrawal  # never worse than the default on the people with no robot near
    config = WindowConfig(
        align="encounter",
        lead_s=meta["check_encounter_lead_s"],
        goal=meta["check_encounter_goal"],
        min_start_speed_mps=0.3,
    )
    enc = build_windows(scenes, config)
    every = np.arange(enc.n_windows, dtype=np.int64)
    assert enc.n_windows == meta["check_encounter_windows"]
    got = float(window_errors(enc, every, params, "srfm")[0].mean())
    ignored = float(window_errors(enc, every, params, "sfm")[0].mean())
    assert got == pytest.approx(meta["check_encounter_ade_m"], rel=1e-9)
    assert ignored == pytest.approx(meta["check_encounter_robot_ignored_ade_m"], rel=1e-9)
