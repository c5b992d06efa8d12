"""Planners by name: ``srfm simulate --planner`` and the benchmark look them up here."""

from __future__ import annotations

from collections.abc import Callable

import attrs

from srfm.errors import PlannerError
from srfm.planners._base import Planner

__all__ = ["PlannerInfo", "available_planners", "make_planner", "register_planner"]


@attrs.frozen
class PlannerInfo:
    """A registered planner: its name, a one-line description and its factory."""

    name: str
    description: str
    factory: Callable[[], Planner]


_REGISTRY: dict[str, PlannerInfo] = {}


def register_planner(
    name: str, factory: Callable[[], Planner], description: str, *, replace: bool = False
) -> None:
    """Register ``factory`` (a callable returning a fresh planner) under ``name``."""
    if not name or not name.replace("-", "").replace("_", "").isalnum():
        raise PlannerError(f"planner name must be letters, digits, '-' or '_', got {name!r}")
    if name in _REGISTRY and not replace:
        raise PlannerError(f"planner {name!r} is already registered")
    _REGISTRY[name] = PlannerInfo(name, description, factory)


def make_planner(name: str) -> Planner:
    """A fresh planner instance by registry name."""
    try:
        info = _REGISTRY[name]
    except KeyError:
        known = ", ".join(sorted(_REGISTRY))
        raise PlannerError(f"unknown planner {name!r}; known: {known}") from None
    return info.factory()


def available_planners() -> list[PlannerInfo]:
    """Every registered planner, sorted by name."""
    return [_REGISTRY[name] for name in sorted(_REGISTRY)]
