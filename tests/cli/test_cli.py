"""The srfm command line, through click's CliRunner and as an installed command."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from click.testing import CliRunner

import srfm
from srfm.cli import main
from srfm.scenarios import BUILTIN_SCENARIOS, LARGE_SCENARIOS
from tests.conftest import write_scenario


def run(*args: str) -> tuple[int, str]:
    result = CliRunner().invoke(main, list(args))
    return result.exit_code, result.output


@pytest.mark.parametrize("cmd", [[], ["scenarios"], ["planners"], ["simulate"]])
def test_help_everywhere(cmd: list[str]) -> None:
    code, out = run(*cmd, "--help")
    assert code == 0
    assert "Usage:" in out


def test_scenarios_lists_every_builtin_with_a_description() -> None:
    code, out = run("scenarios")
    assert code == 0
    lines = out.strip().splitlines()[1:-1]  # less the header and the generated layouts
    assert [line.split()[0] for line in lines] == [*BUILTIN_SCENARIOS, *LARGE_SCENARIOS]
    assert all(len(line.split(maxsplit=2)[2]) > 20 for line in lines)


def test_planners_lists_straight() -> None:
    code, out = run("planners")
    assert code == 0
    assert any(line.startswith("straight ") for line in out.splitlines())


def test_simulate_prints_a_summary() -> None:
    code, out = run("simulate", "--scenario", "crosswalk", "--seed", "3")
    assert code == 0, out
    assert "crosswalk (seed 3, planner straight)" in out
    assert "goal reached" in out
    assert "arrivals   factual 10/10" in out


def test_simulate_json_is_deterministic(tmp_path: Path) -> None:
    outs = []
    for _ in range(2):
        code, out = run("simulate", "--scenario", "circle", "--seed", "1", "--json")
        assert code == 0
        data = json.loads(out)
        data.pop("wall_time_s")
        outs.append(data)
    assert outs[0] == outs[1]
    assert outs[0]["outcome"] == "goal_reached"
    assert outs[0]["twin_max_separation_max_m"] > 0.0


def test_simulate_with_params_preset_and_file(tmp_path: Path) -> None:
    code, base = run("simulate", "--scenario", "footpath", "--json")
    code2, ferrer = run("simulate", "--scenario", "footpath", "--json", "--params", "ferrer2013")
    assert code == code2 == 0
    assert (
        json.loads(base)["twin_max_separation_mean_m"]
        != json.loads(ferrer)["twin_max_separation_mean_m"]
    )
    params = tmp_path / "p.toml"
    params.write_text("schema_version = 1\n[params]\na_robot = 0.0\n")
    code, out = run("simulate", "--scenario", "footpath", "--json", "--params", str(params))
    assert code == 0
    assert json.loads(out)["twin_max_separation_max_m"] == 0.0


def test_simulate_user_scenario_file(tmp_path: Path) -> None:
    path = write_scenario(
        tmp_path / "mine.toml",
        'schema_version = 1\nname = "mine"\ndescription = "d"\n[robot]\nstart = [1.0, 1.0]\n'
        "goal = [4.0, 1.0]\n[pedestrians]\nstarts = [[3.0, 3.0]]\ngoals = [[3.0, 0.5]]\n",
    )
    code, out = run("simulate", "--scenario", str(path))
    assert code == 0, out
    assert "mine (seed 0" in out


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["simulate", "--scenario", "nowhere"], "unknown scenario 'nowhere'"),
        (["simulate", "--scenario", "footpath", "--planner", "warp"], "unknown planner 'warp'"),
        (
            ["simulate", "--scenario", "footpath", "--params", "nobody"],
            "unknown parameter preset 'nobody'",
        ),
        (["simulate", "--scenario", "footpath", "--seed", "-3"], "'-3' is not a seed"),
        (["simulate"], "Missing option '--scenario'"),
        (["fly"], "No such command 'fly'"),
    ],
)
def test_user_errors_are_one_line_with_exit_code_2(args: list[str], message: str) -> None:
    code, out = run(*args)
    assert code == 2
    assert message in out
    assert "Traceback" not in out


def test_bad_files_give_one_line_errors(tmp_path: Path) -> None:
    bad = write_scenario(tmp_path / "bad.toml", "schema_version = 1\nname = 3\n")
    code, out = run("simulate", "--scenario", str(bad))
    assert code == 2
    assert out.strip() == f"Error: {bad}: name: must be a string, got 3"
    params = tmp_path / "p.toml"
    params.write_text("schema_version = 1\n[params]\ntau = -1.0\n")
    code, out = run("simulate", "--scenario", "footpath", "--params", str(params))
    assert code == 2
    assert "tau must be > 0, got -1.0" in out
    assert len(out.strip().splitlines()) == 1


def test_installed_entry_point() -> None:
    exe = shutil.which("srfm") or str(Path(__file__).resolve().parents[2] / ".venv/bin/srfm")
    out = subprocess.run([exe, "scenarios"], capture_output=True, text=True, check=True)
    assert "footpath" in out.stdout
    bad = subprocess.run([exe, "simulate", "--scenario", "nope"], capture_output=True, text=True)
    assert bad.returncode == 2
    assert bad.stderr.strip().startswith("Error: unknown scenario 'nope'")


def test_a_planner_module_in_the_current_folder(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """`-p module:attribute` finds a module of the current folder, as `python -m` would,
    without PYTHONPATH (the installed `srfm` script does not put the folder on the path)."""
    (tmp_path / "h8_cwd_planners.py").write_text(
        "import numpy as np\n\n"
        "class Wait:\n"
        "    name = 'wait'\n"
        "    detection_range_m = 2.0\n"
        "    def reset(self, context, rng):\n"
        "        pass\n"
        "    def act(self, observation):\n"
        "        return np.zeros(2)\n",
        encoding="utf-8",
    )
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(sys, "path", [p for p in sys.path if p not in ("", ".")])
    code, out = run("simulate", "--scenario", "crosswalk", "--planner", "h8_cwd_planners:Wait")
    assert code == 0, out
    assert "planner h8_cwd_planners:Wait" in out
    assert sys.path[-1] == str(tmp_path)


def test_benchmark_output_off_a_terminal(tmp_path: Path) -> None:
    """Off a terminal no progress bar (not even its label), counts in the singular where
    they are 1, and the printed list of result files names manifest.json."""
    out = tmp_path / "one"
    code, text = run(
        "benchmark", "-s", "crosswalk", "-p", "straight", "--seeds", "0", "--out", str(out),
        "--no-logs", "--no-figures", "-j", "1",
    )  # fmt: skip
    assert code == 0, text
    lines = text.splitlines()
    assert f"benchmark: 1 scenario × 1 planner × 1 seed = 1 episode -> {out}" in lines
    assert "episodes" not in " ".join(line.split()[0] for line in lines if line.strip())
    listed = next(line for line in lines if line.startswith("results in "))
    assert listed.endswith(", manifest.json")
    assert (out / "manifest.json").is_file()


def test_the_readme_command_table_lists_every_command() -> None:
    """Every command and subcommand of `srfm` has a row in README's command table."""
    import click

    readme = (Path(__file__).resolve().parents[2] / "README.md").read_text(encoding="utf-8")
    rows = [line for line in readme.split("| command | what it does |", 1)[1].splitlines()]
    table = "\n".join(rows[: next(i for i, r in enumerate(rows[2:], 2) if not r.startswith("|"))])
    names = []
    for name, command in main.commands.items():
        if isinstance(command, click.Group):
            names += [f"srfm {name} {sub}" for sub in command.commands]
        else:
            names.append(f"srfm {name}")
    missing = [n for n in names if f"`{n}" not in table]
    assert not missing, missing


def test_version_names_the_distribution() -> None:
    code, out = run("--version")
    assert code == 0
    assert out == f"srfm, version {srfm.__version__} (social-robot-force-model)\n"


def test_version_of_a_tree_never_installed_is_no_crash() -> None:
    """Without the distribution's metadata (a checkout installed under its old name, or
    never installed) `srfm --version` says 0+unknown instead of a traceback."""
    script = (
        "from importlib import metadata\n"
        "def version(name):\n"
        "    raise metadata.PackageNotFoundError(name)\n"
        "metadata.version = version\n"
        "from srfm.cli import main\n"
        "main(['--version'])\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, timeout=120
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout == "srfm, version 0+unknown (social-robot-force-model)\n"
