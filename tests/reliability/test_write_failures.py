"""Outputs are checked before the work; a failed write is one clean message
(exit 73) that leaves the old files intact; a benchmark's reports change as a whole."""

from __future__ import annotations

import errno
import json
import os
from pathlib import Path

import pytest

import srfm
import srfm._io
from srfm._io import atomic_write_text, check_writable, recover_file_set, write_file_set
from srfm.benchmark import run_benchmark
from tests.reliability.conftest import ETH, cli, tiny_request

REPORTS = (
    "episodes.csv",
    "pedestrians.csv",
    "table.md",
    "table.tex",
    "outcomes.md",
    "summary.json",
)


def _disk_full_after(monkeypatch: pytest.MonkeyPatch, calls: int) -> None:
    """Make fsync fail with ENOSPC from the (calls + 1)-th call on."""
    real = os.fsync
    count = [0]

    def fsync(fd: int) -> None:
        count[0] += 1
        if count[0] > calls:
            raise OSError(errno.ENOSPC, "No space left on device")
        real(fd)

    monkeypatch.setattr(srfm._io.os, "fsync", fsync)


def _leftovers(folder: Path) -> list[str]:
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*.tmp"))


def test_a_file_where_a_folder_is_needed_is_refused_before_the_fit(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    src = tmp_path / "x.txt"
    src.write_text(ETH, encoding="utf-8")
    data = tmp_path / "d.mcap"
    assert cli("data", "convert", "eth-ucy", str(src), str(data)).exit_code == 0
    blocker = tmp_path / "file"
    blocker.write_text("", encoding="utf-8")

    def no_fit(*args: object, **kwargs: object) -> None:
        raise AssertionError("the fit ran before the output was checked")

    monkeypatch.setattr("srfm.fitting.fit_params", no_fit)
    res = cli("fit", str(data), "-o", str(blocker / "p.toml"))
    assert res.exit_code == 2
    assert "is a file, not a folder" in res.output
    res = cli("data", "convert", "eth-ucy", str(src), str(blocker / "d.mcap"))
    assert res.exit_code == 2
    assert "is a file, not a folder" in res.output


@pytest.mark.parametrize(
    "args",
    [
        ["data", "convert", "eth-ucy", "SRC", "OUT/d.mcap"],
        ["simulate", "--scenario", "concert", "--out", "OUT/run", "--no-rrd"],
        ["benchmark", "-s", "concert", "-p", "straight", "--seeds", "0", "--out", "OUT/b"],
        ["train", "--run-dir", "OUT/run", "--steps", "1"],
    ],
    ids=["convert", "simulate", "benchmark", "train"],
)
def test_an_unwritable_output_is_one_line_exit_73_before_the_work(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, args: list[str]
) -> None:
    src = tmp_path / "x.txt"
    src.write_text(ETH, encoding="utf-8")
    out = tmp_path / "ro"
    out.mkdir()

    def refuse(*a: object, **k: object) -> tuple[int, str]:
        raise PermissionError(errno.EACCES, "Permission denied")

    monkeypatch.setattr(srfm._io.tempfile, "mkstemp", refuse)  # as a read-only folder does
    argv = [a.replace("SRC", str(src)).replace("OUT", str(out)) for a in args]
    res = cli(*argv)
    assert res.exit_code == 73, res.output
    assert "Permission denied" in res.output
    assert "Traceback" not in res.output
    assert list(out.iterdir()) == []


def test_a_full_disk_keeps_the_old_file_and_leaves_no_temporary(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    target = tmp_path / "a.txt"
    atomic_write_text(target, "old")
    _disk_full_after(monkeypatch, 0)
    with pytest.raises(srfm.WriteError, match=r"cannot write .*a\.txt: No space left") as info:
        atomic_write_text(target, "new")
    assert isinstance(info.value, OSError)
    assert info.value.errno == errno.ENOSPC
    assert target.read_text() == "old"
    assert _leftovers(tmp_path) == []


def test_the_report_phase_is_atomic_as_a_whole(
    tmp_path: Path, tiny: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    out = tmp_path / "run"
    run_benchmark(tiny_request(tiny, range(3)), out, jobs=1, figures=False)
    old = {name: (out / name).read_bytes() for name in REPORTS}
    # The disk fills while the reports of seeds 0-4 are written (after two of six).
    with monkeypatch.context() as m:
        _disk_full_after(m, 3)  # manifest + two staged reports succeed
        with pytest.raises(srfm.WriteError, match="No space left"):
            run_benchmark(tiny_request(tiny, range(5)), out, jobs=1, figures=False)
    assert {name: (out / name).read_bytes() for name in REPORTS} == old
    assert _leftovers(out) == []
    summary = json.loads((out / "summary.json").read_text())
    assert summary["request"]["seeds"] == [0, 1, 2]
    # The CLI: one line, exit 73.
    with monkeypatch.context() as m:
        _disk_full_after(m, 3)
        res = cli(
            "benchmark", "-s", str(tiny), "-p", "straight", "--seeds", "0-4", "--out", str(out),
            "-j", "1", "--no-figures", "--no-logs",
        )  # fmt: skip
    assert res.exit_code == 73, res.output
    assert res.output.strip().splitlines()[-1].startswith("Error: cannot write")
    assert {name: (out / name).read_bytes() for name in REPORTS} == old
    # Space again: the run completes to the new reports.
    run_benchmark(tiny_request(tiny, range(5)), out, jobs=1, figures=False)
    assert json.loads((out / "summary.json").read_text())["request"]["seeds"] == [0, 1, 2, 3, 4]


def test_a_set_cut_short_during_its_renames_is_completed_by_the_next_run(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    for name in ("a", "b", "c"):
        (tmp_path / name).write_text("old", encoding="utf-8")
    real = os.replace
    done = [0]

    def killed_after_one(src: str, dst: str) -> None:
        if str(dst).endswith(("b", "c")):
            raise KeyboardInterrupt  # the process dies here
        done[0] += 1
        real(src, dst)

    monkeypatch.setattr(srfm._io.os, "replace", killed_after_one)
    with pytest.raises(KeyboardInterrupt):
        write_file_set(tmp_path, {"a": b"new", "b": b"new", "c": b"new"})
    monkeypatch.setattr(srfm._io.os, "replace", real)
    assert [(tmp_path / n).read_text() for n in "abc"] == ["new", "old", "old"]
    assert recover_file_set(tmp_path) == 2
    assert [(tmp_path / n).read_text() for n in "abc"] == ["new", "new", "new"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a", "b", "c"]


def test_check_writable_names_the_blocking_file(tmp_path: Path) -> None:
    (tmp_path / "f").write_text("", encoding="utf-8")
    with pytest.raises(srfm.OutputError, match="is a file, not a folder"):
        check_writable(tmp_path / "f" / "g" / "h.txt")
    with pytest.raises(srfm.OutputError, match="is a folder"):
        check_writable(tmp_path)
    with pytest.raises(srfm.OutputError, match="not a folder"):
        check_writable(tmp_path / "f", folder=True)
    check_writable(tmp_path / "new" / "x.txt")
    assert not (tmp_path / "new").exists()  # the check creates nothing
