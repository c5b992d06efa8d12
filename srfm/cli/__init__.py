"""The ``srfm`` command line: one module per command group, attached here."""

from __future__ import annotations

import os
import sys
from typing import Any

import click

from srfm.cli._common import DEBUG_ENV, quiet_broken_pipe
from srfm.cli.benchmark import benchmark, report
from srfm.cli.data import ade, data, fit
from srfm.cli.logs import score, view
from srfm.cli.simulate import planners, scenarios, simulate
from srfm.cli.sweep import sweep
from srfm.cli.train import export_policy, train

__all__ = ["main"]


class _Main(click.Group):
    """The ``srfm`` group: a closed stdout (``srfm ... | head``) ends it quietly."""

    def invoke(self, ctx: click.Context) -> Any:
        try:
            return super().invoke(ctx)
        except BrokenPipeError:
            quiet_broken_pipe()


@click.group(cls=_Main, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="srfm")
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


def _current_folder_importable() -> None:
    """Modules in the current folder import by name, as under ``python -m``, so that
    ``-p myplanners:Wait`` finds ``./myplanners.py``. The folder goes last on the path:
    a file there never hides an installed package."""
    here = os.getcwd()
    if "" not in sys.path and here not in sys.path:
        sys.path.append(here)


for _command in (
    scenarios,
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
