"""A mistake prints exactly one line and exits 2: click's own usage errors too (they
were three lines: usage, hint, error), and the checks of a run come before its progress
lines (a refused folder or a damaged manifest printed ``benchmark: … episodes`` and
``episodes`` first)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from tests.reliability.conftest import assert_one_line, cli

USAGE = [
    (["benchmark", "--bogus"], "No such option '--bogus'", "(see 'main benchmark --help')"),
    (["benchmark", "--jobs", "0"], "Invalid value for '--jobs' / '-j'", "benchmark --help"),
    (["benchmark", "--executor", "ray"], "'ray' is not one of 'process', 'dask'", "--help"),
    (["benchmark", "--suite", "nope"], "unknown suite 'nope'", "benchmark --help"),
    (["simulate"], "Missing option '--scenario'", "(see 'main simulate --help')"),
    (["simulate", "--scenario"], "Option '--scenario' requires an argument", "--help"),
    (["sweep", "spec.toml"], "Missing option '--out'", "(see 'main sweep run --help')"),
    (["data", "convert", "nope", "a", "b"], "'nope' is not one of 'jrdb'", "data convert --help"),
    (["fly"], "No such command 'fly'", "(see 'main --help')"),
    (["--bogus"], "No such option '--bogus'", "(see 'main --help')"),
    (["train", "--k-div-ramp", "-1"], "Invalid value for '--k-div-ramp'", "train --help"),
]


@pytest.mark.parametrize(("args", "message", "hint"), USAGE, ids=[" ".join(u[0]) for u in USAGE])
def test_usage_errors_are_one_line(args: list[str], message: str, hint: str) -> None:
    assert_one_line(cli(*args), message, hint)


def test_help_is_still_printed() -> None:
    for args in (["--help"], ["benchmark", "--help"], ["data"]):
        res = cli(*args)
        assert "Usage:" in res.output
        assert "Error" not in res.output


def _foreign(tmp_path: Path) -> Path:
    out = tmp_path / "yours"
    out.mkdir()
    (out / "notes.txt").write_text("mine")
    return out


def _damaged(tmp_path: Path) -> Path:
    out = tmp_path / "damaged"
    out.mkdir()
    (out / "manifest.json").write_text("{")
    return out


def _other_params(tmp_path: Path) -> Path:
    out = tmp_path / "other"
    out.mkdir()
    (out / "manifest.json").write_text(json.dumps({"schema": "srfm.benchmark_manifest/1"}))
    return out


@pytest.mark.parametrize(
    ("folder", "message"),
    [
        (_foreign, "is a non-empty folder that srfm did not create (notes.txt)"),
        (_damaged, "damaged manifest"),
        (_other_params, "a results folder of an older or newer srfm"),
    ],
)
def test_a_refused_folder_is_one_line_before_any_progress(
    tiny: Path, tmp_path: Path, folder: object, message: str
) -> None:
    out = folder(tmp_path)  # type: ignore[operator]
    res = cli("benchmark", "-s", str(tiny), "-p", "straight", "--seeds", "0-1", "--out", str(out))
    assert_one_line(res, message)


def test_a_refused_sweep_folder_is_one_line_before_any_progress(tiny: Path, tmp_path: Path) -> None:
    spec = tmp_path / "spec.toml"
    spec.write_text(
        f'schema_version = 1\nscenarios = ["{tiny}"]\nplanners = ["straight"]\nseeds = "0-1"\n'
        '[design]\nkind = "grid"\n[design.factors]\na_robot = [1.0]\n',
        encoding="utf-8",
    )
    res = cli("sweep", str(spec), "--out", str(_foreign(tmp_path)))
    assert_one_line(res, "is a non-empty folder that srfm did not create (notes.txt)")
