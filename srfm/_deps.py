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

from srfm._version import DISTRIBUTION
from srfm.errors import MissingDependencyError

__all__ = ["INSTALL_HINT", "MissingDependencyError", "install_hint", "require"]


def install_hint(extras: str) -> str:
    """The command that installs srfm with ``extras`` (comma-separated, e.g.
    ``"rl,sbx"``); constraints.txt keeps torch on the CPU build."""
    return f"pip install '{DISTRIBUTION}[{extras}]' -c constraints.txt"


INSTALL_HINT: Final = install_hint("rl")


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
        hint = install_hint(extra)
        raise MissingDependencyError(
            f"{module} is needed for {_EXTRA_PURPOSE[extra]} ({exc}); install the "
            f"{extra} extra: {hint}"
        ) from None
