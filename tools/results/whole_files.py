"""The whole files of docs/ that a run tool writes in full (no generated markers): each
rewritten from its committed data by the function its tool writes it with.

``tools/results/generate.py`` registers :data:`FILES` (``make docs-tables`` writes them,
``--check`` names each that differs; the figures beside them are
``tools/results/figures.py``'s). The tools themselves call the same functions on the
data as they save it, so that what a run writes is what the committed data give:

- docs/real_encounters/tables.md, from results.json: ``tables_text`` of
  tools/fitting/real_encounters.py;
- docs/real_encounters/forms_<goal>.md, from forms_<goal>.json: ``tables`` of
  tools/fitting/fit_forms.py;
- docs/real_encounters/cap_diagnostic.md, from cap_diagnostic.json: ``table_text`` of
  tools/fitting/cap_diagnostic.py;
- docs/robot_response/tables.md, from results.json: ``tables`` of
  tools/fitting/fit_response.py;
- docs/sensitivity/report.md and rankings.csv, from episodes.csv.gz and run.json read
  back as the sweep (tools/results/sensitivity.py): ``report_text`` of
  ``srfm sweep report`` (srfm/sweep/report.py).
"""

from __future__ import annotations

import json
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any, Final

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from tools.fitting import cap_diagnostic, fit_forms, fit_response, real_encounters
from tools.results import sensitivity
from tools.results.fitting_pages import MissingDataError

ROOT: Final = Path(__file__).resolve().parents[2]
ENCOUNTERS: Final = ROOT / "docs" / "real_encounters"
RESPONSE: Final = ROOT / "docs" / "robot_response"


def _json(path: Path) -> Any:
    if not path.is_file():
        raise MissingDataError(f"data file `{path.relative_to(ROOT)}`")
    return json.loads(path.read_text(encoding="utf-8"))


def encounters_tables() -> str:
    return real_encounters.tables_text(_json(ENCOUNTERS / "results.json"))


def response_tables() -> str:
    return fit_response.tables(_json(RESPONSE / "results.json"))


def cap_table() -> str:
    return cap_diagnostic.table_text(_json(ENCOUNTERS / "cap_diagnostic.json"))


def _forms(path: Path) -> Callable[[], str]:
    def render() -> str:
        return fit_forms.tables(_json(path))

    return render


def _forms_files() -> dict[str, Callable[[], str]]:
    """One page per goal whose ``forms_<goal>.json`` is committed (not the fit caches)."""
    return {
        f"docs/real_encounters/{p.stem}.md": _forms(p)
        for p in sorted(ENCOUNTERS.glob("forms_*.json"))
        if not p.name.startswith("forms_cache_")
    }


FILES: dict[str, Callable[[], str]] = {
    "docs/real_encounters/tables.md": encounters_tables,
    **_forms_files(),
    "docs/real_encounters/cap_diagnostic.md": cap_table,
    "docs/robot_response/tables.md": response_tables,
    "docs/sensitivity/report.md": sensitivity.report_md,
    "docs/sensitivity/rankings.csv": sensitivity.rankings_csv,
}
"""Path from the repository's root -> the file's whole text from committed data."""
