"""Runs too large for the machine: a benchmark, a sweep or an episode is estimated from
its size before it starts (srfm.sim.budget), and refused with the estimate and the way
to go ahead when it cannot fit this machine's memory or would take longer than the
time limit; a large run that goes ahead prints its estimate. Before issue 33 a sweep of
7 × 10^10 episodes was accepted and reached 2 GB before its first partition, and a
scenario of 100,000 pedestrians stepped on at 6 GB.

The subprocesses run under an address-space limit, so that a build without the guard
fails here with a MemoryError instead of exhausting a shared machine."""

from __future__ import annotations

import math
import os
import resource
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from srfm.errors import ResourceError
from srfm.scenarios import load_scenario
from srfm.sim.episode import MEMORY_LIMIT_ENV, run_episode
from tests.conftest import REPO
from tests.reliability.conftest import assert_one_line, cli

TIME_LIMIT_ENV = "SRFM_TIME_LIMIT"
_ADDRESS_SPACE = 6 * 2**30  # bytes: srfm needs under 1 GiB of it to refuse these runs
SEVEN_PLANNERS = "dwa,orca,social-force,straight,td3-base,td3-srfm,vo"


def _srfm(args: list[str], env: dict[str, str], timeout: float = 120.0) -> tuple[int, str]:
    """``srfm ARGS`` in a process limited to ``_ADDRESS_SPACE`` of memory."""

    def limit() -> None:
        resource.setrlimit(resource.RLIMIT_AS, (_ADDRESS_SPACE, _ADDRESS_SPACE))

    proc = subprocess.run(
        [sys.executable, "-m", "srfm.cli", *args],
        capture_output=True,
        text=True,
        timeout=timeout,
        env={**os.environ, "PYTHONPATH": str(REPO), **env},
        preexec_fn=limit,
    )
    return proc.returncode, proc.stdout + proc.stderr


def test_a_sweep_of_7e10_episodes_is_refused_at_once(tiny: Path, tmp_path: Path) -> None:
    """The issue's sweep: 100,000 cells × 7 planners × 100,000 seeds."""
    spec = tmp_path / "huge.toml"
    a_robot = ", ".join(f"{0.1 * k:.1f}" for k in range(100))
    b_robot = ", ".join(f"{0.5 + 0.001 * k:.3f}" for k in range(1000))
    spec.write_text(
        f'schema_version = 1\nscenarios = ["{tiny}"]\n'
        f"planners = [{', '.join(repr(p) for p in SEVEN_PLANNERS.split(','))}]\n"
        f'seeds = "0-99999"\n[design]\nkind = "grid"\n[design.factors]\n'
        f"a_robot = [{a_robot}]\nb_robot = [{b_robot}]\n",
        encoding="utf-8",
    )
    out = tmp_path / "out"
    code, output = _srfm(["sweep", str(spec), "--out", str(out)], {})
    assert code == 2, output
    lines = output.splitlines()
    assert len(lines) == 1, output
    assert lines[0].startswith("Error: the sweep 'huge' is too large for this machine: ")
    assert "70,000,000,000 episodes: about " in lines[0]
    assert "longer than the limit of 24.0 h (srfm's time limit)" in lines[0]
    assert "Ask for fewer cells, scenarios, planners or seeds, or give --force" in lines[0]
    assert not out.exists()


def _crowd(path: Path, n: int) -> Path:
    """A version-1 scenario of ``n`` pedestrians on a 1.5 m grid, crossing the world."""
    side = int(np.ceil(np.sqrt(n)))
    xs, ys = np.meshgrid(np.arange(side) * 1.5 + 1.0, np.arange(side) * 1.5 + 1.0)
    points = np.stack([xs.ravel(), ys.ravel()], axis=1)[:n]
    width = side * 1.5 + 2.0
    starts = ", ".join(f"[{x:.1f}, {y:.1f}]" for x, y in points)
    goals = ", ".join(f"[{width - x:.1f}, {y:.1f}]" for x, y in points)
    path.write_text(
        f'schema_version = 1\nname = "crowd"\ndescription = "{n} pedestrians"\n'
        f"[world]\nx_min = -5.0\nx_max = {width + 5:.1f}\ny_min = -5.0\ny_max = {width + 5:.1f}\n"
        f"[robot]\nstart = [-4.0, -4.0]\ngoal = [{width + 4:.1f}, {width + 4:.1f}]\n"
        f"[pedestrians]\nstarts = [{starts}]\ngoals = [{goals}]\n",
        encoding="utf-8",
    )
    return path


def test_a_scenario_of_100000_pedestrians_is_refused_with_its_estimate(tmp_path: Path) -> None:
    """An episode of it: about 7 minutes and 12 GB (by the model); beyond a time limit of
    a minute it is refused before anything is allocated."""
    crowd = _crowd(tmp_path / "crowd.toml", 100_000)
    code, output = _srfm(["simulate", "--scenario", str(crowd)], {TIME_LIMIT_ENV: "60"})
    assert code == 2, output
    lines = output.splitlines()
    assert len(lines) == 1, output
    assert lines[0].startswith(
        "Error: an episode of scenario 'crowd' is too large for this machine: 1 episode: about "
    )
    assert "GB of memory; longer than the limit of 60 s (SRFM_TIME_LIMIT=60)" in lines[0]
    assert "a shorter simulation.horizon_steps or fewer pedestrians, or give --force" in lines[0]


