"""Benchmarks on a Dask cluster (``--executor dask``, ``--scheduler-file``): a real
scheduler and real workers on the loopback interface, one of them killed mid-run."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from srfm.benchmark import episode_path, run_benchmark
from srfm.errors import BenchmarkError
from tests.benchmark.test_runner import SHORT, SLOW, TABLES, _request, _tables
from tests.conftest import REPO, write_scenario

if os.environ.get("CI") != "true":  # in CI the dask extra is installed: never skip there
    pytest.importorskip("distributed", reason="the dask extra is not installed")

BIN = Path(sys.executable).parent


@pytest.fixture(scope="module")
def short_scenario(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return write_scenario(tmp_path_factory.mktemp("scn") / "short.toml", SHORT)


def _start(args: list[str], log: Path) -> subprocess.Popen[bytes]:
    """A dask command in its own session (so that it can be killed as a whole)."""
    env = {**os.environ, "PYTHONPATH": str(REPO)}
    with log.open("wb") as out:
        return subprocess.Popen(
            [str(BIN / "dask"), *args],
            cwd=REPO,
            env=env,
            stdout=out,
            stderr=subprocess.STDOUT,
            start_new_session=True,
        )


def _wait_for(predicate: object, what: str, timeout_s: float = 60.0) -> None:
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        if predicate():  # type: ignore[operator]
            return
        time.sleep(0.1)
    raise AssertionError(f"timed out waiting for {what}")


def test_local_cluster_gives_the_process_pool_tables(short_scenario: Path, tmp_path: Path) -> None:
    request = _request(short_scenario, range(6))
    pool = run_benchmark(request, tmp_path / "pool", jobs=2, figures=False)
    one = run_benchmark(request, tmp_path / "dask1", jobs=1, figures=False, executor="dask")
    two = run_benchmark(request, tmp_path / "dask2", jobs=2, figures=False, executor="dask")
    assert pool.simulated == one.simulated == two.simulated == 24
    reference = _tables(tmp_path / "pool")
    assert _tables(tmp_path / "dask1") == reference  # worker count changes nothing
    assert _tables(tmp_path / "dask2") == reference
    with pytest.raises(BenchmarkError, match="unknown executor 'ray'"):
        run_benchmark(request, tmp_path / "x", executor="ray")
    with pytest.raises(BenchmarkError, match="need --executor dask"):
        run_benchmark(request, tmp_path / "y", scheduler="tcp://127.0.0.1:1")
    with pytest.raises(BenchmarkError, match="no such file"):
        run_benchmark(request, tmp_path / "z", executor="dask", scheduler_file=tmp_path / "none")


def test_cluster_survives_a_killed_worker(short_scenario: Path, tmp_path: Path) -> None:
    """A scheduler and two single-thread workers (no nanny: a killed worker stays dead);
    the run goes through ``srfm benchmark --scheduler-file``; one worker is killed once
    the first episodes are written; the run completes on the other with the tables of
    a local run."""
    sched_file = tmp_path / "scheduler.json"
    procs = [
        _start(
            ["scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
             "--scheduler-file", str(sched_file)],
            tmp_path / "scheduler.log",
        )
    ]  # fmt: skip
    try:
        _wait_for(sched_file.exists, "the scheduler file")
        for k in range(2):
            procs.append(
                _start(
                    ["worker", "--scheduler-file", str(sched_file), "--nthreads", "1",
                     "--no-nanny", "--no-dashboard", "--host", "127.0.0.1"],
                    tmp_path / f"worker{k}.log",
                )
            )  # fmt: skip
        time.sleep(1.0)
        out = tmp_path / "cluster"
        seeds = "0-39"
        run = subprocess.Popen(
            [sys.executable, "-m", "srfm.cli", "benchmark", "-s", str(short_scenario),
             "-p", f"straight,{SLOW}", "--seeds", seeds, "--out", str(out), "--no-figures",
             "--no-logs", "--scheduler-file", str(sched_file)],
            cwd=REPO,
            env={**os.environ, "PYTHONPATH": str(REPO)},
            stdout=subprocess.DEVNULL,
            stderr=subprocess.PIPE,
            text=True,
        )  # fmt: skip
        episodes = episode_path(out, "short", SLOW, 0).parent
        _wait_for(lambda: len(list(episodes.glob("seed-*.json"))) >= 3, "first episodes", 120)
        os.killpg(procs[1].pid, signal.SIGKILL)
        procs[1].wait()
        at_kill = len(list(episodes.glob("seed-*.json")))
        assert at_kill < 40, "the run ended before the worker was killed"
        _, err = run.communicate(timeout=300)
        assert run.returncode == 0, err
        done = len(list(episodes.glob("seed-*.json")))
        assert done == 40
    finally:
        for proc in procs:
            if proc.poll() is None:
                os.killpg(proc.pid, signal.SIGKILL)
                proc.wait()
    local = tmp_path / "local"
    subprocess.run(
        [sys.executable, "-m", "srfm.cli", "benchmark", "-s", str(short_scenario), "-p",
         f"straight,{SLOW}", "--seeds", seeds, "--out", str(local), "--no-figures",
         "--no-logs", "-j", "1"],
        cwd=REPO, env={**os.environ, "PYTHONPATH": str(REPO)}, check=True,
        capture_output=True,
    )  # fmt: skip
    for name in TABLES:
        if name.endswith((".md", ".csv", ".tex", ".json", ".parquet")) and name != "report.html":
            assert (out / name).read_bytes() == (local / name).read_bytes(), name
