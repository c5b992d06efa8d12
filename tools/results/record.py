"""What a data file of the docs records about the run that wrote it: the command, the
source commit, when it ran, its wall time and the machine (docs/results/index.md).

    record = run_record(started, t0)        # at the end of a run; t0 from time.monotonic()
    payload["run"] = record
"""

from __future__ import annotations

import os
import shlex
import sys
import time

from tools.results.run import _commit, _machine, _now


def source_commit() -> str:
    """The checkout's short commit, ``-dirty`` when srfm/ has local changes."""
    return _commit()


def command_line(argv: list[str] | None = None) -> str:
    """The command as typed from the repository's root (``python`` for the interpreter)."""
    args = sys.argv if argv is None else argv
    return " ".join(["python", *(shlex.quote(a) for a in args)])


def run_record(started: str, t0: float, load_start: float) -> dict[str, object]:
    """The record of a run that started at ``started`` (UTC, ISO), ``t0`` on the
    monotonic clock, with a 1-minute load of ``load_start`` then."""
    return {
        "command": command_line(),
        "commit": source_commit(),
        "started": started,
        "finished": _now(),
        "wall_s": round(time.monotonic() - t0, 1),
        "machine": _machine(load_start),
    }


def start() -> tuple[str, float, float]:
    """``(started, t0, load)`` for :func:`run_record`, at the start of a run."""
    return _now(), time.monotonic(), os.getloadavg()[0]
