"""``srfm data convert|scenario|info``, ``srfm fit`` and ``srfm ade``: datasets, fitting,
evaluation.

Hooked into the ``srfm`` group at the end of :mod:`srfm.cli`; shared pieces come from
:mod:`srfm.cli._common`, so there is no import cycle.
"""

from __future__ import annotations

import json
import math
import time
import warnings
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any, TypeVar

import click

from srfm._text import plain
from srfm.cli._common import load_params_option, progressbar, user_errors
from srfm.errors import DatasetError
from srfm.models._forms import ROBOT_FORMS

F = TypeVar("F", bound=Callable[..., Any])

DATASETS = ("jrdb", "eth-ucy", "navwareset")


def _echo_warnings(caught: Sequence[warnings.WarningMessage]) -> None:
    for w in caught:
        click.echo(f"warning: {w.message}", err=True)


# --------------------------------------------------------------------------------------
# srfm data


@click.group("data")
def data() -> None:
    """Convert datasets to srfm's MCAP layout and inspect the result."""


def _parse_dt(values: Sequence[str]) -> tuple[float | None, dict[str, float]]:
    from srfm._validate import MAX_DURATION_S

    default: float | None = None
    per_file: dict[str, float] = {}
    for item in values:
        key, sep, text = item.rpartition("=")
        try:
            value = float(text)
        except ValueError:
            raise DatasetError(f"--dt expects SECONDS or FILE=SECONDS, got {plain(item)}") from None
        if not 0.0 < value <= MAX_DURATION_S:  # also false for NaN
            raise DatasetError(f"--dt must be in (0, {MAX_DURATION_S:g}] s, got {plain(item)}")
        if sep:
            per_file[key] = value
        else:
            default = value
    return default, per_file


@data.command("convert")
@click.argument("dataset", type=click.Choice(DATASETS))
@click.argument("src", type=click.Path(path_type=Path))
@click.argument("out", type=click.Path(dir_okay=False, path_type=Path))
@click.option(
    "--dt",
    "dt_values",
    multiple=True,
    metavar="SECONDS|FILE=SECONDS",
    help="eth-ucy: time between annotated frames, for every file (default 0.4) or for one "
    "file by name or stem (biwi_eth.txt=0.6667). Repeatable.",
)
@click.option(
    "--odometry",
    type=click.Path(exists=True, path_type=Path),
    default=None,
    help="jrdb: robot pose file, or folder of <sequence>.json pose files. Without it the "
    "scenes stay in the robot's moving frame.",
)
@user_errors
def convert(
    dataset: str, src: Path, out: Path, dt_values: Sequence[str], odometry: Path | None
) -> None:
    """Convert a DATASET (jrdb, eth-ucy, navwareset) at SRC (a file or folder) to OUT.mcap.

    Nothing is written unless every source file reads cleanly; OUT may not be one of
    the sources.
    """
    from srfm._io import check_writable, refuse_overwriting_inputs
    from srfm.datasets import eth_ucy, jrdb, navwareset, write_mcap

    if dt_values and dataset != "eth-ucy":
        raise DatasetError("--dt applies to eth-ucy only")
    if odometry is not None and dataset != "jrdb":
        raise DatasetError("--odometry applies to jrdb only")
    readers: dict[str, tuple[Callable[[Path], list[Path]], Callable[[Path], Any]]]
    dt_default, dt_files = _parse_dt(dt_values)
    dt_s = eth_ucy.DEFAULT_DT_S if dt_default is None else dt_default
    readers = {
        "eth-ucy": (
            eth_ucy.list_sources,
            lambda f: eth_ucy.read_file(f, eth_ucy.dt_for(f, dt_s, dt_files)),
        ),
        "navwareset": (navwareset.list_sources, navwareset.read_file),
        "jrdb": (jrdb.list_sources, lambda f: jrdb.read_sequence(f, odometry=odometry)),
    }
    list_sources, read_one = readers[dataset]
    files = list_sources(src)
    inputs: list[Path] = [src, *files]
    if odometry is not None:
        inputs += [odometry, *(odometry.rglob("*.json") if odometry.is_dir() else ())]
    refuse_overwriting_inputs(out, inputs, option="OUT")
    check_writable(out)
    if dataset == "eth-ucy":
        eth_ucy.check_overrides(files, dt_files)
    if dataset == "jrdb" and odometry is not None and odometry.is_file() and len(files) > 1:
        raise DatasetError(
            f"{odometry}: one odometry file given for {len(files)} sequences; "
            "pass a folder of <sequence>.json pose files"
        )
    start = time.perf_counter()
    scenes = []
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        with progressbar(files, label=f"reading {len(files)} {dataset} file(s)") as bar:
            for f in bar:
                scenes.append(read_one(f))
    _echo_warnings(caught)
    write_mcap(out, scenes, dataset=dataset, metadata={"source": str(src)})
    samples = sum(s.n_samples for s in scenes)
    click.echo(
        f"wrote {out}: {len(scenes)} scene(s), {samples} samples "
        f"({time.perf_counter() - start:.1f} s)"
    )
    if any(s.frame_of_reference == "robot" for s in scenes):
        click.echo(
            "note: no odometry, so positions are in the robot's moving frame "
            "(fine for viewing; srfm fit and srfm ade need world coordinates)"
        )


