"""Issue 39's last bad inputs:

- a CSV header or a TOML file that names a column, a key or a table twice is an error
  naming it (a ``--param-draws-from`` CSV with ``a_robot,a_robot`` was accepted and the
  last column won);
- values in error messages are plain numbers on one line (``np.float64(-0.5)`` and a
  two-line ``array([[0.], [0.]])`` leaked into messages);
- a benchmark with parameter draws checks every draw's folder before its first line.
"""

from __future__ import annotations

import importlib
import inspect
import pkgutil
import warnings
from pathlib import Path
from typing import Any

import attrs
import numpy as np
import pytest

import srfm
from srfm._text import PLAIN_LIMIT, plain
from srfm.errors import SrfmError
from tests.reliability.conftest import TINY, assert_one_line, cli

# Values that once came out as NumPy reprs: scalars, a column vector (two lines), a row,
# a tuple of NumPy numbers.
NUMPY_VALUES: list[Any] = [
    np.float64(-0.5),
    np.float64(np.nan),
    np.float32(1e30),
    np.int64(-1),
    np.array([[0.0], [0.0]]),
    np.array([-1.0, 2.0]),
    (np.float64(-1.0), np.float64(2.0)),
]


def _clean(message: str) -> bool:
    return "np." not in message and "array(" not in message and "\n" not in message


# -- plain ------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("value", "text"),
    [
        (np.float64(-0.5), "-0.5"),
        (np.int64(3), "3"),
        (np.bool_(True), "True"),
        (np.array([[0.0], [0.0]]), "[[0.0], [0.0]]"),
        ((np.float64(-1.0), np.float64(2.0)), "(-1.0, 2.0)"),
        ({"a": np.float32(0.5)}, "{'a': 0.5}"),
        (
            np.arange(20.0).reshape(10, 2),
            "[0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, …] (shape (10, 2))",
        ),
        ("crosswalk", "'crosswalk'"),
        (-0.5, "-0.5"),
        (None, "None"),
    ],
)
def test_plain_shows_numpy_values_as_python_ones(value: object, text: str) -> None:
    assert plain(value) == text


def test_plain_is_one_short_line() -> None:
    class Multiline:
        def __repr__(self) -> str:
            return "first\n  second"

    assert plain(Multiline()) == "first second"
    long = plain(list(range(1000)))
    assert len(long) == PLAIN_LIMIT
    assert long.endswith("…")


# -- every public configuration class --------------------------------------------------


def _public_attrs_classes() -> list[type]:
    found: dict[str, type] = {}
    for module in pkgutil.walk_packages(srfm.__path__, "srfm."):
        if module.name.endswith("__main__"):
            continue
        try:
            loaded = importlib.import_module(module.name)
        except srfm.MissingDependencyError:
            continue
        for name in getattr(loaded, "__all__", ()):
            obj = getattr(loaded, name, None)
            if inspect.isclass(obj) and attrs.has(obj):
                found[f"{obj.__module__}.{obj.__qualname__}"] = obj
    return [found[k] for k in sorted(found)]


CLASSES = _public_attrs_classes()


def test_the_sweep_finds_the_configuration_classes() -> None:
    names = {c.__name__ for c in CLASSES}
    assert {"SRFMParams", "RobotConfig", "EnvConfig", "TrainConfig", "OracleConfig"} <= names


@pytest.mark.parametrize("cls", CLASSES, ids=[c.__name__ for c in CLASSES])
def test_a_numpy_value_in_any_field_is_a_plain_one_line_error(cls: type) -> None:
    """Every field of every public attrs class, given each NumPy value: either accepted,
    or an SrfmError whose message holds plain numbers on one line (never a NumPy repr,
    never a bare ValueError from comparing an array)."""
    problems = []
    for field in attrs.fields(cls):
        if not field.init:
            continue
        for value in NUMPY_VALUES:
            try:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    cls(**{field.alias: value})
            except SrfmError as exc:
                if not _clean(str(exc)):
                    problems.append((field.name, str(exc)))
            except TypeError as exc:  # a class with required fields: the call, not the value
                if "required" not in str(exc) and "missing" not in str(exc):
                    problems.append((field.name, repr(exc)))
    assert not problems


@pytest.mark.parametrize(
    "call",
    [
        lambda: srfm.SRFMParams.preset(np.float64(1.0)),  # type: ignore[arg-type]
        lambda: srfm.SRFMParams().replace(a_robot=np.array([[0.0], [0.0]])),
        lambda: srfm.run_episode("crosswalk", np.float64(1.5)),  # type: ignore[arg-type]
        lambda: srfm.Obstacles(segments=np.array([[0.0], [0.0]])),
    ],
    ids=["preset", "replace", "seed", "obstacles"],
)
def test_function_error_paths_quote_plain_numbers(call: Any) -> None:
    with pytest.raises(SrfmError) as info:
        call()
    assert _clean(str(info.value)), str(info.value)


def test_training_family_weights_quote_plain_numbers() -> None:
    from srfm.scenarios.training import family_weights

    with pytest.raises(srfm.ScenarioError, match=r"got -1\.0$"):
        family_weights(np.array([1.0, -1.0, 1.0, 1.0, 1.0]))  # type: ignore[arg-type]
    with pytest.raises(srfm.ScenarioError, match=r"got 2: \(0\.5, 0\.5\)$"):
        family_weights((np.float64(0.5), np.float64(0.5)))


# -- repeated columns, keys and tables -------------------------------------------------


