"""``srfm score`` (re-score runs from MCAP logs) and ``srfm view`` (open a recording)."""

from __future__ import annotations

import os
import shlex
import subprocess
import sys
import warnings
from pathlib import Path

import click

from srfm._text import count
from srfm.cli._common import UserError, user_errors
from srfm.errors import LogError

__all__ = ["check_recording", "display_available", "score", "view", "viewer_command"]


@click.command()
@click.argument(
    "paths", nargs=-1, required=True, type=click.Path(path_type=Path), metavar="PATH..."
)
@click.option(
    "--out",
    type=click.Path(path_type=Path),
    default=None,
    help="Also write the tables, CSV files and summary.json here (a new or empty folder, "
    "or one srfm score made).",
)
@click.option(
    "--force", is_flag=True, help="With --out: write into a non-empty folder srfm did not make."
)
@user_errors
def score(paths: tuple[Path, ...], out: Path | None, force: bool) -> None:
    """Recompute every metric and the benchmark tables from MCAP logs alone.

    PATH is a results folder (every .mcap under it is read), a logs folder or .mcap
    files. Each episode is rebuilt from its log, scored with the benchmark's own code
    and compared bit for bit with the metrics logged when it ran. Prints the table
    (the benchmark's table.md); exits with 1 if any episode's metrics differ.
    """
    from srfm._io import check_writable, claim_output_folder, folder_lock
    from srfm.logs import score_logs, write_score_reports
    from srfm.logs.score import check_report_folder
    from srfm.metrics import TABLE_COLUMNS, benchmark_table, to_markdown
    from srfm.models.params import response_model_name

    if out is not None:
        check_report_folder(out)
        check_writable(out, folder=True)
    result = score_logs(paths)  # a bad input names itself before the output is judged
    n = len(result.episodes)
    click.echo(
        f"score: {count(n, 'episode log')}, {count(len(result.scenarios), 'scenario')} × "
        f"{count(len(result.planners), 'planner')}, {count(len(result.seeds), 'seed')} in "
        "every cell",
        err=True,
    )
    for note in result.notes:
        click.echo(f"note: {note}", err=True)
    logged = [e for e in result.episodes if e.online is not None]
    bad = result.mismatches
    if bad:
        for e in bad[:5]:
            click.echo(
                f"MISMATCH {e.path}: recomputed metrics differ from the logged ones", err=True
            )
    elif logged:
        click.echo(f"metrics: all {len(logged)} logged episodes recomputed bit for bit", err=True)
    if result.seeds:
        seeds = set(result.seeds)
        table = benchmark_table(
            [e.metrics for e in result.episodes if e.metrics.seed in seeds],
            scenarios=result.scenarios,
            planners=result.planners,
            seeds=result.seeds,
            reference=result.reference,
            columns=TABLE_COLUMNS,
        )
        click.echo(to_markdown(table, model=response_model_name(result.params)), nl=False)
    if out is not None:
        claim_output_folder(out, kind="score", force=force)
        with folder_lock(out):
            files = write_score_reports(out, result)
        same = " (the benchmark's complete logs: same tables)" if result.complete else ""
        click.echo(f"reports in {out}: {', '.join(files)}{same}", err=True)
    if bad:
        raise SystemExit(1)


def display_available() -> bool:
    """Whether a viewer window can open: macOS, Windows, or an X11/Wayland display."""
    if sys.platform in ("darwin", "win32"):
        return True
    return bool(os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))


def viewer_command(path: Path) -> list[str]:
    """The command that opens ``path`` in the Rerun viewer of this environment."""
    return [sys.executable, "-m", "rerun", str(path)]


def check_recording(path: Path) -> None:
    """Raise :class:`LogError` unless ``path`` is a readable Rerun recording."""
    if not path.exists():
        raise LogError(f"{path}: no such file")
    if not path.is_file():
        raise LogError(f"{path}: not a file")
    try:
        with path.open("rb") as fh:
            magic = fh.read(4)
    except OSError as exc:
        raise LogError(f"{path}: cannot read: {exc.strerror or exc}") from None
    if not magic.startswith(b"RRF"):
        raise LogError(f"{path}: not a Rerun recording (.rrd): no RRF header")
    from rerun.chunk import RrdReader

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            recordings = RrdReader(path).recordings()
    except (RuntimeError, ValueError, OSError) as exc:
        raise LogError(f"{path}: unreadable Rerun recording ({exc})") from None
    if not recordings:
        raise LogError(f"{path}: a Rerun file without a recording")


@click.command()
@click.argument("file", type=click.Path(path_type=Path), metavar="FILE.rrd")
@click.option(
    "--print-command",
    "print_only",
    is_flag=True,
    help="Print the command that opens the viewer instead of running it.",
)
@user_errors
def view(file: Path, print_only: bool) -> None:
    """Open a saved recording in the Rerun viewer.

    Without a display (no DISPLAY or WAYLAND_DISPLAY on Linux), prints the command to
    run where there is one instead.
    """
    check_recording(file)
    command = viewer_command(file)
    text = shlex.join(command)
    if print_only:
        click.echo(text)
        return
    if not display_available():
        click.echo("no display here (DISPLAY and WAYLAND_DISPLAY are unset); to view it, run:")
        click.echo(f"  {text}")
        click.echo(f"or copy the file to a machine with a display and run: rerun {file.name}")
        return
    try:
        code = subprocess.call(command)
    except OSError as exc:
        raise UserError(f"cannot start the Rerun viewer ({exc}); run: {text}") from None
    if code != 0:
        raise SystemExit(code)
