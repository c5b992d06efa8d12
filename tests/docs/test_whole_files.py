"""The whole files of docs/ that run tools write (tools/results/whole_files.py): each is
what its committed data give, a hand-edited number in any of them is named by the check
and put back by ``make docs-tables``, and the sensitivity sweep's report is rebuilt bit
for bit from the episodes it packs."""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import pytest

from srfm.sweep import load_spec, run_sweep
from srfm.sweep.report import report_figures, report_text, write_sweep_report
from tests.sweep.test_sweep import _spec
from tools.results import generate, sensitivity, sets, whole_files
from tools.results.fitting_pages import MissingDataError

KINDS = sorted(generate.FILES)


def test_the_whole_files_are_registered() -> None:
    assert set(whole_files.FILES) <= set(generate.FILES)
    assert {
        "docs/real_encounters/tables.md",
        "docs/real_encounters/forms_heading.md",
        "docs/real_encounters/cap_diagnostic.md",
        "docs/robot_response/tables.md",
        "docs/sensitivity/report.md",
        "docs/sensitivity/rankings.csv",
    } <= set(generate.FILES)


def test_every_whole_file_is_what_its_data_give() -> None:
    assert generate.stale_files() == [], "run `make docs-tables`"


def _edit_a_number(text: str) -> str:
    """The text with one digit of a table row changed (the middle row with a digit)."""
    lines = text.split("\n")
    rows = [i for i, line in enumerate(lines) if re.search(r"\d", line) and "|" in line]
    rows = rows or [i for i, line in enumerate(lines[1:], 1) if re.search(r"\d", line)]
    i = rows[len(rows) // 2]
    m = re.search(r"\d", lines[i])
    assert m is not None
    digit = str((int(m.group()) + 1) % 10)
    lines[i] = lines[i][: m.start()] + digit + lines[i][m.end() :]
    return "\n".join(lines)


@pytest.mark.parametrize("path", KINDS)
def test_a_hand_edited_number_is_named_and_put_back(path: str, tmp_path: Path) -> None:
    for other in generate.FILES:
        (tmp_path / other).parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(sets.ROOT / other, tmp_path / other)
    assert generate.stale_files(tmp_path) == []
    page = tmp_path / path
    committed = page.read_bytes()
    edited = _edit_a_number(committed.decode("utf-8"))
    assert edited.encode("utf-8") != committed
    page.write_text(edited, encoding="utf-8")
    assert generate.stale_files(tmp_path) == [f"{path}: whole file"]
    assert generate.write_files(tmp_path) == [path]
    assert page.read_bytes() == committed
    page.unlink()  # a file the data give but that is missing is stale too
    assert generate.stale_files(tmp_path) == [f"{path}: whole file"]


def test_an_unknown_file_is_refused() -> None:
    with pytest.raises(SystemExit, match=r"unknown generated file 'docs/nope\.md'"):
        generate.file_text("docs/nope.md")


def test_a_packed_sweep_gives_back_its_report(tmp_path: Path) -> None:
    """``srfm sweep report``'s report.md and rankings.csv, rebuilt from the columns
    ``sensitivity.py pack`` keeps and the run record it writes, are the report's bytes."""
    spec = load_spec(_spec(tmp_path, seeds="0-1"))
    folder = tmp_path / "sensitivity"  # the name the committed run's --out gives
    run_sweep(spec, folder, jobs=1)
    write_sweep_report(folder)
    packed = tmp_path / "episodes.csv.gz"
    packed.write_bytes(sensitivity.episodes_csv(folder))
    columns = sensitivity.read_episodes(packed)
    record = sensitivity.run_payload(folder, {"commit": "abc1234"}, len(columns["seed"]))
    report, rankings = report_text(sensitivity.sweep_of(record, columns))
    assert report == (folder / "report" / "report.md").read_text(encoding="utf-8")
    assert rankings == (folder / "report" / "rankings.csv").read_text(encoding="utf-8")
    figures = report_figures(sensitivity.sweep_of(record, columns))
    assert sorted(figures) == sorted(
        ["a_robot.png", "a_robot_by_scenario.png", "b_robot.png", "b_robot_by_scenario.png"]
    )
    for name, png in figures.items():
        assert png == (folder / "report" / name).read_bytes()
    # a run record without the manifest's factors and base parameters is refused
    del record["spec"]["params"]
    with pytest.raises(MissingDataError, match="params in the sweep's run record"):
        sensitivity.sweep_of(record, columns)