@data.command("scenario")
@click.argument("file", type=click.Path(path_type=Path))
@click.argument("out_dir", type=click.Path(file_okay=False, path_type=Path))
@click.option(
    "--scene",
    "scene_names",
    multiple=True,
    metavar="NAME",
    help="Only this scene (repeatable). Default: every scene with a robot in world coordinates.",
)
@click.option("--force", is_flag=True, help="Overwrite scenario files that already exist.")
@user_errors
def scenario(file: Path, out_dir: Path, scene_names: Sequence[str], force: bool) -> None:
    """Write a scenario TOML file for every robot scene of the dataset MCAP FILE into
    OUT_DIR, with the robot's trajectory as [robot.recording].

    Each scenario starts every pedestrian at its first observed position and sends it
    to its last (srfm.planners.recorded.recorded_scenario_doc); the planner `recorded`
    replays the robot: `srfm simulate --scenario OUT_DIR/NAME.toml --planner recorded`,
    `srfm benchmark -s OUT_DIR/NAME.toml -p recorded`. Every scene is checked before
    any file is written; without --scene, scenes that make no valid scenario (e.g. a
    person starting in contact with the robot) are skipped and named.
    """
    from srfm._io import atomic_write_text
    from srfm.datasets import read_mcap
    from srfm.errors import ScenarioError
    from srfm.planners.recorded import recorded_scenario_doc, scenario_toml
    from srfm.scenarios import parse_scenario

    dataset = read_mcap(file)
    by_name = {s.scene: s for s in dataset.scenes}
    unknown = [n for n in scene_names if n not in by_name]
    if unknown:
        raise DatasetError(
            f"{file}: no scene {unknown[0]!r} (it holds {len(by_name)} scenes; "
            "`srfm data info` lists them)"
        )
    chosen = [by_name[n] for n in dict.fromkeys(scene_names)] if scene_names else None
    if chosen is None:
        chosen = [
            s
            for s in dataset.scenes
            if s.robot_index is not None and s.frame_of_reference == "world"
        ]
        if not chosen:
            raise DatasetError(f"{file}: no scene has a robot in world coordinates")
    texts: dict[Path, str] = {}
    invalid: list[str] = []
    for scene in chosen:
        where = f"{file}: scene {scene.scene!r}"
        try:
            doc = recorded_scenario_doc(scene)
            parse_scenario(doc, where)
            text = scenario_toml(doc)
        except ScenarioError as exc:
            if scene_names:  # a scene asked for by name must make a scenario
                raise ScenarioError(f"{where}: no valid scenario: {exc}") from None
            invalid.append(str(exc))
            continue
        path = out_dir / f"{doc['name']}.toml"
        if path in texts:
            raise DatasetError(f"{file}: two scenes give the scenario name {doc['name']!r}")
        texts[path] = text
    if not texts:
        raise DatasetError(f"{file}: no scene makes a valid scenario: {invalid[0]}")
    existing = [p for p in texts if p.exists()]
    if existing and not force:
        raise DatasetError(f"{existing[0]} exists; pass --force to overwrite it")
    out_dir.mkdir(parents=True, exist_ok=True)
    for path, text in texts.items():
        atomic_write_text(path, text)
    click.echo(f"wrote {len(texts)} scenario file(s) to {out_dir}")
    skipped = 0 if scene_names else len(dataset.scenes) - len(chosen)
    if skipped:
        click.echo(f"skipped {skipped} scene(s) without a robot in world coordinates")
    for message in invalid:
        click.echo(f"skipped: {message}")


