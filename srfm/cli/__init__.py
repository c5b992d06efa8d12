"""The ``srfm`` command line: one module per command group, attached here."""

from __future__ import annotations

import click

from srfm.cli.benchmark import benchmark
from srfm.cli.data import ade, data, fit
from srfm.cli.logs import score, view
from srfm.cli.simulate import planners, scenarios, simulate
from srfm.cli.train import export_policy, train

__all__ = ["main"]


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="srfm")
def main() -> None:
    """srfm: simulate crowds with the Social Robot Force Model and measure how much a
    robot makes people deviate from the paths they would have walked."""


for _command in (
    scenarios,
    planners,
    simulate,
    benchmark,
    score,
    view,
    data,
    fit,
    ade,
    train,
    export_policy,
):
    main.add_command(_command)
