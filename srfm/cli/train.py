"""``srfm train``: TD3 on ``srfm/SocialNav-v0`` (needs the ``rl`` extra), and
``srfm export-policy``: a checkpoint to a NumPy policy file."""

from __future__ import annotations

import contextlib
import shlex
from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

from srfm.cli._common import SEED, on_terminal, progressbar, user_errors

if TYPE_CHECKING:
    from srfm.rl.training import TrainOptions

__all__ = ["export_policy", "train"]

_DEFAULTS: dict[str, Any] = {}


def _net_arch(ctx: click.Context, param: click.Parameter, value: Any) -> tuple[int, ...]:
    """``--net-arch``: comma-separated positive layer sizes, e.g. ``256,256``."""
    if isinstance(value, tuple):
        return value
    try:
        sizes = tuple(int(v) for v in str(value).split(","))
    except ValueError:
        sizes = ()
    if not sizes or min(sizes) < 1:
        raise click.BadParameter(f"{value!r} is not a comma-separated list of positive integers")
    return sizes


def _family_weights(
    ctx: click.Context, param: click.Parameter, value: Any
) -> tuple[float, ...] | None:
    """``--family-weights``: five comma-separated non-negative numbers, or None."""
    if value is None or isinstance(value, tuple):
        return value
    from srfm.errors import ScenarioError
    from srfm.scenarios.training import family_weights

    try:
        weights = tuple(float(v) for v in str(value).split(","))
    except ValueError:
        raise click.BadParameter(f"{value!r} is not a comma-separated list of numbers") from None
    try:
        return family_weights(weights)
    except ScenarioError as error:
        raise click.BadParameter(str(error)) from None


def _scenario_list(ctx: click.Context, param: click.Parameter, value: Any) -> tuple[str, ...]:
    """``--library`` / ``--eval-scenarios``: comma-separated built-in scenario names, or
    a set: ``train-split`` (the library's training split), ``validation`` (the mixed
    layouts and the library's validation scenarios), ``paper`` (the five evaluation
    scenarios)."""
    if isinstance(value, tuple):
        return value
    if value is None or value == "":
        return ()
    from srfm.scenarios import BUILTIN_SCENARIOS, EVALUATION_SCENARIOS
    from srfm.scenarios.training import LIBRARY_TRAINING, LIBRARY_VALIDATION, TRAINING_SCENARIO

    sets = {
        "train-split": LIBRARY_TRAINING,
        "validation": (TRAINING_SCENARIO, *LIBRARY_VALIDATION),
        "paper": EVALUATION_SCENARIOS,
    }
    names: list[str] = []
    for word in str(value).split(","):
        word = word.strip()
        if word in sets:
            names += sets[word]
        elif word in BUILTIN_SCENARIOS or (word == TRAINING_SCENARIO and param.name != "library"):
            names.append(word)
        else:
            raise click.BadParameter(f"unknown scenario or set {word!r}")
    return tuple(names)


def _default(name: str) -> Any:
    # TrainConfig's defaults without importing attrs classes at CLI start-up cost.
    if not _DEFAULTS:
        import attrs

        from srfm.rl.training import TrainConfig

        _DEFAULTS.update({f.name: f.default for f in attrs.fields(TrainConfig)})
    return _DEFAULTS[name]


