"""Every single-bit flip of every file format srfm reads here (besides MCAP, which has
its own suite) is a clean srfm error or an unchanged result; never another exception.

Files srfm writes and reads back carry a checksum (episode metrics: CRC-32; figure
episodes: the zip's CRC-32), so there a flip is an error or changes nothing. Files people
write (scenarios, dataset sources) have none: a flip may give another valid file, but
never anything but an srfm error or a validated result.
"""

from __future__ import annotations

import json
import warnings
from collections.abc import Callable, Iterator
from pathlib import Path

import numpy as np
import pytest

import srfm
from srfm.benchmark import episode_path, read_episode, run_benchmark
from srfm.benchmark._request import check_manifest
from srfm.benchmark.figures import figure_episode_path, load_figure_episode
from srfm.datasets import eth_ucy, jrdb, navwareset
from srfm.scenarios import load_scenario
from tests.reliability.conftest import ETH, NAVWARE, TINY, tiny_request


def _flips(data: bytes, step: int = 1) -> Iterator[bytes]:
    """``data`` with one bit flipped, for every ``step``-th bit."""
    for bit in range(0, 8 * len(data), step):
        flipped = bytearray(data)
        flipped[bit // 8] ^= 1 << (bit % 8)
        yield bytes(flipped)


def _each_flip(path: Path, read: Callable[[Path], object], step: int = 1) -> Iterator[object]:
    """Write every flip of ``path`` over it, read it, yield the result or the SrfmError."""
    original = path.read_bytes()
    try:
        for data in _flips(original, step):
            path.write_bytes(data)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", srfm.SrfmWarning)
                try:
                    yield read(path)
                except srfm.SrfmError as exc:
                    yield exc
    finally:
        path.write_bytes(original)


@pytest.fixture(scope="module")
def run(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    root = tmp_path_factory.mktemp("flips")
    tiny = root / "tiny.toml"
    tiny.write_text(TINY, encoding="utf-8")
    run_benchmark(tiny_request(tiny, range(2)), root / "out", jobs=1)
    return tiny, root / "out"


def test_episode_metrics_files(run: tuple[Path, Path]) -> None:
    _, out = run
    path = episode_path(out, "tiny", "straight", 1)
    want = read_episode(path).to_document()
    expect = ("tiny", "straight", 1)
    results = list(_each_flip(path, lambda p: read_episode(p, expect=expect), step=3))
    changed = [r for r in results if not isinstance(r, srfm.SrfmError) and r.to_document() != want]  # type: ignore[attr-defined]
    assert changed == []
    assert sum(isinstance(r, srfm.BenchmarkError) for r in results) > 0.9 * len(results)


def test_figure_episodes(run: tuple[Path, Path]) -> None:
    _, out = run
    path = figure_episode_path(out, "tiny", "straight")
    want = load_figure_episode(out, "tiny", "straight", 0)
    assert want is not None

    def read(_: Path) -> object:
        return load_figure_episode(out, "tiny", "straight", 0)

    for got in _each_flip(path, read, step=23):  # every 23rd bit: ~1,000 flips
        if got is None:  # damaged: the figure's episode is simulated again
            continue
        for name in ("factual_pos", "counterfactual_pos", "robot_pose", "robot_goal"):
            assert np.array_equal(getattr(got, name), getattr(want, name))
        assert (got.outcome, got.end_step) == (want.outcome, want.end_step)  # type: ignore[attr-defined]


def test_manifest(run: tuple[Path, Path]) -> None:
    tiny, out = run
    request = tiny_request(tiny, range(2))
    manifest = out / "manifest.json"
    for result in _each_flip(manifest, lambda p: check_manifest(out, request), step=11):
        assert isinstance(result, dict | srfm.BenchmarkError)


@pytest.mark.parametrize(
    ("name", "text", "read"),
    [
        ("s.toml", TINY, load_scenario),
        ("e.txt", ETH, eth_ucy.read_file),
        ("n.csv", NAVWARE, navwareset.read_file),
        (
            "seq.json",
            json.dumps(
                {
                    "labels": {
                        "000001.pcd": [{"label_id": "pedestrian:1", "box": {"cx": 1, "cy": 2}}]
                    }
                }
            ),
            jrdb.read_sequence,
        ),
    ],
    ids=["scenario", "eth-ucy", "navwareset", "jrdb"],
)
def test_text_inputs(tmp_path: Path, name: str, text: str, read: Callable[[Path], object]) -> None:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    for result in _each_flip(path, read):
        assert isinstance(result, srfm.SrfmError | srfm.Scenario | srfm.datasets.Trajectories)
