"""Named scenario suites for ``srfm benchmark --suite NAME``.

A suite is a tuple of built-in scenario names, run in that order. ``paper`` is the
default of ``srfm benchmark`` (the paper's five evaluation scenarios), ``large`` the
large-crowd scenarios of issue 19. Add a suite by adding an entry here.
"""

from __future__ import annotations

from typing import Final

from srfm.scenarios import EVALUATION_SCENARIOS, LARGE_SCENARIOS

__all__ = ["DEFAULT_SUITE", "SUITES"]

SUITES: Final[dict[str, tuple[str, ...]]] = {
    "paper": EVALUATION_SCENARIOS,
    "large": LARGE_SCENARIOS,
}
DEFAULT_SUITE: Final = "paper"