class _ConfigDefault(click.Option):
    """An option whose default is ``TrainConfig``'s field ``config_field``, read when
    first needed (parsing, ``srfm train --help``): ``srfm --help`` and the other
    commands do not import the trainer, and with it numba."""

    def __init__(self, *args: Any, config_field: str, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self.config_field = config_field

    def get_default(self, ctx: click.Context, call: bool = True) -> Any:
        value = _default(self.config_field)
        if self.config_field == "net_arch":
            return ",".join(map(str, value))
        return value


@click.command()
@click.option(
    "--run-dir",
    type=click.Path(file_okay=False, path_type=Path),
    required=True,
    help="Directory for checkpoints, logs and evaluations (created).",
)
@click.option(
    "--k-div",
    type=click.FloatRange(min=0.0),
    cls=_ConfigDefault,
    config_field="k_div",
    show_default=True,
    help="k2, weight of the one-step deviation penalty (1/m): > 0 trains the "
    "SRFM-aware policy, 0 the RL_base policy.",
)
@click.option(
    "--k-dist",
    type=click.FloatRange(min=0.0),
    cls=_ConfigDefault,
    config_field="k_dist",
    show_default=True,
    help="k1, weight of the normalised goal distance.",
)
@click.option(
    "--k-progress",
    type=click.FloatRange(min=0.0),
    cls=_ConfigDefault,
    config_field="k_progress",
    show_default=True,
    help="Weight of the potential-based progress term (0: the paper's reward).",
)
@click.option(
    "--success-reward",
    type=click.FloatRange(min=0.0),
    cls=_ConfigDefault,
    config_field="success_reward",
    show_default=True,
    help="Terminal reward on reaching the goal.",
)
@click.option(
    "--timeout-penalty",
    type=click.FloatRange(min=0.0),
    cls=_ConfigDefault,
    config_field="timeout_penalty",
    show_default=True,
    help="Terminal penalty at the horizon; a collision or leaving the world costs twice this.",
)
@click.option(
    "--k-div-start",
    type=click.IntRange(min=0),
    cls=_ConfigDefault,
    config_field="k_div_start",
    show_default=True,
    help="Curriculum: k2 is 0 until this step, then ramps up to --k-div.",
)
@click.option(
    "--k-div-ramp",
    type=click.IntRange(min=0),
    cls=_ConfigDefault,
    config_field="k_div_ramp",
    show_default=True,
    help="Curriculum: steps over which k2 rises linearly from 0 to --k-div.",
)
@click.option("--seed", type=SEED, default=0, show_default=True)
@click.option(
    "--steps",
    "total_steps",
    type=click.IntRange(min=1),
    cls=_ConfigDefault,
    config_field="total_steps",
    show_default=True,
    help="Total environment steps (including those of a resumed run).",
)
@click.option(
    "--scenario",
    cls=_ConfigDefault,
    config_field="scenario",
    show_default=True,
    help="Training scenario: a name, a TOML file, or 'mixed' (a new layout per episode).",
)
@click.option(
    "--learning-rate",
    type=float,
    cls=_ConfigDefault,
    config_field="learning_rate",
    show_default=True,
)
@click.option(
    "--action-repeat",
    type=click.IntRange(min=1, max=100),
    cls=_ConfigDefault,
    config_field="action_repeat",
    show_default=True,
    help="Simulation steps per action (1: the paper's set-up); the step counts count actions.",
)
@click.option(
    "--gamma",
    type=click.FloatRange(min=0.0, max=1.0, min_open=True),
    cls=_ConfigDefault,
    config_field="gamma",
    show_default=True,
    help="Discount factor (also the progress term's γ).",
)
@click.option(
    "--buffer-size",
    type=click.IntRange(min=1),
    cls=_ConfigDefault,
    config_field="buffer_size",
    show_default=True,
)
@click.option(
    "--learning-starts",
    type=click.IntRange(min=0),
    cls=_ConfigDefault,
    config_field="learning_starts",
    show_default=True,
    help="Random-action warm-up steps.",
)
@click.option(
    "--batch-size",
    type=click.IntRange(min=1),
    cls=_ConfigDefault,
    config_field="batch_size",
    show_default=True,
)
@click.option(
    "--eval-every",
    type=click.IntRange(min=0),
    cls=_ConfigDefault,
    config_field="eval_every",
    show_default=True,
    help="Steps between evaluations on the five evaluation scenarios (0: never).",
)
@click.option(
    "--eval-seeds",
    type=click.IntRange(min=1),
    cls=_ConfigDefault,
    config_field="eval_seeds",
    show_default=True,
    help="Seeds per scenario in an evaluation (10000, 10001, ...).",
)
@click.option(
    "--checkpoint-every",
    type=click.IntRange(min=0),
    cls=_ConfigDefault,
    config_field="checkpoint_every",
    show_default=True,
    help="Steps between checkpoints (0: only at the end).",
)
@click.option(
    "--resume",
    type=click.Path(dir_okay=False, exists=True, path_type=Path),
    default=None,
    help="Continue from this checkpoint zip (and its <stem>_replay_buffer.pkl).",
)
@click.option(
    "--twin/--no-twin",
    "counterfactual_twin",
    cls=_ConfigDefault,
    config_field="counterfactual_twin",
    show_default=True,
    help="Also step the full counterfactual crowd (the reward does not need it).",
)
@click.option(
    "--save-replay-buffer/--no-save-replay-buffer",
    cls=_ConfigDefault,
    config_field="save_replay_buffer",
    show_default=True,
    help="Keep the replay buffer beside latest.zip, for --resume.",
)
@click.option(
    "--torch-threads",
    type=click.IntRange(min=1),
    default=1,
    show_default=True,
    help="Learner threads: torch intra-op threads; with --backend sbx, 1 turns XLA's "
    "multi-threaded CPU kernels off.",
)
@click.option(
    "--backend",
    type=click.Choice(["sb3", "sbx"]),
    cls=_ConfigDefault,
    config_field="backend",
    show_default=True,
    help="sb3: stable-baselines3 + torch (the paper's reference); sbx: SBX, the same "
    "TD3 in JAX (needs the sbx extra).",
)
@click.option(
    "--net-arch",
    callback=_net_arch,
    cls=_ConfigDefault,
    config_field="net_arch",
    show_default=True,
    help="Hidden layer sizes of actor and critics, comma-separated.",
)
@click.option(
    "--family-weights",
    callback=_family_weights,
    default=None,
    help=(
        "For --scenario mixed: relative probabilities of the layout families walkers, "
        "streams, crossing, standing, circle, comma-separated (e.g. 1,1,1,3,1); "
        "default: each 1/5."
    ),
)
@click.option(
    "--train-freq",
    type=click.IntRange(min=1),
    cls=_ConfigDefault,
    config_field="train_freq",
    show_default=True,
    help="(Vectorised) environment steps between updates.",
)
@click.option(
    "--gradient-steps",
    type=click.IntRange(min=1),
    cls=_ConfigDefault,
    config_field="gradient_steps",
    show_default=True,
    help="Gradient steps per update (update-to-data ratio: gradient steps / (train freq x envs)).",
)
@click.option(
    "--n-envs",
    type=click.IntRange(min=1),
    cls=_ConfigDefault,
    config_field="n_envs",
    show_default=True,
    help="Environments stepped together (seeds seed, seed + 1, ...).",
)
@click.option(
    "--range-beams",
    type=click.IntRange(min=0, max=360),
    cls=_ConfigDefault,
    config_field="range_beams",
    show_default=True,
    help="Range beams to walls and pillars in the observation (0: the paper's observation).",
)
@click.option(
    "--range-max",
    "range_max_m",
    type=click.FloatRange(min=0.0, min_open=True),
    cls=_ConfigDefault,
    config_field="range_max_m",
    show_default=True,
    help="Range of the beams (m).",
)
@click.option(
    "--library",
    callback=_scenario_list,
    default=None,
    help=(
        "For --scenario mixed: built-in scenarios run in a share --library-share of the "
        "episodes, comma-separated, or train-split (the library's training split, "
        "docs/rl.md)."
    ),
)
@click.option(
    "--library-share",
    type=click.FloatRange(0.0, 1.0),
    cls=_ConfigDefault,
    config_field="library_share",
    show_default=True,
    help="Probability that an episode runs a --library scenario.",
)
@click.option(
    "--generated-share",
    type=click.FloatRange(0.0, 1.0),
    cls=_ConfigDefault,
    config_field="generated_share",
    show_default=True,
    help=(
        "For --scenario mixed: probability that an episode runs a generated walled "
        "layout (generated:SEED of the episode seed; docs/scenarios.md)."
    ),
)
@click.option(
    "--eval-scenarios",
    callback=_scenario_list,
    default="paper",
    show_default=True,
    help=(
        "Scenarios of the periodic evaluations, comma-separated: built-in names, mixed "
        "(training layouts), or the sets paper and validation (the mixed layouts and "
        "the library's validation split)."
    ),
)
@click.option(
    "--select-by-deviation/--select-by-outcome",
    default=True,
    show_default=True,
    help=(
        "Rank evaluations by success, collisions, then deviation; or by success and "
        "collisions only."
    ),
)
@click.option("--progress/--no-progress", default=True, show_default=True)
@user_errors
def train(**options: Any) -> None:
    """Train a TD3 navigation policy on srfm/SocialNav-v0 (stable-baselines3).

    Defaults are the paper's TD3 set-up (docs/rl.md). Policy zips are loaded with
    SB3's loader, which unpickles: use only checkpoints from a trusted source.
    """
    from srfm.rl.training import TrainOptions

    # The options are named as TrainConfig's fields, and run_dir, resume, progress.
    _train(TrainOptions.from_settings(**options))


def _command_line() -> str:
    """``srfm train`` with every option spelled out (the exact, reproducible command)."""
    ctx = click.get_current_context()
    words = ["srfm", "train"]
    for param in ctx.command.params:
        if not isinstance(param, click.Option) or param.name is None:
            continue
        value = ctx.params.get(param.name)
        if value is None or param.name == "progress":
            continue
        if param.is_flag and param.secondary_opts:
            words.append(param.opts[0] if value else param.secondary_opts[0])
        elif param.is_flag:
            if value:
                words.append(param.opts[0])
        elif isinstance(value, tuple):
            words += [param.opts[0], ",".join(map(str, value))]
        else:
            words += [param.opts[0], str(value)]
    return shlex.join(words)


def _train(options: TrainOptions) -> None:
    """Run ``options`` as ``srfm train``: the run directory is checked before anything
    else; the progress bar (on a terminal) opens with the first progress report, after
    the set-up, so that an error of the set-up is the only line printed."""
    from srfm._io import check_writable
    from srfm.rl.training import train as run_training

    check_writable(options.run_dir, folder=True)  # before any training, not at the first checkpoint
    command = _command_line()
    if not options.progress:
        result = run_training(
            options.config, options.run_dir, resume=options.resume, log=click.echo, command=command
        )
    else:
        with _TrainingBar(options.config.total_steps) as bar:
            result = run_training(
                options.config,
                options.run_dir,
                resume=options.resume,
                progress=bar.advance,
                log=bar.say,
                command=command,
            )
    click.echo(
        f"trained {result.steps} steps in {result.wall_time_s:.0f} s "
        f"({result.session_wall_time_s:.0f} s in this session); run in {result.run_dir}"
    )


class _TrainingBar:
    """The progress bar of ``srfm train`` (on a terminal), opened at the first report."""

    def __init__(self, steps: int) -> None:
        self.steps = steps
        self.done = 0
        self.bar: Any = None
        self.stack = contextlib.ExitStack()

    def __enter__(self) -> _TrainingBar:
        return self

    def __exit__(self, *exc: object) -> None:
        self.stack.close()

    def advance(self, steps: int) -> None:
        """Steps done so far."""
        if self.bar is None:
            self.bar = self.stack.enter_context(
                progressbar(length=self.steps, label="training", show_pos=True, show_eta=True)
            )
        if steps > self.done:
            self.bar.update(steps - self.done)
            self.done = steps

    def say(self, message: str) -> None:
        """A line of the training's log, below the bar."""
        if self.bar is not None and on_terminal():
            click.echo("", err=True)  # end the progress bar's line
        click.echo(message)


@click.command("export-policy")
@click.argument("checkpoint", type=click.Path(dir_okay=False, exists=True, path_type=Path))
@click.argument("out", type=click.Path(dir_okay=False, path_type=Path))
@click.option(
    "--eval-seeds",
    type=click.IntRange(min=0),
    default=0,
    show_default=True,
    help="Also evaluate the exported actor on the five evaluation scenarios with this "
    "many seeds each (10000, 10001, ...) and record the figures.",
)
@click.option("--note", default=None, help="Free text recorded in the metadata (training.note).")
def export_policy(checkpoint: Path, out: Path, eval_seeds: int, note: str | None) -> None:
    """Export an SB3/SBX TD3 CHECKPOINT (a zip of `srfm train`) to a NumPy policy file.

    Writes OUT with suffixes .npz (the actor's weights) and .json (metadata: observation
    layout version, kinematics, action scaling, training configuration and seed,
    evaluation figures). The result loads with NumPy only and runs as a planner
    (srfm.planners.td3.TD3Planner). Reading the checkpoint unpickles: trusted files only.
    """
    user_errors(_export)(checkpoint, out, eval_seeds=eval_seeds, note=note)


def _export(checkpoint: Path, out: Path, *, eval_seeds: int, note: str | None) -> None:
    from srfm._io import check_writable, refuse_overwriting_inputs
    from srfm.rl.training import export_policy as run_export

    for target in (out.with_suffix(".npz"), out.with_suffix(".json")):
        refuse_overwriting_inputs(target, [checkpoint], option="OUT")
        check_writable(target)
    run_export(checkpoint, out, eval_seeds=eval_seeds, note=note, log=click.echo)
