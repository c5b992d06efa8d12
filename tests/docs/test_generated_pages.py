"""The generated blocks of docs/rl.md, planners.md, metrics.md and scenarios.md
(tools/results/rl_study.py, tools/results/pages.py) read their committed data as the
tools that wrote it meant: the parsers against hand counts, the results sets against
the study's report, a results set's robot outcomes against the episode itself."""

from __future__ import annotations

import contextlib
import io
from pathlib import Path

import pytest

from tools.analysis import convergence, planner_outcomes
from tools.results import pages, rl_study


def test_the_studys_committed_episodes_give_its_report() -> None:
    cells = rl_study.report_targets()
    runs = rl_study.runs_of(cells)
    assert len(runs) == 20
    assert runs[0] == "k0-seed1"
    assert runs[-1] == "k2-seed10"
    # counted by hand in the report of 2026-11-27 (tools/rl/study/report.md, since removed)
    assert sum(c.miss for (_, r), c in cells.items() if r == "k0-seed2") == 5
    assert sum(c.miss for (_, r), c in cells.items() if r == "k2-seed10") == 9
    concert = cells["concert", "k2-seed6"]
    assert (concert.goal, concert.collision, concert.miss) == (0.02, 0.0, True)
    claims = {c.scenario: c for c in rl_study.report_claim()}
    assert claims["concert"].n == 8
    assert round(claims["concert"].mean, 3) == -0.039
    assert claims["down_path"].p == 0.056
    assert claims["footpath"].answer == "equivalent within ±0.03 m"
    ttc = {c.scenario: c for c in rl_study.report_claim("report_ttc")}
    assert list(ttc) == ["footpath", "crosswalk", "cross_footpath", "circle", "concert"]
    assert (ttc["concert"].n, ttc["footpath"].answer) == (8, "equivalent within ±0.03 m")


def test_the_shipped_policies_are_study_runs_and_the_sets_agree_with_the_report() -> None:
    runs = rl_study.shipped_runs()
    assert runs == {"td3-base": "k0-seed4", "td3-srfm": "k2-seed6"}
    study = rl_study.report_targets()
    sets_cells = rl_study.shipped_cells()
    for planner, run in runs.items():
        for scenario in rl_study.REPORT_SCENARIOS:
            # the committed results sets, run on the current code, give the very cells
            # of the study's report (2026-11-27)
            assert sets_cells[scenario, planner][0].text() == study[scenario, run].text()
    assert "disagrees" not in rl_study.shipped_targets()
    assert "the runs shipped." in rl_study.validation_table()


def test_a_run_misses_its_targets_by_one_rule() -> None:
    from tools.rl.study_report import misses_target

    assert misses_target("concert", 0.94, 0.0)
    assert not misses_target("concert", 0.95, 0.02)
    assert misses_target("concert", 1.0, 0.03)
    assert not misses_target("corridor_flow", 0.5, 0.05)
    assert misses_target("corridor_flow", 1.0, 0.06)


def test_a_results_sets_robot_outcomes_are_the_episodes(tmp_path: Path) -> None:
    """planner_outcomes' quantities of an episode equal the benchmark's columns that
    the unicycle table reads from the results set `paper`."""
    from_set = {
        (r.scenario, r.planner, r.seed): r
        for r in pages.set_results("paper")
        if r.seed == 0 and r.scenario == "crosswalk"
    }
    mine = planner_outcomes.run_one(("crosswalk", "dwa", 0, None, {}, {}))
    theirs = from_set["crosswalk", "dwa", 0]
    assert (mine.outcome, mine.end_step) == (theirs.outcome, theirs.end_step)
    assert mine.speed_mps == pytest.approx(theirs.speed_mps, rel=1e-12)
    assert mine.time_to_goal_s == pytest.approx(theirs.time_to_goal_s, rel=1e-12)
    assert mine.min_distance_m == theirs.min_distance_m


def test_planner_outcomes_writes_what_the_pages_read(tmp_path: Path) -> None:
    out = tmp_path / "run"
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        code = planner_outcomes.main(
            [
                "--seeds",
                "2",
                "--planners",
                "straight",
                "--scenarios",
                "footpath",
                "--jobs",
                "1",
                "--out",
                str(out),
            ]
        )
    assert code == 0
    results, manifest = planner_outcomes.read(out)
    assert [(r.scenario, r.planner, r.seed) for r in results] == [
        ("footpath", "straight", 0),
        ("footpath", "straight", 1),
    ]
    assert manifest["seeds"] == [0, 1]
    assert manifest["command"].endswith(f"--out {out}")
    table = "\n".join(planner_outcomes.markdown_table(results, ["footpath"], ["straight"]))
    assert table in printed.getvalue()


def test_the_convergence_tables_are_the_tools_output() -> None:
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        convergence.table(pages.CONVERGENCE)
    assert printed.getvalue() == "\n".join(convergence.table_lines(pages.CONVERGENCE)) + "\n"
    summary = convergence.summary(pages.CONVERGENCE)
    assert summary["n_means"] == 35
    assert summary["pairs"] == 21
    assert summary["worst_mean"] == max(summary["worst_mean_by_scenario"].values())


def _run() -> dict[str, object]:
    return {
        "command": "python tool.py",
        "commit": "abc1234",
        "started": "2026-12-05T16:00:00Z",
        "machine": "x86_64, 2 CPUs, 1-min load 0.5 at the start and 0.4 at the end",
    }


def test_the_range_beam_cost_is_the_best_block(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import json

    rows = [
        {"scenario": "a", "beams": 0, "us_per_step": [12.0, 10.0, 11.0]},
        {"scenario": "a", "beams": 24, "us_per_step": [13.0, 12.0, 30.0]},
        {"scenario": "b", "beams": 0, "us_per_step": [50.0]},
        {"scenario": "b", "beams": 24, "us_per_step": [49.0]},
    ]
    path = tmp_path / "range_beams.json"
    path.write_text(json.dumps({"steps": 100, "repeats": 3, "rows": rows, "run": _run()}))
    monkeypatch.setattr(rl_study, "RANGE_BEAMS", path)
    text = rl_study.range_beams()
    assert "`a`: 10.0 → 12.0 µs (+20 %) and `b`: 50.0 → 49.0 µs (−2 %)" in text
    assert "24 beams" in text
    assert "commit `abc1234`" in text
    monkeypatch.setattr(rl_study, "RANGE_BEAMS", tmp_path / "none.json")
    assert rl_study.range_beams().startswith("*Not measured yet")


def test_the_export_match_is_the_largest_difference(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import json

    doc = {
        "uniform": 20,
        "sparse": 8,
        "per_scenario": 7,
        "scenarios": ["x", "y"],
        "policies": {
            "td3-srfm": {"backend": "sbx", "observations": 42, "max_abs_diff": 6e-6},
            "td3-base": {"backend": "sbx", "observations": 42, "max_abs_diff": 8.14e-6},
        },
        "run": _run(),
    }
    path = tmp_path / "export_match.json"
    path.write_text(json.dumps(doc))
    monkeypatch.setattr(rl_study, "EXPORT_MATCH", path)
    text = rl_study.export_match()
    assert "the SBX checkpoint's deterministic `model.predict` within 8.1e-6 on 42 " in text
    doc["policies"]["td3-base"]["observations"] = 41  # type: ignore[index]
    path.write_text(json.dumps(doc))
    with pytest.raises(SystemExit, match="different observation counts"):
        rl_study.export_match()
