"""Run the ``srfm`` command line as a plain ``pip install social-robot-force-model``
would: with the optional dependencies (torch, stable-baselines3, gymnasium, JAX, SBX)
blocked.

    python tests/no_extras.py benchmark --quick ...

A :data:`sys.meta_path` finder placed first refuses those packages (an
``import torch`` raises ModuleNotFoundError, as when they are not installed). It is
installed when this file is imported, so worker processes started with ``spawn`` (which
re-import the main module) block them too; forked workers inherit it.
"""

from __future__ import annotations

import importlib.abc
import sys
from collections.abc import Sequence
from types import ModuleType
from typing import Any

BLOCKED = ("torch", "stable_baselines3", "gymnasium", "jax", "jaxlib", "sbx", "flax", "optax")


class _Block(importlib.abc.MetaPathFinder):
    def find_spec(
        self, fullname: str, path: Sequence[str] | None, target: ModuleType | None = None
    ) -> Any:
        if fullname.split(".")[0] in BLOCKED:
            raise ModuleNotFoundError(f"No module named {fullname!r} (blocked)", name=fullname)
        return None


if not any(isinstance(f, _Block) for f in sys.meta_path):
    for name in list(sys.modules):
        if name.split(".")[0] in BLOCKED:
            raise SystemExit(f"{name} was imported before the import blocker")
    sys.meta_path.insert(0, _Block())


if __name__ == "__main__":
    from srfm.cli import main

    try:
        main(sys.argv[1:], prog_name="srfm")
    finally:
        leaked = sorted(n for n in sys.modules if n.split(".")[0] in BLOCKED)
        if leaked:
            print(f"blocked modules imported: {leaked}", file=sys.stderr)
            sys.exit(3)
