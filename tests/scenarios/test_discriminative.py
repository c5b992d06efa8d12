"""The `discriminative` suite is what its selection chose (issue 29; docs/benchmark.md,
"Where the benchmark can tell planners apart"): SUITES["discriminative"] against
docs/discrimination/selection.json, written by ``tools/analysis/discrimination.py
select`` from seeds 1000-1099, and the report's seeds never the selection's."""

from __future__ import annotations

import argparse
import copy
import json
from pathlib import Path
from typing import Any

import pytest
from click.testing import CliRunner

from srfm.cli import main
from srfm.metrics.headroom import DETECT_M, MIN_HEADROOM_M, MIN_STANDARD_ERRORS
from srfm.scenarios.suites import SUITES
from tools.analysis import discrimination
from tools.results import generate, sets

DOCS = Path(__file__).resolve().parents[2] / "docs" / "discrimination"


def _load(name: str) -> dict[str, Any]:
    doc: dict[str, Any] = json.loads((DOCS / name).read_text(encoding="utf-8"))
    return doc


@pytest.fixture(scope="module")
def selection() -> dict[str, Any]:
    return _load("selection.json")


def test_suite_is_the_selection(selection: dict[str, Any]) -> None:
    # the recorded selection of 2026-11-27 chose the suite until the results set
    # `selection` (the shipped entries) was committed; then the rule on that set does
    # (test_the_rule_on_the_committed_selection_data_gives_the_suite)
    suite = SUITES["discriminative"]
    if not sets.exists("selection"):
        assert suite == tuple(selection["suite"])
    assert 0 < len(suite) <= discrimination.MAX_SUITE
    # in the library's order
    assert list(suite) == [s for s in SUITES["all"] if s in suite]


def test_selection_used_the_rule_as_written(selection: dict[str, Any]) -> None:
    assert selection["thresholds"] == {
        "min_headroom_m": MIN_HEADROOM_M,
        "min_standard_errors": MIN_STANDARD_ERRORS,
        "min_goal_rate": discrimination.MIN_GOAL_RATE,
        "detect_m": DETECT_M,
        "max_seeds": discrimination.MAX_SEEDS,
        "max_suite": discrimination.MAX_SUITE,
    }
    assert selection["planners"] == list(discrimination.PLANNERS)
    # every candidate of suite `all` was measured on seeds 1000-1099 only, or is listed
    # as not complete (then it was not selected from: docs/benchmark.md says why that
    # cannot change the suite)
    measured = [r["scenario"] for r in selection["scenarios"]]
    assert measured == [s for s in SUITES["all"] if s not in selection["incomplete"]]
    assert not set(selection["incomplete"]) - set(SUITES["all"])
    for row in selection["scenarios"]:
        assert row["seeds"] == [1000, 1099]
        assert row["n_seeds"] == 100


def test_benchmark_help_names_every_suite() -> None:
    result = CliRunner().invoke(main, ["benchmark", "--help"], terminal_width=10_000)
    assert result.exit_code == 0
    help_text = " ".join(result.output.split())
    for name in SUITES:
        assert f"{name} (" in help_text, name


def _meets(row: dict[str, Any], t: dict[str, float]) -> bool:
    """The rule's conditions (a)-(d), recomputed from the row's measured values."""
    return (
        row["headroom_m"] >= t["min_headroom_m"]
        and row["headroom_m"] >= t["min_standard_errors"] * row["standard_error_m"]
        and row["goal_rate"]["oracle"] >= t["min_goal_rate"]
        and row["goal_rate"]["straight"] >= t["min_goal_rate"]
        and row["seeds_needed"] is not None
        and row["seeds_needed"] <= t["max_seeds"]
    )


def test_every_chosen_scenario_met_the_thresholds(selection: dict[str, Any]) -> None:
    t = selection["thresholds"]
    rows = {r["scenario"]: r for r in selection["scenarios"]}
    for name in selection["suite"]:
        row = rows[name]
        assert _meets(row, t), name
        assert row["fails"] == [], name
        assert row["discriminates"], name
    for row in selection["scenarios"]:
        # the recorded verdict is the thresholds' verdict, for every candidate
        assert (row["fails"] == []) == _meets(row, t), row["scenario"]


