"""A plain ``pip install social-robot-force-model`` (no extras) runs the quick benchmark with every
registered planner, including the shipped TD3 policies (NumPy policy files).

torch, stable-baselines3, gymnasium and JAX are blocked in a subprocess by an import
hook (tests/no_extras.py), so the test holds whether or not they are installed here.
"""

from __future__ import annotations

import csv
import subprocess
import sys
from pathlib import Path

from srfm.planners import available_planners

WRAPPER = Path(__file__).with_name("no_extras.py")


def _run(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, str(WRAPPER), *args],
        capture_output=True,
        text=True,
        timeout=600,
        check=False,
    )


def test_blocker_blocks() -> None:
    out = subprocess.run(
        [sys.executable, "-c", f"import runpy; runpy.run_path({str(WRAPPER)!r}); import torch"],
        capture_output=True,
        text=True,
        check=False,
    )
    assert out.returncode != 0
    assert "No module named 'torch' (blocked)" in out.stderr


def test_quick_benchmark_without_extras(tmp_path: Path) -> None:
    names = sorted(p.name for p in available_planners() if p.default)
    assert {"td3-srfm", "td3-base"} <= set(names)
    assert "recorded" not in names  # it needs a scenario with a robot recording
    out = tmp_path / "quick"
    result = _run(
        "benchmark", "--quick", "-s", "crosswalk", "--out", str(out), "-j", "2",
        "--no-figures", "--rrd-seeds", "0",
    )  # fmt: skip
    assert result.returncode == 0, result.stdout + result.stderr
    with (out / "episodes.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    assert sorted({r["planner"] for r in rows}) == names
    assert len(rows) == 3 * len(names)
    assert {r["seed"] for r in rows} == {"0", "1", "2"}
    table = (out / "table.md").read_text()
    for name in names:
        assert name in table
