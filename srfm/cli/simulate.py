"""``srfm simulate``, ``srfm scenarios``, ``srfm suites`` and ``srfm planners``: one
episode, and what there is to run."""

from __future__ import annotations

import json
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import click

from srfm.cli._common import SEED, UserError, load_params_option, user_errors
from srfm.cli._external import external_options

__all__ = ["planners", "scenarios", "simulate", "suites"]


@click.command()
def scenarios() -> None:
    """List every scenario --scenario accepts by name, with a one-line description and
    whether `srfm benchmark` runs it when no scenario is named (default: yes for the
    paper suite). A scenario TOML file of your own runs by its path; `srfm suites`
    lists the named sets of scenarios."""
    from srfm.scenarios import load_scenario, scenario_names
    from srfm.scenarios.generated import GENERATED_KINDS, GENERATED_PREFIX
    from srfm.scenarios.suites import DEFAULT_SUITE, SUITES

    default = SUITES[DEFAULT_SUITE]
    rows = []
    for name in scenario_names():
        scenario = load_scenario(name)
        rows.append((name, _yes(name in default), scenario.description))
    kinds = ", ".join(GENERATED_KINDS)
    rows.append(
        (
            f"{GENERATED_PREFIX}:[KIND:]SEED",
            "no",
            f"Generated: a new walled layout for every SEED, of a KIND drawn from it or "
            f"given ({kinds}).",
        )
    )
    _table(("scenario", "default", "description"), rows)


@click.command()
def suites() -> None:
    """List the scenario suites `srfm benchmark --suite` accepts: what each is for,
    whether the benchmark runs it when no scenario is named, and its scenarios."""
    from srfm.scenarios.suites import DEFAULT_SUITE, SUITE_DESCRIPTIONS, SUITES

    rows = [
        (name, _yes(name == DEFAULT_SUITE), f"{SUITE_DESCRIPTIONS[name]} [{', '.join(names)}]")
        for name, names in SUITES.items()
    ]
    _table(("suite", "default", "what it is for [its scenarios]"), rows)


@click.command()
def planners() -> None:
    """List every planner -p/--planner accepts by name, the reference planners
    included: what each is for, and whether `srfm benchmark` runs it when no planner is
    named (default); then the two forms of a planner of your own."""
    from srfm.planners import available_planners

    rows = [(p.name, _yes(p.default), p.description) for p in available_planners()]
    rows += [
        (
            "external:NAME",
            "no",
            "a planner in any language, a program that speaks the external planner "
            "protocol, defined with --external NAME=COMMAND (docs/planners-any-language.md)",
        ),
        (
            "MODULE:ATTRIBUTE",
            "no",
            "a planner of your own Python code: a class or a factory in an importable module",
        ),
    ]
    _table(("planner", "default", "what it is for"), rows)


def _yes(flag: bool) -> str:
    return "yes" if flag else "no"


def _table(header: tuple[str, str, str], rows: Sequence[tuple[str, str, str]]) -> None:
    """``rows`` under ``header``, every column but the last padded to its widest cell."""
    widths = [max(len(r[i]) for r in (header, *rows)) for i in range(len(header) - 1)]
    for row in (header, *rows):
        cells = [f"{cell:<{w}}" for cell, w in zip(row, widths, strict=False)]
        click.echo("  ".join([*cells, row[-1]]))


