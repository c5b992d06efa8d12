"""The analysis of issue 40's sidestep fit (srfm.fitting._response): starts, the
multi-start fit and its recovery of a known response, profiles and the identification
rule, the relative changes and the success criterion."""

from __future__ import annotations

import attrs
import numpy as np
import pytest

import srfm
from srfm.datasets import Trajectories, navwareset
from srfm.errors import ParameterError
from srfm.fitting import (
    PROTOCOL,
    WindowConfig,
    best_fit,
    build_windows,
    fit_sidestep,
    identification,
    profile_costs,
    profile_grid,
    relative_change,
    spread_starts,
    success,
)
from tests.datasets._synthetic import resimulate_pedestrian

TRUE = srfm.SRFMParams(
    a_ped=2.0,
    b_ped=0.5,
    lambda_ped=0.4,
    tau=0.8,
    robot_form="sidestep",
    ss_a=1.0,
    ss_miss=1.2,
    ss_horizon=3.0,
    ss_speed_gain=0.0,
)
# a small protocol for the tests: two fields, three starts
SMALL = attrs.evolve(PROTOCOL, fields=("ss_a", "ss_miss"), n_starts=2, refine_nfev=60)


def test_starts_are_the_defaults_and_a_deterministic_spread_within_the_bounds() -> None:
    starts = spread_starts()
    assert len(starts) == 1 + PROTOCOL.n_starts >= 9
    defaults = srfm.SRFMParams(robot_form="sidestep")
    assert starts[0] == {f: getattr(defaults, f) for f in PROTOCOL.fields}
    assert spread_starts() == starts
    for s in starts[1:]:
        assert list(s) == list(PROTOCOL.fields)
        for f, v in s.items():
            lo, hi = PROTOCOL.bounds[f]
            assert lo <= v <= hi, (f, v)
        assert s["ss_a"] >= PROTOCOL.bounds["ss_a"][1] / PROTOCOL.log_span
    # spread: every field's starts cover more than half of its (log) range
    for f in PROTOCOL.fields:
        values = np.array([s[f] for s in starts[1:]])
        if f in PROTOCOL.log_fields:
            values = np.log(values)
            top = PROTOCOL.bounds[f][1]
            lo, hi = np.log(top / PROTOCOL.log_span), np.log(top)
        else:
            lo, hi = PROTOCOL.bounds[f]
        assert values.max() - values.min() > 0.5 * (hi - lo), f


@pytest.fixture(scope="module")
def resimulated() -> srfm.fitting.Windows:
    from tests.datasets.conftest import data_dir

    root = data_dir() / "navwareset"
    if not root.is_dir():
        pytest.skip(f"NavWareSet excerpt not found at {root}; set SRFM_DATA_DIR")
    scenes: list[Trajectories] = navwareset.read_navwareset(root)
    truth: dict[str, list[object]] = {}
    scenes = [resimulate_pedestrian(s, TRUE, truth) for s in scenes]
    windows = build_windows(scenes, WindowConfig(stride_s=0.4, min_start_speed_mps=0.3))
    goal = np.array(truth["goal"], dtype=np.float64)[windows.scene]
    v0 = np.array(truth["v0"], dtype=np.float64)[windows.scene]
    return attrs.evolve(windows, goal=np.ascontiguousarray(goal), v0=v0, vmax=1.3 * v0)


