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

Needs the ``dask`` extra (``pip install 'social-robot-force-model[dask]'``).
"""

from __future__ import annotations

import json
import os
from collections.abc import Callable, Iterable, Iterator
from pathlib import Path
from typing import Any, Final

from srfm._deps import require
from srfm._io import MAX_DOCUMENT_BYTES, read_input_bytes
from srfm.benchmark._workers import one_thread
from srfm.errors import BenchmarkError

__all__ = ["check_scheduler", "map_on_dask", "run_on_dask"]

# Address schemes whose location is HOST:PORT (ucx and inproc locations are not).
_HOST_PORT_SCHEMES: Final = ("tcp", "tls", "ws", "wss")

# Retries of a task that *raised* (a worker that died is handled by the scheduler's own
# allowed-failures count): user planners are deterministic, so a second try of a raising
# task raises again; one retry covers transient errors such as a full disk cleared.
_TASK_RETRIES = 1


def _dask_task(run: Callable[[Any], int], task: Any) -> int:
    """On a worker: one thread per process for the kernels, then the task. (Signals
    and the worker's life are the Dask worker's business, not the task's.)"""
    one_thread()
    return run(task)


def _check_address(address: str, what: str) -> str:
    """``address`` if Dask can connect to something there: a known scheme and, for
    tcp, tls, ws and wss, a host and a port in [1, 65535]."""
    from distributed.comm.addressing import get_address_host_port, parse_address
    from distributed.comm.registry import get_backend

    try:
        scheme, _ = parse_address(address)
        get_backend(scheme)  # an unknown scheme raises
        if scheme in _HOST_PORT_SCHEMES:
            host, port = get_address_host_port(address)
            if not host or not 0 < port < 65536:
                raise ValueError("a host and a port in [1, 65535] are needed")
    except ValueError as exc:
        raise BenchmarkError(
            f"{what} {address!r} is not a Dask scheduler address such as tcp://HOST:8786 ({exc})"
        ) from None
    return address


def check_scheduler(scheduler: str | None, scheduler_file: str | Path | None) -> None:
    """Refuse, before anything is written, what cannot name a Dask scheduler: both
    options, a malformed address, or a scheduler file that is missing, not JSON, or
    without a well-formed ``address`` (a reachable scheduler is found only when
    connecting). Needs the ``dask`` extra.

    Raises:
        BenchmarkError: naming the option and the bad value.
        MissingDependencyError: ``distributed`` is not installed.
    """
    require("distributed", extra="dask")
    if scheduler is not None and scheduler_file is not None:
        raise BenchmarkError("give --scheduler or --scheduler-file, not both")
    if scheduler is not None:
        _check_address(scheduler, "--scheduler")
    if scheduler_file is not None:
        what = f"--scheduler-file {scheduler_file}"
        if not os.path.lexists(scheduler_file):
            raise BenchmarkError(f"{what}: no such file")
        data = read_input_bytes(
            scheduler_file,
            max_bytes=MAX_DOCUMENT_BYTES,
            error=BenchmarkError,
            what="Dask scheduler file",
        )
        try:
            doc = json.loads(data.decode("utf-8-sig"))
        except (UnicodeDecodeError, ValueError, RecursionError) as exc:
            raise BenchmarkError(f"{what}: not a Dask scheduler file (not JSON: {exc})") from None
        address = doc.get("address") if isinstance(doc, dict) else None
        if not isinstance(address, str):
            raise BenchmarkError(
                f'{what}: not a Dask scheduler file (no "address" string; `dask scheduler '
                "--scheduler-file FILE` writes one)"
            )
        _check_address(address, f"{what}: address")


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
        BenchmarkError: both ``scheduler`` and ``scheduler_file``, a malformed address
            or scheduler file (:func:`check_scheduler`), or a scheduler that cannot be
            reached.
    """
    distributed = require("distributed", extra="dask")
    check_scheduler(scheduler, scheduler_file)
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
            except (OSError, TimeoutError, ValueError) as error:
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
