"""Checks of every scenario of the library (issue 17): the Francis scenarios and the
NavWareSet room. Over the issue's 20 seeds (their cost: docs/scenarios.md, "Checks"): the
counterfactual pedestrians reach their goals (>= 95 %) and never stand in a wall,
nobody overlaps at the start, DWA reaches the robot goal in >= 90 % of the seeds.
(A_r = 0 keeping the twins bit-identical is checked for every built-in scenario in
tests/sim/test_simulator.py.)"""

from __future__ import annotations

from pathlib import Path

import attrs
import numpy as np
import pytest
from click.testing import CliRunner

from srfm.cli import main
from srfm.errors import ScenarioError
from srfm.models.state import Obstacles
from srfm.scenarios import (
    BUILTIN_SCENARIOS,
    EVALUATION_SCENARIOS,
    FLOW_SCENARIOS,
    FRANCIS_SCENARIOS,
    NAVWARESET_SCENARIOS,
    load_scenario,
)
from srfm.scenarios.suites import SUITES
from srfm.sim.checks import check_scenario, wall_distance
from tests.scenarios.test_scenarios import write_scenario

SEEDS = range(20)
LIBRARY = (*FRANCIS_SCENARIOS, *NAVWARESET_SCENARIOS, *FLOW_SCENARIOS)


@pytest.mark.parametrize("name", LIBRARY)
def test_library_scenario(name: str) -> None:
    check = check_scenario(name, SEEDS, "dwa")
    assert check.overlapping_starts == 0
    assert check.in_wall_samples == 0
    assert check.arrival_rate >= 0.95, check
    assert check.robot_goals >= 0.9 * len(SEEDS), check


def test_library_size_and_suites() -> None:
    assert len(FRANCIS_SCENARIOS) >= 14
    assert len(NAVWARESET_SCENARIOS) == 5
    assert set(LIBRARY) <= set(BUILTIN_SCENARIOS)
    assert SUITES["paper"] == EVALUATION_SCENARIOS
    assert SUITES["francis"] == FRANCIS_SCENARIOS
    assert SUITES["navwareset"] == NAVWARESET_SCENARIOS
    assert SUITES["flows"] == FLOW_SCENARIOS
    assert SUITES["all"] == (*EVALUATION_SCENARIOS, *LIBRARY)
    for name in LIBRARY:
        scenario = load_scenario(name)
        assert scenario.schema_version == 2
        assert scenario.description
        assert "\n" not in scenario.description
    room = load_scenario("navwareset_circular_crossing")
    assert room.map_points is not None
    assert len(room.map_points) > 500
    assert room.region("passage") == (4.35, -8.0, 7.8, -2.3)


def test_srfm_scenarios_lists_the_library() -> None:
    result = CliRunner().invoke(main, ["scenarios"])
    assert result.exit_code == 0, result.output
    for name in LIBRARY:
        assert name in result.output
    assert "NavWareSet room" in result.output


def test_wall_distance() -> None:
    obstacles = Obstacles.create(segments=[[0.0, 0.0, 2.0, 0.0]], circles=[[5.0, 5.0, 1.0]])
    d = wall_distance(np.array([[1.0, 0.5], [3.0, 0.0], [5.0, 5.5], [5.0, 7.0]]), obstacles)
    np.testing.assert_allclose(d, [0.5, 1.0, -0.5, 1.0])


def test_check_catches_a_trapped_pedestrian(tmp_path: Path) -> None:
    """A pedestrian whose goal is boxed in by walls never arrives; the check says so.

    A scenario file of either version with such a goal is refused when it is read
    (issue 33: the router finds no path to it), so the walls are added to the loaded
    scenario, as code building scenarios may do."""
    head = """schema_version = 1
name = "trap"
description = "x"
[robot]
start = [1.0, 1.0]
goal = [4.0, 1.0]
[pedestrians]
noise_m = 0.0
starts = [[2.0, 12.0]]
goals = [[12.0, 12.0]]
"""
    box = [[10.0, 10.0, 14.0, 10.0], [14.0, 10.0, 14.0, 14.0], [14.0, 14.0, 10.0, 14.0],
           [10.0, 14.0, 10.0, 10.0]]  # fmt: skip
    walls = "[obstacles]\nwalls = " + repr(box) + "\n"
    with pytest.raises(ScenarioError, match=r"pedestrians\.goals\[0\]: unreachable"):
        load_scenario(write_scenario(tmp_path / "trap_file.toml", head + walls))
    free = load_scenario(write_scenario(tmp_path / "trap.toml", head))
    trapped = attrs.evolve(free, obstacles=Obstacles.create(segments=box))
    check = check_scenario(trapped, range(1), "straight")
    assert check.ped_arrived == 0
    assert check.ped_total == 1
    assert check.robot_goals == 1


def test_benchmark_runs_the_navwareset_suite(tmp_path: Path) -> None:
    out = tmp_path / "nav"
    result = CliRunner().invoke(
        main,
        [
            "benchmark",
            "--suite",
            "navwareset",
            "-p",
            "straight",
            "--seeds",
            "0",
            "-j",
            "1",
            "--no-logs",
            "--no-figures",
            "--out",
            str(out),
        ],
    )
    assert result.exit_code == 0, result.output
    assert "5 scenarios × 1 planner × 1 seed" in result.output
    rows = (out / "episodes.csv").read_text().splitlines()
    assert len(rows) == 1 + len(NAVWARESET_SCENARIOS)
    for name in NAVWARESET_SCENARIOS:
        assert any(row.startswith(f"{name},straight,0,") for row in rows[1:])
