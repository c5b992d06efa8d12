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


def require(module: str) -> ModuleType:
    """Import ``module`` or raise :class:`MissingDependencyError` naming the extra."""
    try:
        return importlib.import_module(module)
    except ImportError as exc:
        raise MissingDependencyError(
            f"{module} is needed for srfm's RL environment, training and policies "
            f"({exc}); install the rl extra: {INSTALL_HINT}"
        ) from None
