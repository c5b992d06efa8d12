"""Checks of every Francis scenario (issue 17): over 20 seeds the counterfactual
pedestrians reach their goals and never stand in a wall, nobody overlaps at the start,
and a classical planner reaches the robot goal. (A_r = 0 keeping the twins
bit-identical is checked for every built-in scenario in tests/sim/test_simulator.py.)"""

from __future__ import annotations

import numpy as np
import pytest
import shapely

import srfm
from srfm.scenarios import FRANCIS_SCENARIOS, episode_setup, load_scenario

SEEDS = range(20)


def _wall_distance(pos: np.ndarray, scenario: srfm.Scenario) -> np.ndarray:
    """Distance from each point of (..., 2) to the nearest wall."""
    walls = shapely.union_all(
        [shapely.LineString([(a, b), (c, d)]) for a, b, c, d in scenario.obstacles.segments]
    )
    flat = pos.reshape(-1, 2)
    return np.asarray(shapely.distance(shapely.points(flat), walls)).reshape(pos.shape[:-1])


@pytest.mark.parametrize("name", FRANCIS_SCENARIOS)
def test_francis_scenario(name: str) -> None:
    scenario = load_scenario(name)
    assert scenario.obstacles.segments.shape[0] >= 2
    arrived = total = robot_goals = 0
    for seed in SEEDS:
        setup = episode_setup(scenario, seed)
        starts = np.vstack([setup.robot_start[None], setup.crowd.pos])
        radii = np.concatenate([[scenario.robot.radius_m], setup.crowd.radius])
        gap = np.linalg.norm(starts[:, None] - starts[None], axis=2) - radii[:, None] - radii
        np.fill_diagonal(gap, np.inf)
        assert gap.min() > 0.0, f"{name} seed {seed}: agents overlap at the start"
        record = srfm.run_episode(scenario, seed=seed, planner="dwa")
        inside = (
            _wall_distance(record.counterfactual_pos, scenario)
            < np.broadcast_to(scenario.ped_radius_m, (scenario.n_pedestrians,)) * 0.5
        )
        assert not inside.any(), f"{name} seed {seed}: a pedestrian stands in a wall"
        cf_arrivals = {
            e.agent for e in record.events if e.kind == "ped_arrival" and e.twin == "counterfactual"
        }
        arrived += len(cf_arrivals)
        total += scenario.n_pedestrians
        robot_goals += record.outcome == "goal_reached"
    assert arrived >= 0.95 * total, f"{name}: {arrived}/{total} pedestrians arrived"
    assert robot_goals >= 0.9 * len(SEEDS), f"{name}: DWA reached the goal {robot_goals}/20"
