"""The srfm error and warning classes, all in one place and all exported from ``srfm``.

Every error srfm raises on purpose derives from :class:`SrfmError`. Errors about bad
values also derive from :class:`ValueError`, so ``except ValueError`` keeps working for
callers that do not know srfm; :class:`MissingDependencyError` also derives from
:class:`ImportError`, :class:`WriteError` from :class:`OSError` and
:class:`FolderInUseError` from :class:`RuntimeError`. Every warning srfm issues derives
from :class:`SrfmWarning`. ``docs/reliability.md`` gives the command line's exit code
for each class.

This module imports nothing from srfm or from any optional dependency, so every class
here can be caught whatever is installed.
"""

from __future__ import annotations

__all__ = [
    "BenchmarkError",
    "DatasetError",
    "DatasetWarning",
    "FolderInUseError",
    "LogError",
    "MetricError",
    "MissingDependencyError",
    "OutputError",
    "ParameterError",
    "PlannerError",
    "PlannerFailedError",
    "PlannerFailureWarning",
    "ResourceError",
    "ScenarioError",
    "SimulationError",
    "SrfmError",
    "SrfmWarning",
    "SweepError",
    "UserCodeError",
    "WriteError",
]


class SrfmError(Exception):
    """Base class of every error raised by srfm on purpose."""


class ParameterError(SrfmError, ValueError):
    """A model, robot or simulation parameter is out of range or not a number."""


class ScenarioError(SrfmError, ValueError):
    """A scenario name is unknown or a scenario file is malformed."""


class PlannerError(SrfmError, ValueError):
    """A planner name is unknown or a planner returned an unusable command."""


class PlannerFailedError(PlannerError):
    """An external planner failed during an episode (its process crashed, it did not
    answer within its step timeout, it answered garbage, a non-finite command or one
    outside the robot's limits): :func:`srfm.run_episode` ends that episode's robot
    with the outcome ``planner_failed`` instead of raising, and warns with the message
    (:class:`PlannerFailureWarning`), one line naming the planner and what it did."""


class SimulationError(SrfmError, ValueError):
    """A simulation input (state, obstacle, horizon) is malformed."""


class MetricError(SrfmError, ValueError):
    """A metric was given malformed input (empty, wrongly shaped or non-finite arrays)."""


class BenchmarkError(SrfmError, ValueError):
    """A benchmark request or results folder is unusable (unknown names, mixed runs)."""


class SweepError(BenchmarkError):
    """A sweep spec or sweep results folder is unusable; the message names the file and
    the key."""


class DatasetError(SrfmError, ValueError):
    """A dataset file is malformed or unusable; the message names the file and the place."""


class LogError(SrfmError, ValueError):
    """A run log (.mcap, .rrd) is unreadable, truncated, foreign or inconsistent; the
    message names the file."""


class UserCodeError(PlannerError):
    """User code (a planner's factory, ``reset`` or ``act``) raised an exception.

    The message is one line naming the planner, the method and the exception;
    :attr:`traceback_text` keeps the user code's traceback (``srfm --debug`` prints it).
    The exception pickles, so it crosses from a benchmark worker to the parent intact.
    """

    def __init__(self, message: str, traceback_text: str = "") -> None:
        super().__init__(message, traceback_text)

    @property
    def traceback_text(self) -> str:
        """The formatted traceback of the exception raised inside the user's code."""
        return str(self.args[1])

    def __str__(self) -> str:
        return str(self.args[0])


class ResourceError(SimulationError):
    """A run needs more memory than the machine has; the message names the estimate
    and the limit."""


class OutputError(SrfmError, ValueError):
    """An output location is refused before anything is written: it is one of the
    inputs, a non-empty folder srfm did not create (without ``--force``), a file where a
    folder is needed, or not writable."""


class WriteError(SrfmError, OSError):
    """Writing an output failed (disk full, permission denied, read-only file system);
    the message names the file and the reason. What was there before is left intact.

    ``errno``, ``strerror`` and ``filename`` are those of the failed operation."""

    def __str__(self) -> str:
        return str(self.args[0]) if self.args else super().__str__()


class FolderInUseError(SrfmError, RuntimeError):
    """Another srfm process holds the lock of this results folder."""


class MissingDependencyError(SrfmError, ImportError):
    """An optional dependency (gymnasium, stable-baselines3, torch) is not installed;
    the message names the extra that provides it."""


class SrfmWarning(UserWarning):
    """Base class of every warning issued by srfm."""


class DatasetWarning(SrfmWarning):
    """Suspicious but readable data (e.g. implausible walking speeds for the given dt)."""


class PlannerFailureWarning(SrfmWarning):
    """An external planner failed and its episode ended with the outcome
    ``planner_failed``; the message is the :class:`PlannerFailedError`'s line."""
