"""The generated blocks of the pages on real data (tools/results/fitting_pages.py): the
rules they apply beyond formatting, checked on the committed data and on small inputs
whose answer is known."""

from __future__ import annotations

import copy
import math

import numpy as np
import pytest
from scipy import stats

from tools.fitting import fit_navwareset, navwareset_compliance
from tools.results import fitting_pages as fp


def test_fixed_rounds_half_up_with_a_true_minus() -> None:
    assert fp.fixed(3.525, 2) == "3.53"
    assert fp.fixed(1.625, 2) == "1.63"
    assert fp.fixed(-0.0459596, 3, sign=True) == "−0.046"
    assert fp.fixed(0.166373, 3, sign=True) == "+0.166"
    assert fp.fixed(-12.5724, 1) == "−12.6"
    assert fp.signed(-6.6, 1) == "−6.6"
    assert fp.signed(0.0, 1) == "+0.0"


def _row(success: bool, equivalent: bool) -> dict[str, bool]:
    return {"success": success, "equivalent": equivalent}


def test_a_forms_verdict_names_what_succeeded_else_what_each_measure_is() -> None:
    assert fp._verdict(_row(False, False), _row(True, False)) == "**success** (pass)"
    assert fp._verdict(_row(True, True), _row(True, False)) == "**success** (ADE, pass)"
    assert fp._verdict(_row(False, True), _row(False, True)) == "equivalent"
    assert fp._verdict(_row(False, True), _row(False, False)) == (
        "ADE equivalent, pass inconclusive"
    )


def test_the_sweeps_tau_is_one_at_the_reference_and_undefined_without_a_force() -> None:
    scopes, a_values, b_values = fp._axes()
    assert "all" in scopes
    assert 0.0 in a_values
    for scope in scopes:
        assert fp.sensitivity_tau(scope, *fp.REFERENCE_CELL) == pytest.approx(1.0)
        for b in b_values:
            assert math.isnan(fp.sensitivity_tau(scope, 0.0, b))
    # a cell's tau is scipy's tau-b of its planner means against the reference's
    cells = fp._rankings()
    here, ref = cells["footpath", 15.86, 1.5], cells[("footpath", *fp.REFERENCE_CELL)]
    planners = list(ref)
    expected = stats.kendalltau([here[p][0] for p in planners], [ref[p][0] for p in planners])
    assert fp.sensitivity_tau("footpath", 15.86, 1.5) == pytest.approx(expected.statistic)


def test_each_pair_with_a_force_has_exactly_one_lowest_planner() -> None:
    scopes, a_values, b_values = fp._axes()
    pairs = (len(scopes) - 1) * (len(a_values) - 1) * len(b_values)
    counts = [int(line.split("|")[2]) for line in fp.sensitivity_lowest().splitlines()[2:]]
    assert sum(counts) == pairs


def test_table2_lines_keeps_the_cells_asked_for() -> None:
    payload = fp._json(fp.NAVWARESET)
    every = fit_navwareset.table2_lines(payload)
    some = fit_navwareset.table2_lines(payload, frozenset({"all", "hsr"}))
    assert len(every) == 2 + len(payload["table2"])
    assert [line.split("|")[1].strip() for line in some[2:]] == ["all", "all", "hsr", "hsr"]


def _episode(scenario: str, robot: str, compliant: bool, value: float) -> dict[str, object]:
    outcome = "collision" if value > 9 else "goal_reached"
    return {
        "scenario": scenario,
        "robot": robot,
        "compliant": compliant,
        "frechet_m": value,
        "outcome": outcome,
    }


def test_the_episodes_table_is_welchs_test_per_cell() -> None:
    c, n = [1.0, 1.5, 2.0, 2.2], [2.0, 2.5, 3.5, 10.0]
    records = [_episode("frontal_approach", "hsr", True, v) for v in c]
    records += [_episode("frontal_approach", "hsr", False, v) for v in n]
    records += [_episode("blind_corner", "jackal", True, v) for v in (5.0, 6.0)]
    records += [_episode("blind_corner", "jackal", False, v) for v in (4.0, 4.5)]
    lines = navwareset_compliance.episodes_lines(records)
    p = stats.ttest_ind(c, n, equal_var=False).pvalue
    row = next(line for line in lines if line.startswith("| frontal approach | hsr |"))
    assert row == (
        f"| frontal approach | hsr | 4 / 4 | {np.mean(c):.3f} / {np.mean(n):.3f}, "
        f"p = {p:.2g} | 0 / 1 |"
    )
    every = lines[-1]
    assert every.startswith("| all | all | 6 / 6 |")
    assert every.endswith("| 0 / 1 |")


def test_a_claim_whose_pattern_no_longer_holds_stops_the_generator(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    real = fp._json
    doc = copy.deepcopy(real(fp.COMPLIANCE))
    row = next(
        r for r in doc["rows"] if (r["scenario"], r["robot"]) == ("frontal_approach", "jackal")
    )
    row["deviation_m"]["welch_p"] = 0.5  # no longer a significant difference
    monkeypatch.setattr(fp, "_json", lambda rel: doc if rel == fp.COMPLIANCE else real(rel))
    with pytest.raises(SystemExit, match="compliance pattern changed"):
        fp.fitting_compliance_claims()
    params = copy.deepcopy(real(fp.RESPONSE))
    for r in params["parameters"]:
        if r["set"] == "hsr" and r["field"] == "ss_a":
            r["status"] = "identified"
    monkeypatch.setattr(fp, "_json", lambda rel: params if rel == fp.RESPONSE else real(rel))
    with pytest.raises(SystemExit, match="identified parameters"):
        fp.response_identified()


def test_the_lowest_bin_ignores_thin_bins_and_bins_past_the_limit() -> None:
    curve = {
        "centre": [0.125, 0.375, 0.625, 0.875],
        "mean": [-0.9, -0.2, -0.5, None],
        "n": [10, 100, 100, 100],
    }
    assert fp._lowest_bin(curve, 0.5) == -0.2
    assert fp._lowest_bin(curve, 1.0) == -0.5
