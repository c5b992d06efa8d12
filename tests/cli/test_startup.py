"""Start-up cost: ``srfm --help`` and ``import srfm`` do not import the simulator; the
package's API is imported on first use (srfm/_lazy.py) and behaves as before."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

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


def test_the_program_freezes_the_collector_at_exit_and_its_logs_are_whole(
    tmp_path: Path,
) -> None:
    """`srfm simulate --out` run as a program (arguments from sys.argv) freezes the
    garbage collector once the command is done (the interpreter's last collection is
    skipped): the path runs, and the files it wrote are complete and read back."""
    from mcap.reader import make_reader

    out = tmp_path / "out"
    probe = (
        "import atexit, gc, sys\n"
        "atexit.register(lambda: print('frozen', gc.get_freeze_count(), file=sys.stderr))\n"
        f"sys.argv = ['srfm', 'simulate', '--scenario', 'crosswalk', '--out', {str(out)!r}]\n"
        "from srfm.cli import main\n"
        "main()\n"
    )
    run = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    frozen = [line for line in run.stderr.splitlines() if line.startswith("frozen ")]
    assert frozen
    assert int(frozen[0].split()[1]) > 0
    (rrd,) = out.rglob("*.rrd")
    (log,) = out.rglob("*.mcap")
    verify = subprocess.run(
        [sys.executable, "-m", "rerun", "rrd", "verify", str(rrd)], capture_output=True, text=True
    )
    assert verify.returncode == 0, verify.stderr
    with log.open("rb") as f:
        assert sum(1 for _ in make_reader(f).iter_messages()) > 100
