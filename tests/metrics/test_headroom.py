"""Headroom, normalised scores, standard errors and seeds needed against hand-computed
values (srfm.metrics.headroom)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from srfm.errors import MetricError
from srfm.metrics.headroom import (
    discriminates,
    headroom,
    normalised_score,
    paired_sd,
    scenario_references,
    seeds_needed,
    sigma_d,
    standard_error,
)


def test_headroom_is_the_paired_t_interval() -> None:
    straight = np.array([1.0, 1.5, 0.8, math.nan])
    oracle = np.array([0.9, 1.2, 0.6, 0.5])  # differences 0.1, 0.3, 0.2 (the NaN seed out)
    room = headroom(straight, oracle)
    # mean 0.2, SD 0.1, t(0.975, 2) = 4.302653
    half = 4.302652729749464 * 0.1 / math.sqrt(3)
    assert room.n == 3
    assert room.estimate == pytest.approx(0.2)
    assert (room.low, room.high) == pytest.approx((0.2 - half, 0.2 + half))
    assert not room.excludes_zero()  # three seeds are too few to tell
    # six seeds, differences 0.1, 0.3, 0.2, 0.2, 0.2, 0.2: the interval excludes zero
    assert headroom([*straight[:3], 1.0, 1.1, 1.2], [*oracle[:3], 0.8, 0.9, 1.0]).excludes_zero()
    one = headroom([1.0], [0.5])
    assert one.estimate == 0.5
    assert math.isnan(one.low)


def test_normalised_score() -> None:
    s = np.array([1.0, 1.2, 0.9, 1.1, 1.3])
    o = s - np.array([0.4, 0.5, 0.6, 0.5, 0.5])
    assert normalised_score(s, s, o).estimate == 0.0
    top = normalised_score(s, o, o)
    assert (top.estimate, top.low, top.high) == (1.0, 1.0, 1.0)
    # a planner halfway on every seed: 0.5 in every resample
    half = normalised_score(s, (s + o) / 2.0, o)
    assert half.estimate == pytest.approx(0.5)
    assert (half.low, half.high) == pytest.approx((0.5, 0.5))
    # (mean gain 0.1) / (mean headroom 0.5) = 0.2, its interval around it, reproducible
    p = s - np.array([0.0, 0.2, 0.1, 0.0, 0.2])
    score = normalised_score(s, p, o)
    assert score.estimate == pytest.approx(0.2)
    assert score.low < 0.2 < score.high
    assert normalised_score(s, p, o) == score
    # worse than straight: negative; no headroom: undefined
    assert normalised_score(s, s + 0.5, o).estimate == pytest.approx(-1.0)
    assert math.isnan(normalised_score(s, p, s).estimate)


def test_seeds_needed_matches_the_paired_t_test_tables() -> None:
    # two-sided paired t-test, alpha 0.05, power 0.8 (Cohen's d = delta / sd_d):
    # d = 0.5 -> 34 pairs, d = 1 -> 10, d = 0.25 -> 128 (G*Power's values)
    assert seeds_needed(0.1, 0.05) == 34
    assert seeds_needed(0.05, 0.05) == 10
    assert seeds_needed(0.2, 0.05) == 128
    assert seeds_needed(0.0) == 2
    with pytest.raises(MetricError, match="sd_diff"):
        seeds_needed(math.nan)
    with pytest.raises(MetricError, match="delta"):
        seeds_needed(0.1, 0.0)


def test_standard_error_and_paired_sd() -> None:
    assert standard_error([1.0, 2.0, 3.0, math.nan]) == pytest.approx(1.0 / math.sqrt(3))
    assert paired_sd([1.0, 2.0, 4.0], [0.0, 0.0, 0.0]) == pytest.approx(math.sqrt(7 / 3))
    with pytest.raises(MetricError, match="one value per shared seed"):
        paired_sd([1.0, 2.0], [1.0])


def test_discrimination_flag() -> None:
    assert not discriminates(0.09, 0.001)  # below 0.1 m
    assert not discriminates(0.2, 0.1)  # below 3 standard errors
    assert discriminates(0.31, 0.1)
    assert not discriminates(math.nan, 0.1)


def test_scenario_references() -> None:
    s = np.array([1.0, 1.2, 0.9, 1.1])
    values = {
        "straight": s,
        "oracle": s - 0.5,
        "dwa": s - 0.25,
        "vo": s - 0.25 + np.array([0.1, -0.1, 0.1, -0.1]),
    }
    refs = scenario_references(values)
    assert refs.n == 4
    assert refs.headroom.estimate == pytest.approx(0.5)
    assert refs.standard_error == pytest.approx(float(np.std(s, ddof=1)) / 2.0)
    assert refs.scores["dwa"].estimate == pytest.approx(0.5)
    # sigma_d from the only pair of non-reference planners, dwa - vo: SD of +-0.1
    assert refs.sd_diff == pytest.approx(paired_sd(values["dwa"], values["vo"]))
    assert refs.seeds_needed == seeds_needed(refs.sd_diff)
    assert refs.discriminates
    with pytest.raises(MetricError, match="'oracle'"):
        scenario_references({"straight": s})


def test_sigma_d_is_the_median_paired_sd_of_the_entries_without_the_oracle() -> None:
    rng = np.random.default_rng(3)
    values = {p: rng.normal(size=30) for p in ("straight", "stay", "a", "b", "c")}
    expected = float(
        np.median(
            [
                paired_sd(values["a"], values["b"]),
                paired_sd(values["a"], values["c"]),
                paired_sd(values["b"], values["c"]),
            ]
        )
    )
    assert sigma_d(values) == expected
    # the same σ_d as the reference points of a run with the oracle
    with_oracle = {**values, "oracle": values["straight"] - 0.5}
    assert scenario_references(with_oracle).sd_diff == expected
    assert math.isnan(sigma_d({"straight": values["straight"], "a": values["a"]}))
    assert sigma_d({"a": values["a"]}, fallback=("a", "a")) == 0.0
