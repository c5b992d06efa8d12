"""The run figures of docs/fitting.md, real_encounters.md, sensitivity.md, model.md and
metrics.md that were typed in prose are written from committed data
(tools/results/audit_a_pages.py): each block renders from its data and follows them."""

from __future__ import annotations

import copy
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from srfm.models.params import SRFMParams
from tools.results import audit_a_pages as aa
from tools.results import generate, sensitivity


def _patched_json(monkeypatch: pytest.MonkeyPatch, rel: str, edit: Any) -> None:
    real = aa._json
    doc = copy.deepcopy(real(rel))
    edit(doc)
    monkeypatch.setattr(aa, "_json", lambda r: doc if r == rel else real(r))


def test_every_block_is_registered_and_on_a_page() -> None:
    pages = "".join(p.read_text(encoding="utf-8") for p in generate.pages())
    for name in aa.BLOCKS:
        assert generate.BLOCKS[name] is aa.BLOCKS[name]
        assert f"<!-- generated: {name} -->" in pages


def test_the_horizon_bullet_follows_the_robot_speeds(monkeypatch: pytest.MonkeyPatch) -> None:
    speed = aa._json(aa.FACTS)["robot_speed_mps"]
    text = aa.fitting_horizon_pass()
    assert f"close about {(1 + speed['hsr']) * 4.8:.0f} m" in text

    def faster(doc: dict[str, Any]) -> None:
        doc["robot_speed_mps"]["jackal"] = 2.0

    _patched_json(monkeypatch, aa.FACTS, faster)
    assert "2.0 m/s for the Jackal" in aa.fitting_horizon_pass()
    assert "and 14 m in 4.8 s" in aa.fitting_horizon_pass().replace("\n  ", " ")


def test_the_track_end_sentence_counts_the_cached_fits(monkeypatch: pytest.MonkeyPatch) -> None:
    rel = aa.CACHE.format(goal="track_end")
    done = len(aa._fits("track_end", "exponential"))
    need = len(aa._fits("heading", "exponential"))
    assert 0 < done < need
    assert f"{done} of the exponential form's {need} fits" in aa.encounters_track_end_cache()

    def one_more(doc: dict[str, Any]) -> None:
        doc["entries"]["track_end/ttc/pooled/all"] = {}

    _patched_json(monkeypatch, rel, one_more)
    text = aa.encounters_track_end_cache().replace("\n", " ")
    assert "1 of the time-to-collision form's" in text

    def complete(doc: dict[str, Any]) -> None:
        for form in aa.DECISIVE_FORMS:
            for key in aa._fits("heading", form):
                doc["entries"][f"track_end/{key}"] = {}

    _patched_json(monkeypatch, rel, complete)
    with pytest.raises(SystemExit, match="complete"):
        aa.encounters_track_end_cache()


def test_the_sensitivity_captions_count_the_episodes(monkeypatch: pytest.MonkeyPatch) -> None:
    e = sensitivity.episodes()
    assert f"{e['seed'].size:,} twin episodes" in aa.sensitivity_design().replace("\n", " ")
    per_a = int(np.sum((e["planner"] == "dwa") & (e["a_robot"] == 0.0)))
    assert f"({per_a:,} episodes per planner and value of A_r" in aa.sensitivity_pooled_n().replace(
        "\n", " "
    )
    # one seed fewer: every count follows
    keep = e["seed"] != e["seed"].max()
    fewer = {k: v[keep] for k, v in e.items()}
    monkeypatch.setattr(sensitivity, "episodes", lambda: fewer)
    design = aa.sensitivity_design().replace("\n", " ")
    assert f"{int(keep.sum()):,} twin episodes" in design
    assert f"seeds {int(e['seed'].min())}–{int(e['seed'].max()) - 1}" in design
    n = int(
        np.sum(keep & (e["planner"] == "dwa") & (e["a_robot"] > 0) & (e["scenario"] == "circle"))
    )
    assert f"({n:,} episodes per planner and scenario)" in aa.sensitivity_success_n().replace(
        "\n", " "
    )


def test_the_preset_table_reads_the_presets(monkeypatch: pytest.MonkeyPatch) -> None:
    text = aa.model_presets()
    for name in aa.PRESETS:
        assert f"| `{name}`" in text
    assert "| `agrawal2024` (default) | 2 | 0.89 | 0.4 | 0.6 | 7.93 | 0.99 | 1 |" in text
    monkeypatch.setitem(aa.PRESETS, "probe", SRFMParams(a_ped=3.25, robot_form="ttc"))
    row = next(line for line in aa.model_presets().splitlines() if "`probe`" in line)
    assert "| 3.25 |" in row
    assert row.endswith("`robot_force_cap` = 20) |")


def test_the_convergence_caption_counts_the_rows(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    assert "3 × 3,500 episodes" in aa.convergence_design()
    lines = aa.CONVERGENCE.read_text(encoding="utf-8").splitlines()
    short = tmp_path / "frechet.csv"
    short.write_text("\n".join(line for line in lines if not line.startswith("concert,")) + "\n")
    monkeypatch.setattr(aa, "CONVERGENCE", short)
    assert "3 × 2,800 episodes" in aa.convergence_design()


def test_the_attribution_caption_follows_its_data(monkeypatch: pytest.MonkeyPatch) -> None:
    assert "× 100 seeds" in aa.attribution_design()

    def fewer(doc: dict[str, Any]) -> None:
        doc["seeds"] = [0, 49]
        doc["planners"] = [p for p in doc["planners"] if p != "vo"]

    _patched_json(monkeypatch, aa.ATTRIBUTION, fewer)
    text = aa.attribution_design().replace("\n", " ")
    assert "× 50 seeds" in text
    assert "eight planners (the six default ones" in text
