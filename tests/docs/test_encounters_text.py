"""The generated prose of docs/real_encounters.md (tools/results/encounters_text.py): its
data files carry the record of their run, its summaries use the cells and thresholds of
the tables beneath them, and a claim the data no longer show stops the generator."""

from __future__ import annotations

import copy
from typing import Any

import pytest

from tools.results import encounters_text as et


@pytest.mark.parametrize("rel", [rel for rel, _ in et.RUN_FILES])
def test_every_data_file_of_the_page_carries_the_record_of_its_run(rel: str) -> None:
    run = et._json(rel)["run"]
    assert {"command", "commit", "started", "finished", "wall_s", "machine"} <= set(run)
    assert run["command"].startswith("python tools/fitting/")


def _patched(monkeypatch: pytest.MonkeyPatch, rel: str, edit: Any) -> None:
    real = et._json
    doc = copy.deepcopy(real(rel))
    edit(doc)
    monkeypatch.setattr(et, "_json", lambda r: doc if r == rel else real(r))


def test_the_map_keeps_only_cells_with_enough_samples(monkeypatch: pytest.MonkeyPatch) -> None:
    def small(doc: dict[str, Any]) -> None:
        doc["part1"]["tstar_dstar_map"] = {
            "tstar_edges": [0.0, 0.5, 1.0],
            "dstar_edges": [0.0, 0.25, 0.5],
            "mean": [[0.3, None], [0.1, -0.2]],
            "n": [[et.MAP_MIN_N - 1, 100], [et.MAP_MIN_N, 500]],
        }

    _patched(monkeypatch, et.ENCOUNTERS, small)
    assert et.map_cells() == [
        (0.5, 1.0, 0.0, 0.25, 0.1, et.MAP_MIN_N),
        (0.5, 1.0, 0.25, 0.5, -0.2, 500),
    ]


def test_the_summary_of_part_4_says_what_the_decisive_table_says() -> None:
    rows = et._forms()
    text = et.encounters_part4_short().replace("\n  ", " ")
    for robot in ("hsr", "jackal"):
        r = rows["ttc", robot, "pass"]
        assert r["success"]
        assert f"{-100 * r['rel']:.0f}" in text
    # the summary and the verdict use the same rows
    verdict = et.encounters_forms_verdict().replace("\n  ", " ")
    assert f"{-100 * rows['ttc', 'pooled', 'pass']['rel']:.0f} % of the pass-distance" in verdict


def test_a_claim_the_data_no_longer_show_stops_the_generator(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    def ttc_fails(doc: dict[str, Any]) -> None:
        for r in doc["tests"]["decisive"]:
            if (r["form"], r["set"], r["measure"]) == ("ttc", "hsr", "pass"):
                r["success"] = False

    _patched(monkeypatch, et.FORMS, ttc_fails)
    with pytest.raises(SystemExit, match="no longer succeeds"):
        et.encounters_part4_short()
    with pytest.raises(SystemExit, match="no longer succeeds"):
        et.encounters_forms_verdict()
    monkeypatch.undo()

    def positive_offset(doc: dict[str, Any]) -> None:
        doc["part1"]["confirmatory"]["tests"][0]["est"] = 0.1

    _patched(monkeypatch, et.ENCOUNTERS, positive_offset)
    with pytest.raises(SystemExit, match="confirmatory results changed"):
        et.encounters_confirmatory_short()
    monkeypatch.undo()

    def far_response(doc: dict[str, Any]) -> None:
        m = doc["part1"]["tstar_dstar_map"]
        m["mean"][2][6] = 0.2  # t* 1-1.5 s, d* 1.5-1.75 m
        m["n"][2][6] = 100

    _patched(monkeypatch, et.ENCOUNTERS, far_response)
    with pytest.raises(SystemExit, match="d\\* >= 1 m"):
        et.encounters_time_distance()


def test_every_block_of_the_page_renders() -> None:
    for name, block in et.BLOCKS.items():
        assert block().strip(), name