@data.command("info")
@click.argument("file", type=click.Path(path_type=Path))
@click.option("--json", "as_json", is_flag=True, help="Print the summary as JSON.")
@user_errors
def info(file: Path, as_json: bool) -> None:
    """Summarise an srfm dataset MCAP FILE: scenes, agents, frames, rates, speeds."""
    from srfm.datasets import read_mcap

    dataset_file = read_mcap(file)
    scenes = [s.summary() for s in dataset_file.scenes]
    if as_json:
        payload = {
            "file": str(file),
            "dataset": dataset_file.dataset,
            "metadata": dict(dataset_file.metadata),
            "scenes": scenes,
        }
        click.echo(json.dumps(payload, indent=2, sort_keys=True))
        return
    meta = dataset_file.metadata
    click.echo(
        f"{file}: {dataset_file.dataset} dataset, {len(scenes)} scene(s), schema "
        f"{meta.get('schema', '?')}, written by srfm {meta.get('srfm_version', '?')}"
    )
    head = ("scene", "frame", "peds", "robot", "frames", "duration", "dt", "median speed")
    rows = [
        (
            s["scene"],
            s["frame_of_reference"],
            str(s["pedestrians"]),
            "yes" if s["robot"] else "no",
            str(s["frames"]),
            f"{s['duration_s']:.1f} s",
            "-" if s["median_dt_s"] is None else f"{s['median_dt_s']:.3f} s",
            "-" if s["median_speed_mps"] is None else f"{s['median_speed_mps']:.2f} m/s",
        )
        for s in scenes
    ]
    click.echo(_table(head, rows))
    total_peds = sum(s["pedestrians"] for s in scenes)
    total_samples = sum(s["samples"] for s in scenes)
    click.echo(f"total: {total_peds} pedestrians, {total_samples} samples")


def _table(head: Sequence[str], rows: Sequence[Sequence[str]]) -> str:
    widths = [max(len(str(r[i])) for r in (head, *rows)) for i in range(len(head))]
    lines = ["  ".join(str(c).ljust(w) for c, w in zip(head, widths, strict=True)).rstrip()]
    for row in rows:
        lines.append("  ".join(str(c).ljust(w) for c, w in zip(row, widths, strict=True)).rstrip())
    return "\n".join(lines)


# --------------------------------------------------------------------------------------
# srfm fit / srfm ade


def _window_options(stride_s: float) -> Callable[[F], F]:
    """The windowing options shared by ``fit`` and ``ade`` (``stride_s``: the default)."""

    def decorate(func: F) -> F:
        return _add_window_options(func, stride_s)

    return decorate