@click.command()
@click.option(
    "--scenario",
    "scenario_name",
    required=True,
    metavar="NAME|FILE",
    help="Built-in scenario name (see `srfm scenarios`) or a scenario TOML file.",
)
@click.option(
    "--seed",
    type=SEED,
    default=0,
    show_default=True,
    help="Episode seed (integer in [0, 2^32 - 1]).",
)
@click.option(
    "--planner",
    "planner_name",
    default="straight",
    show_default=True,
    help="Planner registry name (see `srfm planners`) or module:attribute of your own.",
)
@click.option(
    "--params",
    "params_spec",
    default=None,
    metavar="PRESET|FILE",
    help="SRFM parameters: a preset (agrawal2024, ferrer2013, navwareset2025, "
    "navwareset2026_ttc) or a parameter TOML file. Default: agrawal2024.",
)
@click.option("--json", "as_json", is_flag=True, help="Print the summary as JSON.")
@click.option(
    "--out",
    type=click.Path(file_okay=False, path_type=Path),
    default=None,
    help="Write the episode's logs into OUT/logs/<scenario>/<planner>/: an MCAP file and "
    "a Rerun recording (docs/logging.md). OUT must be new, empty or made by srfm.",
)
@click.option(
    "--force",
    is_flag=True,
    help="With --out: write into a non-empty folder srfm did not make. Run an episode "
    "estimated to take longer than the time limit (24 h, or SRFM_TIME_LIMIT).",
)
@click.option("--no-mcap", is_flag=True, help="With --out: no MCAP file.")
@click.option("--no-rrd", is_flag=True, help="With --out: no Rerun recording.")
@click.option(
    "--mcap-profile",
    type=click.Choice(["full", "compact"]),
    default="full",
    show_default=True,
    help="full: every channel at every step; compact: the benchmark's smaller files.",
)
@click.option("--forces", is_flag=True, help="With --out: force arrows in the recording.")
@user_errors
@external_options
def simulate(
    scenario_name: str,
    seed: int,
    planner_name: str,
    params_spec: str | None,
    as_json: bool,
    out: Path | None,
    no_mcap: bool,
    no_rrd: bool,
    mcap_profile: str,
    forces: bool,
    force: bool,
) -> None:
    """Run one twin episode and print a short summary (and write its logs with --out)."""
    from srfm._io import claim_output_folder
    from srfm.scenarios import load_scenario
    from srfm.sim.budget import check_run, estimate_run
    from srfm.sim.episode import build_planner, check_episode_memory, run_episode

    if out is not None and no_mcap and no_rrd:
        raise UserError("--out with --no-mcap and --no-rrd writes nothing; drop one of them")
    scenario = load_scenario(scenario_name)
    planner = build_planner(planner_name)
    params = load_params_option(params_spec)
    logs = {"mcap": not no_mcap, "rrd": not no_rrd, "forces": forces} if out is not None else {}
    check_episode_memory(scenario, **logs)
    estimate = estimate_run([(scenario, 1)], logs=logs)
    estimate = check_run(
        estimate,
        what=f"an episode of scenario {scenario.name!r}",
        smaller="a shorter simulation.horizon_steps or fewer pedestrians",
        force=force,
    )
    if out is not None:
        claim_output_folder(
            out,
            kind="simulate",
            accept=("benchmark",),
            force=force,
            legacy_markers=("logs",),
            mark=False,
        )
    if estimate.large:
        click.echo(f"estimate: {estimate.describe()}", err=True)
    start = time.perf_counter()
    record = run_episode(scenario, seed, planner, params)
    wall_s = time.perf_counter() - start
    summary = episode_summary(record)
    summary["wall_time_s"] = wall_s
    if out is not None:
        from srfm.logs import LogOptions, write_episode_logs
        from srfm.metrics import episode_metrics

        options = LogOptions(
            mcap=not no_mcap,
            rrd=not no_rrd,
            mcap_profile="full" if mcap_profile == "full" else "compact",
            forces=forces,
        )
        paths = write_episode_logs(
            out, record, episode_metrics(record), scenario=scenario, options=options
        )
        summary["logs"] = [str(p) for p in paths]
    if as_json:
        click.echo(json.dumps(summary, indent=2, sort_keys=True))
        return
    click.echo(format_summary(summary))


def episode_summary(record: Any) -> dict[str, Any]:
    """A small dict of the headline numbers of an episode record."""
    sep = record.twin_separation_m()  # (T + 1, N)
    per_ped_max = sep.max(axis=0)
    import numpy as np

    dist = np.linalg.norm(record.factual_pos - record.robot_pose[:, None, :2], axis=2)
    arrivals: dict[str, int] = {"factual": 0, "counterfactual": 0}
    for twin in arrivals:
        arrivals[twin] = len(
            {e.agent for e in record.events if e.kind == "ped_arrival" and e.twin == twin}
        )
    return {
        "scenario": record.scenario,
        "seed": record.seed,
        "planner": record.planner,
        "outcome": record.outcome,
        "end_step": record.end_step,
        "end_time_s": record.end_step * record.dt_s,
        "horizon_steps": record.horizon_steps,
        "robot_path_length_m": record.robot_path_length_m(),
        "min_robot_distance_m": float(dist.min()),
        "min_robot_clearance_m": float(
            (dist - record.ped_radius[None, :] - record.robot_radius).min()
        ),
        "twin_max_separation_mean_m": float(per_ped_max.mean()),
        "twin_max_separation_max_m": float(per_ped_max.max()),
        "pedestrians": record.n_pedestrians,
        "pedestrians_arrived_factual": arrivals["factual"],
        "pedestrians_arrived_counterfactual": arrivals["counterfactual"],
    }


def format_summary(s: dict[str, Any]) -> str:
    """Human-readable lines for :func:`episode_summary`'s dict."""
    outcome = s["outcome"].replace("_", " ")
    lines = [
        f"scenario   {s['scenario']} (seed {s['seed']}, planner {s['planner']})",
        f"robot      {outcome} at {s['end_time_s']:.2f} s (step {s['end_step']} of "
        f"{s['horizon_steps']}); path {s['robot_path_length_m']:.2f} m",
        f"closest    {s['min_robot_distance_m']:.2f} m centre to centre "
        f"(clearance {s['min_robot_clearance_m']:.2f} m)",
        f"twins      largest factual-counterfactual distance per pedestrian: "
        f"mean {s['twin_max_separation_mean_m']:.3f} m, max {s['twin_max_separation_max_m']:.3f} m",
        f"arrivals   factual {s['pedestrians_arrived_factual']}/{s['pedestrians']}, "
        f"counterfactual {s['pedestrians_arrived_counterfactual']}/{s['pedestrians']}",
    ]
    if "wall_time_s" in s:
        lines.append(
            f"wall time  {s['wall_time_s'] * 1e3:.1f} ms (the first episode in a process "
            "includes loading the compiled kernels)"
        )
    for path in s.get("logs", ()):
        lines.append(f"log        {path}")
    return "\n".join(lines)
