"""docs/sensitivity.md's committed sweep (tools/results/sensitivity.py): the rules its
blocks apply beyond formatting, on small inputs whose answer is known and on the
committed data."""

from __future__ import annotations

import csv
import math
from typing import Any

import numpy as np
import pytest
from scipy import stats

from tools.results import fitting_pages as fp
from tools.results import sensitivity as sens

PLANNERS = ["p", "q"]


def _fake(monkeypatch: pytest.MonkeyPatch, columns: dict[str, list[Any]]) -> None:
    """Replace the committed episodes and run record by ``columns``."""
    data = {
        c: np.array(v, dtype=object if c in sens.TEXT_COLUMNS else np.float64)
        for c, v in columns.items()
    }
    data["seed"] = np.array(columns["seed"], dtype=np.int64)
    sens.pooled.cache_clear()
    monkeypatch.setattr(sens, "episodes", lambda: data)
    monkeypatch.setattr(sens, "run", lambda: {"spec": {"planners": PLANNERS, "scenarios": ["s"]}})


def _grid(p_values: list[float], q_values: list[float], a: float = 1.0) -> dict[str, list[Any]]:
    n = len(p_values)
    return {
        "a_robot": [a] * 2 * n,
        "b_robot": [0.5] * 2 * n,
        "scenario": ["s"] * 2 * n,
        "planner": ["p"] * n + ["q"] * n,
        "seed": list(range(n)) * 2,
        "frechet_m": [*p_values, *q_values],
        "robot_success": [1.0] * (2 * n - 1) + [0.0],
    }


def test_head_to_head_counts_a_paired_difference_by_its_sign(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    rng = np.random.default_rng(0)
    base = rng.uniform(0.5, 1.5, 12)
    noise = rng.normal(0.0, 0.01, 12)
    _fake(monkeypatch, _grid(list(base), list(base + 0.1 + noise)))
    assert sens.head_to_head() == (1, {("p", "q"): [1, 0, 0, 1, 0]})
    _fake(monkeypatch, _grid(list(base + 0.1 + noise), list(base)))
    assert sens.head_to_head() == (1, {("p", "q"): [0, 1, 0, 0, 1]})
    # the same values in another seed order: no paired difference to find
    _fake(monkeypatch, _grid(list(base), list(base[::-1] + 1e-3)))
    assert sens.head_to_head() == (1, {("p", "q"): [0, 0, 1, 0, 0]})


def test_head_to_head_leaves_out_cells_without_a_robot_force(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    _fake(monkeypatch, _grid([0.0, 0.0, 0.0], [0.0, 0.0, 0.0], a=0.0))
    assert sens.head_to_head() == (0, {("p", "q"): [0, 0, 0, 0, 0]})


def test_pooled_is_the_mean_its_t_interval_and_the_success_rate(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    p_values = [0.2, 0.4, 0.9, 0.5]
    _fake(monkeypatch, _grid(p_values, [1.0, 1.0, 1.0, 1.0]))
    mean, half, rate = sens.pooled("a_robot", "p", 1.0)
    lo, hi = stats.t.interval(0.95, 3, loc=np.mean(p_values), scale=stats.sem(p_values))
    assert mean == pytest.approx(np.mean(p_values))
    assert half == pytest.approx((hi - lo) / 2)
    assert rate == 1.0
    assert sens.pooled("a_robot", "q", 1.0)[2] == pytest.approx(0.75)
    sens.pooled.cache_clear()


def test_a_csv_cell_keeps_a_float_exactly_and_writes_nan_empty() -> None:
    x = 0.1 + 0.2
    assert float(sens._value(np.float64(x))) == x
    assert sens._value(math.nan) == ""
    assert sens._value(np.int64(7)) == "7"
    assert sens._value("footpath") == "footpath"


def test_the_committed_rankings_are_the_means_of_the_committed_episodes() -> None:
    """rankings.csv (srfm sweep report) and episodes.csv.gz (the pack) are one run."""
    e = sens.episodes()
    with fp.RANKINGS.open(encoding="utf-8", newline="") as f:
        rows = list(csv.DictReader(f))
    checked = 0
    for row in rows:
        if row["scope"] == "all":
            continue
        mask = (
            (e["a_robot"] == float(row["a_robot"]))
            & (e["b_robot"] == float(row["b_robot"]))
            & (e["scenario"] == row["scope"])
            & (e["planner"] == row["planner"])
        )
        assert int(mask.sum()) == len(sens.run()["spec"]["seeds"])
        assert float(np.nanmean(e["frechet_m"][mask])) == pytest.approx(
            float(row["mean_frechet_m"]), abs=1e-12
        )
        checked += 1
    assert checked == len(e["seed"]) // len(sens.run()["spec"]["seeds"])


def test_every_pair_of_planners_is_counted_once_per_cell_and_scenario() -> None:
    total, counts = sens.head_to_head()
    a_levels = [a for a in sens.levels("a_robot") if a > 0]
    assert total == len(a_levels) * len(sens.levels("b_robot")) * len(sens.scenarios())
    n = len(sens.planners())
    assert len(counts) == n * (n - 1) // 2
    assert all(sum(c[:3]) == total for c in counts.values())
    # Holm only removes significance: never more significant pairs than uncorrected
    assert all(c[3] <= c[0] and c[4] <= c[1] for c in counts.values())