def test_a_repeated_param_draws_column_is_an_error(tmp_path: Path) -> None:
    (tmp_path / "tiny.toml").write_text(TINY, encoding="utf-8")
    draws = tmp_path / "draws.csv"
    draws.write_text("a_robot,a_robot\n5.0,6.0\n", encoding="utf-8")
    res = cli(
        "benchmark", "-s", str(tmp_path / "tiny.toml"), "-p", "straight", "--seeds", "0",
        "--param-draws", "1", "--param-draws-from", str(draws), "--out", str(tmp_path / "o"),
    )  # fmt: skip
    assert_one_line(res, "draws.csv, line 1: column 'a_robot' appears twice in the header")
    assert not (tmp_path / "o").exists()


def test_a_repeated_episodes_csv_column_is_an_error(tmp_path: Path) -> None:
    """The results page reads episodes.csv back (`srfm report` first checks the file
    against the episode files): a repeated column is named, not merged."""
    from srfm.benchmark._html import _episodes

    data = b"scenario,planner,scenario\nt,straight,t\n"
    with pytest.raises(srfm.BenchmarkError, match=r"column 'scenario' appears twice"):
        _episodes(tmp_path, {"episodes.csv": data})
    rows = _episodes(tmp_path, {"episodes.csv": b"scenario,planner\nt,straight\n"})
    assert rows == [{"scenario": "t", "planner": "straight"}]


SCENARIO_HEAD = 'schema_version = 1\nname = "t"\ndescription = "x"\n'


@pytest.mark.parametrize(
    ("command", "text", "named"),
    [
        (
            "scenario",
            SCENARIO_HEAD + 'name = "u"\n',
            "key 'name' repeats a key set earlier (line 4)",
        ),
        (
            "scenario",
            SCENARIO_HEAD + "[robot]\n[robot]\n",
            "table [robot] is declared twice (line 5)",
        ),
        ("params", "[params]\na_robot = 5.0\na_robot = 6.0\n", "key 'a_robot' repeats a key set"),
        ("sweep", 'schema_version = 1\nseeds = "0-1"\nseeds = "0-2"\n', "key 'seeds' repeats"),
    ],
    ids=["scenario key", "scenario table", "params key", "sweep key"],
)
def test_a_repeated_toml_key_or_table_is_an_error_naming_it(
    tmp_path: Path, command: str, text: str, named: str
) -> None:
    path = tmp_path / "f.toml"
    path.write_text(text, encoding="utf-8")
    if command == "scenario":
        res = cli("simulate", "--scenario", str(path))
    elif command == "params":
        res = cli("simulate", "--scenario", "crosswalk", "--params", str(path))
    else:
        res = cli("sweep", str(path), "--out", str(tmp_path / "o"))
    assert_one_line(res, "f.toml: not valid TOML: ", named)


# -- nothing printed before an error found before the work -----------------------------


@pytest.mark.parametrize(
    ("spoil", "message"),
    [
        (lambda d: (d / "notes.txt").write_text("mine"), "is a non-empty folder that srfm did"),
        (lambda d: (d / "manifest.json").write_text("{"), "damaged manifest"),
    ],
    ids=["foreign draw folder", "damaged draw manifest"],
)
def test_a_refused_draw_folder_is_one_line_before_the_banner(
    tmp_path: Path, spoil: Any, message: str
) -> None:
    (tmp_path / "tiny.toml").write_text(TINY, encoding="utf-8")
    out = tmp_path / "out"
    args = ["-s", str(tmp_path / "tiny.toml"), "-p", "straight", "--seeds", "0", "--no-logs"]
    res = cli("benchmark", *args, "--no-figures", "--out", str(out))
    assert res.exit_code == 0, res.output
    draw = out / "draws" / "draw-000"
    draw.mkdir(parents=True)
    spoil(draw)
    res = cli("benchmark", *args, "--no-figures", "--param-draws", "1", "--out", str(out))
    assert_one_line(res, "draws/draw-000", message)


_ROBOT = "[robot]\nstart = [2.0, 8.0]\ngoal = [12.0, 9.0]\n"
BAD_SCENARIOS = {
    "overlap": _ROBOT + "[pedestrians]\nstarts = [[1.0, 1.0], [1.1, 1.0]]\n"
    "goals = [[10.0, 10.0], [1.0, 9.0]]\n",
    "outside": _ROBOT + "[pedestrians]\nstarts = [[-100.0, 1.0]]\ngoals = [[10.0, 10.0]]\n",
    "radius": _ROBOT.replace("[robot]\n", "[robot]\nradius_m = -0.5\n")
    + "[pedestrians]\nstarts = [[1.0, 1.0]]\ngoals = [[10.0, 10.0]]\n",
    "nan": _ROBOT.replace("8.0]", "nan]", 1)
    + "[pedestrians]\nstarts = [[1.0, 1.0]]\ngoals = [[10.0, 10.0]]\n",
    "wall": _ROBOT + "[obstacles]\nwalls = [[0.0, 1.0, 5.0, 1.0]]\n"
    "[pedestrians]\nstarts = [[1.0, 1.0]]\ngoals = [[10.0, 10.0]]\n",
}


@pytest.mark.parametrize("case", BAD_SCENARIOS, ids=list(BAD_SCENARIOS))
def test_bad_scenario_files_quote_plain_numbers(tmp_path: Path, case: str) -> None:
    """The scenario checks compute with NumPy (distances, overlaps, bounds); what they
    quote is plain."""
    path = tmp_path / "bad.toml"
    path.write_text(SCENARIO_HEAD.replace("1\n", "2\n", 1) + BAD_SCENARIOS[case], "utf-8")
    res = cli("simulate", "--scenario", str(path))
    assert_one_line(res, "bad.toml")
    assert _clean(res.output.rstrip("\n")), res.output
