"""Optional dependencies (the ``rl`` extra: gymnasium, stable-baselines3, torch),
imported lazily.

Outside :mod:`srfm.rl` so that the policy planners (:mod:`srfm.planners.td3`) can load
stable-baselines3 without importing the environment. :class:`~srfm.errors.MissingDependencyError`
lives in :mod:`srfm.errors` (re-exported here and from ``srfm``), so it can be caught
without the extra installed.
"""

from __future__ import annotations

import importlib
from types import ModuleType
from typing import Final

from srfm.errors import MissingDependencyError

__all__ = ["INSTALL_HINT", "MissingDependencyError", "require"]

INSTALL_HINT: Final = "pip install 'srfm[rl]' -c constraints.txt"


# What each extra is for, in the error that names it.
_EXTRA_PURPOSE: Final = {
    "rl": "srfm's RL environment, training and policies",
    "dask": "running benchmarks on a Dask cluster (--executor dask)",
}


def require(module: str, extra: str = "rl") -> ModuleType:
    """Import ``module`` or raise :class:`MissingDependencyError` naming the extra."""
    try:
        return importlib.import_module(module)
    except ImportError as exc:
        hint = INSTALL_HINT if extra == "rl" else f"pip install 'srfm[{extra}]'"
        raise MissingDependencyError(
            f"{module} is needed for {_EXTRA_PURPOSE[extra]} ({exc}); install the "
            f"{extra} extra: {hint}"
        ) from None
