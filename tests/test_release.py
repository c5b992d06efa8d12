"""The release files: ``python -m build`` makes a wheel and an sdist of the distribution
``social-robot-force-model`` that ``twine check`` accepts; the wheel holds the package
``srfm`` and its data only; installed into a fresh virtual environment without extras it
runs the quick benchmark (the ``srfm`` command) and the README's Python example
(``import srfm``).

Needs the ``release`` extra (build, twine) and the package registry for the fresh
environment's dependencies (as any ``pip install``).
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

from srfm._version import DISTRIBUTION
from tests.conftest import REPO

pytest.importorskip("build", reason="needs the release extra (build, twine)")

# The distribution's name in file names (the wheel's and the sdist's, PEP 427 / 625).
STEM = DISTRIBUTION.replace("-", "_")

WHEEL_LIMIT_BYTES = 3_000_000  # the package, scenarios and the two NumPy policies


def _run(*args: str | Path, cwd: Path | None = None, timeout: float = 900) -> str:
    # Without PYTHONPATH: a checkout on it would make the fresh environment's pip see
    # srfm (its egg-info) as installed already.
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    done = subprocess.run(
        [str(a) for a in args], cwd=cwd, capture_output=True, text=True, timeout=timeout, env=env
    )
    assert done.returncode == 0, f"{args}\n{done.stdout}\n{done.stderr}"
    return done.stdout + done.stderr


@pytest.fixture(scope="module")
def dist(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A wheel and an sdist of this checkout, built as `make dist` builds them (the
    wheel from the sdist), with this environment's setuptools (no download)."""
    out = tmp_path_factory.mktemp("dist")
    _run(sys.executable, "-m", "build", "--no-isolation", "--outdir", out, REPO)
    return out


def _wheel(dist: Path) -> Path:
    (wheel,) = dist.glob(f"{STEM}-*.whl")
    return wheel


def test_twine_accepts_both_files(dist: Path) -> None:
    files = sorted(dist.iterdir())
    assert sorted(p.suffix for p in files) == [".gz", ".whl"]
    out = _run(sys.executable, "-m", "twine", "check", "--strict", *files)
    assert out.count("PASSED") == 2


def test_the_wheel_holds_what_a_user_needs_only(dist: Path) -> None:
    wheel = _wheel(dist)
    names = zipfile.ZipFile(wheel).namelist()
    package = [n for n in names if not n.startswith(f"{STEM}-")]  # less the .dist-info
    assert all(n.startswith("srfm/") for n in package), package
    assert not [n for n in package if "__pycache__" in n or n.endswith((".pyc", ".zip"))]
    scenarios = {p.name for p in (REPO / "srfm" / "scenarios").glob("*.toml")}
    assert {Path(n).name for n in package if n.startswith("srfm/scenarios/")} >= scenarios
    for name in ("td3_srfm.npz", "td3_srfm.json", "td3_base.npz", "td3_base.json"):
        assert f"srfm/policies/{name}" in names
    assert "srfm/py.typed" in names
    sources = {str(p.relative_to(REPO)) for p in (REPO / "srfm").rglob("*.py")}
    assert {n for n in package if n.endswith(".py")} == sources
    assert wheel.stat().st_size < WHEEL_LIMIT_BYTES, wheel.stat().st_size


def test_the_sdist_holds_the_package_and_its_notes(dist: Path) -> None:
    import tarfile

    (sdist,) = dist.glob(f"{STEM}-*.tar.gz")
    with tarfile.open(sdist) as tar:
        top = {Path(n).parts[1] for n in tar.getnames() if len(Path(n).parts) > 1}
    assert top == {
        "CHANGELOG.md", "MANIFEST.in", "PKG-INFO", "README.md", "constraints.txt",
        "pyproject.toml", "setup.cfg", "srfm", f"{STEM}.egg-info",
    }  # fmt: skip


def test_the_version_comes_from_pyproject(dist: Path) -> None:
    text = (REPO / "pyproject.toml").read_text(encoding="utf-8")
    version = re.search(r'^version = "([^"]+)"', text, re.MULTILINE)
    assert version is not None
    assert _wheel(dist).name.startswith(f"{STEM}-{version.group(1)}-")
    assert f"## [{version.group(1)}]" in (REPO / "CHANGELOG.md").read_text(encoding="utf-8")


def test_the_distribution_is_named_in_one_place(dist: Path) -> None:
    """pyproject.toml's name is DISTRIBUTION; the wheel's metadata says it, installs the
    ``srfm`` command and the ``srfm`` package, and its extras name the distribution."""
    text = (REPO / "pyproject.toml").read_text(encoding="utf-8")
    name = re.search(r'^name = "([^"]+)"', text, re.MULTILINE)
    assert name is not None
    assert name.group(1) == DISTRIBUTION
    wheel = zipfile.ZipFile(_wheel(dist))
    info = next(n for n in wheel.namelist() if n.endswith(".dist-info/METADATA"))
    meta = wheel.read(info).decode("utf-8")
    assert f"\nName: {DISTRIBUTION}\n" in meta
    assert f'Requires-Dist: {DISTRIBUTION}[rl]; extra == "sbx"' in meta
    scripts = wheel.read(info.replace("METADATA", "entry_points.txt")).decode("utf-8")
    assert "srfm = srfm.cli:main" in scripts
    readme = (REPO / "README.md").read_text(encoding="utf-8")
    assert "**The name.**" in readme
    assert f"The distribution is called `{DISTRIBUTION}`; you still\n`import srfm`" in readme


def _readme_python_example() -> str:
    readme = (REPO / "README.md").read_text(encoding="utf-8")
    section = readme.split("## Python API", 1)[1]
    match = re.search(r"```python\n(.*?)```", section, re.DOTALL)
    assert match is not None
    return match.group(1)


def test_the_wheel_in_a_fresh_environment_without_extras(dist: Path, tmp_path: Path) -> None:
    """`pip install social_robot_force_model-….whl` alone, then the quick benchmark
    (every registered planner, the TD3 policies on NumPy) and the README's Python
    example."""
    venv = tmp_path / "venv"
    _run(sys.executable, "-m", "venv", venv)
    python = venv / "bin" / "python"
    _run(
        python, "-m", "pip", "install", "--disable-pip-version-check", "-q",
        "-c", REPO / "constraints.txt", _wheel(dist),
    )  # fmt: skip
    freeze = _run(python, "-m", "pip", "freeze")
    for extra in ("torch", "gymnasium", "stable-baselines3", "distributed", "pytest"):
        assert f"\n{extra}==" not in f"\n{freeze.lower()}", extra
    work = tmp_path / "work"
    work.mkdir()
    out = _run(
        venv / "bin" / "srfm", "benchmark", "--quick", "--out", work / "quick",
        "--no-logs", "--no-figures", "-j", "2", cwd=work,
    )  # fmt: skip
    assert "benchmark: 5 scenarios × 7 planners × 3 seeds = 105 episodes" in out
    assert "| concert | td3-srfm |" in out
    assert (work / "quick" / "report.html").is_file()
    # The README's example reads "my_scenario.toml": a scenario file of one's own.
    (work / "my_scenario.toml").write_bytes((REPO / "examples" / "lobby.toml").read_bytes())
    (work / "example.py").write_text(_readme_python_example(), encoding="utf-8")
    _run(python, "example.py", cwd=work)
