"""An output is never one of the inputs, and reports never land among a
user's own files (a non-empty folder srfm did not create) unless --force."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

import srfm
from srfm._io import OUTPUT_MARKER, claim_output_folder, refuse_overwriting_inputs
from srfm.benchmark import run_benchmark
from tests.reliability.conftest import ETH, cli, tiny_request


def test_convert_refuses_to_write_over_its_source_however_spelled(tmp_path: Path) -> None:
    src = tmp_path / "data" / "x.txt"
    src.parent.mkdir()
    src.write_text(ETH, encoding="utf-8")
    link = tmp_path / "link.txt"
    link.symlink_to(src)
    for out in (src, tmp_path / "data" / ".." / "data" / "x.txt", link):
        res = cli("data", "convert", "eth-ucy", str(src), str(out))
        assert res.exit_code == 2, res.output
        assert "never writes over its input" in res.output
        assert src.read_text(encoding="utf-8") == ETH
    # A file of a source folder counts too.
    res = cli("data", "convert", "eth-ucy", str(src.parent), str(src))
    assert res.exit_code == 2
    assert src.read_text(encoding="utf-8") == ETH


def test_fit_refuses_to_write_over_its_dataset(tmp_path: Path) -> None:
    src = tmp_path / "x.txt"
    src.write_text(ETH, encoding="utf-8")
    data = tmp_path / "d.mcap"
    assert cli("data", "convert", "eth-ucy", str(src), str(data)).exit_code == 0
    before = data.read_bytes()
    res = cli("fit", str(data), "-o", str(data))
    assert res.exit_code == 2
    assert "--output" in res.output
    assert "never writes over its input" in res.output
    assert data.read_bytes() == before
    start = tmp_path / "start.toml"
    start.write_text("schema_version = 1\n[params]\na_robot = 1.0\n", encoding="utf-8")
    res = cli("fit", str(data), "--start", str(start), "-o", str(start))
    assert res.exit_code == 2
    assert "never writes over its input" in res.output


def test_export_policy_refuses_to_write_over_its_checkpoint(tmp_path: Path) -> None:
    checkpoint = tmp_path / "policy.json"
    checkpoint.write_text("{}", encoding="utf-8")
    res = cli("export-policy", str(checkpoint), str(tmp_path / "policy"))
    assert res.exit_code == 2
    assert "never writes over its input" in res.output
    assert checkpoint.read_text(encoding="utf-8") == "{}"


def test_benchmark_refuses_a_users_folder_and_keeps_their_files(tmp_path: Path, tiny: Path) -> None:
    out = tmp_path / "mine"
    out.mkdir()
    (out / "summary.json").write_text("my own summary", encoding="utf-8")
    (out / "table.md").write_text("my own table", encoding="utf-8")
    res = cli("benchmark", "-s", str(tiny), "-p", "straight", "--seeds", "0-1", "--out", str(out))
    assert res.exit_code == 2
    assert "non-empty folder that srfm did not create" in res.output
    assert "--force" in res.output
    assert sorted(p.name for p in out.iterdir()) == ["summary.json", "table.md"]
    assert (out / "summary.json").read_text(encoding="utf-8") == "my own summary"
    with pytest.raises(srfm.OutputError, match="did not create"):
        run_benchmark(tiny_request(tiny), out, jobs=1)
    # Asked to: it writes, and the folder is srfm's from then on.
    res = cli(
        "benchmark", "-s", str(tiny), "-p", "straight", "--seeds", "0-1", "--out", str(out),
        "--force", "-j", "1", "--no-figures", "--no-logs",
    )  # fmt: skip
    assert res.exit_code == 0, res.output
    assert (out / OUTPUT_MARKER).is_file()
    res = cli(
        "benchmark", "-s", str(tiny), "-p", "straight", "--seeds", "0-2", "--out", str(out),
        "-j", "1", "--no-figures", "--no-logs",
    )  # fmt: skip
    assert res.exit_code == 0, res.output


def test_new_empty_and_own_folders_are_accepted(tmp_path: Path, tiny: Path) -> None:
    empty = tmp_path / "empty"
    empty.mkdir()
    run_benchmark(tiny_request(tiny, range(1)), empty, jobs=1, figures=False)
    run_benchmark(tiny_request(tiny, range(2)), empty, jobs=1, figures=False)  # its own
    run_benchmark(tiny_request(tiny, range(1)), tmp_path / "new" / "deep", jobs=1, figures=False)


def test_a_folder_of_another_srfm_command_is_refused(tmp_path: Path, tiny: Path) -> None:
    out = claim_output_folder(tmp_path / "reports", kind="score")
    (out / "table.md").write_text("score's table", encoding="utf-8")
    with pytest.raises(srfm.OutputError, match="holds the output of `srfm score`"):
        run_benchmark(tiny_request(tiny, range(1)), out, jobs=1)


def test_simulate_out_refuses_a_users_folder_but_reuses_its_own(tmp_path: Path) -> None:
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "notes.txt").write_text("mine", encoding="utf-8")
    res = cli("simulate", "--scenario", "concert", "--out", str(mine), "--no-rrd")
    assert res.exit_code == 2
    assert "did not create" in res.output
    assert sorted(os.listdir(mine)) == ["notes.txt"]
    own = tmp_path / "own"
    for seed in ("0", "1"):
        res = cli(
            "simulate", "--scenario", "concert", "--seed", seed, "--out", str(own), "--no-rrd"
        )
        assert res.exit_code == 0, res.output


def test_the_same_file_check_is_by_identity_not_by_name(tmp_path: Path) -> None:
    a = tmp_path / "a.txt"
    a.write_text("a", encoding="utf-8")
    hard = tmp_path / "hard.txt"
    os.link(a, hard)
    with pytest.raises(srfm.OutputError, match="is the input"):
        refuse_overwriting_inputs(hard, [a])
    refuse_overwriting_inputs(tmp_path / "b.txt", [a])  # another file: fine
