"""run_planners: the counterfactual crowd simulated once for several planners gives the
records that one run_episode per planner gives, bit for bit (issue 39)."""

from __future__ import annotations

import attrs
import numpy as np
import pytest

import srfm
from srfm.sim.episode import run_planners
from srfm.sim.record import EpisodeRecord

_PLANNERS = ("straight", "dwa", "social-force")


def _assert_same(shared: EpisodeRecord, alone: EpisodeRecord) -> None:
    for name, value in alone.arrays().items():
        other = shared.arrays()[name]
        assert other.dtype == value.dtype, name
        assert other.tobytes() == value.tobytes(), name
    for field in attrs.fields(EpisodeRecord):
        value = getattr(alone, field.name)
        if not isinstance(value, np.ndarray):
            assert getattr(shared, field.name) == value, field.name


@pytest.mark.parametrize(
    ("scenario", "seed"),
    [
        ("crosswalk", 0),  # a paper scenario: the robot at rest for most of the horizon
        ("random", 3),  # re-goaling: both twins draw new goals
        ("entering_room", 1),  # pedestrians entering, routes around obstacles
        ("corridor_flow", 2),  # entries, walls
        ("blind_corner", 0),  # the robot's route
    ],
)
def test_shared_counterfactual_gives_each_planner_s_own_record(scenario: str, seed: int) -> None:
    shared = list(run_planners(scenario, seed, list(_PLANNERS)))
    assert [r.planner for r in shared] == list(_PLANNERS)
    arrivals = 0
    for record in shared:
        alone = srfm.run_episode(scenario, seed, record.planner)
        _assert_same(record, alone)
        arrivals += sum(e.twin == "counterfactual" for e in alone.events)
    if scenario in ("crosswalk", "random"):  # the events of both twins were merged
        assert arrivals > 0


def test_shared_counterfactual_with_the_cut_off_and_other_parameters() -> None:
    scenario = attrs.evolve(srfm.load_scenario("station_concourse"), horizon_steps=60)
    params = srfm.SRFMParams(a_robot=3.0)
    shared = list(run_planners(scenario, 0, ["straight", "orca"], params))
    for record in shared:
        _assert_same(record, srfm.run_episode(scenario, 0, record.planner, params))


def test_each_record_has_arrays_of_its_own() -> None:
    first, second = run_planners("crosswalk", 0, ["straight", "dwa"])
    assert not np.shares_memory(first.counterfactual_pos, second.counterfactual_pos)
    assert second.counterfactual_pos.flags.writeable
    assert np.array_equal(first.counterfactual_vel, second.counterfactual_vel)


def test_no_planner_gives_no_record() -> None:
    assert list(run_planners("crosswalk", 0, [])) == []
