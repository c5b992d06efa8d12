"""The command line's external planners: ``--external NAME=COMMAND`` (or
``NAME=unix:PATH``, ``NAME=tcp:HOST:PORT``) and ``--external-timeout``, shared by
``srfm simulate`` and ``srfm benchmark`` (docs/planners-any-language.md)."""

from __future__ import annotations

import functools
import sys
import warnings
from collections.abc import Callable
from typing import Any, TextIO, TypeVar

import click

__all__ = ["external_options"]

F = TypeVar("F", bound=Callable[..., Any])


def _one_line_failures() -> None:
    """Print every :class:`~srfm.errors.PlannerFailureWarning` as its one line."""
    from srfm.errors import PlannerFailureWarning

    shown = warnings.showwarning

    def show(
        message: Warning | str,
        category: type[Warning],
        filename: str,
        lineno: int,
        file: TextIO | None = None,
        line: str | None = None,
    ) -> None:
        if issubclass(category, PlannerFailureWarning):
            print(f"srfm: {message}", file=sys.stderr, flush=True)
        else:
            shown(message, category, filename, lineno, file, line)

    warnings.showwarning = show
    warnings.filterwarnings("always", category=PlannerFailureWarning)


def external_options(func: F) -> F:
    """Add ``--external`` and ``--external-timeout`` to a command (put it below
    ``@user_errors``): the planners are defined (:func:`srfm.planners.external.define_external`)
    before the command runs, and their failures print as one line each."""

    @functools.wraps(func)
    def wrapper(
        *args: Any, external: tuple[str, ...], external_timeout: float, **kwargs: Any
    ) -> Any:
        if external:
            from srfm.errors import PlannerError
            from srfm.planners.external import define_external
            from srfm.planners.external._planner import is_address, parse_external_option

            seen: set[str] = set()
            for text in external:
                name, target = parse_external_option(text)
                if name in seen:
                    raise PlannerError(f"--external {name}=... is given twice")
                seen.add(name)
                if is_address(target):
                    define_external(name, address=target, step_timeout_s=external_timeout)
                else:
                    define_external(name, target, step_timeout_s=external_timeout)
            _one_line_failures()
        return func(*args, **kwargs)

    wrapper = click.option(
        "--external-timeout",
        type=float,
        default=1.0,
        show_default=True,
        metavar="SECONDS",
        help="How long an external planner may take to answer one step; past it, its "
        "episode ends with the outcome planner_failed.",
    )(wrapper)
    wrapper = click.option(
        "--external",
        multiple=True,
        metavar="NAME=COMMAND",
        help="Define the planner external:NAME: a program srfm starts (one per worker) "
        "that speaks the external planner protocol, or NAME=unix:PATH / "
        "NAME=tcp:HOST:PORT of one that listens. Repeat for several; run it with "
        "--planner external:NAME (docs/planners-any-language.md).",
    )(wrapper)
    return wrapper  # type: ignore[return-value]
