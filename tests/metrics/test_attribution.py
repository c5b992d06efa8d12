"""The noise floor, the direct / knock-on split, the suite statistics and the paired
normalised score (issue 41)."""

from __future__ import annotations

import math

import attrs
import numpy as np
import pytest
from scipy import stats

import srfm
from srfm.errors import MetricError
from srfm.metrics import episode_metrics
from srfm.metrics.attribution import (
    FELT_FORCE_MPS2,
    attributable,
    deviation_split,
    felt_robot,
    floor_summary,
    floor_verdict,
    noise_floor,
)
from srfm.metrics.headroom import min_score_seeds, scenario_references
from srfm.metrics.suite import improvement_probability, iqm, iqm_interval, profile
from srfm.scenarios import load_scenario
from srfm.sim.floor import NUDGE_M, nudged_twins


def test_split_adds_up_to_the_deviation() -> None:
    scenario = attrs.evolve(load_scenario("cross_footpath"), horizon_steps=150)
    m = episode_metrics(srfm.run_episode(scenario, 1, "dwa"))
    split = deviation_split(m)
    assert split["frechet_direct_m"] + split["frechet_knock_on_m"] == pytest.approx(m["frechet_m"])
    felt = felt_robot(m)
    expect = m.pedestrians["robot_force_max_mps2"] >= FELT_FORCE_MPS2
    np.testing.assert_array_equal(felt, expect)
    assert split["pedestrians_felt"] == np.count_nonzero(expect)
    # a pedestrian who never felt the robot counts as knock-on
    peds = dict(m.pedestrians)
    peds["robot_force_max_mps2"] = np.where(np.arange(felt.size) == 0, 0.0, 1.0)
    other = attrs.evolve(m, pedestrians=peds)
    split = deviation_split(other)
    n = felt.size
    assert split["frechet_knock_on_m"] == pytest.approx(m.pedestrians["frechet_m"][0] / n)
    assert split["pedestrians_felt"] == n - 1


def test_noise_floor() -> None:
    scenario = attrs.evolve(load_scenario("footpath"), horizon_steps=60)
    values = noise_floor(nudged_twins(scenario, 0))
    assert values.shape == (scenario.n_pedestrians,)
    assert values[0] >= NUDGE_M - 1e-15  # the nudged one: at least its start offset
    assert np.all(values >= 0.0)
    f = floor_summary([0.001, 0.003], [1.0, 1.0, 1.0])
    assert f.mean == pytest.approx(0.002)
    assert f.std == pytest.approx(math.sqrt(2.0) * 0.001)
    assert f.verdict == "robot"
    assert attributable(0.01, f)
    assert not attributable(0.001, f)
    assert floor_verdict(0.05) == "robot"
    assert floor_verdict(0.3) == "both"
    assert floor_verdict(0.5) == "chaos"
    assert floor_verdict(math.nan) == "–"
    with pytest.raises(MetricError, match="one finite floor value per seed"):
        floor_summary([], [1.0])


def test_iqm_and_its_stratified_interval() -> None:
    rng = np.random.default_rng(3)
    strata = [rng.normal(k, 1.0, 40) for k in range(3)]
    x = iqm_interval(strata)
    assert x.estimate == pytest.approx(stats.trim_mean(np.concatenate(strata), 0.25))
    assert x.low < x.estimate < x.high
    assert x.n == 120
    assert iqm_interval(strata) == x  # a fixed generator: the same interval
    assert iqm([1.0, 2.0, 3.0, 100.0]) == pytest.approx(2.5)
    one = iqm_interval([[1.0], [2.0, 3.0]])  # nothing to resample in a stratum of one
    assert math.isnan(one.low)


def test_improvement_probability() -> None:
    a = [[np.array([0.1, 0.2]), np.array([0.3, 0.1])], [np.array([1.0]), np.array([2.0])]]
    b = [[np.array([0.2, 0.1]), np.array([0.3, 0.5])], [np.array([2.0]), np.array([1.0])]]
    # scenario 1: seed 0 one of two, seed 1 (tie, win) 0.75 -> 0.625; scenario 2: 0.5
    x = improvement_probability(a, b)
    assert x.estimate == pytest.approx((0.625 + 0.5) / 2.0)
    same = improvement_probability(a, a)
    assert same.estimate == 0.5
    with pytest.raises(MetricError, match="same seeds"):
        improvement_probability(a, [b[0][:1], b[1]])


def test_profile() -> None:
    taus = np.array([0.5, 1.0, 2.0, 3.0])
    np.testing.assert_array_equal(profile([1.0, 2.0, 2.0, 4.0], taus), [0.0, 0.25, 0.75, 0.75])


def test_score_on_the_seeds_all_three_reach_the_goal() -> None:
    straight = np.array([2.0, 2.0, 2.0, 2.0])
    oracle = np.array([1.0, 1.0, 1.0, 1.0])
    gentle = np.array([0.5, 0.5, 1.5, 1.5])  # gentle where it fails
    values = {"straight": straight, "oracle": oracle, "p": gentle, "q": gentle}
    ok = np.ones(4, dtype=bool)
    success = {
        "straight": ok,
        "oracle": ok,
        "p": np.array([False, False, True, True]),
        "q": np.array([False, False, False, True]),
    }
    refs = scenario_references(values, success=success, n_bootstrap=200)
    assert refs.scores["p"].estimate == pytest.approx(0.5)  # seeds 2, 3 only
    assert refs.scores["p"].n == 2
    assert min_score_seeds(4) == 2
    assert math.isnan(refs.scores["q"].estimate)  # k = 1 < 2: undefined
    assert refs.scores["q"].n == 1
    assert refs.oracle_is_bound
    # a goal-reaching planner gentler than the oracle: the headroom is a lower bound
    success["p"] = ok
    refs = scenario_references(values, success=success, n_bootstrap=200)
    assert refs.scores["p"].estimate == pytest.approx(1.0)
    values["p"] = np.array([0.5, 0.5, 0.5, 0.5])
    refs = scenario_references(values, success=success, n_bootstrap=200)
    assert refs.beats_oracle == ("p",)
    assert not refs.oracle_is_bound
