"""Running a benchmark's tasks on a Dask cluster (``srfm benchmark --executor dask``).

Dask's ``distributed`` scheduler does the work a cluster needs: it places the tasks on
the workers, resubmits the tasks of a worker that dies (up to its
``distributed.scheduler.allowed-failures`` limit, 3 by default), and reports results
as they complete. srfm adds nothing of its own to that: each task is the same
:func:`srfm.benchmark._runner._run_task` the process pool runs, which writes its
episode files atomically into the results folder; a resubmitted task rewrites them
with the same bytes (an episode depends only on its scenario, planner, seed and
parameters). The workers must therefore see the results folder at the same path (one
machine, or a shared file system) and import the same srfm and user planners.

Needs the ``dask`` extra (``pip install 'srfm[dask]'``).
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterable, Iterator
from pathlib import Path
from typing import Any

from srfm._deps import require
from srfm.benchmark._workers import one_thread
from srfm.errors import BenchmarkError

__all__ = ["map_on_dask", "run_on_dask"]

# Retries of a task that *raised* (a worker that died is handled by the scheduler's own
# allowed-failures count): user planners are deterministic, so a second try of a raising
# task raises again; one retry covers transient errors such as a full disk cleared.
_TASK_RETRIES = 1


def _dask_task(run: Callable[[Any], int], task: Any) -> int:
    """On a worker: one thread per process for the kernels, then the task. (Signals
    and the worker's life are the Dask worker's business, not the task's.)"""
    one_thread()
    return run(task)


def run_on_dask(
    run: Callable[[Any], int],
    tasks: Iterable[Any],
    *,
    workers: int,
    scheduler: str | None = None,
    scheduler_file: str | Path | None = None,
    on_progress: Callable[[int], None] | None = None,
) -> int:
    """Run ``run(task)`` for every task on a Dask cluster; return the summed results
    (see :func:`map_on_dask`; ``on_progress`` is called with each result)."""
    done = 0
    for count in map_on_dask(
        run, tasks, workers=workers, scheduler=scheduler, scheduler_file=scheduler_file
    ):
        done += int(count)
        if on_progress is not None:
            on_progress(int(count))
    return done


def map_on_dask(
    run: Callable[[Any], Any],
    tasks: Iterable[Any],
    *,
    workers: int,
    scheduler: str | None = None,
    scheduler_file: str | Path | None = None,
) -> Iterator[Any]:
    """Run ``run(task)`` for every task on a Dask cluster; yield the results as the
    tasks complete (in completion order).

    Args:
        run: the task function (top-level, picklable).
        tasks: picklable task objects.
        workers: worker processes of the local cluster started when neither
            ``scheduler`` nor ``scheduler_file`` is given (one thread each).
        scheduler: address of a running scheduler, e.g. ``tcp://127.0.0.1:8786``.
        scheduler_file: the JSON file a running scheduler wrote (``dask scheduler
            --scheduler-file``).

    Raises:
        BenchmarkError: both ``scheduler`` and ``scheduler_file``, a missing scheduler
            file, or a scheduler that cannot be reached.
    """
    distributed = require("distributed", extra="dask")
    if scheduler is not None and scheduler_file is not None:
        raise BenchmarkError("give --scheduler or --scheduler-file, not both")
    if scheduler_file is not None and not os.path.isfile(scheduler_file):
        raise BenchmarkError(f"--scheduler-file {scheduler_file}: no such file")
    cluster = None
    try:
        if scheduler is None and scheduler_file is None:
            cluster = distributed.LocalCluster(
                n_workers=workers,
                threads_per_worker=1,
                processes=True,
                dashboard_address=None,
            )
            client = distributed.Client(cluster)
        else:
            try:
                client = distributed.Client(
                    address=scheduler,
                    scheduler_file=None if scheduler_file is None else str(scheduler_file),
                    timeout="20s",
                )
            except (OSError, TimeoutError) as error:
                where = scheduler or scheduler_file
                raise BenchmarkError(f"cannot reach the Dask scheduler {where}: {error}") from None
        with client:
            futures = [
                client.submit(_dask_task, run, task, pure=False, retries=_TASK_RETRIES)
                for task in tasks
            ]
            for future in distributed.as_completed(futures):
                yield future.result()
                future.release()
    finally:
        if cluster is not None:
            cluster.close()
