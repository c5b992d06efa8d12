"""``srfm benchmark``: scenarios × planners × seeds into a results folder."""

from __future__ import annotations

import contextlib
import re
import shlex
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

from srfm._text import count, plain
from srfm.cli._common import EXIT_INTERRUPTED, load_params_option, progressbar, user_errors
from srfm.cli._external import external_options

if TYPE_CHECKING:
    from srfm.benchmark import BenchmarkRequest, BenchmarkSummary, ResponseModels
    from srfm.logs import EpisodeLogger
    from srfm.sim.budget import RunEstimate

__all__ = ["benchmark", "report"]


_SEED_RE = re.compile(r"(\d{1,20})(?:-(\d{1,20}))?", re.ASCII)


def _parse_seeds(text: str) -> list[int]:
    """``"0-99"``, ``"0,3,7"`` or a mix such as ``"0-9,20"``: at most
    :data:`~srfm.benchmark.MAX_SEEDS` seeds in [0, 2^32 - 1]; the count is checked from
    the ranges' bounds before any list is built, so ``0-99999999`` is refused at once."""
    from srfm._validate import MAX_SEED
    from srfm.benchmark import MAX_SEEDS

    ranges: list[tuple[int, int]] = []
    count = 0
    for part in text.split(","):
        part = part.strip()
        match = _SEED_RE.fullmatch(part)
        a = int(match.group(1)) if match else 0
        b = int(match.group(2)) if match and match.group(2) is not None else a
        if match is None or b < a:
            raise click.BadParameter(
                f"{part!r} is not a seed or a range like 0-99", param_hint="--seeds"
            )
        if b > MAX_SEED:
            raise click.BadParameter(
                f"seeds must be in [0, {MAX_SEED}] (2^32 - 1), got {plain(part)}",
                param_hint="--seeds",
            )
        count += b - a + 1
        if count > MAX_SEEDS:
            raise click.BadParameter(
                f"{text!r} asks for more than {MAX_SEEDS} seeds", param_hint="--seeds"
            )
        ranges.append((a, b))
    return [seed for a, b in ranges for seed in range(a, b + 1)]


def _parse_rrd_seeds(text: str) -> int | None:
    """``"all"`` (None) or a non-negative count."""
    from srfm._validate import decimal

    if text.strip().lower() == "all":
        return None
    value = decimal(text)
    if value is None:
        raise click.BadParameter(
            f"{text!r} is not a number of seeds (0, 1, 2, ...) or 'all'", param_hint="--rrd-seeds"
        )
    return value


def _log_writer(
    request: BenchmarkRequest,
    out: Path,
    logs: bool,
    mcap: bool,
    mcap_profile: str,
    rrd_seeds: str,
    forces: bool,
) -> EpisodeLogger | None:
    """The per-episode writer the options ask for (None: no logs)."""
    from srfm.logs import EpisodeLogger, LogOptions

    rrd_count = _parse_rrd_seeds(rrd_seeds)
    if not logs or (not mcap and rrd_count == 0):
        return None
    compact = mcap_profile == "compact"
    options = LogOptions(
        mcap=mcap,
        mcap_profile="compact" if compact else "full",
        rrd=rrd_count != 0,
        rrd_seeds=rrd_count,
        forces=forces,
        share_counterfactual=compact,
    )
    # Stale temporaries are removed by run_benchmark, under the folder's lock: never
    # here, where they may belong to another run still in progress.
    return EpisodeLogger.create(
        options,
        scenarios=request.scenarios,
        planners=request.planners,
        seeds=request.seeds,
        reference=request.reference,
    )


def _logs_line(out: Path) -> str:
    """What OUT/logs holds: file counts and sizes by kind."""
    from srfm.logs import LOGS_DIR
    from srfm.logs._writer import COUNTERFACTUAL_DIR

    sizes: dict[str, list[int]] = {"episode .mcap": [], "counterfactual .mcap": [], ".rrd": []}
    root = out / LOGS_DIR
    if root.is_dir():
        for path in root.rglob("*"):
            if path.name.startswith(".") or not path.is_file():
                continue
            if path.suffix == ".rrd":
                sizes[".rrd"].append(path.stat().st_size)
            elif path.suffix == ".mcap":
                kind = "counterfactual" if path.parent.name == COUNTERFACTUAL_DIR else "episode"
                sizes[f"{kind} .mcap"].append(path.stat().st_size)
    parts = [f"{len(v)} {k} files ({sum(v) / 1e6:.1f} MB)" for k, v in sizes.items() if v]
    return f"logs in {root}: " + (", ".join(parts) if parts else "none")


