"""Shared pieces of the bad-input suite: a tiny scenario, the CLI, tiny dataset files."""

from __future__ import annotations

from pathlib import Path

import pytest
from click.testing import CliRunner, Result

from srfm.benchmark import BenchmarkRequest
from srfm.cli import main

# Two pedestrians, 40 steps: every episode takes milliseconds.
TINY = """schema_version = 1
name = "tiny"
description = "two pedestrians, forty steps"

[simulation]
horizon_steps = 40

[robot]
start = [2.0, 8.0]
goal = [12.0, 9.0]

[pedestrians]
starts = [[1.0, 1.0], [5.0, 5.0]]
goals = [[10.0, 10.0], [1.0, 9.0]]
"""

ETH = "0 1 1.0 2.0\n0 2 3.0 4.0\n10 1 1.4 2.0\n10 2 3.0 4.4\n20 1 1.8 2.0\n20 2 3.0 4.8\n"
NAVWARE = (
    "timestamp,x,y,robot_x,robot_y,column\n"
    "1000000000,1.0,2.0,5.0,5.0,3\n"
    "1100000000,1.1,2.0,5.0,5.1,3\n"
    "1200000000,1.2,2.0,5.0,5.2,3\n"
)


def cli(*args: str) -> Result:
    """Run ``srfm ARGS`` in-process; exceptions become exit codes as on a terminal."""
    return CliRunner().invoke(main, list(args))


def assert_one_line(result: Result, *fragments: str, code: int = 2) -> None:
    """``result`` printed exactly one line, ``Error: ...`` holding every fragment (stdout
    and stderr together, as a terminal shows them), and exited with ``code``."""
    lines = result.output.splitlines()
    assert result.exit_code == code, result.output
    assert len(lines) == 1, result.output
    assert lines[0].startswith("Error: "), result.output
    assert "Traceback" not in result.output
    for fragment in fragments:
        assert fragment in lines[0], (fragment, result.output)


@pytest.fixture
def tiny(tmp_path: Path) -> Path:
    path = tmp_path / "tiny.toml"
    path.write_text(TINY, encoding="utf-8")
    return path


def tiny_request(tiny: Path, seeds: range = range(3)) -> BenchmarkRequest:
    return BenchmarkRequest.create(scenarios=[str(tiny)], planners=["straight"], seeds=list(seeds))
