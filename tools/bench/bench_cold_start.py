"""First-run time of the quick benchmark: an empty numba cache, then the same run warm.

Runs ``srfm benchmark --quick`` (what ``make benchmark`` runs; 5 scenarios × 7
planners × seeds 0-2) twice in fresh output folders: first with ``NUMBA_CACHE_DIR``
pointing at a new, empty folder (every kernel compiled: a fresh clone), then again with
that cache filled (a second run). For each run it prints the simulation phase as the
command reports it ("simulated ... in X s", wall time, compilation included), the
wall time of the whole command and the CPU time of all its processes (the command and
its workers): on a machine shared with other work the wall times grow with the load,
the CPU times much less.

Usage::

    .venv/bin/python tools/bench/bench_cold_start.py
    .venv/bin/python tools/bench/bench_cold_start.py --jobs 2 --extra --no-logs --no-figures
"""

from __future__ import annotations

import argparse
import datetime
import os
import re
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

SIMULATED = re.compile(r"simulated (\d+) of (\d+) episodes in ([0-9.]+) s")


def _commit() -> str:
    try:
        out = subprocess.run(
            ["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True, check=True
        ).stdout.strip()
        dirty = subprocess.run(
            ["git", "status", "--porcelain", "srfm"], capture_output=True, text=True
        )
        return out + (" + uncommitted changes" if dirty.stdout.strip() else "")
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def run_once(
    cache: Path, out: Path, jobs: int | None, extra: list[str]
) -> tuple[float, float, float]:
    """(simulation phase s, command wall s, CPU s of the command and its workers)."""
    srfm = Path(sys.executable).with_name("srfm")
    cmd = [str(srfm), "benchmark", "--quick", "--out", str(out), *extra]
    if jobs is not None:
        cmd += ["-j", str(jobs)]
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache))
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    proc = subprocess.run(cmd, env=env, capture_output=True, text=True)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if proc.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed ({proc.returncode}):\n{proc.stderr[-2000:]}")
    match = SIMULATED.search(proc.stdout + proc.stderr)
    if match is None:
        sys.exit(f"no 'simulated ... in X s' line in the output of {' '.join(cmd)}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return float(match.group(3)), wall, cpu


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--jobs", type=int, default=None, help="-j of srfm benchmark (default: its own)"
    )
    parser.add_argument(
        "--extra", nargs=argparse.REMAINDER, default=[], help="further srfm benchmark options"
    )
    args = parser.parse_args()
    print(
        f"date: {datetime.datetime.now(datetime.UTC):%Y-%m-%d %H:%M} UTC, srfm commit {_commit()}"
    )
    print(f"cores: {os.cpu_count()}, load average at start: {os.getloadavg()}")
    with tempfile.TemporaryDirectory(prefix="srfm-cold-") as tmp:
        cache = Path(tmp) / "numba-cache"
        cache.mkdir()
        print(
            "| run | simulation phase (s, as printed) | whole command, wall (s)"
            " | CPU time, all processes (s) |"
        )
        print("|---|---:|---:|---:|")
        for label, folder in (("empty numba cache", "cold"), ("warm numba cache", "warm")):
            sim, wall, cpu = run_once(cache, Path(tmp) / folder, args.jobs, args.extra)
            print(f"| {label} | {sim:.1f} | {wall:.1f} | {cpu:.1f} |", flush=True)
    print(f"load average at end: {os.getloadavg()}")


if __name__ == "__main__":
    main()
