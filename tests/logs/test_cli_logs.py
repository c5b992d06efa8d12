"""The logging options of `srfm simulate` and `srfm benchmark`, and `srfm view`."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import pytest
from click.testing import CliRunner

from srfm.cli import main
from srfm.logs import load_episode


def test_simulate_out_writes_both_logs(tmp_path: Path) -> None:
    res = CliRunner().invoke(
        main, ["simulate", "--scenario", "concert", "--seed", "2", "--out", str(tmp_path), "--json"]
    )
    assert res.exit_code == 0, res.output
    logs = json.loads(res.output)["logs"]
    folder = tmp_path / "logs" / "concert" / "straight"
    assert logs == [str(folder / "seed-000002.mcap"), str(folder / "seed-000002.rrd")]
    logged = load_episode(folder / "seed-000002.mcap")
    assert logged.exact_velocities
    assert logged.record.seed == 2
    res = CliRunner().invoke(
        main,
        [
            "simulate",
            "--scenario",
            "concert",
            "--out",
            str(tmp_path / "b"),
            "--no-rrd",
            "--mcap-profile",
            "compact",
        ],
    )
    assert res.exit_code == 0, res.output
    assert "log        " in res.output
    files = sorted(p.name for p in (tmp_path / "b").rglob("*") if p.is_file())
    assert files == ["seed-000000.mcap"]
    assert not load_episode(tmp_path / "b/logs/concert/straight/seed-000000.mcap").exact_velocities


def test_simulate_refuses_out_without_any_log(tmp_path: Path) -> None:
    res = CliRunner().invoke(
        main, ["simulate", "--scenario", "concert", "--out", str(tmp_path), "--no-rrd", "--no-mcap"]
    )
    assert res.exit_code == 2
    assert "writes nothing" in res.output


def test_benchmark_log_options(tmp_path: Path) -> None:
    base = ["benchmark", "-s", "concert", "-p", "straight", "--seeds", "0-2", "--no-figures"]
    res = CliRunner().invoke(
        main, [*base, "--out", str(tmp_path / "a"), "-j", "2", "--rrd-seeds", "2"]
    )
    assert res.exit_code == 0, res.output
    folder = tmp_path / "a" / "logs" / "concert" / "straight"
    assert sorted(p.name for p in folder.iterdir()) == [
        "seed-000000.mcap",
        "seed-000000.rrd",
        "seed-000001.mcap",
        "seed-000001.rrd",
        "seed-000002.mcap",
    ]
    assert "3 episode .mcap files" in res.stderr
    assert "2 .rrd files" in res.stderr
    assert "3 counterfactual .mcap files" in res.stderr
    res = CliRunner().invoke(main, [*base, "--out", str(tmp_path / "b"), "-j", "1", "--no-logs"])
    assert res.exit_code == 0
    assert not (tmp_path / "b" / "logs").exists()
    res = CliRunner().invoke(
        main,
        [
            *base,
            "--out",
            str(tmp_path / "c"),
            "-j",
            "1",
            "--rrd-seeds",
            "0",
            "--mcap-profile",
            "full",
        ],
    )
    assert res.exit_code == 0
    files = sorted(p.name for p in (tmp_path / "c" / "logs").rglob("*") if p.is_file())
    assert files == ["seed-000000.mcap", "seed-000001.mcap", "seed-000002.mcap"]  # no sharing
    res = CliRunner().invoke(main, [*base, "--out", str(tmp_path / "d"), "--rrd-seeds", "some"])
    assert res.exit_code == 2
    assert "--rrd-seeds" in res.output


@pytest.fixture(scope="module")
def recording(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("view")
    res = CliRunner().invoke(
        main, ["simulate", "--scenario", "concert", "--out", str(out), "--no-mcap"]
    )
    assert res.exit_code == 0, res.output
    return out / "logs" / "concert" / "straight" / "seed-000000.rrd"


def test_view_without_a_display_prints_the_command(
    recording: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(sys, "platform", "linux")
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    res = CliRunner().invoke(main, ["view", str(recording)])
    assert res.exit_code == 0, res.output
    assert "no display here" in res.output
    assert f"-m rerun {recording}" in res.output
    res = CliRunner().invoke(main, ["view", str(recording), "--print-command"])
    assert res.output.strip().endswith(f"-m rerun {recording}")


@pytest.mark.parametrize(
    ("content", "match"),
    [
        (None, "no such file"),
        (b"hello", "not a Rerun recording"),
        (b"RRF2" + b"\0" * 8, "unreadable"),
    ],
)
def test_view_rejects_missing_and_foreign_files(
    tmp_path: Path, content: bytes | None, match: str
) -> None:
    path = tmp_path / "x.rrd"
    if content is not None:
        path.write_bytes(content)
    res = CliRunner().invoke(main, ["view", str(path)])
    assert res.exit_code == 2
    assert match in res.output
    assert "x.rrd" in res.output
    assert "Traceback" not in res.output


def test_score_names_the_schema_version_and_writer_of_an_old_file() -> None:
    old = Path(__file__).with_name("data") / "schema-v2-episode.mcap"
    res = CliRunner().invoke(main, ["score", str(old)])
    assert res.exit_code == 2
    assert "log schema version 2, written by srfm 0.1.0" in res.output
    assert "Traceback" not in res.output
