"""Planners by name: ``srfm simulate --planner`` and the benchmark look them up here."""

from __future__ import annotations

import importlib
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
    """A fresh planner instance by registry name, or from ``"module:attribute"``.

    The second form imports ``module`` and calls ``attribute`` (a planner class or a
    factory) with no arguments, so the command line can run planners that live in the
    user's own code: ``srfm simulate --planner mypackage.planners:MyPlanner``.
    """
    if ":" in name:
        return _import_planner(name)
    try:
        info = _REGISTRY[name]
    except KeyError:
        known = ", ".join(sorted(_REGISTRY))
        raise PlannerError(
            f"unknown planner {name!r}; known: {known}; or give module:attribute"
        ) from None
    return info.factory()


def _import_planner(spec: str) -> Planner:
    module_name, _, attr = spec.partition(":")
    try:
        module = importlib.import_module(module_name)
    except ImportError as exc:
        raise PlannerError(f"planner {spec!r}: cannot import {module_name!r}: {exc}") from None
    factory = getattr(module, attr, None)
    if not callable(factory):
        raise PlannerError(f"planner {spec!r}: {module_name} has no callable {attr!r}")
    planner = factory()
    if not isinstance(planner, Planner):
        raise PlannerError(
            f"planner {spec!r}: {attr}() returned {planner!r}, which lacks the Planner "
            "protocol (name, detection_range_m, reset, act)"
        )
    return planner


def available_planners() -> list[PlannerInfo]:
    """Every registered planner, sorted by name."""
    return [_REGISTRY[name] for name in sorted(_REGISTRY)]
