"""Episode files are validated on read (schema, one value per pedestrian,
CRC-32); a damaged one is named with what to do, and a resumed run simulates it again,
ending with the tables of an undamaged run."""

from __future__ import annotations

import json
import shutil
from collections.abc import Callable
from pathlib import Path

import pytest

import srfm
from srfm.benchmark import episode_path, load_results, read_episode, run_benchmark
from srfm.benchmark.figures import figure_episode_path
from tests.reliability.conftest import tiny_request

TABLES = ("table.md", "summary.json", "episodes.csv", "pedestrians.csv")


def _edit_json(
    edit: Callable[[dict], None],  # type: ignore[type-arg]
    keep_checksum: bool = False,
) -> Callable[[Path], None]:
    """A hand edit; without ``keep_checksum`` the CRC goes too (as in a file written
    before episode files had one), so that the schema check itself is what fails."""

    def damage(path: Path) -> None:
        doc = json.loads(path.read_text())
        if not keep_checksum:
            doc.pop("crc32")
        edit(doc)
        path.write_text(json.dumps(doc, indent=1))

    return damage


DAMAGE: dict[str, tuple[Callable[[Path], None], str]] = {
    "nan-string": (
        _edit_json(lambda d: d["metrics"].__setitem__("frechet_m", "NaN")),
        "must be a finite number or null, got 'NaN'",
    ),
    "cut-short": (
        _edit_json(lambda d: d["pedestrians"]["frechet_m"].pop()),
        "lists of different lengths",
    ),
    "edited-value": (
        _edit_json(lambda d: d["metrics"].__setitem__("frechet_m", 0.5), keep_checksum=True),
        "checksum mismatch",
    ),
    # One digit changed in place: the layout as written, so the checksum is checked on
    # the file's text (the fast path of read_episode) rather than on a re-print.
    "edited-digit": (
        lambda p: p.write_text(p.read_text().replace('"end_step": ', '"end_step": 1', 1)),
        "checksum mismatch",
    ),
    "truncated": (lambda p: p.write_bytes(p.read_bytes()[:100]), "damaged episode metrics file"),
    "empty": (lambda p: p.write_bytes(b""), "damaged episode metrics file"),
    "other-episode": (
        lambda p: shutil.copy(p.with_name("seed-000000.json"), p),
        r"holds episode \('tiny', 'straight', 0\)",
    ),
}


@pytest.fixture(scope="module")
def clean(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    from tests.reliability.conftest import TINY

    root = tmp_path_factory.mktemp("clean")
    tiny = root / "tiny.toml"
    tiny.write_text(TINY, encoding="utf-8")
    out = root / "out"
    run_benchmark(tiny_request(tiny), out, jobs=1)
    return tiny, out


@pytest.mark.parametrize("kind", sorted(DAMAGE))
def test_a_damaged_episode_is_named_and_simulated_again(
    clean: tuple[Path, Path], tmp_path: Path, kind: str
) -> None:
    tiny, reference = clean
    out = tmp_path / "out"
    shutil.copytree(reference, out)
    path = episode_path(out, "tiny", "straight", 1)
    damage, match = DAMAGE[kind]
    damage(path)
    with pytest.raises(srfm.BenchmarkError, match=match) as info:
        read_episode(path, expect=("tiny", "straight", 1))
    assert str(path) in str(info.value)
    assert "delete it" in str(info.value)
    with pytest.raises(srfm.BenchmarkError, match="delete it"):
        load_results(out, tiny_request(tiny))
    summary = run_benchmark(tiny_request(tiny), out, jobs=1)
    assert summary.resimulated == (str(path),)
    assert summary.simulated == 1
    for name in TABLES:
        assert (out / name).read_bytes() == (reference / name).read_bytes(), name


def test_a_damaged_manifest_is_a_clean_error(clean: tuple[Path, Path], tmp_path: Path) -> None:
    tiny, reference = clean
    out = tmp_path / "out"
    shutil.copytree(reference, out)
    (out / "manifest.json").write_text('{"schema": "srfm.benchmark_manifest/1", "scen')
    with pytest.raises(srfm.BenchmarkError, match=r"damaged manifest .*use a new --out"):
        run_benchmark(tiny_request(tiny), out, jobs=1)
    (out / "manifest.json").write_text("[1, 2]")
    with pytest.raises(srfm.BenchmarkError, match="damaged manifest"):
        run_benchmark(tiny_request(tiny), out, jobs=1)


def test_a_damaged_figure_episode_is_simulated_again(
    clean: tuple[Path, Path], tmp_path: Path
) -> None:
    tiny, reference = clean
    out = tmp_path / "out"
    shutil.copytree(reference, out)
    saved = figure_episode_path(out, "tiny", "straight")
    saved.write_bytes(saved.read_bytes()[:200])
    (out / "figures" / "paths_tiny.png").unlink()
    run_benchmark(tiny_request(tiny), out, jobs=1)
    assert (out / "figures" / "paths_tiny.png").read_bytes() == (
        reference / "figures" / "paths_tiny.png"
    ).read_bytes()


def test_an_episode_file_is_printed_once_and_read_without_a_reprint(
    clean: tuple[Path, Path],
) -> None:
    """episode_json appends the checksum to the text instead of printing the document
    twice: the same bytes as the two prints; read_episode accepts it by its text."""
    import zlib

    from srfm.benchmark._results import EPISODE_SCHEMA, _checksum_matches, _text, episode_json

    _, out = clean
    path = episode_path(out, "tiny", "straight", 1)
    metrics = read_episode(path)
    doc = {"schema": EPISODE_SCHEMA, **metrics.to_document()}
    crc = zlib.crc32(_text(doc).encode("utf-8"))
    twice = _text({**doc, "crc32": f"{crc:08x}"}) + "\n"
    assert episode_json(metrics) == twice == path.read_text()
    assert _checksum_matches(twice, json.loads(twice))
    assert not _checksum_matches(twice.replace('"seed": 1', '"seed": 2'), json.loads(twice))