def _split(values: tuple[str, ...]) -> list[str]:
    return [v.strip() for value in values for v in value.split(",") if v.strip()]


@click.command()
@click.option(
    "--scenario",
    "-s",
    "scenarios",
    multiple=True,
    metavar="NAME|FILE",
    help="Scenario name or TOML file; repeat or separate with commas. "
    "Default: the five evaluation scenarios (--suite paper).",
)
@click.option(
    "--suite",
    default=None,
    metavar="NAME",
    help="A named set of built-in scenarios instead of --scenario: paper (the five "
    "evaluation scenarios, the default), francis (17 scenarios after Francis et al. "
    "2023: walls, doors, corners, rooms), navwareset (the NavWareSet room's five "
    "layouts), flows (pedestrians entering during the run), all (paper, francis, "
    "navwareset and flows), discriminative (the scenarios of all where planners can "
    "be told apart, chosen on seeds 1000-1099: docs/benchmark.md) or large (crowds of "
    "300-400 pedestrians).",
)
@click.option(
    "--planner",
    "-p",
    "planners",
    multiple=True,
    metavar="NAME",
    help="Planner name; repeat or separate with commas. Default: every registered "
    "planner except `recorded` (which needs a scenario with a robot recording).",
)
@click.option(
    "--seeds",
    default=None,
    metavar="RANGE",
    help="Seeds, e.g. 0-99 or 0,5,9. Default: 0-99 (0-2 with --quick).",
)
@click.option("--quick", is_flag=True, help="A small subset that runs in seconds: seeds 0-2 only.")
@click.option(
    "--out",
    type=click.Path(file_okay=False, path_type=Path),
    default=Path("results"),
    show_default=True,
    help="Results folder; an interrupted run there is resumed. It must be new, empty or "
    "made by srfm benchmark; one run at a time.",
)
@click.option(
    "--force",
    is_flag=True,
    help="Write into a non-empty folder srfm did not make; run a request that is "
    "estimated to need more memory than this machine has or longer than the time "
    "limit (24 h, or SRFM_TIME_LIMIT).",
)
@click.option(
    "--jobs",
    "-j",
    type=click.IntRange(min=1),
    default=None,
    help="Worker processes. Default: one per CPU.",
)
@click.option(
    "--executor",
    type=click.Choice(["process", "dask"]),
    default=None,
    help="Where the episodes run: 'process' (a local process pool, the default) or "
    "'dask' (a Dask LocalCluster of --jobs workers, or the cluster of --scheduler / "
    "--scheduler-file). Same results, byte for byte. Needs the dask extra for 'dask'.",
)
@click.option(
    "--scheduler",
    default=None,
    metavar="ADDRESS",
    help="A running Dask scheduler, e.g. tcp://HOST:8786 (implies --executor dask).",
)
@click.option(
    "--scheduler-file",
    type=click.Path(path_type=Path, dir_okay=False),
    default=None,
    help="The scheduler file of a running Dask scheduler (implies --executor dask).",
)
@click.option(
    "--params",
    "params_spec",
    default=None,
    metavar="PRESET|FILE[,...]",
    help="SRFM parameters: a preset or a parameter TOML file. Default: agrawal2024. "
    "Several, comma-separated (agrawal2024,navwareset2026_ttc,my.toml): the same episodes "
    "under each response model (the first is the folder's own; the others in "
    "OUT/models/NAME/) and which orderings of planners hold under all (robustness.md).",
)
@click.option(
    "--reference",
    default=None,
    metavar="PLANNER",
    help="Planner the others are tested against. Default: td3-srfm when it runs.",
)
@click.option(
    "--crowd-substeps",
    type=click.IntRange(min=1, max=64),
    default=None,
    metavar="N",
    help="Step the crowd N times per control step (dt / N each), the planner's control "
    "rate unchanged: the convergence check of docs/metrics.md. Default: each "
    "scenario's own (1, the paper's scheme, for every built-in one).",
)
@click.option("--no-figures", is_flag=True, help="Skip the PNG figures.")
@click.option(
    "--logs/--no-logs",
    default=True,
    show_default=True,
    help="Write episode logs into OUT/logs (docs/logging.md).",
)
@click.option("--mcap/--no-mcap", default=True, show_default=True, help="With --logs: MCAP files.")
@click.option(
    "--mcap-profile",
    type=click.Choice(["compact", "full"]),
    default="compact",
    show_default=True,
    help="compact: every episode's exact trajectories, the Foxglove scene at 3 Hz, the "
    "counterfactual crowd stored once per scenario and seed; full: everything, per step.",
)
@click.option(
    "--rrd-seeds",
    default="1",
    show_default=True,
    metavar="N|all",
    help="With --logs: a Rerun recording for the first N seeds of each scenario × planner "
    "cell (0: none).",
)
@click.option("--forces", is_flag=True, help="Force arrows in the Rerun recordings.")
@click.option(
    "--param-draws",
    type=click.IntRange(min=1, max=1000),
    default=None,
    metavar="K",
    help="Also run every episode under K parameter sets drawn from --param-draws-from, "
    "each into OUT/draws/draw-NNN, and report each planner's rank probabilities and "
    "deviation interval over the draws (rankings.md, report.html; docs/benchmark.md).",
)
@click.option(
    "--param-draws-from",
    default="sensitivity",
    show_default=True,
    metavar="sensitivity|wide|FILE",
    help="The distribution of the draws: 'sensitivity' (A_r ~ U(3.965, 15.86), "
    "B_r ~ U(0.5, 1.5)), 'wide' (A_r ~ log-U(0.25, 15.86), B_r ~ log-U(0.1, 1.5): "
    "from below the real-data fit to the top of the sensitivity ranges) or a CSV file "
    "of parameter sets (header: parameter names), e.g. the bootstrap replicates of a fit.",
)
@click.option(
    "--param-draws-seed",
    type=click.IntRange(min=0),
    default=0,
    show_default=True,
    help="Seed of the parameter draws.",
)
@user_errors
@external_options
def benchmark(
    scenarios: tuple[str, ...],
    suite: str | None,
    planners: tuple[str, ...],
    seeds: str | None,
    quick: bool,
    out: Path,
    jobs: int | None,
    executor: str | None,
    scheduler: str | None,
    scheduler_file: Path | None,
    params_spec: str | None,
    reference: str | None,
    crowd_substeps: int | None,
    no_figures: bool,
    logs: bool,
    mcap: bool,
    mcap_profile: str,
    rrd_seeds: str,
    forces: bool,
    force: bool,
    param_draws: int | None,
    param_draws_from: str,
    param_draws_seed: int,
) -> None:
    """Run scenarios × planners × seeds of twin episodes and write tables and figures.

    Writes into --out: report.html (the results page: tables, figures, outcomes, links
    to every log, the manifest), episodes/ (one metrics file per episode),
    episodes.csv and pedestrians.csv (and .parquet copies), table.md and table.tex
    (the paper's Table 3 layout), outcomes.md, table_extended.md and .tex (every
    metric), summary.json, figures/ and manifest.json, and the episode logs in logs/
    (by default an MCAP file for every episode and a Rerun recording for the first
    seed of each cell; `srfm score OUT` re-scores them). Re-running on the same folder
    skips finished episodes (their logs are not rewritten). With --param-draws K, the
    episodes also run under K parameter draws (OUT/draws/, param_draws.json) and
    rankings.md holds each planner's rank probabilities over them.
    """
    from srfm.benchmark import BenchmarkRequest, draw_params, run_benchmark

    remote = scheduler is not None or scheduler_file is not None
    if executor == "process" and remote:
        raise click.UsageError("--scheduler and --scheduler-file need --executor dask")
    executor = executor or ("dask" if remote else "process")
    names = _split(scenarios) or None
    if suite is not None:
        from srfm.scenarios.suites import SUITES

        if suite not in SUITES:
            known = ", ".join(SUITES)
            raise click.BadParameter(
                f"unknown suite {suite!r}; known: {known}", param_hint="--suite"
            )
        if names:
            raise click.UsageError("give --suite or --scenario, not both")
        names = list(SUITES[suite])
    models = _response_models(params_spec)
    request = BenchmarkRequest.create(
        scenarios=names,
        planners=_split(planners) or None,
        seeds=_parse_seeds(seeds) if seeds is not None else None,
        params=models.params[0] if models else load_params_option(params_spec),
        reference=reference,
        quick=quick,
        crowd_substeps=crowd_substeps,
    )
    draws = (
        None
        if param_draws is None
        else draw_params(
            request.params, param_draws, seed=param_draws_seed, source=param_draws_from
        )
    )
    writer = _log_writer(request, out, logs, mcap, mcap_profile, rrd_seeds, forces)
    cells = len(request.scenarios) * len(request.planners) * len(request.seeds)
    total = cells * (1 + (param_draws or 0) + (len(models.names) - 1 if models else 0))
    bar: Any = None
    # Nothing is printed before every check has passed (run_benchmark calls start):
    # a mistake is one line. Ctrl-C, up to the last line, keeps what is done.
    try:
        with contextlib.ExitStack() as stack:

            def start(estimate: RunEstimate) -> None:
                nonlocal bar
                click.echo(
                    f"benchmark: {count(len(request.scenarios), 'scenario')} × "
                    f"{count(len(request.planners), 'planner')} × "
                    f"{count(len(request.seeds), 'seed')} = {count(cells, 'episode')}"
                    + (
                        f", again under {count(len(draws.params), 'parameter draw')}"
                        if draws
                        else ""
                    )
                    + (f", under {count(len(models.names), 'response model')}" if models else "")
                    + f" -> {out}",
                    err=True,
                )
                if estimate.large:
                    click.echo(f"estimate: {estimate.describe()}", err=True)
                bar = stack.enter_context(progressbar(length=total, label="episodes"))

            def advance(n: int) -> None:
                bar.update(n)

            summary = run_benchmark(
                request,
                out,
                jobs=jobs,
                on_start=start,
                on_progress=advance,
                figures=not no_figures,
                writer=writer,
                force=force,
                command=shlex.join(["srfm", *sys.argv[1:]]),
                executor=executor,
                scheduler=scheduler,
                scheduler_file=scheduler_file,
                param_draws=draws,
                models=models,
            )
        _print_summary(summary, out, jobs, writer is not None)
    except KeyboardInterrupt:
        done = len(list((out / "episodes").rglob("seed-*.json")))
        click.echo(
            f"\ninterrupted: {done} finished episodes are kept in {out}; run the same "
            "command again to resume",
            err=True,
        )
        sys.exit(EXIT_INTERRUPTED)


