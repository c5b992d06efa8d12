"""Where the quick benchmark's first run spends its compilation time, kernel by kernel.

Runs the work of ``srfm benchmark --quick`` (5 scenarios × 7 planners × seeds 0-2, logs
as the command writes them by default) in this one process with ``NUMBA_CACHE_DIR``
pointing at a new, empty folder, in the order the command does it with workers:

1. the warm-up the command runs in the parent before forking its workers
   (``_compile_in_parent``: one two-step episode per planner, and its metrics), one
   planner at a time;
2. every episode (``_run_task``, what a worker runs): whatever compiles here is
   compiled again in every worker;
3. the reports and figures (the parent, at the end).

Each phase's CPU time is printed, and every numba compilation (numba's
``numba:compile`` events, timed with this process's CPU time) is attributed to the
dispatcher being compiled: "inclusive" counts the callees numba compiles while typing
it, "self" does not. Loading from the cache is not a compilation and is not counted
(it is part of the phases' CPU time).

Usage::

    .venv/bin/python tools/bench/profile_compile.py
    .venv/bin/python tools/bench/profile_compile.py --top 40 --planners orca dwa
"""

from __future__ import annotations

import argparse
import contextlib
import datetime
import json
import os
import resource
import sys
import tempfile
import time
from collections import defaultdict
from pathlib import Path
from typing import Any

