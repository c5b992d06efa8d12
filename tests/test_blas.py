"""srfm._blas: numba's BLAS check without importing scipy.linalg (issue 39)."""

from __future__ import annotations

import subprocess
import sys
import textwrap


def _run(code: str) -> list[str]:
    """Run ``code`` in a fresh interpreter (imports are process-wide); its printed lines."""
    done = subprocess.run(
        [sys.executable, "-c", textwrap.dedent(code)],
        capture_output=True,
        text=True,
        timeout=600,
        check=False,
    )
    assert done.returncode == 0, done.stderr
    return done.stdout.split()


def test_numba_finds_blas_and_scipy_linalg_stays_whole() -> None:
    lines = _run(
        """
        import sys
        from srfm._blas import load_cython_blas
        print(load_cython_blas(), load_cython_blas())  # the second call does nothing
        import numba, numpy as np
        import numba.np.arraymath
        print(numba.np.arraymath._HAVE_BLAS, "scipy.linalg" in sys.modules)
        @numba.njit
        def dot(a, b):
            return np.dot(a, b)
        a = np.arange(9.0).reshape(3, 3)
        print(np.array_equal(dot(a, a), a @ a))
        import scipy.linalg
        from scipy.linalg import cython_blas
        print(cython_blas is sys.modules["scipy.linalg.cython_blas"])
        x = scipy.linalg.solve(a + 5 * np.eye(3), np.ones(3))
        print(np.allclose((a + 5 * np.eye(3)) @ x, 1.0))
        """
    )
    assert lines == ["True", "False", "True", "False", "True", "True", "True"]


def test_nothing_is_done_once_scipy_linalg_is_there() -> None:
    lines = _run(
        """
        import scipy.linalg
        from srfm._blas import load_cython_blas
        print(load_cython_blas())
        """
    )
    assert lines == ["False"]


def test_the_srfm_program_runs_a_kernel_without_scipy_linalg() -> None:
    lines = _run(
        """
        import sys
        from srfm.cli import main
        main(["simulate", "--scenario", "crosswalk", "--seed", "0"], standalone_mode=False)
        print("scipy.linalg" in sys.modules, "scipy.linalg.cython_blas" in sys.modules)
        """
    )
    assert lines[-2:] == ["False", "True"]
