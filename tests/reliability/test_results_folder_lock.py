"""One srfm run at a time on a results folder; the second is refused (exit 75)
before it touches anything, and the lock dies with its holder."""

from __future__ import annotations

import subprocess
import sys
import time
from pathlib import Path

import pytest

import srfm
from srfm._io import LOCK_FILE, folder_lock
from srfm.benchmark import run_benchmark
from tests.reliability.conftest import cli, tiny_request


def test_a_second_run_is_refused_and_leaves_the_first_ones_temporaries(
    tmp_path: Path, tiny: Path
) -> None:
    out = tmp_path / "run"
    run_benchmark(tiny_request(tiny, range(1)), out, jobs=1, figures=False)
    in_flight = out / "episodes" / "tiny" / "straight" / ".seed-000001.json.x1y2.tmp"
    in_flight.write_text("being written by the first run", encoding="utf-8")
    log_tmp = out / "logs" / ".seed-000001.mcap.abc.tmp"
    log_tmp.parent.mkdir(parents=True, exist_ok=True)
    log_tmp.write_bytes(b"x")
    with folder_lock(out):  # the first run, still going
        with pytest.raises(srfm.FolderInUseError, match="in use by another srfm run"):
            run_benchmark(tiny_request(tiny, range(3)), out, jobs=1, figures=False)
        res = cli(
            "benchmark", "-s", str(tiny), "-p", "straight", "--seeds", "0-2", "--out", str(out),
            "-j", "1",
        )  # fmt: skip
        assert res.exit_code == 75, res.output
        assert "in use by another srfm run" in res.output
        assert in_flight.exists()
        assert log_tmp.exists()
        assert not (out / "episodes" / "tiny" / "straight" / "seed-000002.json").exists()
    # Once the first run is over, the next run cleans up and completes.
    summary = run_benchmark(tiny_request(tiny, range(3)), out, jobs=1, figures=False)
    assert summary.simulated == 2
    assert not in_flight.exists()
    assert not log_tmp.exists()


def test_the_lock_is_released_when_its_holder_is_killed(tmp_path: Path, tiny: Path) -> None:
    out = tmp_path / "run"
    out.mkdir()
    holder = subprocess.Popen(
        [
            sys.executable,
            "-c",
            "import sys, time\nfrom srfm._io import folder_lock\n"
            f"with folder_lock({str(out)!r}):\n    print('locked', flush=True)\n"
            "    time.sleep(600)\n",
        ],
        stdout=subprocess.PIPE,
        text=True,
    )
    try:
        assert holder.stdout is not None
        assert holder.stdout.readline().strip() == "locked"
        with pytest.raises(srfm.FolderInUseError):
            run_benchmark(tiny_request(tiny, range(1)), out, jobs=1, figures=False)
    finally:
        holder.kill()
        holder.wait()
    deadline = time.monotonic() + 10
    while True:
        try:
            run_benchmark(tiny_request(tiny, range(1)), out, jobs=1, figures=False)
            break
        except srfm.FolderInUseError:
            if time.monotonic() > deadline:
                raise
            time.sleep(0.1)
    assert (out / LOCK_FILE).exists() or True  # the lock file may stay; the lock does not
