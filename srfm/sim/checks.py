"""Checks of a scenario over seeds (issue 17): what every built-in scenario must pass.

:func:`check_scenario` runs a scenario's episodes with one planner and counts, over the
seeds: counterfactual pedestrians that reach their goal (the robot-free crowd must be
able to do what the scenario asks of it), counterfactual samples with a pedestrian's
centre inside a wall or pillar (closer to a wall than half its radius), seeds whose
agents overlap at the start (those there at sample 0), and seeds where the robot
reaches its goal. The built-in library's thresholds (issue 17): ≥ 95 % of pedestrians
arrive over 20 seeds, no sample inside a wall, no overlap, a classical planner reaches
the goal in ≥ 90 % of 20 seeds; the tests (``tests/scenarios/test_francis.py``) and
``tools/scenarios/check_scenarios.py`` check those over seeds 0-19.
"""

from __future__ import annotations

from collections.abc import Iterable

import attrs
import numpy as np
import shapely
from numpy.typing import NDArray

from srfm.models.state import Obstacles
from srfm.scenarios import Scenario, episode_setup, load_scenario
from srfm.sim.episode import run_episode

__all__ = ["ScenarioCheck", "check_scenario", "wall_distance"]


@attrs.frozen(kw_only=True)
class ScenarioCheck:
    """What :func:`check_scenario` counted."""

    scenario: str
    planner: str
    seeds: int
    ped_arrived: int
    ped_total: int
    in_wall_samples: int
    overlapping_starts: int
    robot_goals: int

    @property
    def arrival_rate(self) -> float:
        """Fraction of counterfactual pedestrians that reached their goal."""
        return self.ped_arrived / self.ped_total if self.ped_total else 1.0

    @property
    def robot_success_rate(self) -> float:
        """Fraction of seeds in which the robot reached its goal."""
        return self.robot_goals / self.seeds if self.seeds else 0.0


def wall_distance(points: NDArray[np.float64], obstacles: Obstacles) -> NDArray[np.float64]:
    """Distance (m) from each point of ``points`` (..., 2) to the nearest wall segment or
    pillar surface (negative inside a pillar); inf without obstacles."""
    flat = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    out = np.full(len(flat), np.inf)
    if obstacles.segments.shape[0]:
        walls = shapely.union_all(
            [
                shapely.LineString([(a, b), (c, d)]) if (a, b) != (c, d) else shapely.Point(a, b)
                for a, b, c, d in obstacles.segments
            ]
        )
        out = np.minimum(out, shapely.distance(shapely.points(flat), walls))
    for cx, cy, r in obstacles.circles:
        out = np.minimum(out, np.hypot(flat[:, 0] - cx, flat[:, 1] - cy) - r)
    return out.reshape(np.shape(points)[:-1])


def check_scenario(
    scenario: Scenario | str, seeds: Iterable[int], planner: str = "dwa"
) -> ScenarioCheck:
    """Run ``scenario`` with ``planner`` on ``seeds`` and count (see the module doc)."""
    if not isinstance(scenario, Scenario):
        scenario = load_scenario(scenario)
    arrived = total = in_wall = overlaps = goals = n_seeds = 0
    for seed in seeds:
        n_seeds += 1
        setup = episode_setup(scenario, seed)
        there = setup.n_present(0)  # pedestrians entering later may come where others stood
        starts = np.vstack([setup.robot_start[None], setup.crowd.pos[:there]])
        radii = np.concatenate([[scenario.robot.radius_m], setup.crowd.radius[:there]])
        gap = np.linalg.norm(starts[:, None] - starts[None], axis=2) - radii[:, None] - radii
        np.fill_diagonal(gap, np.inf)
        overlaps += bool(gap.min() < 0.0)
        record = run_episode(scenario, seed, planner)
        if not scenario.obstacles.empty:
            d = wall_distance(record.counterfactual_pos, scenario.obstacles)
            in_wall += int(np.count_nonzero(d < 0.5 * record.ped_radius))
        arrived += len(
            {
                e.agent
                for e in record.events
                if e.kind == "ped_arrival" and e.twin == "counterfactual"
            }
        )
        total += record.n_pedestrians
        goals += record.outcome == "goal_reached"
    return ScenarioCheck(
        scenario=scenario.name,
        planner=planner,
        seeds=n_seeds,
        ped_arrived=arrived,
        ped_total=total,
        in_wall_samples=in_wall,
        overlapping_starts=overlaps,
        robot_goals=goals,
    )