def test_suite_is_the_best_ranked_qualifiers(selection: dict[str, Any]) -> None:
    t = selection["thresholds"]
    qualified = [r for r in selection["scenarios"] if _meets(r, t)]
    qualified.sort(key=lambda r: -r["headroom_m"] / r["sd_diff_m"])
    best = {r["scenario"] for r in qualified[: int(t["max_suite"])]}
    assert set(selection["suite"]) == best
    assert [r["rank"] for r in qualified] == list(range(1, len(qualified) + 1))


def test_the_rule_on_the_committed_selection_data_gives_the_suite(
    selection: dict[str, Any],
) -> None:
    # the selection measured again with the shipped entries (results set `selection`,
    # docs/results/discriminative.md) once it is committed, else the recorded one
    if sets.exists("selection"):
        rows = generate._rows("selection")
        assert sets.manifest("selection")["request"]["planners"] == list(discrimination.PLANNERS)
        assert sets.manifest("selection")["request"]["seeds"] == list(range(1000, 1100))
    else:
        rows = copy.deepcopy(selection["scenarios"])
    suite = discrimination.select(rows)
    assert tuple(suite) == SUITES["discriminative"]
    t = discrimination.thresholds()
    for row in rows:
        assert (row["fails"] == []) == _meets(row, t), row["scenario"]


@pytest.mark.parametrize("name", [n for n in ("paper", "francis", "navwareset") if sets.exists(n)])
def test_report_never_saw_the_selection_seeds(name: str) -> None:
    # the suite's table on docs/results/discriminative.md comes from these sets
    seeds = sets.manifest(name)["request"]["seeds"]
    assert seeds == list(range(100))
    if sets.exists("selection"):
        assert not set(seeds) & set(sets.manifest("selection")["request"]["seeds"])


def _fake_run(out: Path, planners: list[str], values: dict[str, list[float]]) -> None:
    """A results folder as `srfm benchmark` leaves it, as far as the tool reads it: the
    manifest's request and one episode file per (planner, seed) of scenario `s`."""
    seeds = list(range(len(next(iter(values.values())))))
    request = {"scenarios": ["s"], "planners": planners, "seeds": seeds}
    out.mkdir()
    (out / "manifest.json").write_text(json.dumps({"request": request}), encoding="utf-8")
    for planner, series in values.items():
        folder = out / "episodes" / "s" / planner
        folder.mkdir(parents=True)
        for seed, value in zip(seeds, series, strict=True):
            doc = {
                "scenario": "s",
                "planner": planner,
                "seed": seed,
                "outcome": "goal_reached" if planner != "dwa" or seed else "collision",
                "metrics": {"frechet_m": value},
            }
            (folder / f"seed-{seed:06d}.json").write_text(json.dumps(doc), encoding="utf-8")


def test_report_reads_a_run_of_any_planners(tmp_path: Path) -> None:
    # a suite run without td3-srfm (the Francis suite before its policy is final)
    straight = [1.0 + 0.01 * k for k in range(10)]
    values = {
        "straight": straight,
        "oracle": [x - 0.5 for x in straight],
        "dwa": [x - 0.1 + 0.001 * k for k, x in enumerate(straight)],
    }
    _fake_run(tmp_path / "run", ["straight", "oracle", "dwa"], values)
    rows = discrimination._measure(tmp_path / "run")
    assert [r["scenario"] for r in rows] == ["s"]
    row = rows[0]
    assert list(row["mean_m"]) == ["straight", "oracle", "dwa"]
    assert row["headroom_m"] == pytest.approx(0.5)
    assert row["goal_rate"]["dwa"] == pytest.approx(0.9)
    assert set(row["scores"]) == set(values)
    assert row["scores"]["dwa"][0] == pytest.approx((0.1 - 0.0045) / 0.5)
    assert discrimination._planners(rows) == ["straight", "oracle", "dwa"]
    assert "td3-srfm" not in discrimination.means_table(rows)
    # a planner of the request with seeds missing: the scenario is not complete yet
    (tmp_path / "run" / "episodes" / "s" / "dwa" / "seed-000009.json").unlink()
    assert discrimination._measure(tmp_path / "run") == []


def test_selection_needs_every_planner_of_the_rule(tmp_path: Path) -> None:
    values = {"straight": [1.0, 1.1, 1.2], "oracle": [0.5, 0.6, 0.6]}
    _fake_run(tmp_path / "run", ["straight", "oracle"], values)
    args = argparse.Namespace(out=tmp_path / "run", json=tmp_path / "selection.json")
    with pytest.raises(SystemExit, match="needs the planners"):
        discrimination.cmd_select(args)
    assert not (tmp_path / "selection.json").exists()
