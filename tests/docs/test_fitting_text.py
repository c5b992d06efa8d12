"""The generated prose of docs/fitting.md (tools/results/fitting_text.py) and the tools
that write its data: every data file carries the record of its run, the counts agree
across files, a claim whose pattern the data no longer show stops the generator, and
the small computations of the tools give known answers on small inputs."""

from __future__ import annotations

import copy
from typing import Any

import numpy as np
import pytest

from srfm.datasets import Trajectories
from srfm.datasets._trajectories import PEDESTRIAN, ROBOT
from srfm.fitting import WindowConfig, build_windows
from tools.fitting import navwareset_facts, navwareset_variants
from tools.results import fitting_pages as fp
from tools.results import fitting_text as ft

RUN_KEYS = {"command", "commit", "started", "finished", "wall_s", "machine"}


@pytest.mark.parametrize("rel", [rel for rel, _ in ft.RUNS])
def test_every_data_file_of_the_page_carries_the_record_of_its_run(rel: str) -> None:
    run = ft._json(rel)["run"]
    assert set(run) >= RUN_KEYS
    assert run["command"].startswith("python tools/fitting/")
    assert run["wall_s"] > 0
    assert "load" in run["machine"]


def test_the_page_names_every_data_file_it_generates_from() -> None:
    text = ft.fitting_runs()
    for rel, _ in ft.RUNS:
        assert f"`docs/{rel}`" in text


def test_wall_times_are_written_in_minutes_and_seconds() -> None:
    assert ft._minutes(47.7) == "48 s"
    assert ft._minutes(228.6) == "3 min 49 s"
    assert ft._minutes(60.0) == "1 min 00 s"


def test_the_counts_of_the_facts_and_of_the_fit_agree() -> None:
    facts, eth = ft._json(ft.FACTS), ft._json(ft.ETHUCY)
    assert facts["fit_windows"]["windows"] == (
        facts["fit_windows"]["interaction"] + facts["fit_windows"]["non_interaction"]
    )
    # the generator checks the robot-part run against these counts
    assert "Fitting windows" in ft.fitting_protocol_windows()
    # ETH/UCY has no robot: every window is a non-interaction window
    assert eth["windows"]["all"] == eth["windows"]["non_interaction"]


def _patched(monkeypatch: pytest.MonkeyPatch, rel: str, edit: Any) -> None:
    real = ft._json
    doc = copy.deepcopy(real(rel))
    edit(doc)
    for module in (ft, fp):  # fitting_pages' readers too (_compliance_rows)
        monkeypatch.setattr(module, "_json", lambda r: doc if r == rel else real(r))


def test_a_claim_the_data_no_longer_show_stops_the_generator(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    def other_windows(doc: dict[str, Any]) -> None:
        doc["windows"]["fit"] += 1

    _patched(monkeypatch, ft.NAVWARESET, other_windows)
    with pytest.raises(SystemExit, match="other windows"):
        ft.fitting_protocol_windows()
    monkeypatch.undo()

    def overlap(doc: dict[str, Any]) -> None:
        doc["overlapping_recordings"] = 1

    _patched(monkeypatch, ft.FACTS, overlap)
    with pytest.raises(SystemExit, match="overlap"):
        ft.fitting_protocol_replay()
    monkeypatch.undo()

    def hsr_ranked_right(doc: dict[str, Any]) -> None:
        for r in doc["rows"]:
            if (r["scenario"], r["robot"]) == ("frontal_approach", "hsr"):
                r["deviation_m"].update(welch_p=0.01, compliant=1.0, non_compliant=2.0)
                r["min_distance_m"].update(welch_p=0.01, compliant=1.0, non_compliant=0.5)

    _patched(monkeypatch, ft.COMPLIANCE, hsr_ranked_right)
    with pytest.raises(SystemExit, match="compliance summary"):
        ft.fitting_compliance_short()
    monkeypatch.undo()

    def no_bias(doc: dict[str, Any]) -> None:
        for r in doc["rows"]:
            r["params"]["tau"] = doc["true"]["tau"]

    _patched(monkeypatch, ft.IDENTIFIABILITY, no_bias)
    with pytest.raises(SystemExit, match="underestimated"):
        ft.fitting_identifiability_bias()


def test_the_compliance_summary_names_the_cells_of_the_table() -> None:
    rows = ft._compliance_rows(ft.COMPLIANCE)
    right, wrong = ft._right_and_wrong(rows)
    text = ft.fitting_compliance_short().replace("\n  ", " ")
    for scenario, robot in right + wrong:
        assert rows[scenario, robot]["deviation_m"]["welch_p"] < 0.05
        assert scenario.replace("_", " ") in text
    assert ft._by_scenario(right) in text
    assert ft._by_scenario(wrong) in text
    assert ft._by_scenario([("a_b", "hsr"), ("a_b", "jackal"), ("c", "hsr")]) == (
        "a b (both robots) and the HSR's c"
    )


def _scene(ped_xy: list[tuple[float, float]], robot_xy: list[tuple[float, float]]) -> Trajectories:
    n = len(ped_xy)
    frames = np.repeat(np.arange(n), 2)
    return Trajectories.from_samples(
        scene="s",
        agent_ids=("pedestrian", "robot"),
        kinds=(PEDESTRIAN, ROBOT),
        agent=np.tile([0, 1], n),
        frame=frames,
        t_ns=frames * 100_000_000,
        xy=np.array([xy for pair in zip(ped_xy, robot_xy, strict=True) for xy in pair]),
        source={"navwareset_scene": "1", "robot": "hsr"},
    )


def test_repeats_are_counted_in_runs_with_the_distance_after_each() -> None:
    ped = [(0.0, 0.0), (0.0, 0.0), (0.01, 0.0), (0.01, 0.0), (0.01, 0.0), (0.04, 0.0)]
    robot = [(5.0, float(k)) for k in range(6)]
    out = navwareset_facts.repeats([_scene(ped, robot)], PEDESTRIAN)
    assert (out["steps"], out["repeated"]) == (5, 3)
    assert out["runs"] == {"1": 1, "2": 1}
    assert out["median_distance_after_run_m"] == pytest.approx(0.02)
    # after one repeat, 0.01 m in two intervals of 0.1 s
    assert out["speed_after_one_repeat_mps"]["median"] == pytest.approx(0.05)
    assert navwareset_facts.repeats([_scene(ped, robot)], ROBOT)["repeated"] == 0
    # the closest centre distance of the one track: 5 m at frame 0
    assert navwareset_facts.closest_passes([_scene(ped, robot)]) == {"1": pytest.approx(5.0)}


def test_the_window_end_goal_is_each_windows_last_observed_position() -> None:
    ped = [(0.1 * k, 0.0) for k in range(80)]
    robot = [(4.0, 0.05 * k) for k in range(80)]
    w = build_windows([_scene(ped, robot)], WindowConfig(stride_s=1.2))
    moved = navwareset_variants.window_end_goals(w)
    assert w.n_windows > 1
    for k in range(w.n_windows):
        last = w.out_row[k] + w.steps[k] - 1
        np.testing.assert_array_equal(moved.goal[k], w.observed[last])
        assert not np.array_equal(moved.goal[k], w.goal[k]) or k == w.n_windows - 1


def test_the_robot_part_was_fitted_with_the_committed_pedestrian_part() -> None:
    eth, nws = ft._json(ft.ETHUCY), ft._json(ft.NAVWARESET)
    variants = ft._json(ft.VARIANTS)
    for part in (nws["pedestrian_part"], variants["pedestrian_part"]):
        assert part == pytest.approx(eth["fitted"], rel=1e-12)
