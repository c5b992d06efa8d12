"""Optional dependencies of the RL parts (the ``rl`` extra), imported lazily."""

from __future__ import annotations

import importlib
from types import ModuleType
from typing import Final

from srfm.errors import SrfmError

__all__ = ["INSTALL_HINT", "MissingDependencyError", "require"]

INSTALL_HINT: Final = "pip install 'srfm[rl]' -c constraints.txt"


class MissingDependencyError(SrfmError, ImportError):
    """An optional dependency (gymnasium, stable-baselines3, torch) is not installed."""


def require(module: str) -> ModuleType:
    """Import ``module`` or raise :class:`MissingDependencyError` naming the extra."""
    try:
        return importlib.import_module(module)
    except ImportError as exc:
        raise MissingDependencyError(
            f"{module} is needed for srfm's RL environment, training and policies "
            f"({exc}); install the rl extra: {INSTALL_HINT}"
        ) from None
