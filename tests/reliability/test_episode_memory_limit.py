"""An episode's memory is estimated before it starts; one that cannot fit is
refused, naming the estimate and the limit."""

from __future__ import annotations

import tracemalloc
from pathlib import Path

import attrs
import pytest

import srfm
from srfm.benchmark import run_benchmark
from srfm.metrics import episode_metrics
from srfm.scenarios import load_scenario
from srfm.sim.episode import (
    MEMORY_LIMIT_ENV,
    check_episode_memory,
    estimate_episode_memory,
    memory_limit,
)
from tests.reliability.conftest import cli, tiny_request

HUGE = """schema_version = 1
name = "huge"
description = "300 pedestrians for a million steps"
kind = "random"

[simulation]
horizon_steps = 1000000

[random]
count = 300
"""


def test_a_huge_episode_is_refused_before_it_starts(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    path = tmp_path / "huge.toml"
    path.write_text(HUGE, encoding="utf-8")
    monkeypatch.setenv(MEMORY_LIMIT_ENV, "23G")
    message = r"300 pedestrians x 1000001 samples needs about 48\.\d\d GB .* 24\.\d\d GB"
    with pytest.raises(srfm.ResourceError, match=message):
        srfm.run_episode(load_scenario(path), 0)
    res = cli("simulate", "--scenario", str(path))
    assert res.exit_code == 2
    assert "needs about" in res.output
    assert "SRFM_MEMORY_LIMIT=23G" in res.output
    assert "shorten simulation.horizon_steps or use fewer pedestrians" in res.output


def test_the_machine_limit_is_found_and_a_bad_setting_is_refused(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.delenv(MEMORY_LIMIT_ENV, raising=False)
    found = memory_limit()
    if found is not None:  # Linux: /proc/meminfo
        assert found[0] > 0
    monkeypatch.setenv(MEMORY_LIMIT_ENV, "lots")
    with pytest.raises(srfm.ResourceError, match="not a size such as 8G"):
        memory_limit()
    monkeypatch.setenv(MEMORY_LIMIT_ENV, "1.5G")
    assert memory_limit() == (int(1.5 * 2**30), "SRFM_MEMORY_LIMIT=1.5G")


def test_fewer_workers_when_episodes_do_not_fit_side_by_side(
    tmp_path: Path, tiny: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    scenario = load_scenario(tiny)
    need = estimate_episode_memory(scenario)
    monkeypatch.setenv(MEMORY_LIMIT_ENV, str(64 * 2**20 + int(2.5 * need)))
    assert check_episode_memory(scenario, jobs=8) == 2
    monkeypatch.setenv(MEMORY_LIMIT_ENV, str(64 * 2**20 + need // 2))
    with pytest.raises(srfm.ResourceError, match="needs about"):
        check_episode_memory(scenario, jobs=8)
    with pytest.raises(srfm.ResourceError):
        run_benchmark(tiny_request(tiny), tmp_path / "out", jobs=1)
    assert not (tmp_path / "out").exists()  # refused before anything was written


def test_the_estimate_bounds_the_measured_memory() -> None:
    base = load_scenario("random")
    scenario = attrs.evolve(base, horizon_steps=400, random=attrs.evolve(base.random, count=40))
    srfm.run_episode(scenario, 0)  # compile first: numba's own memory is not the episode's
    tracemalloc.start()
    try:
        episode_metrics(srfm.run_episode(scenario, 0))
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    estimate = estimate_episode_memory(scenario)
    assert peak <= estimate <= 3 * peak
    assert estimate_episode_memory(scenario, mcap=True, rrd=True, forces=True) > estimate
