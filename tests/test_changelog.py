"""CHANGELOG.md names every public module that was removed or moved, with its new place
(issue 39: `import srfm.env` had been removed without a note)."""

from __future__ import annotations

import importlib
import re

import pytest

from tests.conftest import REPO

# Every public module path srfm once had and has no more (from the repository's history:
# `git log --name-status` of srfm/), and where its names are now.
MOVED = {
    "srfm.env": "srfm.rl",
    "srfm.training": "srfm.rl.training",
    "srfm.episode": "srfm.sim.episode",
    "srfm.record": "srfm.sim.record",
    "srfm.simulator": "srfm.sim.simulator",
    "srfm.robot": "srfm.models.robot",
    "srfm.state": "srfm.models.state",
    "srfm.planners.routing": "srfm.world",
    "srfm.planners.oracle": "srfm.sim.oracle",
}


def _changelog() -> str:
    return (REPO / "CHANGELOG.md").read_text(encoding="utf-8")


@pytest.mark.parametrize(("old", "new"), MOVED.items(), ids=list(MOVED))
def test_a_moved_module_is_named_with_its_new_place(old: str, new: str) -> None:
    with pytest.raises(ModuleNotFoundError):
        importlib.import_module(old)
    importlib.import_module(new)
    # one table row or one bullet of CHANGELOG.md names both
    entries = re.split(r"\n(?=\| |- )", _changelog())
    assert any(f"`{old}`" in e and f"`{new}`" in e for e in entries), old


def test_the_moved_modules_are_under_a_heading_that_says_so() -> None:
    text = _changelog()
    removed = text.index("### Removed", text.index("## [0.1.0]"))
    assert "`srfm.env`" in text[removed : text.index("### Added", removed)]