def test_a_benchmark_beyond_the_time_limit_is_refused_before_its_folder_is_touched(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """7 planners × 100,000 seeds of crosswalk: hours; refused, in one line, before the
    folder is checked (a build without the guard refuses the folder instead)."""
    monkeypatch.setenv(TIME_LIMIT_ENV, "1h")
    out = tmp_path / "yours"
    out.mkdir()
    (out / "notes.txt").write_text("mine")
    args = ["benchmark", "-s", "crosswalk", "-p", SEVEN_PLANNERS, "--seeds", "0-99999"]
    assert_one_line(
        cli(*args, "--out", str(out)),
        "the benchmark is too large for this machine: 700,000 episodes: about ",
        "longer than the limit of 60 min (SRFM_TIME_LIMIT=1h)",
        "Ask for fewer scenarios, planners or seeds, or give --force to run it anyway",
    )
    assert sorted(p.name for p in out.iterdir()) == ["notes.txt"]


def test_a_forced_run_goes_ahead_and_prints_its_estimate(
    tiny: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv(TIME_LIMIT_ENV, "0.001")
    args = ["benchmark", "-s", str(tiny), "-p", "straight", "--seeds", "0-2", "-j", "1"]
    refused = cli(*args, "--out", str(tmp_path / "refused"))
    assert_one_line(refused, "longer than the limit of 0 s (SRFM_TIME_LIMIT=0.001)")
    res = cli(*args, "--out", str(tmp_path / "forced"), "--no-logs", "--no-figures", "--force")
    assert res.exit_code == 0, res.output
    estimate = [line for line in res.output.splitlines() if line.startswith("estimate: ")]
    assert len(estimate) == 1, res.output
    assert estimate[0].startswith("estimate: 3 episodes: about ")
    assert estimate[0].endswith("; longer than the limit of 0 s (SRFM_TIME_LIMIT=0.001)")


def test_the_memory_a_run_holds_is_checked(tiny: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A run whose bookkeeping (the benchmark's reports hold every episode's metrics)
    and one episode exceed the memory is refused, though each episode fits."""
    from srfm.sim.budget import check_run, estimate_run

    scenario = load_scenario(tiny)
    monkeypatch.setenv(MEMORY_LIMIT_ENV, str(64 * 2**20 + 10 * 2**20))
    small = estimate_run([(scenario, 10)], held_per_episode=5_200)
    assert check_run(small, what="the run", smaller="less").beyond == ()
    big = estimate_run([(scenario, 10_000)], held_per_episode=5_200)
    with pytest.raises(ResourceError, match=r"more memory than the 10\.5 MB of SRFM_MEMORY_LIMIT"):
        check_run(big, what="the run", smaller="less")
    assert check_run(big, what="the run", smaller="less", force=True).beyond != ()


def test_the_time_limit_and_its_setting(monkeypatch: pytest.MonkeyPatch) -> None:
    from srfm.sim.budget import DEFAULT_TIME_LIMIT_S, time_limit

    monkeypatch.delenv(TIME_LIMIT_ENV, raising=False)
    assert time_limit() == (DEFAULT_TIME_LIMIT_S, "srfm's time limit")
    for text, seconds in (("90", 90.0), ("90m", 5400.0), ("48h", 172800.0), ("7d", 604800.0)):
        monkeypatch.setenv(TIME_LIMIT_ENV, text)
        assert time_limit() == (seconds, f"{TIME_LIMIT_ENV}={text}")
    for text in ("soon", "-5", "0", "1e9", "٣h"):
        monkeypatch.setenv(TIME_LIMIT_ENV, text)
        with pytest.raises(ResourceError, match="is not a duration such as"):
            time_limit()


def test_the_episode_time_model_scales_as_real_episodes_do() -> None:
    """The model's structure against the CPU time of real episodes of very different
    sizes (the paper's 10 pedestrians, a corridor of 27 with walls, a crowd of 400), on
    whatever machine runs the tests. The model's scale is the reference machine's
    (docs/performance.md) and a faster or slower CPU shifts every episode alike, so the
    test compares ratios, never this machine's speed: measured / estimated must be the
    same for every scenario within a factor of four (the estimate of a run that cannot
    fit errs the same way for all its episodes)."""
    from srfm.sim.budget import estimate_episode_time

    ratios: dict[str, float] = {}
    for name, seeds in (("crosswalk", range(5)), ("corridor_flow", range(2)),
                        ("concert_crowd", range(1))):  # fmt: skip
        scenario = load_scenario(name)
        run_episode(scenario, 99)  # compiled or loaded
        best = math.inf
        for _ in range(2):  # the faster of two passes: a neighbour's burst only slows one
            start = time.process_time()
            for seed in seeds:
                run_episode(scenario, seed)
            best = min(best, (time.process_time() - start) / len(seeds))
        ratios[name] = best / estimate_episode_time(scenario)
    assert max(ratios.values()) < 4 * min(ratios.values()), ratios
