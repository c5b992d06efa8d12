"""``srfm benchmark``: scenarios × planners × seeds into a results folder."""

from __future__ import annotations

import sys
from pathlib import Path

import click

from srfm._cli_common import load_params_option, user_errors

__all__ = ["benchmark"]


def _parse_seeds(text: str) -> list[int]:
    """``"0-99"``, ``"0,3,7"`` or a mix such as ``"0-9,20"``."""
    seeds: list[int] = []
    for part in text.split(","):
        part = part.strip()
        lo, sep, hi = part.partition("-")
        try:
            if sep:
                a, b = int(lo), int(hi)
                if b < a:
                    raise ValueError
                seeds.extend(range(a, b + 1))
            else:
                seeds.append(int(part))
        except ValueError:
            raise click.BadParameter(
                f"{part!r} is not a seed or a range like 0-99", param_hint="--seeds"
            ) from None
    if any(s < 0 for s in seeds):
        raise click.BadParameter(f"seeds must be non-negative, got {text!r}", param_hint="--seeds")
    return seeds


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
    "Default: the five evaluation scenarios.",
)
@click.option(
    "--planner",
    "-p",
    "planners",
    multiple=True,
    metavar="NAME",
    help="Planner name; repeat or separate with commas. Default: every registered planner.",
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
    help="Results folder; an interrupted run there is resumed.",
)
@click.option(
    "--jobs",
    "-j",
    type=click.IntRange(min=1),
    default=None,
    help="Worker processes. Default: one per CPU.",
)
@click.option(
    "--params",
    "params_spec",
    default=None,
    metavar="PRESET|FILE",
    help="SRFM parameters: a preset or a parameter TOML file. Default: agrawal2024.",
)
@click.option(
    "--reference",
    default=None,
    metavar="PLANNER",
    help="Planner the others are tested against. Default: td3-srfm when it runs.",
)
@click.option("--no-figures", is_flag=True, help="Skip the PNG figures.")
@user_errors
def benchmark(
    scenarios: tuple[str, ...],
    planners: tuple[str, ...],
    seeds: str | None,
    quick: bool,
    out: Path,
    jobs: int | None,
    params_spec: str | None,
    reference: str | None,
    no_figures: bool,
) -> None:
    """Run scenarios × planners × seeds of twin episodes and write tables and figures.

    Writes into --out: episodes/ (one metrics file per episode), episodes.csv,
    pedestrians.csv, table.md and table.tex (the paper's Table 3 layout),
    outcomes.md, summary.json, figures/ and manifest.json. Re-running on the same
    folder skips finished episodes.
    """
    from srfm.benchmark import BenchmarkRequest, run_benchmark

    request = BenchmarkRequest.create(
        scenarios=_split(scenarios) or None,
        planners=_split(planners) or None,
        seeds=_parse_seeds(seeds) if seeds is not None else None,
        params=load_params_option(params_spec),
        reference=reference,
        quick=quick,
    )
    total = len(request.scenarios) * len(request.planners) * len(request.seeds)
    click.echo(
        f"benchmark: {len(request.scenarios)} scenarios × {len(request.planners)} planners "
        f"× {len(request.seeds)} seeds = {total} episodes -> {out}",
        err=True,
    )
    with click.progressbar(
        length=total, label="episodes", file=sys.stderr
    ) as bar:

        def advance(n: int) -> None:
            bar.update(n)

        summary = run_benchmark(
            request, out, jobs=jobs, on_progress=advance, figures=not no_figures
        )
    click.echo(
        f"simulated {summary.simulated} of {summary.episodes} episodes in "
        f"{summary.wall_time_s:.1f} s ({summary.episodes - summary.simulated} were already done)",
        err=True,
    )
    click.echo((out / "table.md").read_text(encoding="utf-8"))
    click.echo(f"results in {out}: " + ", ".join(summary.files))
