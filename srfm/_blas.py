"""numba's BLAS check without importing ``scipy.linalg`` (the ``srfm`` program only).

numba, on its first compilation or cache load in a process, checks that a BLAS is
there for ``np.dot`` and friends by importing ``scipy.linalg.cython_blas``. Importing
that module runs the ``scipy.linalg`` package first, which imports all of SciPy's
linear algebra and its array-API layer: 0.12 s of `srfm simulate`'s 1.04 s on an idle
machine (docs/performance.md, "Commands"), although no srfm kernel calls a BLAS
routine. :func:`load_cython_blas` loads the ``cython_blas`` extension module alone (the
same file, the same module object numba and SciPy use) before numba asks for it, so
numba's check finds it there and ``scipy.linalg`` is imported only by code that uses it.

Only the ``srfm`` program calls it (:func:`srfm.cli.main`), never ``import srfm``: in
that process, code that imports ``scipy.linalg`` later gets the complete package and
the same ``cython_blas`` module; only the attribute ``scipy.linalg.cython_blas`` is
missing until something imports it by ``from scipy.linalg import cython_blas``.
"""

from __future__ import annotations

import importlib.machinery
import importlib.util
import sys

__all__ = ["load_cython_blas"]

_NAME = "scipy.linalg.cython_blas"


def load_cython_blas() -> bool:
    """Load ``scipy.linalg.cython_blas`` without running the ``scipy.linalg`` package.

    Nothing is done when ``scipy.linalg`` or the module is loaded already, or when numba
    has made its check; any failure to find or load the module leaves everything as it
    was (numba then imports it its own way).

    Returns:
        Whether this call loaded it.
    """
    if _NAME in sys.modules or "scipy.linalg" in sys.modules or "numba.np.arraymath" in sys.modules:
        return False
    try:
        package = importlib.util.find_spec("scipy.linalg")  # imports scipy, not scipy.linalg
        if package is None or package.submodule_search_locations is None:
            return False
        spec = importlib.machinery.PathFinder.find_spec(_NAME, package.submodule_search_locations)
        if spec is None or spec.loader is None:
            return False
        module = importlib.util.module_from_spec(spec)
        sys.modules[_NAME] = module
        spec.loader.exec_module(module)
    except Exception:  # anything: numba then imports it its own way
        sys.modules.pop(_NAME, None)
        return False
    return True
