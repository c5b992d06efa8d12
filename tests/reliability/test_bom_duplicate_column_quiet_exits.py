"""A duplicated CSV column, UTF-8 byte-order marks, quiet ends of workers and
of a closed stdout."""

from __future__ import annotations

import json
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

import srfm
from srfm.datasets import eth_ucy, jrdb, navwareset
from srfm.scenarios import load_scenario
from tests.conftest import REPO
from tests.reliability.conftest import ETH, NAVWARE, TINY

BOM = "\ufeff"


def test_a_duplicated_navwareset_column_is_an_error(tmp_path: Path) -> None:
    path = tmp_path / "n.csv"
    path.write_text(NAVWARE.replace("timestamp,x,y,", "timestamp,x,y,x,", 1), encoding="utf-8")
    with pytest.raises(srfm.DatasetError, match=r"n\.csv:1: column 'x' appears twice"):
        navwareset.read_file(path)


def test_a_byte_order_mark_is_accepted_everywhere(tmp_path: Path) -> None:
    scenario = tmp_path / "s.toml"
    scenario.write_text(BOM + TINY, encoding="utf-8")
    assert load_scenario(scenario).name == "tiny"
    for name, text, read in (
        ("e.txt", ETH, eth_ucy.read_file),
        ("n.csv", NAVWARE, navwareset.read_file),
    ):
        plain, marked = tmp_path / f"plain-{name}", tmp_path / name
        plain.write_text(text, encoding="utf-8")
        marked.write_text(BOM + text, encoding="utf-8")
        a, b = read(plain), read(marked)
        assert a.xy.tolist() == b.xy.tolist()
        assert a.t_ns.tolist() == b.t_ns.tolist()
    labels = tmp_path / "seq.json"
    doc = {"labels": {"000001.pcd": [{"label_id": "pedestrian:1", "box": {"cx": 1, "cy": 2}}]}}
    labels.write_text(BOM + json.dumps(doc), encoding="utf-8")
    with pytest.warns(srfm.DatasetWarning):
        assert jrdb.read_sequence(labels).n_samples == 2


def test_workers_end_quietly_when_the_parent_is_killed(tmp_path: Path, tiny: Path) -> None:
    out = tmp_path / "run"
    proc = subprocess.Popen(
        [sys.executable, "-m", "srfm.cli", "benchmark", "-s", str(tiny), "-p", "straight",
         "--seeds", "0-3999", "-j", "2", "--out", str(out), "--no-figures", "--no-logs"],
        stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, cwd=REPO,
    )  # fmt: skip
    episodes = out / "episodes" / "tiny" / "straight"
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and len(list(episodes.glob("seed-*.json"))) < 20:
        time.sleep(0.05)
    proc.send_signal(signal.SIGKILL)  # the parent only: its workers are orphaned
    _, err = proc.communicate(timeout=60)  # EOF once every worker has ended too
    assert "BrokenPipeError" not in err
    assert "Traceback" not in err
    assert 20 <= len(list(episodes.glob("seed-*.json"))) < 4000


def test_a_closed_stdout_ends_quietly() -> None:
    proc = subprocess.Popen(
        [sys.executable, "-m", "srfm.cli", "scenarios"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, cwd=REPO,
    )  # fmt: skip
    assert proc.stdout is not None
    proc.stdout.close()  # like `srfm scenarios | head -0`
    _, err = proc.communicate(timeout=60)
    assert b"Traceback" not in err
    assert proc.returncode in (0, 141)