def test_fit_recovers_a_known_sidestep_response(resimulated: srfm.fitting.Windows) -> None:
    every = np.arange(resimulated.n_windows, dtype=np.int64)
    base = TRUE.replace(ss_a=0.2, ss_miss=0.75)
    fits = fit_sidestep(resimulated, base, every, full=True, protocol=SMALL)
    assert len(fits) == 1 + SMALL.n_starts
    assert not any(f.refined for f in fits)
    best = best_fit(fits)
    assert best.cost == min(f.cost for f in fits)
    assert best.end["ss_a"] == pytest.approx(TRUE.ss_a, rel=0.3)
    assert best.end["ss_miss"] == pytest.approx(TRUE.ss_miss, rel=0.2)
    # a held-out fold's procedure: short starts, the best one refined
    short = fit_sidestep(resimulated, base, every, full=False, protocol=SMALL)
    assert sum(f.refined for f in short) == 1
    assert best_fit(short).refined
    # the profile of the amplitude rises on both sides: identified
    costs = profile_costs(resimulated, base, every, best.end, "ss_a", protocol=SMALL)
    grid = profile_grid("ss_a", SMALL)
    status = identification("ss_a", best.end["ss_a"], grid, costs, best.cost, SMALL)
    assert status == "identified"
    with pytest.raises(ParameterError, match="no interaction windows"):
        fit_sidestep(resimulated, base, np.zeros(0, dtype=np.int64), full=True, protocol=SMALL)


def test_identification_rule() -> None:
    grid = np.linspace(0.1, 3.0, 9)
    v = 100.0 + 10.0 * (grid - 1.2) ** 2
    assert identification("ss_miss", 1.2, grid, v, 100.0) == "identified"
    flat = 100.0 + 0.5 * (grid - 1.2) ** 2  # rises by < 1 % on the left
    assert identification("ss_miss", 1.2, grid, flat, 100.0) == "not identified"
    one_sided = 100.0 + 10.0 * (grid - 1.2) ** 2 * (grid > 1.2)
    assert identification("ss_miss", 1.2, grid, one_sided, 100.0) == "not identified"
    rising = 100.0 + 5.0 * (grid - 0.1)
    assert identification("ss_miss", 0.1, grid, rising, 100.0) == "identified at its bound"
    np.testing.assert_allclose(profile_grid("ss_miss"), np.linspace(0.1, 3.0, 9))
    cap = profile_grid("robot_force_cap")
    np.testing.assert_allclose([cap[0], cap[-1]], [20.0 / 500.0, 20.0])
    np.testing.assert_allclose(cap[1:] / cap[:-1], cap[1] / cap[0])


def test_relative_change_and_its_scene_level_test() -> None:
    rng = np.random.default_rng(0)
    of = np.repeat(np.arange(8), 5)
    track = np.arange(40)
    base = rng.uniform(0.5, 1.0, 40)
    model = 0.8 * base
    row = relative_change(model, base, of, track, list(range(8)), seed=1)
    assert row["rel"] == pytest.approx(-0.2)
    np.testing.assert_allclose(row["ci95"], [-0.2, -0.2])
    assert (row["n_windows"], row["n_tracks"], row["n_scenes"]) == (40, 40, 8)
    assert row["p"] == pytest.approx(2.0 / 2**8)  # every scene better: the exact minimum
    # a subset of scenes, NaN windows left out
    model[0] = np.nan
    sub = relative_change(model, base, of, track, [0, 1], seed=1)
    assert (sub["n_windows"], sub["n_scenes"]) == (9, 2)
    again = relative_change(model, base, of, track, [0, 1], seed=1)
    assert again == sub
    with pytest.raises(ParameterError, match="no windows"):
        relative_change(model, base, of, track, [], seed=1)


def test_success_needs_all_three_parts() -> None:
    good = {"rel": -0.15, "p_holm": 0.01, "ci90": [-0.2, -0.1]}
    ade = {"rel": 0.0, "ci90": [-0.01, 0.015]}
    assert success(good, good, ade) == {"pass": True, "offset": True, "ade": True, "met": True}
    assert not success({**good, "rel": -0.09}, good, ade)["met"]  # pass gain < 10 %
    assert not success(good, {**good, "rel": -0.04}, ade)["met"]  # offset gain < 5 %
    assert not success(good, {**good, "p_holm": 0.06}, ade)["met"]
    assert not success(good, good, {"rel": 0.0, "ci90": [-0.01, 0.021]})["met"]
    # better than equivalent counts
    assert success(good, good, {"rel": -0.05, "ci90": [-0.08, -0.03]})["met"]
