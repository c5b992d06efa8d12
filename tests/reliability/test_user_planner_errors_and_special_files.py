"""Errors in a user's planner are one line naming the planner, the method and
the exception (--debug or SRFM_DEBUG=1 shows the traceback), never exit status 0; FIFOs,
devices and huge files are refused as inputs without blocking."""

from __future__ import annotations

import os
import pickle
import subprocess
import sys
import threading
from collections.abc import Callable
from pathlib import Path

import pytest

import srfm
from srfm._io import MAX_TOML_BYTES, read_input_bytes
from srfm.benchmark import BenchmarkRequest, run_benchmark
from srfm.datasets import eth_ucy
from tests.conftest import REPO
from tests.reliability.conftest import cli

M = "tests.reliability.user_planners"


@pytest.mark.parametrize(
    ("spec", "match"),
    [
        (":X", "is not module:attribute"),
        ("..:X", "is not module:attribute"),
        ("../x:Y", "is not module:attribute"),
        ("nowhere_module_xyz:X", "cannot import 'nowhere_module_xyz'"),
        (f"{M}:NeedsArguments", "failed in its factory: TypeError: .*callable without arguments"),
        (f"{M}:exits_in_factory", r"failed in its factory: called sys\.exit\(None\)"),
        ("sys:exit", r"failed in its factory: called sys\.exit\(None\)"),
        ("json:loads", "failed in its factory: TypeError"),
    ],
)
def test_bad_planner_specs_are_one_line_with_exit_2(spec: str, match: str) -> None:
    res = cli("simulate", "--scenario", "concert", "--planner", spec)
    assert res.exit_code == 2, res.output
    lines = res.output.strip().splitlines()
    assert len(lines) == 1
    assert lines[0].startswith("Error: ")
    assert "Traceback" not in res.output
    with pytest.raises(srfm.PlannerError, match=match):
        srfm.run_episode("concert", 0, spec)


@pytest.mark.parametrize(
    ("planner", "match"),
    [
        ("Boom", r"'tests\.reliability\.user_planners:Boom' failed in act\(\) at step 3 "
         r"\(scenario concert, seed 0\): ZeroDivisionError: the user's own bug"),
        ("ResetBoom", r"failed in reset\(\) \(scenario concert, seed 0\): KeyError: 'missing'"),
        ("Exits", r"failed in act\(\) at step 0 .*called sys\.exit\(0\)"),
    ],
)  # fmt: skip
def test_an_exception_inside_a_users_planner(planner: str, match: str) -> None:
    spec = f"{M}:{planner}"
    with pytest.raises(srfm.UserCodeError, match=match) as info:
        srfm.run_episode("concert", 0, spec)
    assert "user_planners.py" in info.value.traceback_text
    res = cli("simulate", "--scenario", "concert", "--planner", spec)
    assert res.exit_code == 2
    assert "Traceback" not in res.output
    assert "srfm --debug" in res.output
    assert len(res.output.strip().splitlines()) == 1
    debug = cli("--debug", "simulate", "--scenario", "concert", "--planner", spec)
    assert debug.exit_code == 2
    assert "Traceback" in debug.output
    assert "user_planners.py" in debug.output


def test_srfm_debug_variable_shows_the_traceback(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("SRFM_DEBUG", "1")
    res = cli("simulate", "--scenario", "concert", "--planner", f"{M}:Boom")
    assert res.exit_code == 2
    assert "Traceback" in res.output
    assert "ZeroDivisionError" in res.output


def test_the_error_crosses_from_a_worker_intact() -> None:
    err = srfm.UserCodeError("planner 'x' failed in act(): E", "Traceback ...")
    again = pickle.loads(pickle.dumps(err))
    assert str(again) == str(err)
    assert again.traceback_text == "Traceback ..."


def test_a_benchmark_worker_error_is_one_line(tmp_path: Path, tiny: Path) -> None:
    with pytest.raises(srfm.UserCodeError, match=r"failed in act\(\) at step 3 \(scenario tiny"):
        run_benchmark(
            BenchmarkRequest.create(scenarios=[str(tiny)], planners=[f"{M}:Boom"], seeds=[0, 1]),
            tmp_path / "a",
            jobs=1,
        )

    # Worker processes: nothing but the one line on stderr, exit 2.
    proc = subprocess.run(
        [sys.executable, "-m", "srfm.cli", "benchmark", "-s", str(tiny), "-p", f"{M}:Boom",
         "--seeds", "0-5", "-j", "2", "--out", str(tmp_path / "b"), "--no-figures"],
        capture_output=True, text=True, cwd=REPO, timeout=300,
    )  # fmt: skip
    assert proc.returncode == 2, proc.stderr
    assert "Traceback" not in proc.stderr
    assert "failed in act() at step 3" in proc.stderr


def _finishes(func: Callable[[], object], seconds: float = 10.0) -> object:
    """Run ``func`` in a thread; fail (instead of hanging the suite) if it blocks."""
    result: list[object] = []

    def target() -> None:
        try:
            result.append(func())
        except BaseException as exc:
            result.append(exc)

    thread = threading.Thread(target=target, daemon=True)
    thread.start()
    thread.join(seconds)
    assert not thread.is_alive(), "blocked on a special file"
    return result[0]


def test_a_fifo_or_a_device_is_refused_without_blocking(tmp_path: Path) -> None:
    fifo = tmp_path / "scenario.toml"
    os.mkfifo(fifo)
    for path in (fifo, Path("/dev/zero")):
        got = _finishes(lambda p=path: srfm.load_scenario(p))  # type: ignore[misc]
        assert isinstance(got, srfm.ScenarioError)
        assert "not a regular file" in str(got)
        res = cli("simulate", "--scenario", str(path))
        assert res.exit_code == 2
        assert "not a regular file" in res.output
    res = cli("simulate", "--scenario", "concert", "--params", str(fifo))
    assert res.exit_code == 2
    assert "not a regular file" in res.output
    got = _finishes(lambda: eth_ucy.read_file(fifo))
    assert isinstance(got, srfm.DatasetError)
    assert "not a regular file" in str(got)


def test_an_oversized_file_is_refused_before_it_is_read(tmp_path: Path) -> None:
    big = tmp_path / "big.toml"
    with big.open("wb") as fh:
        fh.truncate(MAX_TOML_BYTES + 1)  # sparse: no disk used
    with pytest.raises(srfm.ScenarioError, match="larger than the 16,777,216 bytes"):
        srfm.load_scenario(big)
    with pytest.raises(srfm.DatasetError, match="larger than the 10 bytes"):
        read_input_bytes(big, max_bytes=10, error=srfm.DatasetError)
    with pytest.raises(srfm.ScenarioError, match="is a folder"):
        srfm.load_scenario(tmp_path)
