"""Start-up cost: ``srfm --help`` and ``import srfm`` do not import the simulator; the
package's API is imported on first use (srfm/_lazy.py) and behaves as before."""

from __future__ import annotations

import subprocess
import sys

import pytest

import srfm

_HEAVY = ("numba", "scipy", "numpy", "srfm.sim", "srfm.rl", "srfm.models.forces")


def _imported_after(code: str) -> set[str]:
    """The top-level and srfm modules a fresh interpreter holds after running ``code``."""
    probe = f"{code}\nimport sys\nprint('\\n'.join(sys.modules))"
    out = subprocess.run(
        [sys.executable, "-c", probe], capture_output=True, text=True, check=True
    ).stdout
    return set(out.split())


@pytest.mark.parametrize(
    "code",
    [
        "import srfm",
        "import srfm.cli",
        "from srfm.cli import main\ntry:\n    main(['--help'])\nexcept SystemExit:\n    pass",
    ],
)
def test_start_up_imports_no_simulator(code: str) -> None:
    modules = _imported_after(code)
    assert not modules & set(_HEAVY), sorted(modules & set(_HEAVY))


def test_a_lazy_name_imports_its_module() -> None:
    modules = _imported_after("import srfm\nsrfm.run_episode")
    assert {"srfm.sim.episode", "numba"} <= modules


def test_every_public_name_resolves() -> None:
    for name in srfm.__all__:
        assert getattr(srfm, name) is not None, name
    assert set(srfm.__all__) <= set(dir(srfm))
    from srfm.models import SRFMParams, step_crowd
    from srfm.sim.episode import run_episode

    assert srfm.run_episode is run_episode
    assert srfm.models.SRFMParams is SRFMParams
    assert srfm.step_crowd is step_crowd


def test_an_unknown_name_is_an_attribute_error() -> None:
    with pytest.raises(AttributeError, match="no_such_name"):
        srfm.no_such_name  # noqa: B018
    with pytest.raises(AttributeError, match="no_such_name"):
        srfm.models.no_such_name  # noqa: B018
