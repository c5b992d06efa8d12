"""The figures of ``tools/results/audit_b_pages.py`` (issue 42): each block renders from
what it comes from, is registered and on a page, and changes when its data change."""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any

import attrs
import pytest

from srfm.models.params import SRFMParams
from srfm.sim import budget, episode
from tools.results import audit_b_pages, rl_study, sets
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
    text = _flat(audit_b_pages.run_size_crowd())
    assert "100,000 pedestrians (750 steps)" in text
    minutes = budget.estimate_episode_time(audit_b_pages.crowd_scenario()) / 60
    assert f"about {minutes:.0f} min" in text
    monkeypatch.setattr(budget, "_SAMPLE_S", 10 * budget._SAMPLE_S)
    monkeypatch.setattr(episode, "_PER_PED_SAMPLE", {k: 0 for k in episode._PER_PED_SAMPLE})
    assert audit_b_pages.run_size_crowd() != text


def test_the_preset_sentence_reads_the_preset(monkeypatch: pytest.MonkeyPatch) -> None:
    p = SRFMParams.preset("navwareset2025")
    text = _flat(audit_b_pages.robustness_fitted_preset())
    assert f"A_r = {p.a_robot:.2f} m/s²" in text
    assert f"B_r = {p.b_robot:.2f} m" in text
    changed = attrs.evolve(p, a_robot=1.234)
    monkeypatch.setattr(SRFMParams, "preset", staticmethod(lambda name: changed))
    assert "A_r = 1.23 m/s²" in _flat(audit_b_pages.robustness_fitted_preset())


def test_the_shipped_runs_come_from_the_policy_files(monkeypatch: pytest.MonkeyPatch) -> None:
    runs = rl_study.shipped_runs()
    text = _flat(audit_b_pages.rl_shipped_runs())
    for planner, run in runs.items():
        steps = sets.read_json(rl_study.STUDY / "validation" / f"{run}.json")["best"]["steps"]
        assert f"`{planner}`" in text
        assert f"`{run}`" in text
        assert f"{steps:,} actions" in text
    read = sets.read_json

    def edited(path: Path) -> Any:
        doc = read(path)
        if "best" in doc:
            doc["best"]["episodes"] = 999
        return doc

    monkeypatch.setattr(sets, "read_json", edited)
    assert "(999 episodes;" in _flat(audit_b_pages.rl_shipped_runs())

    def moved(path: Path) -> Any:
        doc = read(path)
        if "training" in doc:
            doc["training"]["steps"] = 12_345
        return doc

    monkeypatch.setattr(sets, "read_json", moved)
    with pytest.raises(SystemExit, match="step 12345 is not the chosen checkpoint"):
        audit_b_pages.rl_shipped_runs()


def _flat(text: str) -> str:
    """The text on one line, every run of white space (wrapped lines) one space."""
    return " ".join(text.split())


def _one_missed(results: list[Any], planner: str) -> list[Any]:
    """``results`` with the first episode of ``planner`` timed out."""
    first = next(i for i, r in enumerate(results) if r.planner == planner)
    out = list(results)
    out[first] = dataclasses.replace(out[first], outcome="timeout")
    return out


def test_the_vo_sentence_counts_the_episodes(monkeypatch: pytest.MonkeyPatch) -> None:
    text = _flat(audit_b_pages.planner_vo_range())
    shipped = audit_b_pages.set_results("paper")
    n = sum(r.planner == "vo" for r in shipped)
    goals = sum(r.planner == "vo" and r.outcome == "goal_reached" for r in shipped)
    assert f"reaches the goal in {goals} of {n} episodes at the default 2 m" in text
    monkeypatch.setattr(audit_b_pages, "set_results", lambda name: _one_missed(shipped, "vo"))
    assert f"in {goals - 1} of {n} episodes at the default" in _flat(
        audit_b_pages.planner_vo_range()
    )


def test_the_francis_sentence_names_a_planner_that_missed(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    francis = audit_b_pages.set_results("francis")
    text = _flat(audit_b_pages.planner_francis_goals())
    n = sum(r.planner == "dwa" for r in francis)
    if all(r.outcome == "goal_reached" for r in francis if r.planner == "dwa"):
        assert f"reach the goal in all {n:,} episodes each" in text
    monkeypatch.setattr(audit_b_pages, "set_results", lambda name: _one_missed(francis, "dwa"))
    assert f"`dwa` in {n - 1:,} of {n:,}" in _flat(audit_b_pages.planner_francis_goals())
