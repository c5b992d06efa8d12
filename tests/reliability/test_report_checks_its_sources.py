"""``srfm report DIR`` checks what it reads, as a resumed benchmark does: the manifest,
every episode file of the request, and ``summary.json`` and ``episodes.csv`` against
the tables those episodes give. Before issue 33 a truncated ``episodes.csv`` ended in
``KeyError: 'outcome'`` and a damaged episode file went unnoticed."""

from __future__ import annotations

import json
import shutil
from collections.abc import Callable
from pathlib import Path

import pytest

from srfm.benchmark import episode_path, run_benchmark
from tests.reliability.conftest import assert_one_line, cli, tiny_request


@pytest.fixture(scope="module")
def results(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A finished benchmark folder (tiny scenario, straight, seeds 0-2, no figures)."""
    from tests.reliability.conftest import TINY

    root = tmp_path_factory.mktemp("report")
    tiny = root / "tiny.toml"
    tiny.write_text(TINY, encoding="utf-8")
    out = root / "results"
    run_benchmark(tiny_request(tiny), out, jobs=1, figures=False)
    return out


def _truncate(path: Path) -> None:
    data = path.read_bytes()
    path.write_bytes(data[: len(data) // 2])


def _edit_number(path: Path) -> None:
    text = path.read_text(encoding="utf-8")
    at = next(i for i, c in enumerate(text) if c.isdigit() and text[i - 1] in " :,[")
    path.write_text(text[:at] + str((int(text[at]) + 1) % 10) + text[at + 1 :], encoding="utf-8")


def _episode(out: Path) -> Path:
    return episode_path(out, "tiny", "straight", 1)


DAMAGE: list[tuple[str, Callable[[Path], Path], Callable[[Path], None]]] = [
    ("episodes.csv cut short", lambda out: out / "episodes.csv", _truncate),
    ("episodes.csv emptied", lambda out: out / "episodes.csv", lambda p: p.write_bytes(b"")),
    ("episodes.csv edited", lambda out: out / "episodes.csv", _edit_number),
    ("summary.json edited", lambda out: out / "summary.json", _edit_number),
    ("summary.json cut short", lambda out: out / "summary.json", _truncate),
    ("an episode file cut short", _episode, _truncate),
    ("an episode file edited", _episode, _edit_number),
    ("an episode file deleted", _episode, lambda p: p.unlink()),
]


def test_an_intact_folder_gives_its_page(results: Path, tmp_path: Path) -> None:
    out = tmp_path / "intact"
    shutil.copytree(results, out)
    (out / "report.html").unlink()
    res = cli("report", str(out))
    assert res.exit_code == 0, res.output
    assert (out / "report.html").read_bytes() == (results / "report.html").read_bytes()


@pytest.mark.parametrize(("what", "target", "damage"), DAMAGE, ids=[d[0] for d in DAMAGE])
def test_a_damaged_source_is_named_and_the_page_is_kept(
    results: Path,
    tmp_path: Path,
    what: str,
    target: Callable[[Path], Path],
    damage: Callable[[Path], None],
) -> None:
    out = tmp_path / "damaged"
    shutil.copytree(results, out)
    path = target(out)
    damage(path)
    page = (out / "report.html").read_bytes()
    assert_one_line(cli("report", str(out)), str(path))
    assert (out / "report.html").read_bytes() == page  # not rewritten from damaged files


def test_a_manifest_without_its_request_is_named(results: Path, tmp_path: Path) -> None:
    out = tmp_path / "manifest"
    shutil.copytree(results, out)
    manifest = json.loads((out / "manifest.json").read_text(encoding="utf-8"))
    manifest["request"]["seeds"] = ["0"]
    (out / "manifest.json").write_text(json.dumps(manifest), encoding="utf-8")
    assert_one_line(cli("report", str(out)), f"{out / 'manifest.json'}: damaged manifest")