from bench_cold_start import _commit  # the sibling script (tools/bench/ is sys.path[0])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--top", type=int, default=30, help="rows of the kernel table")
    parser.add_argument("--planners", nargs="*", default=None, help="default: every planner")
    parser.add_argument("--no-logs", action="store_true", help="without the episode logs")
    parser.add_argument(
        "--cache",
        type=Path,
        default=None,
        help="use this NUMBA_CACHE_DIR as it is (default: a new, empty one)",
    )
    parser.add_argument("--warm-up-only", action="store_true", help="only the warm-up (phase 1)")
    parser.add_argument(
        "--as-benchmark",
        action="store_true",
        help="phase 1 as the command runs it with workers (_compile_in_parent: the shared "
        "kernels, then the planners split with a forked helper); prints its CPU time in "
        "this process and in the helper, and its wall time",
    )
    parser.add_argument("--passes", action="store_true", help="also the CPU time per compiler pass")
    parser.add_argument(
        "--signatures", action="store_true", help="list the signatures of every compilation"
    )
    args = parser.parse_args()

    tmp = tempfile.TemporaryDirectory(prefix="srfm-compile-")
    cache = args.cache if args.cache is not None else Path(tmp.name) / "numba-cache"
    cache.mkdir(exist_ok=True)
    os.environ["NUMBA_CACHE_DIR"] = str(cache)  # before numba is imported
    print(
        f"date: {datetime.datetime.now(datetime.UTC):%Y-%m-%d %H:%M} UTC, srfm commit {_commit()}"
    )
    print(f"cores: {os.cpu_count()}, load average at start: {os.getloadavg()}")

    cpu0 = time.process_time()
    import numba.core.event as ev

    from srfm.benchmark import _request, _runner
    from srfm.cli.benchmark import _log_writer

    print(f"imports: {time.process_time() - cpu0:.1f} CPU-s, NUMBA_CACHE_DIR {cache}")

    inclusive: dict[str, float] = defaultdict(float)
    own: dict[str, float] = defaultdict(float)
    count: dict[str, int] = defaultdict(int)
    signatures: dict[str, list[str]] = defaultdict(list)
    stack: list[list[Any]] = []  # [name, start, time of nested compilations]
    phase_compile: dict[str, float] = defaultdict(float)
    phase = ["import"]

    class Timer(ev.Listener):  # type: ignore[misc]
        def on_start(self, event: ev.Event) -> None:
            disp = event.data["dispatcher"]
            name = f"{disp.py_func.__module__}.{disp.py_func.__qualname__}"
            stack.append([name, time.process_time(), 0.0])
            signatures[name].append(str(event.data["args"]))

        def on_end(self, event: ev.Event) -> None:
            name, start, nested = stack.pop()
            spent = time.process_time() - start
            inclusive[name] += spent
            own[name] += spent - nested
            count[name] += 1
            if stack:
                stack[-1][2] += spent
            else:
                phase_compile[phase[0]] += spent

    out = Path(tmp.name) / "out"
    request = _request.BenchmarkRequest.create(planners=args.planners, quick=True)
    writer = _log_writer(request, out, not args.no_logs, True, "compact", "1", False)
    out.mkdir()
    manifest = _request.new_manifest(request, None)
    (out / _request.MANIFEST).write_text(json.dumps(manifest, indent=2, sort_keys=True) + "\n")
    tasks = _runner._pending_tasks(out, request, writer, True, [])
    phases: list[tuple[str, float]] = []
    pass_time: dict[str, float] = defaultdict(float)
    pass_stack: list[list[Any]] = []  # [pass name, start, time of nested passes]

    class PassTimer(ev.Listener):  # type: ignore[misc]
        def on_start(self, event: ev.Event) -> None:
            name = event.data["name"].split(" [")[0]
            pass_stack.append([name, time.process_time(), 0.0])

        def on_end(self, event: ev.Event) -> None:
            name, start, nested = pass_stack.pop()
            spent = time.process_time() - start
            pass_time[name] += spent - nested
            if pass_stack:
                pass_stack[-1][2] += spent

    with contextlib.ExitStack() as listeners:
        listeners.enter_context(ev.install_listener("numba:compile", Timer()))
        if args.passes:
            listeners.enter_context(ev.install_listener("numba:run_pass", PassTimer()))
        if args.as_benchmark:
            phase[0] = "_compile_in_parent (this process)"
            start = time.process_time()
            wall = time.perf_counter()
            before = resource.getrusage(resource.RUSAGE_CHILDREN)
            _runner._compile_in_parent(tasks)
            after = resource.getrusage(resource.RUSAGE_CHILDREN)
            phases.append((phase[0], time.process_time() - start))
            helper = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
            print(
                f"_compile_in_parent: wall {time.perf_counter() - wall:.1f} s, "
                f"helper process {helper:.1f} CPU-s (its compilations are not in the tables)"
            )
        else:
            first: dict[str, Any] = {}
            for task in tasks:
                for seed, planners in task.episodes:
                    for planner in planners:
                        first.setdefault(
                            planner, _runner._Start(task.scenario, planner, seed, task.params)
                        )
            for name, task in first.items():
                phase[0] = f"warm-up {name}"
                start = time.process_time()
                _runner._warm_up(task)
                phases.append((phase[0], time.process_time() - start))
        if not args.warm_up_only:
            phase[0] = "episodes (each worker)"
            start = time.process_time()
            for task in tasks:
                _runner._run_task(task)
            phases.append((phase[0], time.process_time() - start))
            phase[0] = "reports and figures"
            start = time.process_time()
            _runner._write_reports(out, request, figures=True)
            phases.append((phase[0], time.process_time() - start))

    print("\n| phase | CPU-s | of which compiling |")
    print("|---|---:|---:|")
    for name, spent in phases:
        print(f"| {name} | {spent:.1f} | {phase_compile[name]:.1f} |")
    total = sum(s for _, s in phases)
    print(f"| all | {total:.1f} | {sum(phase_compile.values()):.1f} |")

    print("\n| kernel (dispatcher) | compilations | self CPU-s | inclusive CPU-s |")
    print("|---|---:|---:|---:|")
    for name in sorted(own, key=own.__getitem__, reverse=True)[: args.top]:
        print(f"| `{name}` | {count[name]} | {own[name]:.2f} | {inclusive[name]:.2f} |")
    if args.passes:
        print("\n| compiler pass | self CPU-s |")
        print("|---|---:|")
        for name in sorted(pass_time, key=pass_time.__getitem__, reverse=True)[:15]:
            print(f"| {name} | {pass_time[name]:.2f} |")
    if args.signatures:
        for name, sigs in signatures.items():
            for sig in sigs:
                print(f"{name}{sig}")
    print(f"\nself time of all {sum(count.values())} compilations: {sum(own.values()):.1f} CPU-s")
    print(f"load average at end: {os.getloadavg()}")
    tmp.cleanup()


if __name__ == "__main__":
    sys.exit(main())
