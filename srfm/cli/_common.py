"""Shared pieces of the command line: errors and exit codes, parameter loading.

Exit codes (docs/reliability.md):

- 0: success;
- 1: ``srfm score`` found metrics that differ, or an internal error (a traceback: a bug);
- 2: a user error: a bad option, value or file, a refused output, a user's planner
  that raised (one line naming the planner, the method and the exception);
- 73: an output could not be written (disk full, permission, read-only file system);
- 75: the results folder is in use by another srfm run;
- 130: interrupted (Ctrl-C).

Every error is one line, ``Error: MESSAGE``: srfm's own, and click's usage errors too
(an unknown option, a missing argument, a bad value), which click prints as three lines
(usage, hint, error) and :func:`one_line_usage_error` turns into one.

``srfm --debug COMMAND`` or the environment variable ``SRFM_DEBUG=1`` prints the
traceback behind a one-line error as well (for a user's planner: the traceback inside
the planner's own code).
"""

from __future__ import annotations

import functools
import os
import sys
import traceback
from collections.abc import Callable, Iterable, Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any, Final, Generic, TypeVar

import click

from srfm.errors import FolderInUseError, SrfmError, UserCodeError, WriteError

if TYPE_CHECKING:
    from srfm.models.params import SRFMParams

__all__ = [
    "DEBUG_ENV",
    "EXIT_INTERRUPTED",
    "EXIT_IN_USE",
    "EXIT_USER",
    "EXIT_WRITE",
    "SEED",
    "UserError",
    "debug_enabled",
    "load_params_option",
    "on_terminal",
    "one_line_usage_error",
    "progressbar",
    "user_errors",
]

F = TypeVar("F", bound=Callable[..., Any])
V = TypeVar("V")

DEBUG_ENV: Final = "SRFM_DEBUG"
EXIT_USER: Final = 2
EXIT_WRITE: Final = 73  # sysexits EX_CANTCREAT
EXIT_IN_USE: Final = 75  # sysexits EX_TEMPFAIL: try again later
EXIT_INTERRUPTED: Final = 130  # 128 + SIGINT, as a shell reports a process ended by Ctrl-C


class UserError(click.ClickException):
    """A user mistake: printed as one line, exit code 2 (or ``exit_code`` given)."""

    exit_code = EXIT_USER

    def __init__(self, message: str, exit_code: int = EXIT_USER) -> None:
        super().__init__(message)
        self.exit_code = exit_code  # type: ignore[misc]  # click declares a class default


def one_line_usage_error(exc: click.UsageError, command: str | None = None) -> UserError:
    """Click's usage error as srfm's one line (``Error: MESSAGE (see 'srfm CMD --help')``),
    exit code 2, instead of click's usage line, hint line and error line. ``command``
    names the command when click's error does not (some parser errors)."""
    path = exc.ctx.command_path if exc.ctx is not None else command
    where = f" (see '{path} --help')" if path else ""
    return UserError(f"{exc.format_message()}{where}", exc.exit_code)


class _Seed(click.ParamType[int, Any]):
    """An episode seed on the command line: plain ASCII decimal digits, in [0, 2^32 - 1]
    (``int()`` would also take ``1_000`` and ``٣``)."""

    name = "integer"

    def convert(self, value: Any, param: click.Parameter | None, ctx: click.Context | None) -> int:
        from srfm._validate import MAX_SEED, decimal

        if isinstance(value, int) and not isinstance(value, bool):  # a default
            number: int | None = value
        else:
            number = decimal(str(value))
        if number is None or not 0 <= number <= MAX_SEED:
            self.fail(
                f"{value!r} is not a seed: plain decimal digits, in [0, {MAX_SEED}] (2^32 - 1)",
                param,
                ctx,
            )
        return number


SEED: Final = _Seed()
"""The click type of every ``--seed`` option."""


