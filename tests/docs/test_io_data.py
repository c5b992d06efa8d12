"""The measured figures of the logging, external-planner, distributed, reliability,
scenario and convergence pages: their committed data carries its run record, and the
blocks of ``tools/results/io_pages.py`` say what the data says (issue 42)."""

from __future__ import annotations

import copy
import re
from pathlib import Path
from typing import Any

import pytest

from srfm.sim import budget
from srfm.sweep._spec import load_spec
from tools.results import io_pages
from tools.results.generate import BLOCKS

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize("path", sorted(io_pages.DATA), ids=lambda p: p.name)
def test_every_data_file_carries_its_run_record(path: Path) -> None:
    run = io_pages.load(path)["run"]
    assert set(io_pages.RUN_KEYS) <= set(run), sorted(run)
    assert run["command"].startswith("python "), run["command"]
    assert re.fullmatch(r"[0-9a-f]{7,40}(-dirty)?", run["commit"]), run["commit"]
    assert re.fullmatch(r"\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ", run["started"]), run["started"]
    assert run["wall_s"] > 0
    assert "load" in run["machine"]


def test_every_block_is_registered_and_on_a_page() -> None:
    pages = "".join(p.read_text(encoding="utf-8") for p in (ROOT / "docs").rglob("*.md"))
    for name in io_pages.BLOCKS:
        assert BLOCKS[name] is io_pages.BLOCKS[name]
        assert f"<!-- generated: {name} -->" in pages, name


def test_the_logging_run_measured_every_stage_and_file_of_every_episode() -> None:
    doc = io_pages.load(io_pages.LOGGING)
    cells = {(e["scenario"], e["planner"], e["seed"]) for e in doc["episodes"]}
    assert (
        len(cells)
        == len(doc["episodes"])
        == (len(doc["scenarios"]) * len(doc["planners"]) * len(doc["seeds"]))
    )
    for e in doc["episodes"]:
        assert set(io_pages.STAGES) == set(e["cpu_s"]), e["cpu_s"]
        assert set(io_pages.FILES) - {"shared counterfactual file"} <= set(e["bytes"])
        assert e["compact_channels"]["file"] == e["bytes"]["compact episode file"]
    # one shared counterfactual file per scenario and seed
    assert len(io_pages._sizes("shared counterfactual file")) == (
        len(doc["scenarios"]) * len(doc["seeds"])
    )
    runs = {r["run"]: r for r in doc["full_benchmark"]}
    assert runs["no logs"]["mcap_files"] == 0
    assert runs["default logs"]["mcap_files"] > runs["default logs"]["counterfactual_files"] > 0


def test_the_time_model_data_holds_the_shipped_coefficients() -> None:
    doc = io_pages.load(io_pages.TIME_MODEL)
    shipped = (
        budget._SAMPLE_S,
        budget._PED_SAMPLE_S,
        budget._PAIR_SAMPLE_S,
        budget._OBSTACLE_PED_SAMPLE_S,
        budget._METRIC_PED_SAMPLE_S,
        budget._METRIC_PED_SAMPLE_SQ_S,
    )
    assert tuple(doc["shipped"][t] for t in io_pages.TERMS) == shipped
    assert set(doc["shipped"]) == set(doc["refit"]) == set(io_pages.TERMS)
    assert all(v >= 0 for v in doc["refit"].values())
    from srfm.benchmark._runner import _HELD_PER_EPISODE, _HELD_PER_PEDESTRIAN

    memory = doc["held_memory"]
    assert memory["shipped"] == {
        "per_episode": _HELD_PER_EPISODE,
        "per_pedestrian": _HELD_PER_PEDESTRIAN,
    }
    sizes = [r["pedestrians"] for r in memory["scenarios"]]
    assert len(set(sizes)) == len(sizes) >= 2  # a + b·N needs two crowd sizes


def test_the_formula_on_the_reliability_page_is_the_shipped_model() -> None:
    text = (ROOT / "docs" / "reliability.md").read_text(encoding="utf-8")

    def us(x: float) -> str:
        return f"{x * 1e6:g} µs"

    formula = (
        f"S · ({us(budget._SAMPLE_S)} + N · ({us(budget._PED_SAMPLE_S)} + "
        f"{budget._PAIR_SAMPLE_S * 1e9:g} ns · K + {us(budget._OBSTACLE_PED_SAMPLE_S)} · M)) "
        f"+ N · S · ({us(budget._METRIC_PED_SAMPLE_S)} + "
        f"{budget._METRIC_PED_SAMPLE_SQ_S * 1e9:g} ns · S)"
    )
    assert formula in text, formula


def test_a_sweeps_default_task_is_the_pages_task(tmp_path: Path) -> None:
    spec = tmp_path / "s.toml"
    spec.write_text(
        'schema_version = 1\nscenarios = ["crosswalk"]\nplanners = ["straight"]\n'
        'seeds = "0-1"\n[design]\nkind = "grid"\n[design.factors]\na_robot = [1.0]\n',
        encoding="utf-8",
    )
    assert load_spec(spec).seeds_per_task == io_pages.SEEDS_PER_TASK


def _with(monkeypatch: pytest.MonkeyPatch, path: Path, doc: dict[str, Any]) -> None:
    real = io_pages.load

    def fake(p: Path) -> dict[str, Any]:
        return doc if p == path else real(p)

    monkeypatch.setattr(io_pages, "load", fake)


def test_an_overhead_beyond_a_target_is_reported_as_not_met(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    doc = copy.deepcopy(io_pages.load(io_pages.EXTERNAL))
    doc["per_step_us"]["builtin"]["median"] = 1.0
    doc["per_step_us"]["cpp"]["median"] = 61.0
    doc["per_episode_ms"]["overhead"] = {"median": 12.0, "p90": 30.0, "max": 45.0}
    _with(monkeypatch, io_pages.EXTERNAL, doc)
    text = " ".join(io_pages.external_overhead().split())
    assert "60.0 µs, **not met**" in text
    assert "12.0 ms median, met, 45.0 ms for the slowest block, **not met**." in text
    assert "costs 60.0 µs per control step" in " ".join(io_pages.external_cost().split())


def test_a_missing_data_file_names_the_command_that_writes_it(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    missing = tmp_path / "nothing.json"
    monkeypatch.setitem(io_pages.DATA, missing, "python tools/x.py")
    with pytest.raises(io_pages.MissingDataError, match=r"nothing\.json.*python tools/x\.py"):
        io_pages.load.__wrapped__(missing)
