"""A package's public names imported on first use (PEP 562) instead of with the package.

``srfm --help`` and the commands that simulate nothing then start without numba and
scipy; ``import srfm`` followed by ``srfm.run_episode(...)`` works as before. The
package keeps the same names under ``if TYPE_CHECKING:`` for a type checker and a
reader.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Mapping
from typing import Any


def lazy_names(
    package: str, names: Mapping[str, str], namespace: dict[str, Any]
) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """The ``__getattr__`` and ``__dir__`` of ``package``: ``names`` maps each lazy name
    to the module that defines it; a name, once imported, is kept in ``namespace``
    (the package's globals) so that it costs nothing the next time."""

    def attribute(name: str) -> Any:
        module = names.get(name)
        if module is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(module), name)
        namespace[name] = value
        return value

    def listing() -> list[str]:
        return sorted(set(namespace) | set(names))

    return attribute, listing
