"""Every figure of the docs, drawn again from what the repository commits.

    .venv/bin/python tools/results/figures.py           # redraw every figure (make docs-tables)
    .venv/bin/python tools/results/figures.py --check   # change nothing; exit 1 if stale

Each entry of :data:`FIGURES` draws a group of PNG files into a folder with the same
function the run that measured them uses, from the data that run committed:

- ``real_encounters``: the five figures of docs/real_encounters.md, from the curves in
  ``docs/real_encounters/results.json`` (``tools/fitting/real_encounters.py``);
- ``fitting_navwareset``: observed against simulated paths (docs/fitting.md), from the
  fits in ``docs/fitting_navwareset.json`` and the NavWareSet windows of the shared data
  (``tools/fitting/fit_navwareset.py``; needs ``SRFM_DATA_DIR`` or ``../shared/data``);
- ``scenarios``: the scenario library's drawings (docs/scenarios.md), from the scenario
  definitions (``tools/scenarios/draw_scenarios.py``);
- ``sensitivity``: the sweep report's four figures (docs/sensitivity.md), from the
  committed episodes and run record read back as the sweep
  (``srfm.sweep.report.report_figures``, as ``srfm sweep report``;
  ``tools/results/sensitivity.py``).

``--check`` compares pixels, not bytes (``matplotlib.testing.compare.compare_images``
with a tolerance of 0.001 RMS on the 0-255 scale): PNG encoders may differ in their
compression. Text rendering differs between matplotlib minor versions, so
``pyproject.toml`` pins the minor.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path:  # run as a script
    sys.path.insert(0, str(ROOT))

DOCS = ROOT / "docs"
TOLERANCE = 0.001  # RMS of the pixel difference, 0-255 scale


class MissingInputError(RuntimeError):
    """A figure's input (a data folder outside the repository) is not on this machine."""


def _json(rel: str) -> dict[str, Any]:
    doc: dict[str, Any] = json.loads((DOCS / rel).read_text(encoding="utf-8"))
    return doc


def real_encounters(out: Path) -> list[str]:
    """docs/real_encounters/*.png from the committed part-1 curves."""
    from tools.fitting.real_encounters import figures

    return figures(_json("real_encounters/results.json")["part1"], out)


def navwareset_folder() -> Path:
    """The NavWareSet folder of the shared data, as the fitting tools find it."""
    root = Path(os.environ.get("SRFM_DATA_DIR", ROOT.parent / "shared" / "data"))
    return root / "navwareset_quant"


def fitting_navwareset(out: Path) -> list[str]:
    """docs/fitting_navwareset.png from the committed fits and the shared NavWareSet data."""
    from tools.fitting.fit_navwareset import figure_from_saved

    data = navwareset_folder()
    if not data.is_dir():
        raise MissingInputError(
            f"NavWareSet not found at {data}; set SRFM_DATA_DIR to the shared data folder"
        )
    figure_from_saved(_json("fitting_navwareset.json"), data, out / "fitting_navwareset.png")
    return ["fitting_navwareset.png"]


# Seed 1 of each kind of generated layout, as docs/scenarios.md shows them.
GENERATED = tuple(
    f"generated:{kind}:1" for kind in ("bend", "corridor", "door", "hall", "junction", "room")
)


def scenarios(out: Path) -> list[str]:
    """docs/scenarios/*.png: every built-in scenario and seed 1 of each generated kind."""
    from srfm.scenarios import FLOW_SCENARIOS, FRANCIS_SCENARIOS, NAVWARESET_SCENARIOS
    from tools.scenarios.draw_scenarios import draw

    names = [*FRANCIS_SCENARIOS, *NAVWARESET_SCENARIOS, *FLOW_SCENARIOS, *GENERATED]
    return [draw(name, out).name for name in names]


def sensitivity(out: Path) -> list[str]:
    """docs/sensitivity/*.png: the sweep report's figures, from the committed episodes."""
    from tools.results.sensitivity import figures

    drawn = figures()
    for name, png in drawn.items():
        (out / name).write_bytes(png)
    return list(drawn)


# group -> (folder of its figures in docs/, the function that draws them into a folder)
FIGURES: dict[str, tuple[Path, Callable[[Path], list[str]]]] = {
    "real_encounters": (DOCS / "real_encounters", real_encounters),
    "fitting_navwareset": (DOCS, fitting_navwareset),
    "scenarios": (DOCS / "scenarios", scenarios),
    "sensitivity": (DOCS / "sensitivity", sensitivity),
}


def stale(group: str) -> list[str]:
    """The committed figures of ``group`` whose pixels differ from a fresh drawing, or that
    are missing, as paths relative to the repository.

    Raises:
        MissingInputError: the group's input is not on this machine.
    """
    from matplotlib.testing.compare import compare_images

    folder, draw = FIGURES[group]
    found = []
    with tempfile.TemporaryDirectory(prefix="srfm-figures-") as tmp:
        for name in draw(Path(tmp)):
            committed = folder / name
            rel = str(committed.relative_to(ROOT))
            if not committed.is_file():
                found.append(f"{rel} (missing)")
            elif compare_images(str(committed), str(Path(tmp) / name), tol=TOLERANCE) is not None:
                found.append(rel)
    return found


def redraw(group: str) -> list[str]:
    """Draw the figures of ``group`` into docs/; return the names written."""
    folder, draw = FIGURES[group]
    return draw(folder)


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--check", action="store_true", help="change nothing; exit 1 if stale")
    ap.add_argument("groups", nargs="*", help=f"default: all ({', '.join(FIGURES)})")
    args = ap.parse_args(argv)
    groups = args.groups or list(FIGURES)
    unknown = [g for g in groups if g not in FIGURES]
    if unknown:
        raise SystemExit(f"unknown figure group(s) {unknown}; known: {', '.join(FIGURES)}")
    bad: list[str] = []
    for group in groups:
        try:
            if args.check:
                bad += stale(group)
            else:
                print(f"{group}: {len(redraw(group))} figures")
        except MissingInputError as exc:
            print(f"{group}: not drawn: {exc}")
    for line in bad:
        print(f"stale: {line}")
    if bad:
        raise SystemExit("figures differ from what the committed data draw: make docs-tables")


if __name__ == "__main__":
    main()
