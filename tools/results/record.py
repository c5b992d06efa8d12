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


def machine() -> dict[str, object]:
    """The machine and the software a timing ran on: CPU model, logical cores, memory,
    OS, Python and the packages whose speed the docs report (``not installed`` if not)."""
    import importlib.metadata
    import platform
    from pathlib import Path

    cpu = platform.processor() or "unknown"
    memory_gib = 0.0
    if Path("/proc/cpuinfo").is_file():
        for line in Path("/proc/cpuinfo").read_text(encoding="utf-8").splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    if Path("/proc/meminfo").is_file():
        first = Path("/proc/meminfo").read_text(encoding="utf-8").splitlines()[0]
        memory_gib = round(int(first.split()[1]) / 2**20, 1)  # "MemTotal: N kB"

    def version(dist: str) -> str:
        try:
            return importlib.metadata.version(dist)
        except importlib.metadata.PackageNotFoundError:
            return "not installed"

    return {
        "cpu": cpu,
        "cores": os.cpu_count(),
        "memory_gib": memory_gib,
        "os": f"{platform.system()} {platform.release()}",
        "python": platform.python_version(),
        "packages": {
            dist: version(dist)
            for dist in (
                "numpy",
                "numba",
                "gymnasium",
                "stable-baselines3",
                "sbx-rl",
                "torch",
                "jax",
                "pysocialforce",
                "jupedsim",
            )
        },
    }


def load_average() -> list[float]:
    """The 1, 5 and 15 minute load averages, rounded to 0.01."""
    return [round(x, 2) for x in os.getloadavg()]


def write_json(
    path: str | os.PathLike[str], figures: dict[str, object], begun: tuple[str, float, float]
) -> None:
    """Write a timing's ``figures`` to ``path`` with the run's record (``run``: command,
    commit, start, end, wall time, load; :func:`run_record`), the load averages at the
    end (``load_end``) and the machine (``machine``), atomically."""
    import json
    from pathlib import Path

    payload = {
        "run": run_record(*begun),
        "load_end": load_average(),
        "machine": machine(),
        **figures,
    }
    out = Path(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    tmp = out.with_suffix(".tmp")
    tmp.write_text(json.dumps(payload, indent=1, sort_keys=True) + "\n", encoding="utf-8")
    tmp.replace(out)
    print(f"wrote {out}")
