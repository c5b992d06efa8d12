"""Shared pieces of the command line: user errors and parameter loading."""

from __future__ import annotations

import functools
from collections.abc import Callable
from pathlib import Path
from typing import Any, TypeVar

import click

from srfm.errors import SrfmError
from srfm.models.params import SRFMParams

__all__ = ["UserError", "load_params_option", "user_errors"]

F = TypeVar("F", bound=Callable[..., Any])


class UserError(click.ClickException):
    """A user mistake: printed as one line, exit code 2."""

    exit_code = 2


def user_errors(func: F) -> F:
    """Turn srfm's own errors into one-line messages with exit code 2."""

    @functools.wraps(func)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        try:
            return func(*args, **kwargs)
        except SrfmError as exc:
            raise UserError(str(exc)) from None

    return wrapper  # type: ignore[return-value]


def load_params_option(value: str | None) -> SRFMParams:
    """The SRFM parameters named by a ``--params PRESET|FILE`` option (default preset)."""
    from srfm.models import load_params

    if value is None:
        return SRFMParams()
    if value.endswith(".toml") or Path(value).exists():
        return load_params(value)
    return SRFMParams.preset(value)  # an unknown name raises a ParameterError listing them
