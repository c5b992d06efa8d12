"""Every error and warning class lives in srfm.errors and is exported from srfm."""

from __future__ import annotations

import inspect
import subprocess
import sys
from importlib import metadata

import pytest

import srfm
import srfm.datasets
import srfm.errors
from srfm.metrics.stats import compare
from tests.conftest import REPO

CLASSES = [
    cls
    for _, cls in inspect.getmembers(srfm.errors, inspect.isclass)
    if cls.__module__ == "srfm.errors"
]


def test_the_module_lists_every_class_it_defines() -> None:
    assert sorted(srfm.errors.__all__) == sorted(cls.__name__ for cls in CLASSES)


@pytest.mark.parametrize("cls", CLASSES, ids=lambda cls: cls.__name__)
def test_every_class_is_exported_from_srfm(cls: type) -> None:
    assert cls.__name__ in srfm.__all__
    assert getattr(srfm, cls.__name__) is cls
    assert issubclass(cls, srfm.SrfmError | srfm.SrfmWarning)
    if issubclass(cls, Warning):
        assert issubclass(cls, UserWarning)
    else:
        assert (
            issubclass(cls, ValueError | ImportError | OSError | RuntimeError)
            or cls is srfm.SrfmError
        )


def test_old_import_places_still_work() -> None:
    assert srfm.datasets.DatasetWarning is srfm.DatasetWarning
    from srfm.datasets._trajectories import DatasetWarning

    assert DatasetWarning is srfm.DatasetWarning
    assert issubclass(srfm.MissingDependencyError, ImportError)


def test_mismatched_comparison_raises_a_metric_error() -> None:
    with pytest.raises(srfm.MetricError, match="one value per shared seed") as info:
        compare([1.0, 2.0, 3.0], [1.0, 2.0])
    assert isinstance(info.value, ValueError)


_NO_RL = """
import importlib.abc, sys

class Block(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path, target=None):
        if name.split(".")[0] in {"gymnasium", "stable_baselines3", "torch"}:
            raise ModuleNotFoundError(f"No module named {name!r} (blocked)")
        return None

sys.meta_path.insert(0, Block())
import srfm
from srfm import MissingDependencyError
import srfm.rl  # light: the training configuration and EnvConfig need no gymnasium
try:
    import srfm.rl.env
except srfm.MissingDependencyError as exc:
    assert "install the rl extra" in str(exc), exc
    assert isinstance(exc, ImportError)
else:
    raise AssertionError("srfm.rl.env imported without gymnasium")
assert not any(m.split(".")[0] in {"gymnasium", "stable_baselines3", "torch"} for m in sys.modules)
print("ok")
"""


def test_missing_dependency_error_is_importable_without_the_rl_extra() -> None:
    proc = subprocess.run(
        [sys.executable, "-c", _NO_RL], cwd=REPO, capture_output=True, text=True, timeout=300
    )
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == "ok"


def test_version_comes_from_the_installed_metadata() -> None:
    assert srfm.__version__ == metadata.version("social-robot-force-model")


def test_version_without_installed_metadata() -> None:
    script = (
        "from importlib import metadata\n"
        "def version(name):\n"
        "    raise metadata.PackageNotFoundError(name)\n"
        "metadata.version = version\n"
        "import srfm\n"
        "print(srfm.__version__)\n"
    )
    out = subprocess.run(
        [sys.executable, "-c", script], cwd=REPO, capture_output=True, text=True, check=True
    ).stdout
    assert out.strip() == "0+unknown"
