"""The set-up of a process that runs benchmark tasks: one thread for every thread pool
(a process-pool worker and a Dask worker's task both call :func:`one_thread`), Ctrl-C
left to the parent, and an end with the parent (:func:`init_worker`)."""

from __future__ import annotations

import ctypes
import ctypes.util
import gc
import os
import signal
import sys

__all__ = ["init_worker", "one_thread"]


def one_thread() -> None:
    """Limit this process's BLAS/OpenMP pools and numba's pool to one thread (see
    :func:`init_worker`; a Dask worker's task calls it too)."""
    import numba
    from threadpoolctl import threadpool_limits  # type: ignore[import-untyped]

    for var in ("OMP_NUM_THREADS", "MKL_NUM_THREADS", "OPENBLAS_NUM_THREADS"):
        os.environ[var] = "1"
    threadpool_limits(limits=1)
    numba.set_num_threads(1)


def init_worker() -> None:
    """Set up a worker process: one thread, and Ctrl-C left to the parent.

    One thread per worker: threaded kernels stall when the cores are shared. A forked
    worker has its libraries loaded already, where environment variables come too late:
    their BLAS/OpenMP pools are limited with threadpoolctl and numba's own pool with
    :func:`numba.set_num_threads`. The variables still cover libraries loaded later
    (e.g. torch for a policy) and spawned workers.
    """
    one_thread()
    # What the worker inherits (numba's compiled kernels and their objects, the parent's
    # imports) lives as long as the process: left out of the garbage collector's passes
    # (0.39 -> 0.15 ms of collections an episode, history/performance.md), and their
    # pages are not written by the collector's bookkeeping after the fork.
    gc.freeze()
    # Ctrl-C reaches the whole process group: the parent stops the pool, the workers
    # should not each print a traceback.
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    _die_with_parent()


def _die_with_parent() -> None:
    """End this worker quietly when the parent dies, instead of a BrokenPipeError
    traceback per worker: SIGPIPE back to its default (a write to the closed result
    pipe ends the process silently) and, on Linux, a SIGTERM when the parent dies."""
    if hasattr(signal, "SIGPIPE"):
        signal.signal(signal.SIGPIPE, signal.SIG_DFL)
    if not sys.platform.startswith("linux"):
        return
    parent = os.getppid()
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6", use_errno=True)
        pr_set_pdeathsig = 1
        libc.prctl(pr_set_pdeathsig, int(signal.SIGTERM), 0, 0, 0)
    except (OSError, AttributeError):
        return
    if os.getppid() != parent:  # the parent died before prctl took effect
        os._exit(1)