def _response_models(spec: str | None) -> ResponseModels | None:
    """The response models of ``--params A,B,...`` (None for one model): each a preset
    or a parameter file, named by the preset or the file's stem."""
    import os

    from srfm.benchmark import ResponseModels

    if spec is None or "," not in spec or os.path.lexists(spec):
        return None
    parts = [part.strip() for part in spec.split(",")]
    if any(not part for part in parts):
        raise click.BadParameter(f"an empty name in {spec!r}", param_hint="--params")
    names = [Path(part).stem if part.endswith(".toml") else part for part in parts]
    return ResponseModels(
        names=tuple(names), params=tuple(load_params_option(part) for part in parts)
    )


def _print_summary(summary: BenchmarkSummary, out: Path, jobs: int | None, logs: bool) -> None:
    """What a finished benchmark prints: notes, timing, Table 3, the files."""
    if summary.resimulated:
        shown = ", ".join(summary.resimulated[:3])
        more = f" and {len(summary.resimulated) - 3} more" if len(summary.resimulated) > 3 else ""
        click.echo(
            f"note: {len(summary.resimulated)} damaged episode file(s) simulated again: "
            f"{shown}{more}",
            err=True,
        )
    if jobs is not None and summary.jobs < jobs:
        click.echo(
            f"note: {summary.jobs} worker(s) instead of {jobs}: more episodes side by side "
            "would not fit in memory",
            err=True,
        )
    click.echo(
        f"simulated {summary.simulated} of {summary.episodes} episodes in "
        f"{summary.wall_time_s:.1f} s ({summary.episodes - summary.simulated} were already done)",
        err=True,
    )
    click.echo((out / "table.md").read_text(encoding="utf-8"))
    click.echo(f"results in {out}: " + ", ".join(summary.files))
    if "report.html" in summary.files:
        click.echo(f"results page: {out / 'report.html'} (open it in a browser)")
    if logs:
        click.echo(_logs_line(out), err=True)


@click.command()
@click.argument("folder", type=click.Path(file_okay=False, exists=True, path_type=Path))
@user_errors
def report(folder: Path) -> None:
    """Rebuild FOLDER/report.html, the results page of a benchmark results folder,
    from the folder's own files (tables, figures, episode list, logs, manifest).

    The page opens offline: every image and link is a path inside FOLDER.
    """
    from srfm.benchmark import write_report

    path = write_report(folder)
    click.echo(f"wrote {path}")
