"""tools/analysis/suite_summary.py: the per-scenario summary of a results folder
(docs/benchmark.md, the Francis suite), with the success-conditioned means and their n."""

from __future__ import annotations

from tools.analysis.suite_summary import cell, summary


def _row(scenario: str, planner: str, frechet: str, success: int) -> dict[str, str]:
    return {
        "scenario": scenario,
        "planner": planner,
        "frechet_m": frechet,
        "robot_success": str(float(success)),
        "robot_collision": str(float(1 - success)),
    }


ROWS = [
    _row("b", "stay", "0.5", 0),
    _row("b", "stay", "0.7", 0),
    _row("b", "dwa", "1.0", 1),
    _row("b", "dwa", "2.0", 0),
    _row("a", "stay", "", 0),  # undefined: left out of the mean, counted in the rate
    _row("a", "stay", "0.4", 0),
    _row("a", "dwa", "1.5", 1),
    _row("a", "dwa", "2.5", 1),
]


def test_cell_conditions_on_success_with_n() -> None:
    dwa_b = ROWS[2:4]
    assert cell(dwa_b, success=False) == "1.50 (50 %)"
    assert cell(dwa_b, success=True) == "1.50; 1.00 (1/2)"
    # every episode reached the goal: the conditioned mean is the mean, shown once
    assert cell(ROWS[6:8], success=True) == "2.00 (2/2)"
    # no episode reached the goal: no conditioned mean, n = 0
    assert cell(ROWS[0:2], success=True) == "0.60; – (0/2)"


def test_summary_keeps_the_run_order_and_averages() -> None:
    lines = summary(ROWS, without=["a"], success=True)
    assert lines[0] == "8 episodes, seeds per cell: [2]"
    assert lines[2] == "| scenario | stay | dwa |"
    assert lines[4] == "| b | 0.60; – (0/2) | 1.50; 1.00 (1/2) |"
    assert lines[5] == "| a | 0.40; – (0/2) | 2.00 (2/2) |"
    # the average of the scenario means; outcome rates pooled over the episodes
    assert lines[6] == "| **all 2** | 0.50 (0 %, 100 % coll.) | 1.75 (75 %, 25 % coll.) |"
    assert (
        lines[7] == "| **all 1 (without a)** | 0.60 (0 %, 100 % coll.) | 1.50 (50 %, 50 % coll.) |"
    )
