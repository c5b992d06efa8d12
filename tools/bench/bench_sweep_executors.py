"""Throughput of ``srfm sweep`` on the local process pool and on a Dask LocalCluster.

The same sweep (by default 2,000 twin episodes: A_r × B_r = 5 × 2 cells, the
``crosswalk`` and ``footpath`` scenarios, the ``dwa`` and ``straight`` planners, seeds
0-49, ten seeds a task) runs into a fresh folder with each executor and ``--jobs``
workers, alternating ``process, dask, process, dask, ...`` so that a change of load
from other work hits both alike. Reported per run: the wall time of the whole
:func:`srfm.sweep.run_sweep` call (the Dask run includes starting and stopping its
LocalCluster), episodes per second and per second per worker, and whether the
Parquet files are byte-identical to the first run's. The start and stop of an empty
LocalCluster of the same size is timed on its own, to tell the fixed cost from the
per-episode cost.

Usage::

    nice .venv/bin/python tools/bench/bench_sweep_executors.py --jobs 2 --repeats 2
"""

from __future__ import annotations

import argparse
import hashlib
import os
import resource
import statistics
import tempfile
import time
from pathlib import Path

SPEC = """
schema_version = 1
name = "executor-bench"
scenarios = {scenarios}
planners = {planners}
seeds = "0-{last_seed}"
seeds_per_task = {per_task}

[design]
kind = "grid"
[design.factors]
a_robot = [3.965, 5.9475, 7.93, 11.895, 15.86]
b_robot = [0.5, 1.5]
"""


def _digest(out: Path) -> str:
    h = hashlib.sha256()
    for path in sorted((out / "data").rglob("*.parquet")):
        h.update(str(path.relative_to(out)).encode())
        h.update(path.read_bytes())
    return h.hexdigest()


def _cpu_s() -> float:
    """User + system CPU time of this process and of its reaped descendants (the pool's
    workers; the LocalCluster's nannies and their workers, which are waited for when
    the cluster closes)."""
    total = 0.0
    for who in (resource.RUSAGE_SELF, resource.RUSAGE_CHILDREN):
        usage = resource.getrusage(who)
        total += usage.ru_utime + usage.ru_stime
    return total


def _cluster_start_stop(jobs: int) -> float:
    import distributed

    start = time.perf_counter()
    with (
        distributed.LocalCluster(
            n_workers=jobs, threads_per_worker=1, processes=True, dashboard_address=None
        ) as cluster,
        distributed.Client(cluster) as client,
    ):
        client.wait_for_workers(jobs)
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--repeats", type=int, default=2)
    parser.add_argument("--seeds", type=int, default=50)
    parser.add_argument("--per-task", type=int, default=10)
    parser.add_argument("--scenarios", nargs="+", default=["crosswalk", "footpath"])
    parser.add_argument("--planners", nargs="+", default=["dwa", "straight"])
    args = parser.parse_args()

    from srfm.sweep import load_spec, run_sweep

    with tempfile.TemporaryDirectory() as tmp:
        spec_path = Path(tmp) / "bench.toml"
        spec_path.write_text(
            SPEC.format(
                scenarios=list(args.scenarios),
                planners=list(args.planners),
                last_seed=args.seeds - 1,
                per_task=args.per_task,
            ).replace("'", '"'),
            encoding="utf-8",
        )
        spec = load_spec(spec_path)
        print(
            f"sweep: {len(spec.cells)} cells × {len(spec.scenarios)} scenarios × "
            f"{len(spec.planners)} planners × {len(spec.seeds)} seeds = {spec.episodes} "
            f"episodes, {args.per_task} seeds a task; {args.jobs} workers; "
            f"os.getloadavg() before: {os.getloadavg()[0]:.2f}"
        )
        startup = _cluster_start_stop(args.jobs)
        print(f"LocalCluster of {args.jobs} workers, start + stop alone: {startup:.2f} s")
        rates: dict[str, list[float]] = {"process": [], "dask": []}
        per_cpu: dict[str, list[float]] = {"process": [], "dask": []}
        first_digest = None
        for k in range(args.repeats):
            for executor in ("process", "dask"):
                out = Path(tmp) / f"{executor}{k}"
                load = os.getloadavg()[0]
                start, cpu0 = time.perf_counter(), _cpu_s()
                summary = run_sweep(spec, out, executor=executor, jobs=args.jobs)
                wall, cpu = time.perf_counter() - start, _cpu_s() - cpu0
                digest = _digest(out)
                first_digest = first_digest or digest
                rate = summary.simulated / wall
                rates[executor].append(rate)
                per_cpu[executor].append(summary.simulated / cpu)
                print(
                    f"{executor:8s} run {k}: {wall:7.1f} s, {rate:6.2f} episodes/s, "
                    f"{rate / args.jobs:6.2f} per worker; CPU {cpu:7.1f} s, "
                    f"{summary.simulated / cpu:6.2f} episodes per CPU-second; load "
                    f"{load:.2f} before; same bytes as the first run: {digest == first_digest}",
                    flush=True,
                )
        p, d = statistics.median(rates["process"]), statistics.median(rates["dask"])
        print(
            f"median episodes/s per worker: process {p / args.jobs:.2f}, dask "
            f"{d / args.jobs:.2f} (dask / process = {d / p:.3f})"
        )
        p, d = statistics.median(per_cpu["process"]), statistics.median(per_cpu["dask"])
        print(
            f"median episodes per CPU-second: process {p:.2f}, dask {d:.2f} "
            f"(dask / process = {d / p:.3f})"
        )


if __name__ == "__main__":
    main()
