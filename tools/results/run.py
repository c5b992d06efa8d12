"""Run a results set from scratch and commit-ready pack it (docs/results/index.md).

    .venv/bin/python tools/results/run.py paper            # results/paper, then docs/results/paper
    .venv/bin/python tools/results/run.py paper -j 1       # fewer workers: the same episodes
    .venv/bin/python tools/results/run.py --list           # every set with its command

The run is ``srfm benchmark`` with the set's options into ``results/NAME`` (under
``nice -n 5``): interrupt it at any moment and run the same command again, and the
benchmark's own resume skips every finished episode. Once it is finished the set is
packed into ``docs/results/NAME/`` (``tools/results/sets.py``): the episodes, the
benchmark's manifest, the commit, the command, the start and end of this invocation and
its wall time. Then ``make docs-tables`` rewrites the docs from it.

``--pack-only --started ISO --finished ISO --wall-s S`` packs a folder that an earlier
invocation (or the same command typed by hand) finished, with the times it took.
"""

from __future__ import annotations

import argparse
import datetime as dt
import os
import platform
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from tools.results.sets import FIXED_OPTIONS, ROOT, SETS, pack


def _now() -> str:
    return dt.datetime.now(dt.UTC).strftime("%Y-%m-%dT%H:%M:%SZ")


def _commit() -> str:
    head = subprocess.run(
        ["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"],
        check=True,
        capture_output=True,
        text=True,
    ).stdout.strip()
    dirty = subprocess.run(
        ["git", "-C", str(ROOT), "status", "--porcelain", "--untracked-files=no", "srfm"],
        check=True,
        capture_output=True,
        text=True,
    ).stdout.strip()
    return head + ("-dirty" if dirty else "")


def _machine(load_start: float) -> str:
    load = os.getloadavg()[0]
    return (
        f"{platform.machine()}, {os.cpu_count()} CPUs, 1-min load {load_start:.1f} at the "
        f"start and {load:.1f} at the end"
    )


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("name", nargs="?", choices=sorted(SETS))
    ap.add_argument("-j", "--jobs", type=int, default=2, help="worker processes (default 2)")
    ap.add_argument("--list", action="store_true", help="print every set and its command")
    ap.add_argument("--pack-only", action="store_true", help="pack a finished folder")
    ap.add_argument("--out", type=Path, help="the benchmark folder (default results/NAME)")
    ap.add_argument("--commit", help="with --pack-only: the commit the run used")
    ap.add_argument("--started", help="with --pack-only: when the run started (UTC, ISO)")
    ap.add_argument("--finished", help="with --pack-only: when it finished (UTC, ISO)")
    ap.add_argument("--wall-s", type=float, help="with --pack-only: its wall time (s)")
    ap.add_argument("--machine", help="with --pack-only: the machine and its load")
    args = ap.parse_args(argv)
    if args.list:
        for rset in SETS.values():
            print(f"{rset.name}: {rset.command()}\n    {rset.purpose}")
        return
    if args.name is None:
        ap.error("name a results set (or --list)")
    rset = SETS[args.name]
    out = args.out or ROOT / "results" / rset.name
    if args.pack_only:
        if None in (args.started, args.finished, args.wall_s, args.machine):
            ap.error("--pack-only needs --started, --finished, --wall-s and --machine")
        dest = pack(
            rset,
            out,
            commit=args.commit or _commit(),
            started=args.started,
            finished=args.finished,
            wall_s=args.wall_s,
            machine=args.machine,
            jobs=args.jobs,
        )
        print(f"packed {out} into {dest}")
        return
    command = [
        "nice",
        "-n",
        "5",
        sys.executable,
        "-m",
        "srfm.cli",
        "benchmark",
        *rset.options,
        *FIXED_OPTIONS,
        "-j",
        str(args.jobs),
        "--out",
        str(out),
    ]
    commit, started, t0, load = _commit(), _now(), time.monotonic(), os.getloadavg()[0]
    print(" ".join(command), flush=True)
    subprocess.run(command, check=True, cwd=ROOT)
    dest = pack(
        rset,
        out,
        commit=commit,
        started=started,
        finished=_now(),
        wall_s=time.monotonic() - t0,
        machine=_machine(load),
        jobs=args.jobs,
    )
    print(f"packed into {dest}; now `make docs-tables`")


if __name__ == "__main__":
    main()
