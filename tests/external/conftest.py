"""Helpers of the external planner tests: real planner processes, the C++ client built
with CMake."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from tests.conftest import REPO

HERE = Path(__file__).resolve().parent
RAW_PLANNER = HERE / "raw_planner.py"
CPP_SOURCES = REPO / "clients" / "cpp"


def raw_command(mode: str) -> list[str]:
    """The command of ``raw_planner.py`` in ``mode`` (see its docstring)."""
    return [sys.executable, str(RAW_PLANNER), mode]


@pytest.fixture(scope="session")
def cpp_build(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The C++ client and its example planners, built once with CMake and the system
    compiler against Debian's libmsgpack-cxx-dev (``make setup`` installs it). Without
    CMake or the library the tests skip and say why, except in CI (CI=true), where they
    fail."""
    missing = [tool for tool in ("cmake", "c++") if shutil.which(tool) is None]
    if missing:
        message = f"no {' or '.join(missing)}: run `make setup` (installs cmake, g++)"
        if os.environ.get("CI") == "true":
            pytest.fail(message)
        pytest.skip(message)
    build = tmp_path_factory.mktemp("cpp-build")
    configure = subprocess.run(
        ["cmake", "-S", str(CPP_SOURCES), "-B", str(build), "-DCMAKE_BUILD_TYPE=Release"],
        capture_output=True,
        text=True,
    )
    if configure.returncode != 0:
        message = (
            "cmake cannot configure clients/cpp (libmsgpack-cxx-dev missing? run `make setup`):\n"
        )
        if os.environ.get("CI") == "true" or "msgpack" not in configure.stderr:
            pytest.fail(message + configure.stderr[-2000:])
        pytest.skip(message + configure.stderr[-500:])
    built = subprocess.run(
        ["cmake", "--build", str(build), "-j", "2"], capture_output=True, text=True
    )
    assert built.returncode == 0, built.stdout[-3000:] + built.stderr[-3000:]
    return build


@pytest.fixture(autouse=True)
def _own_definitions(monkeypatch: pytest.MonkeyPatch) -> None:
    """Each test's external planner definitions are its own (the environment variable
    they live in is restored afterwards)."""
    from srfm.planners.external import DEFINITIONS_ENV

    monkeypatch.setenv(DEFINITIONS_ENV, os.environ.get(DEFINITIONS_ENV, "{}"))
