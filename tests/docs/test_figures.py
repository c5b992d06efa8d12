"""Every figure of the docs is what its committed data draw (tools/results/figures.py):
a figure left behind when its data changed, or edited by hand, fails ``make test``."""

from __future__ import annotations

import shutil
from pathlib import Path

import matplotlib.image as mpimg
import pytest

from tools.results import figures


@pytest.mark.parametrize("group", sorted(figures.FIGURES))
def test_every_committed_figure_is_what_its_data_draw(group: str) -> None:
    try:
        stale = figures.stale(group)
    except figures.MissingInputError as exc:
        pytest.skip(str(exc))
    assert stale == [], "run `make docs-tables`: " + "; ".join(stale)


def _one_scenario(out: Path) -> list[str]:
    from tools.scenarios.draw_scenarios import draw

    return [draw("frontal_approach", out).name]


def test_a_changed_or_missing_figure_is_found(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    folder = tmp_path / "docs"
    folder.mkdir()
    monkeypatch.setattr(figures, "ROOT", tmp_path)
    monkeypatch.setitem(figures.FIGURES, "one", (folder, _one_scenario))
    assert figures.stale("one") == ["docs/frontal_approach.png (missing)"]
    shutil.copy(
        figures.DOCS / "scenarios" / "frontal_approach.png", folder / "frontal_approach.png"
    )
    assert figures.stale("one") == []
    pixels = mpimg.imread(folder / "frontal_approach.png")
    pixels[10:14, 10:14, :3] = 0.0  # a 4-pixel black square: a hand edit
    mpimg.imsave(folder / "frontal_approach.png", pixels)
    assert figures.stale("one") == ["docs/frontal_approach.png"]


def test_an_unknown_group_is_named() -> None:
    with pytest.raises(SystemExit, match=r"unknown figure group.*'nope'"):
        figures.main(["--check", "nope"])