def _add_window_options(func: F, stride_s: float) -> F:
    options = [
        click.option(
            "--horizon",
            "horizon_s",
            type=float,
            default=4.8,
            show_default=True,
            help="Prediction horizon of each window (s).",
        ),
        click.option(
            "--stride",
            "stride_s",
            type=float,
            default=stride_s,
            show_default=True,
            help="Time between the starts of consecutive windows of a track (s).",
        ),
        click.option(
            "--interaction-radius",
            "interaction_radius_m",
            type=float,
            default=3.0,
            show_default=True,
            help="Windows that come this close to the robot (m) are interaction windows.",
        ),
        click.option(
            "--ped-radius",
            "ped_radius_m",
            type=float,
            default=0.3,
            show_default=True,
            help="Pedestrian radius (m), as in the simulator.",
        ),
        click.option(
            "--robot-radius",
            "robot_radius_m",
            type=float,
            default=0.2,
            show_default=True,
            help="Robot radius (m), as in the simulator.",
        ),
        click.option(
            "--min-start-speed",
            "min_start_speed_mps",
            type=float,
            default=0.0,
            show_default=True,
            help="Start windows only where the initial speed is at least this (m/s); "
            "the NavWareSet protocol uses 0.3 (docs/fitting.md).",
        ),
        click.option(
            "--align",
            type=click.Choice(["stride", "encounter"]),
            default="stride",
            show_default=True,
            help="Where windows start: every --stride along each track, or once per "
            "encounter with the robot, --lead before the closest approach "
            "(docs/real_encounters.md).",
        ),
        click.option(
            "--lead",
            "lead_s",
            type=float,
            default=3.0,
            show_default=True,
            help="With --align encounter: time from the window start to the closest "
            "approach (s); shorter than --horizon.",
        ),
        click.option(
            "--goal",
            type=click.Choice(["track_end", "heading"]),
            default="track_end",
            show_default=True,
            help="The pedestrian's goal: the track's last position, or a point "
            "--goal-distance straight ahead along the initial velocity (uses nothing "
            "observed after the window start).",
        ),
        click.option(
            "--goal-distance",
            "goal_distance_m",
            type=float,
            default=10.0,
            show_default=True,
            help="With --goal heading: distance of the goal ahead (m).",
        ),
    ]
    for option in reversed(options):
        func = option(func)
    return func


def _load_windows(files: Sequence[Path], **config: Any) -> Any:
    from srfm.datasets import read_mcap
    from srfm.errors import ParameterError
    from srfm.fitting import WindowConfig, build_windows

    try:
        window_config = WindowConfig(**config)
    except ParameterError as exc:
        raise ParameterError(f"window option: {exc}") from None
    from srfm.datasets.navwareset import drop_supersets

    # A NavWareSet recording that contains others of its scene (the full scene 13 and
    # its slices) would count their tracks twice.
    scenes, _ = drop_supersets([scene for f in files for scene in read_mcap(f).scenes])
    return build_windows(scenes, window_config)


