"""``srfm planners``, ``srfm scenarios`` and ``srfm suites`` list every name that ``-p``,
``--scenario`` and ``--suite`` accept, with what each is for and whether the benchmark
runs it by default (issue 39: ``oracle`` was missing, its module not yet imported when
the list was built)."""

from __future__ import annotations

import ast
import json
import re
import subprocess
import sys
from pathlib import Path

from srfm.benchmark import default_planners
from srfm.planners import make_planner
from srfm.scenarios import load_scenario, scenario_names
from srfm.scenarios.generated import GENERATED_KINDS
from srfm.scenarios.suites import DEFAULT_SUITE, SUITE_DESCRIPTIONS, SUITES
from tests.conftest import REPO

# Every module of the package imported, then the registry as it is then. Modules that
# need an extra that is not installed are left out (their planners could not run).
_FULL_REGISTRY = """
import importlib, json, pkgutil
import srfm
from srfm.errors import MissingDependencyError
for module in pkgutil.walk_packages(srfm.__path__, "srfm."):
    if module.name.endswith("__main__"):
        continue
    try:
        importlib.import_module(module.name)
    except (MissingDependencyError, ModuleNotFoundError):
        pass
from srfm.planners import available_planners
print(json.dumps([[p.name, p.default, p.description] for p in available_planners()]))
"""


def _srfm(*args: str) -> str:
    """``srfm ARGS`` in a fresh process: what a user sees, nothing imported before."""
    done = subprocess.run(
        [sys.executable, "-m", "srfm.cli", *args],
        capture_output=True, text=True, cwd=REPO, timeout=120, check=True,
    )  # fmt: skip
    assert done.stderr == ""
    return done.stdout


def _rows(text: str, header: tuple[str, str, str]) -> list[tuple[str, str, str]]:
    lines = text.splitlines()
    assert tuple(re.split(r"\s{2,}", lines[0], maxsplit=2)) == header
    rows = [tuple(re.split(r"\s{2,}", line, maxsplit=2)) for line in lines[1:]]
    assert all(len(row) == 3 for row in rows), rows
    return rows  # type: ignore[return-value]


def test_srfm_planners_lists_the_whole_registry() -> None:
    listed = _rows(_srfm("planners"), ("planner", "default", "what it is for"))
    done = subprocess.run(
        [sys.executable, "-c", _FULL_REGISTRY],
        capture_output=True, text=True, cwd=REPO, timeout=300, check=True,
    )  # fmt: skip
    registry = json.loads(done.stdout.splitlines()[-1])
    own = listed[-2:]  # the two forms of a planner of one's own
    assert [row[0] for row in own] == ["external:NAME", "MODULE:ATTRIBUTE"]
    assert all(default == "no" for _, default, _ in own)
    listed = listed[:-2]
    assert listed == [(name, "yes" if default else "no", text) for name, default, text in registry]
    names = [row[0] for row in listed]
    assert {"oracle", "stay", "straight"} <= set(names)
    assert [n for n, default, _ in listed if default == "yes"] == sorted(default_planners())
    for name in names:  # every listed name makes a planner, as -p NAME does
        assert make_planner(name).name == name


def test_built_in_planners_are_registered_in_one_module_only() -> None:
    """A planner registered in a module that the command line does not import would be
    missing from `srfm planners` (and from `-p`): every registration is in
    srfm/planners/__init__.py, which every lookup imports."""
    places = []
    for path in sorted((REPO / "srfm").rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Call) and getattr(node.func, "id", None) == "register_planner":
                places.append(str(path.relative_to(REPO)))
    assert places
    assert set(places) == {"srfm/planners/__init__.py"}


def test_srfm_scenarios_lists_every_name_scenario_accepts() -> None:
    listed = _rows(_srfm("scenarios"), ("scenario", "default", "description"))
    names = [row[0] for row in listed]
    shipped = {p.stem for p in Path(REPO / "srfm" / "scenarios").glob("*.toml")}
    assert names[-1] == "generated:[KIND:]SEED"  # the generated layouts, by seed
    for kind in GENERATED_KINDS:
        assert kind in listed[-1][2]
        assert load_scenario(f"generated:{kind}:3").name.startswith("generated")
    names = names[:-1]
    assert names == list(scenario_names())
    assert set(names) == shipped
    assert {"concert_crowd", "station_concourse", "random"} <= set(names)
    assert [n for n, default, _ in listed if default == "yes"] == list(SUITES[DEFAULT_SUITE])
    assert all(description for _, _, description in listed)


def test_srfm_suites_lists_every_suite() -> None:
    listed = _rows(_srfm("suites"), ("suite", "default", "what it is for [its scenarios]"))
    assert set(SUITE_DESCRIPTIONS) == set(SUITES)
    assert [row[0] for row in listed] == list(SUITES)
    assert [n for n, default, _ in listed if default == "yes"] == [DEFAULT_SUITE]
    known = set(scenario_names())
    for name, _, text in listed:
        assert text == f"{SUITE_DESCRIPTIONS[name]} [{', '.join(SUITES[name])}]"
        assert set(SUITES[name]) <= known, name
