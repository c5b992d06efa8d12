"""Crowd substeps (the crowd at a finer step, the control rate unchanged) and the noise
floor's nudged twins (issue 41)."""

from __future__ import annotations

import attrs
import numpy as np
import pytest

import srfm
from srfm.benchmark._results import fingerprint
from srfm.errors import BenchmarkError, ScenarioError, SimulationError
from srfm.metrics import episode_metrics
from srfm.scenarios import load_scenario, parse_scenario
from srfm.sim.floor import NUDGE_M, nudged_pedestrian, nudged_twins


def test_substeps_are_the_crowd_at_the_finer_step() -> None:
    """With the robot unfelt, two substeps of dt/2 per step are the crowd stepped at
    dt/2 for twice the horizon, sampled at every other step: bit for bit."""
    base = attrs.evolve(load_scenario("footpath"), horizon_steps=60)
    off = srfm.SRFMParams(a_robot=0.0)
    sub = srfm.run_episode(attrs.evolve(base, crowd_substeps=2), 0, "stay", off)
    fine = srfm.run_episode(
        attrs.evolve(base, dt_s=base.dt_s / 2.0, horizon_steps=120), 0, "stay", off
    )
    np.testing.assert_array_equal(sub.factual_pos, fine.factual_pos[::2])
    np.testing.assert_array_equal(sub.counterfactual_pos, fine.counterfactual_pos[::2])
    assert sub.dt_s == base.dt_s  # the record keeps the control step's samples
    assert sub.factual_pos.shape[0] == 61


def test_substeps_change_the_episode_and_keep_its_samples() -> None:
    base = attrs.evolve(load_scenario("crosswalk"), horizon_steps=120)
    one = srfm.run_episode(base, 0, "dwa")
    again = srfm.run_episode(attrs.evolve(base, crowd_substeps=1), 0, "dwa")
    four = srfm.run_episode(attrs.evolve(base, crowd_substeps=4), 0, "dwa")
    np.testing.assert_array_equal(one.factual_pos, again.factual_pos)
    assert four.factual_pos.shape == one.factual_pos.shape
    assert not np.array_equal(four.factual_pos, one.factual_pos)
    d1 = episode_metrics(one)["frechet_m"]
    d4 = episode_metrics(four)["frechet_m"]
    assert d4 == pytest.approx(d1, rel=0.2)  # the same episode, a finer crowd step


def test_substeps_in_the_schema_and_the_fingerprint() -> None:
    base = load_scenario("footpath")
    assert base.crowd_substeps == 1
    # the default leaves the fingerprint of before (folders keep their manifests)
    assert fingerprint(base) == fingerprint(attrs.evolve(base, crowd_substeps=1))
    assert fingerprint(base) != fingerprint(attrs.evolve(base, crowd_substeps=2))
    doc = {
        "schema_version": 1,
        "name": "s",
        "description": "d",
        "simulation": {"crowd_substeps": 3},
        "robot": {"start": [1.0, 1.0], "goal": [5.0, 5.0]},
        "pedestrians": {"starts": [[8.0, 8.0]], "goals": [[12.0, 12.0]]},
    }
    assert parse_scenario(doc, "x").crowd_substeps == 3
    doc["simulation"] = {"crowd_substeps": 0}
    with pytest.raises(ScenarioError, match=r"crowd_substeps.*got 0"):
        parse_scenario(doc, "x")


def test_request_substeps() -> None:
    from srfm.benchmark import BenchmarkRequest

    req = BenchmarkRequest.create(scenarios=["footpath"], planners=["straight"], crowd_substeps=4)
    assert req.scenarios[0].crowd_substeps == 4
    with pytest.raises(
        BenchmarkError, match=r"crowd_substeps must be an integer in \[1, 64\], got 65"
    ):
        BenchmarkRequest.create(scenarios=["footpath"], planners=["straight"], crowd_substeps=65)


def test_nudged_twins() -> None:
    scenario = attrs.evolve(load_scenario("crosswalk"), horizon_steps=90)
    twins = nudged_twins(scenario, 3)
    who = nudged_pedestrian(3, scenario.n_pedestrians)
    assert twins.nudged == who == 3 % scenario.n_pedestrians
    start = twins.nudged_pos[0] - twins.reference_pos[0]
    expect = np.zeros_like(start)
    expect[who, 0] = NUDGE_M
    np.testing.assert_allclose(start, expect, atol=1e-12)
    # the reference crowd is the benchmark episode's counterfactual crowd
    record = srfm.run_episode(scenario, 3, "dwa")
    np.testing.assert_array_equal(twins.reference_pos, record.counterfactual_pos)
    again = nudged_twins(scenario, 3)
    np.testing.assert_array_equal(again.nudged_pos, twins.nudged_pos)
    with pytest.raises(SimulationError, match=r"nudge_m must be a finite number > 0, got -1\.0"):
        nudged_twins(scenario, 0, nudge_m=-1.0)
    with pytest.raises(SimulationError, match="seed must be"):
        nudged_twins(scenario, -1)


@pytest.mark.parametrize("name", ["crosswalk", "circle", "blind_corner", "random"])
def test_the_floor_from_an_episodes_counterfactual_crowd_is_the_same(name: str) -> None:
    """The benchmark computes a seed's floor from the counterfactual crowd its first
    planner's episode simulated (only the nudged copy is stepped): the same bits as
    simulating both."""
    from srfm.models.params import SRFMParams
    from srfm.sim.episode import run_planners

    scenario = load_scenario(name)
    params = SRFMParams.preset("navwareset2026_ttc")
    record = next(run_planners(scenario, 3, ["dwa"], params))
    both = nudged_twins(scenario, 3, params)
    shared = nudged_twins(scenario, 3, params, reference=record.counterfactual_pos)
    assert np.array_equal(both.reference_pos, record.counterfactual_pos)
    assert np.array_equal(both.nudged_pos, shared.nudged_pos)
    assert both.nudged == shared.nudged
    with pytest.raises(SimulationError, match="reference must be the crowd's"):
        nudged_twins(scenario, 3, params, reference=record.counterfactual_pos[:-1])


def test_the_floor_of_a_scenario_whose_people_all_enter_later() -> None:
    """corridor_flow has nobody at sample 0: the first pedestrians to enter are nudged
    (at their starts, where they wait until they enter), and the benchmark runs."""
    from srfm.sim.episode import episode_setup
    from srfm.sim.floor import first_present

    scenario = attrs.evolve(load_scenario("corridor_flow"), horizon_steps=240)
    enter = episode_setup(scenario, 5).ped_enter_step
    assert enter is not None
    assert not np.any(enter == 0)
    assert np.all(np.diff(enter) >= 0)  # entry order: the first ones enter first
    n_first = first_present(enter, len(enter))
    assert n_first == np.count_nonzero(enter == enter.min()) >= 1
    twins = nudged_twins(scenario, 5)
    assert twins.nudged == 5 % n_first
    assert enter[twins.nudged] == enter.min()
    moved = twins.nudged_pos[0] - twins.reference_pos[0]
    assert moved[twins.nudged, 0] == pytest.approx(NUDGE_M)
    k = int(enter.min()) + 1  # once entered, the nudged start has moved the walk
    assert twins.nudged_pos[k, twins.nudged, 0] != twins.reference_pos[k, twins.nudged, 0]
    assert first_present(None, 7) == 7
    with pytest.raises(SimulationError, match="needs a pedestrian"):
        nudged_pedestrian(0, 0)
