"""A Dask scheduler that cannot be one (a malformed address, a scheduler file that is
not JSON or has no address) is refused in one line before anything is written. Before
issue 33: a ``ValueError`` or an ``AssertionError`` from ``distributed``, with
``OUT/manifest.json`` (``OUT/sweep.json``) left behind."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from srfm.benchmark import run_benchmark
from srfm.errors import BenchmarkError
from tests.reliability.conftest import assert_one_line, cli, tiny_request

if os.environ.get("CI") != "true":  # in CI the dask extra is installed: never skip there
    pytest.importorskip("distributed", reason="the dask extra is not installed")

SPEC = """schema_version = 1
scenarios = ["{tiny}"]
planners = ["straight"]
seeds = "0-1"
[design]
kind = "grid"
[design.factors]
a_robot = [1.0, 2.0]
"""

BAD = [
    ("--scheduler", "garbage-address", "--scheduler 'garbage-address' is not a Dask scheduler"),
    ("--scheduler", "tcp://localhost:0", "a host and a port in [1, 65535] are needed"),
    ("--scheduler", "tcp://:8786", "a host and a port in [1, 65535] are needed"),
    ("--scheduler", "foo://host:8786", "unknown address scheme 'foo'"),
    ("--scheduler-file", "{not json", "not a Dask scheduler file (not JSON"),
    ("--scheduler-file", '{"id": "Scheduler-1"}', 'not a Dask scheduler file (no "address"'),
    ("--scheduler-file", '{"address": "nowhere"}', "address 'nowhere' is not a Dask scheduler"),
    ("--scheduler-file", "", "not a Dask scheduler file (not JSON"),
]


@pytest.mark.parametrize("command", ["benchmark", "sweep"])
@pytest.mark.parametrize(("option", "value", "message"), BAD)
def test_a_bad_scheduler_is_one_line_and_nothing_is_written(
    tiny: Path, tmp_path: Path, command: str, option: str, value: str, message: str
) -> None:
    if option == "--scheduler-file":
        path = tmp_path / "scheduler.json"
        path.write_text(value, encoding="utf-8")
        value = str(path)
    out = tmp_path / "out"
    if command == "benchmark":
        args = ["benchmark", "-s", str(tiny), "-p", "straight", "--seeds", "0-1", "--out", str(out)]
    else:
        spec = tmp_path / "spec.toml"
        spec.write_text(SPEC.format(tiny=tiny), encoding="utf-8")
        args = ["sweep", str(spec), "--out", str(out)]
    assert_one_line(cli(*args, option, value), message)
    assert not out.exists()


def test_the_library_refuses_before_claiming_the_folder(tiny: Path, tmp_path: Path) -> None:
    out = tmp_path / "out"
    with pytest.raises(BenchmarkError, match="not a Dask scheduler address"):
        run_benchmark(tiny_request(tiny), out, jobs=1, executor="dask", scheduler="nowhere")
    with pytest.raises(BenchmarkError, match="--scheduler or --scheduler-file, not both"):
        run_benchmark(
            tiny_request(tiny),
            out,
            jobs=1,
            executor="dask",
            scheduler="tcp://localhost:8786",
            scheduler_file=tmp_path / "s.json",
        )
    assert not out.exists()
