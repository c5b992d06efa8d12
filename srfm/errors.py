"""The srfm error hierarchy.

Every error srfm raises on purpose derives from :class:`SrfmError`. Errors about bad
values also derive from :class:`ValueError`, so ``except ValueError`` keeps working for
callers that do not know srfm.
"""

from __future__ import annotations

__all__ = [
    "BenchmarkError",
    "DatasetError",
    "LogError",
    "MetricError",
    "ParameterError",
    "PlannerError",
    "ScenarioError",
    "SimulationError",
    "SrfmError",
]


class SrfmError(Exception):
    """Base class of every error raised by srfm on purpose."""


class ParameterError(SrfmError, ValueError):
    """A model, robot or simulation parameter is out of range or not a number."""


class ScenarioError(SrfmError, ValueError):
    """A scenario name is unknown or a scenario file is malformed."""


class PlannerError(SrfmError, ValueError):
    """A planner name is unknown or a planner returned an unusable command."""


class SimulationError(SrfmError, ValueError):
    """A simulation input (state, obstacle, horizon) is malformed."""


class MetricError(SrfmError, ValueError):
    """A metric was given malformed input (empty, wrongly shaped or non-finite arrays)."""


class BenchmarkError(SrfmError, ValueError):
    """A benchmark request or results folder is unusable (unknown names, mixed runs)."""


class DatasetError(SrfmError, ValueError):
    """A dataset file is malformed or unusable; the message names the file and the place."""


class LogError(SrfmError, ValueError):
    """A run log (.mcap, .rrd) is unreadable, truncated, foreign or inconsistent; the
    message names the file."""
