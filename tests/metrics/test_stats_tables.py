"""Aggregates, t-tests and the table layouts."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import stats

from srfm.errors import MetricError
from srfm.metrics import (
    EpisodeMetrics,
    benchmark_table,
    compare,
    summarize,
    summary_dict,
    to_latex,
    to_markdown,
)


def test_summary_is_mean_and_sample_std_of_finite_values() -> None:
    s = summarize([1.0, 2.0, math.nan, 4.0])
    assert s.n == 3
    assert s.mean == pytest.approx(7 / 3)
    assert s.std == pytest.approx(np.std([1.0, 2.0, 4.0], ddof=1))
    one = summarize([5.0])
    assert (one.n, one.mean) == (1, 5.0)
    assert math.isnan(one.std)
    assert math.isnan(summarize([math.nan]).mean)


def test_tests_match_scipy() -> None:
    rng = np.random.default_rng(0)
    a = rng.normal(1.0, 0.2, 30)
    b = a + rng.normal(0.05, 0.05, 30)
    c = compare(a, b)
    assert c.welch_p == pytest.approx(stats.ttest_ind(a, b, equal_var=False).pvalue)
    assert c.paired_p == pytest.approx(stats.ttest_rel(a, b).pvalue)
    assert c.n_pairs == 30
    # A small shift hidden by the spread between seeds: only the paired test sees it.
    assert not c.welch_significant
    assert c.paired_significant


def test_tests_skip_undefined_cases() -> None:
    same = compare([1.0, 1.0, 1.0], [1.0, 1.0, 1.0])
    assert math.isnan(same.welch_p)
    assert math.isnan(same.paired_p)
    assert not same.welch_significant
    partly = compare([1.0, math.nan, 2.0, 3.0], [1.5, 2.0, math.nan, 3.7])
    assert partly.n_pairs == 2


def _fake(scenario: str, planner: str, seed: int, frechet: float) -> EpisodeMetrics:
    values = {
        "frechet_m": frechet,
        "min_robot_distance_m": 1.0 + frechet,
        "path_length_m": 10.0,
        "time_to_goal_s": math.nan if seed == 0 else 12.0 + seed,
    }
    return EpisodeMetrics(
        scenario=scenario,
        planner=planner,
        seed=seed,
        outcome="goal_reached",
        end_step=100,
        values=values,
        pedestrians={},
    )


@pytest.fixture
def results() -> list[EpisodeMetrics]:
    rng = np.random.default_rng(1)
    out = []
    for seed in range(20):
        base = rng.normal(1.0, 0.1)
        out.append(_fake("s1", "ours", seed, base))
        out.append(_fake("s1", "other", seed, base + 0.3))
        out.append(_fake("s1", "close", seed, base + 0.001 + 0.001 * abs(rng.normal())))
    return out


def test_table_best_and_marks(results: list[EpisodeMetrics]) -> None:
    table = benchmark_table(
        results,
        scenarios=["s1"],
        planners=["ours", "other", "close"],
        seeds=range(20),
        reference="ours",
    )
    ours = table.cells[("s1", "ours")]
    other = table.cells[("s1", "other")]
    close = table.cells[("s1", "close")]
    assert ours["frechet_m"].summary.n == 20
    assert ours["frechet_m"].best  # lower is better
    assert other["min_robot_distance_m"].best  # higher is better
    assert other["frechet_m"].welch
    assert other["frechet_m"].paired
    assert not close["frechet_m"].welch
    assert not ours["frechet_m"].welch  # not significant against "close"
    assert ours["time_to_goal_s"].summary.n == 19  # NaN at seed 0 left out
    md = to_markdown(table)
    assert "| s1 | other | \\*†" in md
    assert "**" in md
    assert "Welch" in md
    assert "paired" in md
    tex = to_latex(table)
    assert "\\multirow{3}{*}{s1}" in tex
    assert "^{\\ast\\dagger}" in tex
    summary = summary_dict(table)
    entry = summary["scenarios"]["s1"]["other"]["frechet_m"]
    assert entry["welch_p"] < 0.05
    assert entry["paired_n"] == 20


def test_table_rejects_missing_results_and_unknown_names(results: list[EpisodeMetrics]) -> None:
    with pytest.raises(MetricError, match=r"seeds \[20\]"):
        benchmark_table(
            results, scenarios=["s1"], planners=["ours"], seeds=[19, 20], reference=None
        )
    with pytest.raises(MetricError, match="reference planner 'nope'"):
        benchmark_table(results, scenarios=["s1"], planners=["ours"], seeds=[1], reference="nope")
    with pytest.raises(MetricError, match="unknown metric 'speed'"):
        benchmark_table(
            results,
            scenarios=["s1"],
            planners=["ours"],
            seeds=[1],
            reference=None,
            columns=[("speed", "Speed")],
        )