@click.command("fit")
@click.argument("files", nargs=-1, required=True, type=click.Path(path_type=Path))
@click.option(
    "-o",
    "--output",
    type=click.Path(dir_okay=False, path_type=Path),
    required=True,
    help="Parameter file to write (TOML, accepted by --params of srfm simulate).",
)
@click.option(
    "--start",
    "start_spec",
    default=None,
    metavar="PRESET|FILE",
    help="Starting parameters, kept for whatever is not fitted. Default: agrawal2024.",
)
@click.option(
    "--stage",
    "stages",
    multiple=True,
    type=click.Choice(["pedestrian", "robot"]),
    help="Fit only this stage (repeatable). Default: both; a stage without windows is skipped.",
)
@click.option(
    "--max-nfev",
    type=click.IntRange(min=1),
    default=200,
    show_default=True,
    help="Most model evaluations per starting point.",
)
@click.option(
    "--robot-force",
    type=click.Choice(ROBOT_FORMS),
    default=None,
    help="The form of the robot force (docs/model.md) that the result uses and the robot "
    "stage fits: its strength and range (exponential: A_r, B_r; ttc: k, τ0; "
    "collision_prediction: A, B; elliptical: A_e, B_e, Δt; sidestep: A, d_on, T, γ). "
    "Default: the --start "
    "parameters' form (the paper's exponential one for a preset).",
)
@click.option(
    "--fit-lambda-robot",
    is_flag=True,
    help="The robot stage also fits λ_r (the robot force's anisotropy; the exponential "
    "and elliptical forms).",
)
@_window_options(stride_s=1.2)
@click.option("--json", "as_json", is_flag=True, help="Print the result as JSON.")
@user_errors
def fit(
    files: Sequence[Path],
    output: Path,
    start_spec: str | None,
    stages: Sequence[str],
    max_nfev: int,
    robot_force: str | None,
    fit_lambda_robot: bool,
    as_json: bool,
    **window: Any,
) -> None:
    """Learn SRFM parameters from dataset MCAP FILES by nonlinear least squares.

    Stage 1 fits A_p, B_p, λ, τ on non-interaction windows (farther than the
    interaction radius from the robot), stage 2 fits the robot force (A_r, B_r of the
    paper's form, or another form's parameters: --robot-force) on interaction windows
    with the pedestrian part fixed. See docs/fitting.md for the residual and
    docs/real_encounters.md for the windows of real encounters (--align encounter).
    """
    from srfm._io import check_writable, refuse_overwriting_inputs
    from srfm._version import __version__
    from srfm.errors import ParameterError
    from srfm.fitting import FORM_FIT_FIELDS, fit_params
    from srfm.models import save_params
    from srfm.models.params import FORM_FIELDS

    inputs = [*files, *([Path(start_spec)] if start_spec is not None else [])]
    refuse_overwriting_inputs(output, inputs, option="--output")
    check_writable(output)  # before the fit, not after it
    start = load_params_option(start_spec)
    if robot_force is not None:
        start = start.replace(robot_form=robot_force)
    form = start.robot_form
    robot_fields = FORM_FIT_FIELDS[form]
    if fit_lambda_robot:
        if "lambda_robot" not in FORM_FIELDS[form]:
            raise ParameterError(
                f"--fit-lambda-robot: the {form} robot force has no λ_r "
                "(only the exponential and elliptical forms read it)"
            )
        robot_fields = (*robot_fields, "lambda_robot")
    windows = _load_windows(files, **window)
    chosen = tuple(stages) or ("pedestrian", "robot")
    t0 = time.perf_counter()
    log = None if as_json else (lambda msg: click.echo(f"  {msg}", err=True))
    fields = {"robot": robot_fields}
    result = fit_params(
        windows, start=start, stages=chosen, max_nfev=max_nfev, log=log, fields=fields
    )
    elapsed = time.perf_counter() - t0
    done = [s for s in result.stages if not s.skipped]
    if not done:
        reasons = "; ".join(f"{s.stage}: {s.message}" for s in result.stages)
        raise DatasetError(f"nothing to fit ({reasons})")
    meta: dict[str, Any] = {
        "created_by": f"srfm fit (srfm {__version__})",
        "data": ", ".join(f.name for f in files),
        "start": start_spec or "agrawal2024",
        **{k: v if isinstance(v, str) else float(v) for k, v in window.items()},
        "fit_time_s": round(elapsed, 1),
        "robot_force": form,
        "fit_lambda_robot": fit_lambda_robot,
    }
    for s in result.stages:
        meta[f"{s.stage}_stage"] = "skipped" if s.skipped else "fitted"
        if not s.skipped:
            meta[f"{s.stage}_windows"] = s.n_windows
            meta[f"{s.stage}_tracks"] = s.n_tracks
            meta[f"{s.stage}_ade_m"] = round(s.ade_m, 6)
            meta[f"{s.stage}_rms_m"] = round(s.rms_m, 6)
    save_params(result.params, output, meta=meta)
    if as_json:
        payload = {
            "output": str(output),
            "params": result.params.as_dict(),
            "stages": [_stage_dict(s) for s in result.stages],
            "fit_time_s": elapsed,
        }
        click.echo(json.dumps(payload, indent=2, sort_keys=True))
        return
    head = ("stage", "windows", "tracks", "ADE start", "ADE fitted", "fitted parameters")
    rows = []
    for s in result.stages:
        if s.skipped:
            rows.append((s.stage, "0", "0", "-", "-", s.message))
            continue
        values = ", ".join(f"{k} = {v:.4g}" for k, v in s.fitted.items())
        rows.append(
            (
                s.stage,
                str(s.n_windows),
                str(s.n_tracks),
                f"{s.ade_start_m:.3f} m",
                f"{s.ade_m:.3f} m",
                values,
            )
        )
    click.echo(_table(head, rows))
    click.echo(f"wrote {output} ({elapsed:.1f} s)")


