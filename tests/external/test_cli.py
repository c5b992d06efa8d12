"""``srfm simulate`` and ``srfm benchmark`` with external planners, as a user runs
them: real planner processes, parallel workers, a failing planner beside good ones, a
resumed run, and a planner listening on TCP (the Python client)."""

from __future__ import annotations

import json
import socket
import subprocess
import sys
from pathlib import Path

import pytest

from srfm.benchmark._results import episode_path, read_episode
from tests.external.conftest import RAW_PLANNER

SRFM = [sys.executable, "-m", "srfm.cli"]


def _srfm(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([*SRFM, *args], capture_output=True, text=True, timeout=900)


def test_simulate_runs_a_cpp_planner(cpp_build: Path) -> None:
    planner = cpp_build / "straight_planner"
    run = _srfm(
        "simulate", "--scenario", "circle", "--planner", "external:cpp",
        "--external", f"cpp={planner}", "--json",
    )  # fmt: skip
    assert run.returncode == 0, run.stderr
    summary = json.loads(run.stdout)
    builtin = json.loads(_srfm("simulate", "--scenario", "circle", "--json").stdout)
    assert summary["planner"] == "external:cpp"
    assert summary["outcome"] == builtin["outcome"] == "goal_reached"
    assert summary["end_step"] == builtin["end_step"]


def test_simulate_refuses_an_undefined_external_planner() -> None:
    run = _srfm("simulate", "--scenario", "circle", "--planner", "external:nope")
    assert run.returncode == 2
    assert run.stderr.strip() == (
        "Error: planner 'external:nope' is not defined: give --external nope=COMMAND (or "
        "nope=unix:PATH, nope=tcp:HOST:PORT), or call srfm.planners.external.define_external first"
    )


def test_benchmark_goes_on_past_a_failing_planner_and_resumes(
    cpp_build: Path, tmp_path: Path
) -> None:
    out = tmp_path / "results"
    command = [
        "benchmark", "-s", "crosswalk", "-p", "straight,external:cpp,external:bad",
        "--external", f"cpp={cpp_build / 'straight_planner'}",
        "--external", f"bad={sys.executable} {RAW_PLANNER} crash@7",
        "--seeds", "0-1", "--jobs", "2", "--no-figures", "--out", str(out),
    ]  # fmt: skip
    first = _srfm(*command)
    assert first.returncode == 0, first.stderr
    lines = [line for line in first.stderr.splitlines() if "planner_failed" in line]
    assert len(lines) == 1, first.stderr
    assert lines[0].startswith("srfm: planner 'external:bad' (")
    assert (
        "crashed: its process exited with status 3 at step 7 (scenario crosswalk, seed 0)"
        in (lines[0])
    )
    outcome = {
        (p, s): read_episode(episode_path(out, "crosswalk", p, s)).outcome
        for p in ("straight", "external:cpp", "external:bad")
        for s in (0, 1)
    }
    assert outcome[("external:bad", 0)] == "planner_failed"
    assert outcome[("external:bad", 1)] == "goal_reached"
    for s in (0, 1):
        mine = read_episode(episode_path(out, "crosswalk", "external:cpp", s))
        builtin = read_episode(episode_path(out, "crosswalk", "straight", s))
        assert mine.values == builtin.values
    assert "failed" in (out / "outcomes.md").read_text(encoding="utf-8")
    # The logs of a failed episode score to the same tables.
    score = _srfm("score", str(out / "logs"), "--out", str(tmp_path / "score"))
    assert score.returncode == 0, score.stderr
    assert "same tables" in score.stderr
    kept = episode_path(out, "crosswalk", "external:bad", 0).read_bytes()
    # A resumed run keeps the failed episode (delete its file to run it again).
    again = _srfm(*command)
    assert again.returncode == 0, again.stderr
    assert "planner_failed" not in again.stderr
    assert episode_path(out, "crosswalk", "external:bad", 0).read_bytes() == kept


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


SERVER = """
import math, sys
from srfm.planners.external import serve

def act(step, episode):
    dx = float(step.goal[0]) - step.x
    dy = float(step.goal[1]) - step.y
    error = math.remainder(math.atan2(dy, dx) - step.theta, 2.0 * math.pi)
    wmax = episode.max_angular_speed_radps
    return episode.max_speed_mps * max(math.cos(error), 0.0), max(-wmax, min(wmax, 2.0 * error))

serve(act, detection_range_m=0.0, address=sys.argv[1])
"""


def test_benchmark_connects_workers_to_a_listening_python_planner(tmp_path: Path) -> None:
    address = f"tcp:127.0.0.1:{_free_port()}"
    server = subprocess.Popen(
        [sys.executable, "-c", SERVER, address], stderr=subprocess.PIPE, text=True
    )
    try:
        assert server.stderr is not None
        assert server.stderr.readline().strip() == f"srfm planner listening on {address}"
        out = tmp_path / "results"
        run = _srfm(
            "benchmark", "-s", "circle", "-p", "straight,external:py",
            "--external", f"py={address}", "--seeds", "0-5", "--jobs", "2",
            "--no-figures", "--no-logs", "--out", str(out),
        )  # fmt: skip
        assert run.returncode == 0, run.stderr
        for seed in range(6):
            mine = read_episode(episode_path(out, "circle", "external:py", seed))
            builtin = read_episode(episode_path(out, "circle", "straight", seed))
            assert mine.values == builtin.values
    finally:
        server.kill()
        server.wait()


@pytest.mark.parametrize("bad", [["cpp"], ["=prog"], ["a b=prog"], ["x=a", "x=b"]])
def test_bad_external_options_are_one_line_errors(bad: list[str]) -> None:
    options = [arg for text in bad for arg in ("--external", text)]
    run = _srfm("simulate", "--scenario", "circle", *options)
    assert run.returncode == 2
    assert len(run.stderr.strip().splitlines()) == 1
    assert run.stderr.startswith("Error: ")


def test_run_benchmark_with_only_external_planners(cpp_build: Path, tmp_path: Path) -> None:
    """The Python API, two workers, no built-in planner to warm up beside them."""
    from srfm.benchmark import BenchmarkRequest, run_benchmark
    from srfm.planners.external import define_external

    name = define_external("only", [str(cpp_build / "straight_planner")])
    request = BenchmarkRequest.create(scenarios=["circle"], planners=[name], seeds=[0, 1, 2])
    summary = run_benchmark(request, tmp_path / "out", jobs=2, figures=False)
    assert summary.simulated == 3
    for seed in range(3):
        assert read_episode(episode_path(tmp_path / "out", "circle", name, seed)).outcome == (
            "goal_reached"
        )
