"""Named scenario suites for ``srfm benchmark --suite NAME``.

A suite is a tuple of built-in scenario names, run in that order. ``paper`` is the
default of ``srfm benchmark`` (the paper's five evaluation scenarios), ``large`` the
large-crowd scenarios of issue 19, ``francis`` the scenarios after Francis et al. 2023,
``navwareset`` the NavWareSet room's five layouts and ``flows`` the scenarios with
pedestrians entering during the run (issue 17); ``all`` is paper, francis, navwareset
and flows (not ``large``, a performance suite of 300-400 pedestrians).
``discriminative`` is the scenarios of ``all`` where the benchmark can tell planners
apart, chosen by the rule of ``tools/analysis/discrimination.py`` on seeds 1000-1099
(``docs/discrimination/selection.json``; a test checks that the two agree; issue 29,
docs/benchmark.md). Add a suite by adding an entry to SUITES and SUITE_DESCRIPTIONS
(``srfm suites`` lists them).
"""

from __future__ import annotations

from typing import Final

from srfm.scenarios import (
    EVALUATION_SCENARIOS,
    FLOW_SCENARIOS,
    FRANCIS_SCENARIOS,
    LARGE_SCENARIOS,
    NAVWARESET_SCENARIOS,
)

__all__ = ["DEFAULT_SUITE", "DISCRIMINATIVE_SCENARIOS", "SUITES", "SUITE_DESCRIPTIONS"]

DISCRIMINATIVE_SCENARIOS: Final = (
    "crosswalk",
    "robot_overtaking",
    "intersection",
    "intersection_open",
    "narrow_hallway",
    "perpendicular_traffic",
    "navwareset_blind_corner",
    "navwareset_perpendicular_crossing",
)
"""The scenarios the selection rule chose on the committed results set
``docs/results/selection`` (seeds 1000-1099, the shipped entries, 2026-12-05), in its
order (``python tools/results/run.py selection``, then copy the rule's choice here;
docs/results/discriminative.md)."""

SUITES: Final[dict[str, tuple[str, ...]]] = {
    "paper": EVALUATION_SCENARIOS,
    "large": LARGE_SCENARIOS,
    "francis": FRANCIS_SCENARIOS,
    "navwareset": NAVWARESET_SCENARIOS,
    "flows": FLOW_SCENARIOS,
    "all": (*EVALUATION_SCENARIOS, *FRANCIS_SCENARIOS, *NAVWARESET_SCENARIOS, *FLOW_SCENARIOS),
    "discriminative": DISCRIMINATIVE_SCENARIOS,
}
DEFAULT_SUITE: Final = "paper"
SUITE_DESCRIPTIONS: Final[dict[str, str]] = {
    "paper": "the paper's five evaluation scenarios (Table 3)",
    "large": "large crowds of 300-400 pedestrians: a performance suite",
    "francis": "the scenarios after Francis et al. 2023: corridors, doors, corners, rooms",
    "navwareset": "the NavWareSet room with the dataset's five layouts",
    "flows": "pedestrians entering during the run",
    "all": "paper, francis, navwareset and flows (not large)",
    "discriminative": "the scenarios of all where the benchmark tells planners apart "
    "(docs/benchmark.md)",
}
"""What each suite is for, in a line (``srfm suites``); one entry per suite of SUITES."""
