"""``srfm sweep SPEC.toml`` (run a sweep) and ``srfm sweep report DIR`` (analyse it)."""

from __future__ import annotations

import contextlib
import sys
import time
from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

from srfm._text import count
from srfm.cli._common import EXIT_INTERRUPTED, progressbar, user_errors

if TYPE_CHECKING:
    from srfm.sim.budget import RunEstimate

__all__ = ["sweep"]


class _SweepGroup(click.Group):
    """``srfm sweep SPEC.toml ...`` is ``srfm sweep run SPEC.toml ...``; ``srfm sweep
    report DIR`` is the report."""

    def parse_args(self, ctx: click.Context, args: list[str]) -> list[str]:
        if args and args[0] not in self.commands and args[0] not in ("-h", "--help"):
            args = ["run", *args]
        return super().parse_args(ctx, args)


@click.group(cls=_SweepGroup)
def sweep() -> None:
    """Sweeps over model parameters, crowds, scenarios and planners.

    \b
    srfm sweep SPEC.toml --out DIR      run (or resume) the sweep of SPEC.toml
    srfm sweep report DIR               figures and ranking stability of a sweep
    """


class _Rate:
    """The progress bar's text after the bar: this run's episodes per second and the
    time left at that rate (episodes found done when it started do not count)."""

    def __init__(self, total: int) -> None:
        self.total = total
        self.start = time.monotonic()
        self.done = 0
        self.present = 0

    def text(self, _item: Any) -> str:
        elapsed = time.monotonic() - self.start
        if elapsed <= 0 or not self.done:
            return ""
        rate = self.done / elapsed
        left = (self.total - self.present - self.done) / rate
        hours, rest = divmod(int(left), 3600)
        return f"{rate:.1f} ep/s, {hours}:{rest // 60:02d}:{rest % 60:02d} left"


@sweep.command("run")
@click.argument("spec_file", metavar="SPEC.toml", type=click.Path(dir_okay=False, path_type=Path))
@click.option(
    "--out",
    type=click.Path(file_okay=False, path_type=Path),
    required=True,
    help="Results folder (a Parquet dataset in OUT/data); an interrupted sweep there is resumed.",
)
@click.option(
    "--force",
    is_flag=True,
    help="Write into a non-empty folder srfm did not make; run a sweep that is estimated "
    "to need more memory than this machine has or longer than the time limit (24 h, or "
    "SRFM_TIME_LIMIT).",
)
@click.option(
    "--jobs", "-j", type=click.IntRange(min=1), default=1, show_default=True, help="Workers."
)
@click.option(
    "--executor",
    type=click.Choice(["process", "dask"]),
    default=None,
    help="'process' (a local process pool, the default) or 'dask' (a Dask LocalCluster "
    "of --jobs workers, or the cluster of --scheduler / --scheduler-file).",
)
@click.option("--scheduler", default=None, metavar="ADDRESS", help="A running Dask scheduler.")
@click.option(
    "--scheduler-file",
    type=click.Path(path_type=Path, dir_okay=False),
    default=None,
    help="The scheduler file of a running Dask scheduler.",
)
@user_errors
def run(
    spec_file: Path,
    out: Path,
    force: bool,
    jobs: int,
    executor: str | None,
    scheduler: str | None,
    scheduler_file: Path | None,
) -> None:
    """Run the sweep of SPEC.toml into --out: one Parquet row per episode, one file per
    task, written atomically; re-running the command finishes only what is missing."""
    from srfm.sweep import load_spec, run_sweep

    remote = scheduler is not None or scheduler_file is not None
    if executor == "process" and remote:
        raise click.UsageError("--scheduler and --scheduler-file need --executor dask")
    spec = load_spec(spec_file)
    rate = _Rate(spec.episodes)
    bar: Any = None
    first = True
    # Nothing is printed before every check has passed (run_sweep calls start): a
    # mistake is one line. Ctrl-C, up to the last line, keeps the finished partitions.
    try:
        with contextlib.ExitStack() as stack:

            def start(estimate: RunEstimate) -> None:
                nonlocal bar
                click.echo(
                    f"sweep {spec.name}: {count(len(spec.cells), 'cell')} × "
                    f"{count(len(spec.scenarios), 'scenario')} × "
                    f"{count(len(spec.planners), 'planner')} × "
                    f"{count(len(spec.seeds), 'seed')} = {count(spec.episodes, 'episode')} "
                    f"-> {out}",
                    err=True,
                )
                if estimate.large:
                    click.echo(f"estimate: {estimate.describe()}", err=True)
                bar = stack.enter_context(
                    progressbar(
                        length=spec.episodes,
                        label="episodes",
                        show_pos=True,
                        show_eta=False,
                        item_show_func=rate.text,
                    )
                )

            def advance(n: int) -> None:
                nonlocal first
                if first:  # the episodes already there: not part of this run's rate
                    first = False
                    rate.start = time.monotonic()
                    rate.present = n
                else:
                    rate.done += n
                bar.update(n, None)

            summary = run_sweep(
                spec,
                out,
                executor=executor or ("dask" if remote else "process"),
                jobs=jobs,
                scheduler=scheduler,
                scheduler_file=scheduler_file,
                on_start=start,
                on_progress=advance,
                force=force,
            )
        if summary.rewritten:
            click.echo(f"note: {len(summary.rewritten)} damaged partition(s) run again", err=True)
        click.echo(
            f"simulated {summary.simulated} of {summary.episodes} episodes in "
            f"{summary.wall_time_s:.1f} s; dataset: {out / 'data'} ({summary.partitions} files)"
        )
    except KeyboardInterrupt:
        click.echo(
            f"\ninterrupted: finished partitions are kept in {out}; run the same "
            "command again to resume",
            err=True,
        )
        sys.exit(EXIT_INTERRUPTED)


@sweep.command("report")
@click.argument("folder", type=click.Path(file_okay=False, exists=True, path_type=Path))
@click.option(
    "--metric",
    default="frechet_m",
    show_default=True,
    help="The metric the planners are ranked by (lower is better).",
)
@user_errors
def report(folder: Path, metric: str) -> None:
    """Figures (each planner's Fréchet deviation and success against each factor,
    with 95 % confidence bands) and the stability of the planner ranking across the
    design (Kendall's tau, and where the ranking flips), into FOLDER/report/."""
    from srfm.sweep.report import write_sweep_report

    files = write_sweep_report(folder, metric=metric)
    click.echo(f"wrote {', '.join(str(f) for f in files)}")
