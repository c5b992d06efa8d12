"""Planners by name: ``srfm simulate --planner`` and the benchmark look them up here.

The name a planner is made by is its name: :func:`make_planner` gives the planner it
returns that name, so episode records, metrics and tables say the registry name (or the
``module:attribute`` spec) whatever the class calls itself.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable

import attrs
import numpy as np

from srfm._text import plain
from srfm.errors import PlannerError
from srfm.planners._base import (
    FloatArray,
    Observation,
    Planner,
    PlannerContext,
    protocol_error,
    protocol_problems,
)

__all__ = ["PlannerInfo", "available_planners", "make_planner", "register_planner"]


@attrs.frozen
class PlannerInfo:
    """A registered planner: its name, a one-line description, its factory (a callable,
    or the ``"module:attribute"`` of one), and whether ``srfm benchmark`` runs it when no
    planner is named (``default``)."""

    name: str
    description: str
    factory: Callable[[], Planner] | str
    default: bool = True


_REGISTRY: dict[str, PlannerInfo] = {}


def register_planner(
    name: str,
    factory: Callable[[], Planner] | str,
    description: str,
    *,
    replace: bool = False,
    default: bool = True,
) -> None:
    """Register ``factory`` under ``name``: a callable returning a fresh planner, or
    ``"module:attribute"`` of one, imported when the planner is first made (a planner
    whose code lives in a package that imports this one). ``default=False`` leaves it
    out of the benchmark's default planner list (a reference, or a planner that runs
    only on some scenarios)."""
    if not name or not name.replace("-", "").replace("_", "").isalnum():
        raise PlannerError(f"planner name must be letters, digits, '-' or '_', got {plain(name)}")
    if name in _REGISTRY and not replace:
        raise PlannerError(f"planner {name!r} is already registered")
    _REGISTRY[name] = PlannerInfo(name, description, factory, default)


def make_planner(name: str) -> Planner:
    """A fresh planner instance by registry name, or from ``"module:attribute"``.

    The second form imports ``module`` and calls ``attribute`` (a planner class or a
    factory) with no arguments, so the command line can run planners that live in the
    user's own code: ``srfm simulate --planner mypackage.planners:MyPlanner``.

    ``"external:NAME"`` is the external planner defined as NAME
    (:func:`srfm.planners.external.define_external`, ``--external NAME=COMMAND``): a planner in
    another process, reached through the external planner protocol.

    Either way the planner's ``name`` becomes ``name`` (the registry name, or the whole
    ``module:attribute`` spec), so its episode records carry the name it was asked for.
    The name is set on the instance; a planner whose ``name`` cannot be set (slots, a
    frozen class, a read-only property) is wrapped in a thin renaming planner instead.

    Raises:
        PlannerError: unknown name, import failure, or a result that lacks the
            :class:`Planner` protocol.
    """
    if name.startswith("external:"):
        from srfm.planners.external import ExternalPlanner  # lazy: loaded when used

        return ExternalPlanner(name)
    if ":" in name:
        planner = _import_planner(name)
    else:
        try:
            info = _REGISTRY[name]
        except KeyError:
            known = ", ".join(sorted(_REGISTRY))
            raise PlannerError(
                f"unknown planner {plain(name)}; known: {known}; or give module:attribute"
            ) from None
        planner = _import_planner(info.factory) if isinstance(info.factory, str) else info.factory()
    return _named(planner, name)


def _import_planner(spec: str) -> object:
    module_name, _, attr = spec.partition(":")
    try:
        module = importlib.import_module(module_name)
    except ImportError as exc:
        raise PlannerError(f"planner {spec!r}: cannot import {module_name!r}: {exc}") from None
    factory = getattr(module, attr, None)
    if not callable(factory):
        raise PlannerError(f"planner {spec!r}: {module_name} has no callable {attr!r}")
    return factory()


def _named(planner: object, name: str) -> Planner:
    """``planner`` under ``name``, checked against the protocol."""
    if getattr(planner, "name", None) != name:
        try:
            planner.name = name  # type: ignore[attr-defined]
        except AttributeError:  # slots, frozen attrs/dataclass, read-only property
            planner = _RenamedPlanner(_checked(planner, name, check_name=False), name)
    return _checked(planner, name)  # type: ignore[return-value]


def _checked(planner: object, name: str, *, check_name: bool = True) -> object:
    problems = protocol_problems(planner, check_name=check_name)
    if problems:
        raise protocol_error(f"{name!r} ({type(planner).__qualname__})", problems)
    return planner


class _RenamedPlanner:
    """A planner whose own ``name`` is read-only, run under its registered name."""

    def __init__(self, inner: object, name: str) -> None:
        self.name = name
        self.inner = inner

    @property
    def detection_range_m(self) -> float | None:
        """The wrapped planner's detection range (read at every episode start)."""
        value: float | None = getattr(self.inner, "detection_range_m", None)
        return value

    @detection_range_m.setter
    def detection_range_m(self, value: float | None) -> None:
        self.inner.detection_range_m = value  # type: ignore[attr-defined]

    def reset(self, context: PlannerContext, rng: np.random.Generator) -> None:
        """Reset the wrapped planner."""
        self.inner.reset(context, rng)  # type: ignore[attr-defined]

    def act(self, observation: Observation) -> FloatArray:
        """The wrapped planner's command."""
        command: FloatArray = self.inner.act(observation)  # type: ignore[attr-defined]
        return command


def available_planners() -> list[PlannerInfo]:
    """Every registered planner, sorted by name."""
    return [_REGISTRY[name] for name in sorted(_REGISTRY)]
