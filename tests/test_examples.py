"""Every script of examples/ runs in its fast mode (``--fast``, under a minute each on
an idle two-core machine) and leaves what it says it writes. One test per example."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from tests.conftest import REPO

EXAMPLES = REPO / "examples"


def _run(name: str, tmp_path: Path) -> str:
    env = {
        **os.environ,
        "SRFM_EXAMPLES_OUT": str(tmp_path),
        "PYTHONPATH": os.pathsep.join([str(REPO), os.environ.get("PYTHONPATH", "")]),
    }
    done = subprocess.run(
        [sys.executable, str(EXAMPLES / name), "--fast"],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        timeout=600,
        check=False,
    )
    assert done.returncode == 0, done.stdout + done.stderr
    return done.stdout


def test_every_example_has_a_test() -> None:
    tested = {
        "01_own_planner.py",
        "02_own_scenario.py",
        "03_dataset_fit.py",
        "04_train_policy.py",
        "05_score_and_view_logs.py",
        "06_dask_sweep.py",
        "07_external_planner.py",
    }
    assert {p.name for p in EXAMPLES.glob("*.py")} == tested


def test_own_planner(tmp_path: Path) -> None:
    out = _run("01_own_planner.py", tmp_path)
    folder = tmp_path / "01_own_planner"
    table = (folder / "table.md").read_text(encoding="utf-8")
    for planner in ("cautious", "straight", "dwa"):
        assert f"| crosswalk | {planner} |" in table
    assert (folder / "report.html").is_file()
    assert f"open {folder / 'report.html'}" in out


def test_own_scenario(tmp_path: Path) -> None:
    out = _run("02_own_scenario.py", tmp_path)
    folder = tmp_path / "02_own_scenario"
    assert (folder / "lobby-seed0.rrd").stat().st_size > 0
    assert (folder / "lobby-seed0.mcap").stat().st_size > 0
    assert "12 pedestrians in all" in out
    assert f"srfm view {folder / 'lobby-seed0.rrd'}" in out


def test_dataset_fit(tmp_path: Path) -> None:
    out = _run("03_dataset_fit.py", tmp_path)
    assert (tmp_path / "03_dataset_fit" / "fitted.toml").is_file()
    for name in ("agrawal2024", "ferrer2013", "navwareset2025", "fitted here"):
        assert f"\n{name}" in out


def test_train_policy(tmp_path: Path) -> None:
    pytest.importorskip("stable_baselines3", reason="needs the rl extra")
    out = _run("04_train_policy.py", tmp_path)
    assert (tmp_path / "04_train_policy" / "my_policy.npz").is_file()
    assert "trained 300 steps" in out
    assert "   my-td3: success" in out
    assert " td3-srfm: success" in out


def test_score_and_view_logs(tmp_path: Path) -> None:
    out = _run("05_score_and_view_logs.py", tmp_path)
    assert "identical to the benchmark's: True" in out
    assert "srfm view " in out
    assert "foxglove_layout.json" in out
    assert (REPO / "docs" / "foxglove_layout.json").is_file()


def test_dask_sweep(tmp_path: Path) -> None:
    pytest.importorskip("distributed", reason="needs the sweep extra")
    out = _run("06_dask_sweep.py", tmp_path)
    report = tmp_path / "06_dask_sweep" / "results" / "report"
    assert (report / "report.md").is_file()
    assert (report / "a_robot.png").is_file()
    assert "8 episodes in" in out


def test_external_planner(tmp_path: Path) -> None:
    out = _run("07_external_planner.py", tmp_path)
    table = (tmp_path / "07_external_planner" / "results" / "table.md").read_text(encoding="utf-8")
    for planner in ("straight", "external:cpp", "external:reactive", "external:py"):
        assert f"| crosswalk | {planner} |" in table
    # The C++ straight planner's row is the built-in one's, number for number.
    rows = {
        tuple(c.strip() for c in line.split("|")[1:3]): line.split("|")[3:]
        for line in table.splitlines()
        if line.startswith("| crosswalk |") or line.startswith("| circle |")
    }
    for scenario in ("crosswalk", "circle"):
        assert rows[(scenario, "external:cpp")] == rows[(scenario, "straight")]
    assert "8 episodes in" in out