def debug_enabled() -> bool:
    """``srfm --debug`` was given, or ``SRFM_DEBUG`` is set to something other than 0."""
    if os.environ.get(DEBUG_ENV, "").strip() not in ("", "0"):
        return True
    ctx = click.get_current_context(silent=True)
    return bool(ctx is not None and ctx.find_root().meta.get("srfm.debug"))


def _exit_code(exc: BaseException) -> int:
    if isinstance(exc, FolderInUseError):
        return EXIT_IN_USE
    if isinstance(exc, WriteError):
        return EXIT_WRITE
    return EXIT_USER


def _os_message(exc: OSError) -> str:
    name = f"{exc.filename}: " if exc.filename else ""
    return f"{name}{exc.strerror or exc}"


def user_errors(func: F) -> F:
    """Turn srfm's own errors and operating-system errors into one-line messages.

    :class:`SrfmError` exits with 2 (73 for a :class:`WriteError`, 75 for a
    :class:`FolderInUseError`); any other :class:`OSError` (e.g. raised by a library
    while writing) with 73. With ``--debug`` the traceback is printed first.
    """

    @functools.wraps(func)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        try:
            return func(*args, **kwargs)
        except (SrfmError, OSError) as exc:
            if isinstance(exc, BrokenPipeError):
                raise
            debug = debug_enabled()
            if debug:
                if isinstance(exc, UserCodeError) and exc.traceback_text:
                    click.echo(exc.traceback_text.rstrip(), err=True)
                else:
                    click.echo("".join(traceback.format_exception(exc)).rstrip(), err=True)
            if isinstance(exc, SrfmError):
                message = str(exc)
                code = _exit_code(exc)
            else:
                message = f"cannot complete: {_os_message(exc)}"
                code = EXIT_WRITE
            if isinstance(exc, UserCodeError) and not debug:
                message += f" (srfm --debug, or {DEBUG_ENV}=1, shows its traceback)"
            raise UserError(message, code) from None

    return wrapper  # type: ignore[return-value]


def load_params_option(value: str | None) -> SRFMParams:
    """The SRFM parameters named by a ``--params PRESET|FILE`` option (default preset)."""
    from srfm._io import MAX_TOML_BYTES, read_input_bytes
    from srfm.errors import ParameterError
    from srfm.models.params import SRFMParams, load_params

    if value is None:
        return SRFMParams()
    if value.endswith(".toml") or os.path.lexists(value):
        # A FIFO or a device must not hang or exhaust memory (load_params reads it).
        read_input_bytes(
            Path(value), max_bytes=MAX_TOML_BYTES, error=ParameterError, what="parameter file"
        )
        return load_params(value)
    return SRFMParams.preset(value)  # an unknown name raises a ParameterError listing them


def quiet_broken_pipe() -> None:
    """After stdout's reader went away (``srfm ... | head``): exit quietly, 141 like a
    shell, instead of a ``BrokenPipeError`` traceback."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError):
        pass
    sys.exit(141)


class _NoBar(Generic[V]):
    """The progress bar's interface, showing nothing."""

    def __init__(self, iterable: Iterable[V] | None) -> None:
        self._iterable = iterable

    def __enter__(self) -> _NoBar[V]:
        return self

    def __exit__(self, *exc: object) -> None:
        return None

    def __iter__(self) -> Iterator[V]:
        return iter(self._iterable if self._iterable is not None else ())

    def update(self, n_steps: int, current_item: V | None = None) -> None:
        """Nothing to show."""


def progressbar(
    iterable: Iterable[V] | None = None, *, length: int | None = None, label: str, **options: Any
) -> Any:
    """click's progress bar on stderr when stderr is a terminal; otherwise (a file, a
    pipe, CI logs) an object with the same interface that prints nothing, not even the
    label click would print once."""
    if not _is_terminal(sys.stderr):
        return _NoBar(iterable)
    return click.progressbar(iterable, length=length, label=label, file=sys.stderr, **options)


def on_terminal() -> bool:
    """Whether stderr is a terminal (progress bars are shown)."""
    return _is_terminal(sys.stderr)


def _is_terminal(stream: Any) -> bool:
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError):  # replaced or closed
        return False
