"""The ``srfm`` command line: one module per command group, attached here."""

from __future__ import annotations

import gc
import os
import signal
import sys
import threading
from collections.abc import Sequence
from typing import Any

import click

from srfm._blas import load_cython_blas
from srfm._version import DISTRIBUTION, __version__
from srfm.cli._common import (
    DEBUG_ENV,
    EXIT_INTERRUPTED,
    one_line_usage_error,
    quiet_broken_pipe,
)
from srfm.cli.benchmark import benchmark, report
from srfm.cli.data import ade, data, fit
from srfm.cli.logs import score, view
from srfm.cli.simulate import planners, scenarios, simulate, suites
from srfm.cli.sweep import sweep
from srfm.cli.train import export_policy, train

__all__ = ["main"]


class _Main(click.Group):
    """The ``srfm`` group: every command's exits in one place.

    - a usage error (an unknown option, a bad value) is one line, like every error;
    - a closed stdout (``srfm ... | head``) ends the command quietly (141);
    - Ctrl-C ends any command with 130 and ``interrupted`` (the benchmark and the
      sweep say what they kept); once the command has finished, Ctrl-C is ignored
      while the interpreter shuts down, which would otherwise end the process by the
      signal itself (not 130) after the work was done.
    """

    def main(
        self,
        args: Sequence[str] | None = None,
        prog_name: str | None = None,
        complete_var: str | None = None,
        standalone_mode: bool = True,
        **extra: Any,
    ) -> Any:
        try:
            return super().main(args, prog_name, complete_var, standalone_mode, **extra)
        finally:
            # `srfm ...` as a program (args from sys.argv), not a caller's own process
            # (CliRunner passes args): the interpreter's shutdown, after the work, takes
            # up to a second, during which Python no longer handles SIGINT.
            if args is None and threading.current_thread() is threading.main_thread():
                signal.signal(signal.SIGINT, signal.SIG_IGN)
                # The shutdown's last garbage collection walks every object numba and
                # the libraries made: 0.17 s of `srfm simulate`'s 1.1 s
                # (docs/performance.md, "Commands"). The work is done and every file it
                # wrote is closed, so what is still there is left to the exit.
                gc.freeze()

    def make_context(
        self,
        info_name: str | None,
        args: list[str],
        parent: click.Context | None = None,
        **extra: Any,
    ) -> click.Context:
        try:
            return super().make_context(info_name, args, parent, **extra)
        except click.exceptions.NoArgsIsHelpError:
            raise  # `srfm` alone prints the help
        except click.UsageError as exc:
            raise one_line_usage_error(exc) from None

    def invoke(self, ctx: click.Context) -> Any:
        try:
            return super().invoke(ctx)
        except click.exceptions.NoArgsIsHelpError:
            raise  # `srfm data` alone prints the group's help
        except click.UsageError as exc:
            command = " ".join(filter(None, (ctx.command_path, ctx.invoked_subcommand)))
            raise one_line_usage_error(exc, command) from None
        except BrokenPipeError:
            quiet_broken_pipe()
        except KeyboardInterrupt:
            click.echo("\ninterrupted", err=True)
            sys.exit(EXIT_INTERRUPTED)


@click.group(cls=_Main, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(
    __version__,  # srfm's one version lookup (a tree never installed: 0+unknown, no crash)
    package_name=DISTRIBUTION,
    prog_name="srfm",
    message="%(prog)s, version %(version)s (%(package)s)",
)
@click.option(
    "--debug",
    is_flag=True,
    help=f"Print the traceback behind an error message (also: {DEBUG_ENV}=1).",
)
@click.pass_context
def main(ctx: click.Context, debug: bool) -> None:
    """srfm: simulate crowds with the Social Robot Force Model and measure how much a
    robot makes people deviate from the paths they would have walked.

    Exit codes: 0 success; 1 score mismatch or internal error; 2 user error; 73 cannot
    write the output; 75 results folder in use; 130 interrupted (docs/reliability.md).
    """
    ctx.meta["srfm.debug"] = debug
    _current_folder_importable()
    # numba's BLAS check without importing scipy.linalg: 0.12 s of every command
    # that runs a kernel (srfm._blas).
    load_cython_blas()


def _current_folder_importable() -> None:
    """Modules in the current folder import by name, as under ``python -m``, so that
    ``-p myplanners:Wait`` finds ``./myplanners.py``. The folder goes last on the path:
    a file there never hides an installed package."""
    here = os.getcwd()
    if "" not in sys.path and here not in sys.path:
        sys.path.append(here)


for _command in (
    scenarios,
    suites,
    planners,
    simulate,
    benchmark,
    report,
    sweep,
    score,
    view,
    data,
    fit,
    ade,
    train,
    export_policy,
):
    main.add_command(_command)
