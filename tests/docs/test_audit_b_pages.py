"""The figures of ``tools/results/audit_b_pages.py`` (issue 42): each block renders from
what it comes from, is registered and on a page, and changes when its data change."""

from __future__ import annotations

from pathlib import Path

import attrs
import pytest

from srfm.models.params import SRFMParams
from srfm.sim import budget, episode
from tools.results import audit_b_pages
from tools.results.generate import BLOCKS

ROOT = Path(__file__).resolve().parents[2]


def test_every_block_is_registered_and_on_a_page() -> None:
    pages = "".join(p.read_text(encoding="utf-8") for p in (ROOT / "docs").rglob("*.md"))
    pages += (ROOT / "README.md").read_text(encoding="utf-8")
    for name in audit_b_pages.BLOCKS:
        assert BLOCKS[name] is audit_b_pages.BLOCKS[name]
        assert f"<!-- generated: {name} -->" in pages, name


def test_the_formula_shows_the_shipped_coefficients(monkeypatch: pytest.MonkeyPatch) -> None:
    text = audit_b_pages.run_size_formula()
    assert "S · (15 µs + N · (3.3 µs + 5.2 ns · K + 0.4 µs · M))" in text
    assert "N · S · (0.4 µs + 0.5 ns · S)" in text
    monkeypatch.setattr(budget, "_PAIR_SAMPLE_S", 7.1e-9)
    assert "7.1 ns · K" in audit_b_pages.run_size_formula()


def test_the_crowd_estimate_is_the_models(monkeypatch: pytest.MonkeyPatch) -> None:
    crowd = audit_b_pages.crowd_scenario(400)
    assert crowd.n_pedestrians == 400
    text = audit_b_pages.run_size_crowd()
    assert "100,000 pedestrians (750 steps)" in text
    minutes = budget.estimate_episode_time(audit_b_pages.crowd_scenario()) / 60
    assert f"about {minutes:.0f} min" in text
    monkeypatch.setattr(budget, "_SAMPLE_S", 10 * budget._SAMPLE_S)
    monkeypatch.setattr(episode, "_PER_PED_SAMPLE", {k: 0 for k in episode._PER_PED_SAMPLE})
    assert audit_b_pages.run_size_crowd() != text


def test_the_preset_sentence_reads_the_preset(monkeypatch: pytest.MonkeyPatch) -> None:
    p = SRFMParams.preset("navwareset2025")
    text = audit_b_pages.robustness_fitted_preset()
    assert f"A_r = {p.a_robot:.2f} m/s²" in text
    assert f"B_r = {p.b_robot:.2f} m" in text
    changed = attrs.evolve(p, a_robot=1.234)
    monkeypatch.setattr(SRFMParams, "preset", staticmethod(lambda name: changed))
    assert "A_r = 1.23 m/s²" in audit_b_pages.robustness_fitted_preset()