def _stage_dict(s: Any) -> dict[str, Any]:
    return {
        "stage": s.stage,
        "skipped": s.skipped,
        "fitted": s.fitted,
        "start": s.start,
        "windows": s.n_windows,
        "tracks": s.n_tracks,
        "ade_start_m": None if math.isnan(s.ade_start_m) else s.ade_start_m,
        "ade_m": None if math.isnan(s.ade_m) else s.ade_m,
        "rms_m": None if math.isnan(s.rms_m) else s.rms_m,
        "nfev": s.nfev,
        "success": s.success,
        "message": s.message,
    }


@click.command("ade")
@click.argument("files", nargs=-1, required=True, type=click.Path(path_type=Path))
@click.option(
    "--params",
    "params_spec",
    default=None,
    metavar="PRESET|FILE",
    help="SRFM parameters: a preset or a parameter file (e.g. from srfm fit). "
    "Default: agrawal2024.",
)
@_window_options(stride_s=0.4)
@click.option("--json", "as_json", is_flag=True, help="Print the table as JSON.")
@user_errors
def ade(files: Sequence[Path], params_spec: str | None, as_json: bool, **window: Any) -> None:
    """ADE/FDE of the paper's models and a constant-velocity baseline on dataset FILES.

    Rows: CV and SFM on non-interaction windows; CV, SFM (robot ignored), SFM (robot as
    a pedestrian) and SRFM on interaction windows. The paper's JRDB values are shown
    beside its three rows.
    """
    from srfm.fitting import evaluate_ade

    params = load_params_option(params_spec)
    windows = _load_windows(files, **window)
    if windows.n_windows == 0:
        if window["align"] == "encounter":
            raise DatasetError(
                "no prediction windows: no track comes within the interaction radius "
                f"({window['interaction_radius_m']:g} m) of the robot with "
                f"{window['lead_s']:g} s before and "
                f"{window['horizon_s'] - window['lead_s']:g} s after its closest approach"
            )
        raise DatasetError(
            "no prediction windows: every pedestrian track is shorter than the horizon "
            f"({window['horizon_s']:g} s) plus the initial-velocity span (0.4 s)"
        )
    rows = evaluate_ade(windows, params)
    if as_json:
        payload = {
            "files": [str(f) for f in files],
            "params": params.as_dict(),
            "window": window,
            "rows": [
                {
                    "model": r.model,
                    "forces": r.forces,
                    "tracks": r.tracks,
                    "windows": r.n_windows,
                    "n_tracks": r.n_tracks,
                    "ade_m": None if math.isnan(r.ade_m) else r.ade_m,
                    "fde_m": None if math.isnan(r.fde_m) else r.fde_m,
                    "paper_ade_m": r.paper_ade_m,
                }
                for r in rows
            ],
        }
        click.echo(json.dumps(payload, indent=2, sort_keys=True))
        return
    head = ("model", "forces", "tracks", "windows", "ADE", "FDE", "paper ADE (JRDB)")
    body = [
        (
            r.model,
            r.forces,
            f"{r.tracks} ({r.n_tracks})",
            str(r.n_windows),
            "-" if math.isnan(r.ade_m) else f"{r.ade_m:.3f} m",
            "-" if math.isnan(r.fde_m) else f"{r.fde_m:.3f} m",
            "" if r.paper_ade_m is None else f"{r.paper_ade_m:.2f} m",
        )
        for r in rows
    ]
    click.echo(_table(head, body))
    click.echo(f"parameters: {params_spec or 'agrawal2024'}; horizon {window['horizon_s']:g} s")
