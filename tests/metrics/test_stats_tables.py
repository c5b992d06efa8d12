"""Aggregates, t-tests and the table layouts."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import stats

from srfm.errors import MetricError
from srfm.metrics import (
    TABLE_COLUMNS,
    EpisodeMetrics,
    adjust_p_values,
    base_metric,
    benchmark_table,
    compare,
    given_success,
    min_n_for_best,
    summarize,
    summary_dict,
    to_latex,
    to_latex_extended,
    to_markdown,
    to_markdown_extended,
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
        "robot_duration_s": 20.0,
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
        columns=[*TABLE_COLUMNS, ("time_to_goal_s", "Pedestrian time (s)")],
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


def test_undefined_values_are_counted_not_dropped() -> None:
    s = summarize([1.0, math.nan, 3.0, math.inf])
    assert (s.n, s.undefined) == (2, 2)
    assert summarize([1.0, 2.0]).undefined == 0


def test_min_n_for_best() -> None:
    assert [min_n_for_best(s) for s in (1, 2, 3, 5, 10, 100)] == [2, 2, 3, 4, 8, 80]


def _time_results(arrived: dict[str, int], seeds: int = 10) -> list[EpisodeMetrics]:
    """Planner p reaches its goal in the first arrived[p] seeds, faster the fewer."""
    out = []
    for planner, k in arrived.items():
        for seed in range(seeds):
            t = 10.0 + k + 0.1 * seed if seed < k else math.nan
            out.append(
                EpisodeMetrics(
                    scenario="s",
                    planner=planner,
                    seed=seed,
                    outcome="goal_reached" if seed < k else "timeout",
                    end_step=10,
                    values={"robot_time_to_goal_s": t, "robot_success": float(seed < k)},
                    pedestrians={},
                )
            )
    return out


def test_nothing_is_bold_below_the_minimum_n_and_n_is_shown() -> None:
    # "lucky" reaches its goal in 1 seed of 10 (fastest mean), "steady" in 9, "most" in 8.
    results = _time_results({"lucky": 1, "steady": 9, "most": 8})
    table = benchmark_table(
        results,
        scenarios=["s"],
        planners=["lucky", "steady", "most"],
        seeds=range(10),
        reference=None,
        columns=[("robot_time_to_goal_s", "Robot time (s)"), ("robot_success", "Success")],
    )
    cells = {p: table.cells[("s", p)]["robot_time_to_goal_s"] for p in ("lucky", "steady", "most")}
    assert table.min_n == 8
    assert cells["lucky"].summary.mean < cells["most"].summary.mean < cells["steady"].summary.mean
    assert not cells["lucky"].best  # n = 1 < 8
    assert cells["most"].best  # the best mean among n >= 8
    assert cells["lucky"].summary.undefined == 9
    md = to_markdown(table)
    assert "| s | lucky | 11.00 ± – (n=1) |" in md
    assert "**18.35 ± 0.24** (n=8)" in md
    assert "(n=" not in md.split("| s | steady |")[1].split("|")[2]  # success: n = 10
    assert "n ≥ 8" in md
    assert "max(2, ⌈0.8 × 10 seeds⌉)" in md
    tex = to_latex(table)
    assert "$11.00 \\pm \\text{--}$ (n=1)" in tex
    summary = summary_dict(table)
    entry = summary["scenarios"]["s"]["lucky"]["robot_time_to_goal_s"]
    assert (entry["n"], entry["undefined"], entry["best"]) == (1, 9, False)
    assert summary["min_n_for_best"] == 8
    assert summary["n_seeds"] == 10


def test_extended_table_has_every_metric_grouped() -> None:
    from srfm.metrics import EPISODE_METRICS, EXTENDED_COLUMNS, METRIC_GROUPS

    values = {m.name: 1.0 for m in EPISODE_METRICS}
    results = [
        EpisodeMetrics(
            scenario=s,
            planner=p,
            seed=seed,
            outcome="goal_reached",
            end_step=10,
            values={**values, "frechet_m": 1.0 + seed + (p == "b")},
            pedestrians={},
        )
        for s in ("s1", "s2")
        for p in ("a", "b")
        for seed in range(3)
    ]
    table = benchmark_table(
        results,
        scenarios=["s1", "s2"],
        planners=["a", "b"],
        seeds=range(3),
        reference="a",
        columns=EXTENDED_COLUMNS,
    )
    md = to_markdown_extended(table)
    assert {base_metric(n) for n, _ in EXTENDED_COLUMNS} == {m.name for m in EPISODE_METRICS}
    for m in EPISODE_METRICS:
        conditioned = m.group in ("pedestrian", "social")
        assert (given_success(m.name), given_success(m.name)) in EXTENDED_COLUMNS or (
            not conditioned
        )
        rows = md.count(f"| `{m.name}` ")  # one row per scenario, one more conditioned
        assert md.count(f"| `{m.name}` \\| success") == (2 if conditioned else 0)
        assert rows == (4 if conditioned else 2)
    for title in METRIC_GROUPS.values():
        assert md.count(f"*{title}*") == 2
    assert "## s1" in md
    assert "## s2" in md
    assert "| `frechet_m` ↓ | m | **2.00 ± 1.00** | 3.00 ± 1.00 |" in md
    tex = to_latex_extended(table)
    assert tex.count("\\begin{tabular}") == 2
    assert "\\texttt{frechet\\_m} $\\downarrow$ & m & $\\mathbf{2.00 \\pm 1.00}$" in tex


def test_nothing_is_bold_when_every_planner_ties() -> None:
    # Success: "a" and "b" reach the goal in all 10 seeds, "c" in 8 of them.
    results = _time_results({"a": 10, "b": 10, "c": 8})
    columns = [("robot_success", "Success")]
    table = benchmark_table(
        results,
        scenarios=["s"],
        planners=["a", "b"],
        seeds=range(10),
        reference=None,
        columns=columns,
    )
    assert not any(table.cells[("s", p)]["robot_success"].best for p in ("a", "b"))
    assert "**" not in to_markdown(table).split("\n\n")[0]
    assert "none where every planner ties" in to_markdown(table)
    table = benchmark_table(
        results,
        scenarios=["s"],
        planners=["a", "b", "c"],
        seeds=range(10),
        reference=None,
        columns=columns,
    )
    best = {p for p in ("a", "b", "c") if table.cells[("s", p)]["robot_success"].best}
    assert best == {"a", "b"}  # a tie at the top is still bold when someone is worse


def test_the_t_tests_give_scipys_bits() -> None:
    """compare's two t-tests are scipy.stats.ttest_ind(equal_var=False) and ttest_rel
    written out: the same p-values to the bit on random samples (sizes 2-60, rounded
    values with ties, tiny spreads, one sample a copy of the other)."""
    from scipy import stats

    from srfm.metrics.stats import _paired_p, _welch_p

    rng = np.random.default_rng(7)
    for trial in range(400):
        n, m = (int(k) for k in rng.integers(2, 60, size=2))
        a = rng.normal(rng.uniform(-5, 5), rng.uniform(1e-3, 3), n)
        b = rng.normal(rng.uniform(-5, 5), rng.uniform(1e-3, 3), m)
        if trial % 4 == 1:
            a, b = np.round(a, 1), np.round(b, 1)
        elif trial % 4 == 2:
            a = np.abs(a) * 1e-7
        elif trial % 4 == 3:
            b = a[: min(n, m)] + rng.normal(0, 1e-9, min(n, m))
        welch = float(stats.ttest_ind(a, b, equal_var=False).pvalue)
        assert _welch_p(a, b) == welch or (np.isnan(welch) and np.isnan(_welch_p(a, b)))
        k = min(a.size, b.size)
        paired = float(stats.ttest_rel(a[:k], b[:k]).pvalue)
        assert _paired_p(a[:k], b[:k]) == paired


def test_holm_and_bh_match_hand_computed_values() -> None:
    p = [0.01, 0.04, 0.03, 0.005, math.nan]
    # m = 4 defined; sorted 0.005, 0.01, 0.03, 0.04.
    # Holm: 4·0.005 = 0.02, 3·0.01 = 0.03, 2·0.03 = 0.06, 1·0.04 = 0.04 -> running max.
    holm = adjust_p_values(p, "holm")
    np.testing.assert_allclose(holm[:4], [0.03, 0.06, 0.06, 0.02], rtol=0, atol=1e-15)
    # BH: 4/1·0.005 = 0.02, 4/2·0.01 = 0.02, 4/3·0.03 = 0.04, 4/4·0.04 = 0.04 -> running
    # min from the largest.
    bh = adjust_p_values(p, "bh")
    np.testing.assert_allclose(bh[:4], [0.02, 0.04, 0.04, 0.02], rtol=0, atol=1e-15)
    assert math.isnan(holm[4])
    assert math.isnan(bh[4])
    assert adjust_p_values([0.6, 0.5], "holm").tolist() == [1.0, 1.0]  # capped at 1
    np.testing.assert_array_equal(adjust_p_values(p, "none"), np.array(p))
    with pytest.raises(MetricError, match="unknown correction 'bonf'"):
        adjust_p_values(p, "bonf")
    with pytest.raises(MetricError, match=r"\[0, 1\], got 1.5"):
        adjust_p_values([0.1, 1.5], "holm")


def _episode(planner: str, seed: int, outcome: str, frechet: float) -> EpisodeMetrics:
    return EpisodeMetrics(
        scenario="s",
        planner=planner,
        seed=seed,
        outcome=outcome,
        end_step=10,
        values={"frechet_m": frechet, "min_robot_distance_m": 1.0 + seed},
        pedestrians={},
    )


def test_columns_conditioned_on_success_and_outcome_shares() -> None:
    # ref reaches its goal in seeds 0, 1, 3 (a collision in seed 2, where it deviates
    # people most); "stops" only in seeds 0 and 3 (two timeouts, little deviation).
    results = [
        _episode("ref", 0, "goal_reached", 1.0),
        _episode("ref", 1, "goal_reached", 2.0),
        _episode("ref", 2, "collision", 9.0),
        _episode("ref", 3, "goal_reached", 3.0),
        _episode("stops", 0, "goal_reached", 0.5),
        _episode("stops", 1, "timeout", 0.1),
        _episode("stops", 2, "timeout", 0.2),
        _episode("stops", 3, "goal_reached", 1.5),
    ]
    table = benchmark_table(
        results,
        scenarios=["s"],
        planners=["ref", "stops"],
        seeds=range(4),
        reference="ref",
        columns=[("frechet_m", "Fréchet"), (given_success("frechet_m"), "Fréchet | success")],
    )
    ref = table.cells[("s", "ref")]
    stops = table.cells[("s", "stops")]
    assert ref["frechet_m"].summary.mean == pytest.approx(15.0 / 4)
    assert ref["frechet_m|success"].summary.n == 3
    assert ref["frechet_m|success"].summary.mean == pytest.approx(2.0)
    assert ref["frechet_m|success"].summary.std == pytest.approx(1.0)
    assert stops["frechet_m"].summary.mean == pytest.approx(0.575)
    assert stops["frechet_m|success"].summary.n == 2
    assert stops["frechet_m|success"].summary.mean == pytest.approx(1.0)
    # Paired over the seeds where both reached the goal: 0 and 3.
    assert table.comparisons[("s", "stops")]["frechet_m|success"].n_pairs == 2
    assert table.outcomes[("s", "ref")] == {
        "goal_reached": 3,
        "collision": 1,
        "out_of_bounds": 0,
        "timeout": 0,
        "planner_failed": 0,
    }
    md = to_markdown(table)
    # The conditioned cell always shows n, the unconditional one only below S.
    # stops deviates less but reached the goal 25 percentage points less often than
    # ref, beyond the 10-point margin (GOAL_MARGIN): it is not bold, ref is.
    assert "| s | ref | **3.75 ± 3.59** | 2.00 ± 1.00 (n=3) | 75 % goal, 25 % coll. |" in md
    assert "| s | stops | 0.57 ± 0.64 | 1.00 ± 0.71 (n=2) | 50 % goal, 50 % timeout |" in md
    assert md.splitlines()[0] == (
        "| Scenario | Planner | Fréchet ↓ | Fréchet \\| success ↓ | Outcomes |"
    )
    tex = to_latex(table)
    assert "75 \\% goal, 25 \\% coll." in tex
    summary = summary_dict(table)
    assert summary["outcomes"]["s"]["stops"]["timeout"] == 2
    assert summary["scenarios"]["s"]["stops"]["frechet_m|success"]["n"] == 2
    extended = to_markdown_extended(table)
    assert "| Outcomes | | 75 % goal, 25 % coll. | 50 % goal, 50 % timeout |" in extended
    assert "| `frechet_m` \\| success ↓ | m | 2.00 ± 1.00 (n=3) | 1.00 ± 0.71 (n=2) |" in extended


def test_marks_follow_the_adjusted_p_values_of_the_table_family() -> None:
    # Six scenarios, each with a small paired shift of "b" against "a": several are
    # significant before the correction and fewer after it.
    rng = np.random.default_rng(7)
    scenarios = [f"s{k}" for k in range(6)]
    results = []
    for k, scenario in enumerate(scenarios):
        for seed in range(12):
            base = rng.normal(1.0, 0.2)
            for planner, shift in (("a", 0.0), ("b", 0.01 * k + rng.normal(0.0, 0.04))):
                results.append(
                    EpisodeMetrics(
                        scenario=scenario,
                        planner=planner,
                        seed=seed,
                        outcome="goal_reached",
                        end_step=10,
                        values={"frechet_m": base + shift},
                        pedestrians={},
                    )
                )
    kwargs = {
        "scenarios": scenarios,
        "planners": ["a", "b"],
        "seeds": range(12),
        "reference": "a",
        "columns": [("frechet_m", "F")],
    }
    holm = benchmark_table(results, **kwargs)  # type: ignore[arg-type]
    plain = benchmark_table(results, correction="none", **kwargs)  # type: ignore[arg-type]
    raw = np.array([holm.comparisons[(s, "b")]["frechet_m"].paired_p for s in scenarios])
    adjusted = np.array(
        [holm.comparisons[(s, "b")]["frechet_m"].paired_p_adjusted for s in scenarios]
    )
    np.testing.assert_array_equal(adjusted, adjust_p_values(raw, "holm"))
    marks = [holm.cells[(s, "b")]["frechet_m"].paired for s in scenarios]
    assert marks == [bool(p < 0.05) for p in adjusted]
    plain_marks = [plain.cells[(s, "b")]["frechet_m"].paired for s in scenarios]
    assert plain_marks == [bool(p < 0.05) for p in raw]
    assert sum(plain_marks) > sum(marks) > 0  # the correction takes some marks away
    assert holm.family == {"welch": 6, "paired": 6}
    md = to_markdown(holm)
    assert "Holm's step-down correction" in md
    assert "6 Welch and, separately, 6 paired tests" in md
    entry = summary_dict(holm)["scenarios"]["s0"]["b"]["frechet_m"]
    assert entry["paired_p_adjusted"] == adjusted[0]
    assert summary_dict(holm)["correction"] == "holm"
    with pytest.raises(MetricError, match="unknown correction 'sidak'"):
        benchmark_table(results, correction="sidak", **kwargs)  # type: ignore[arg-type]


def test_reference_points_when_the_run_has_straight_and_oracle() -> None:
    from srfm.benchmark._html import _wide_table
    from srfm.metrics.headroom import headroom

    # "wide": straight 1.0 + noise, oracle 0.6, "half" halfway; "flat": everyone at 1.0
    # but the oracle 0.98 (headroom 0.02 m < 0.1 m: does not discriminate).
    rng = np.random.default_rng(3)
    results = []
    for seed in range(10):
        noise = rng.normal(0.0, 0.05)
        for scenario, values in (
            ("wide", {"straight": 1.0, "oracle": 0.6, "half": 0.8}),
            ("flat", {"straight": 1.0, "oracle": 0.98, "half": 1.0}),
        ):
            for planner, value in values.items():
                results.append(
                    EpisodeMetrics(
                        scenario=scenario,
                        planner=planner,
                        seed=seed,
                        outcome="goal_reached",
                        end_step=10,
                        values={"frechet_m": value + noise + 0.01 * rng.normal()},
                        pedestrians={},
                    )
                )
    table = benchmark_table(
        results,
        scenarios=["wide", "flat"],
        planners=["straight", "oracle", "half"],
        seeds=range(10),
        reference=None,
        columns=[("frechet_m", "F")],
    )
    wide = table.references["wide"]
    values = {
        p: [r.values["frechet_m"] for r in results if r.scenario == "wide" and r.planner == p]
        for p in ("straight", "oracle", "half")
    }
    assert wide.headroom == headroom(values["straight"], values["oracle"])
    assert wide.headroom.estimate == pytest.approx(0.4, abs=0.02)
    assert wide.scores["half"].estimate == pytest.approx(0.5, abs=0.05)
    assert wide.scores["straight"].estimate == 0.0
    assert wide.discriminates
    assert not table.references["flat"].discriminates
    md = to_markdown(table)
    assert "Norm. score ↑" in md.splitlines()[0]
    flat = table.references["flat"].headroom
    assert f"| flat | {flat.estimate:.3f} [{flat.low:.3f}, {flat.high:.3f}] |" in md
    assert flat.estimate == pytest.approx(0.02, abs=0.01)
    assert "**does not discriminate** (headroom < 0.1 m" in md
    summary = summary_dict(table)
    assert summary["references"]["flat"]["discriminates"] is False
    assert summary["references"]["wide"]["scores"]["oracle"]["estimate"] == 1.0
    page = _wide_table(summary)
    assert "<th>Norm. score ↑</th>" in page
    assert '<td class="name bad nodisc">does not discriminate</td>' in page
    # Without the oracle, or without asking, there are no reference points.
    assert not benchmark_table(
        results,
        scenarios=["wide"],
        planners=["straight", "half"],
        seeds=range(10),
        reference=None,
        columns=[("frechet_m", "F")],
    ).references
    assert "Norm. score" not in to_markdown(
        benchmark_table(
            results,
            scenarios=["wide"],
            planners=["straight", "oracle"],
            seeds=range(10),
            reference=None,
            columns=[("frechet_m", "F")],
            with_references=False,
        )
    )
