"""TD3 training on ``srfm/SocialNav-v0`` (stable-baselines3 or SBX), policy evaluation
and export.

Needs the ``rl`` extra (gymnasium, stable-baselines3, torch), imported lazily; the
``sbx`` backend (``backend="sbx"``: SBX, the JAX implementation of the same algorithms
by SB3's maintainers, same API) also the ``sbx`` extra. SB3 + torch is the reference
of the paper's set-up. The command line front ends are ``srfm train`` (which builds one
:class:`TrainOptions`) and ``srfm export-policy``; the defaults are the paper's TD3 set-up
(docs/rl.md, "Training"): learning rate 1e-4, replay buffer 1e6, [256, 256] networks, batch 256,
10,000 random warm-up steps, 5 gradient steps every 5 environment steps, τ = 0.005,
γ = 0.99, policy delay 2, target noise 0.2 clipped at 0.5, Gaussian exploration
noise σ = 0.3, up to 2e6 steps.

A run directory holds::

    config.json              the TrainConfig, the EnvConfig, versions, the command
    state.json               steps trained and wall time so far (updated at checkpoints)
    checkpoints/step_N.zip   periodic checkpoints (SB3 zips; no replay buffer)
    latest.zip               the latest checkpoint, and beside it
    latest_replay_buffer.pkl its replay buffer (for resuming)
    best.zip                 the checkpoint with the best periodic evaluation
    eval.jsonl               one line per evaluation
    monitor.csv, logs/       SB3's episode monitor and CSV (and TensorBoard) logs

Policy zips are read with SB3's loader, which unpickles: trusted files only.
:func:`export_policy` turns one into a NumPy policy file (``.npz`` + ``.json``) that
loads with NumPy only (:mod:`srfm.planners.td3`).
"""

from __future__ import annotations

import functools
import importlib.util
import json
import operator
import os
import platform
import sys
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any, Final

import attrs
import numpy as np

from srfm._text import plain
from srfm._validate import keyword_options, non_negative, positive, unit_interval
from srfm.errors import ParameterError, ScenarioError, SrfmError
from srfm.scenarios import BUILTIN_SCENARIOS, EVALUATION_SCENARIOS
from srfm.scenarios.training import TRAINING_SCENARIO, family_weights

__all__ = [
    "BACKENDS",
    "EvalResult",
    "TrainConfig",
    "TrainOptions",
    "TrainResult",
    "evaluate_planner",
    "export_policy",
    "k2_schedule",
    "train",
]

EVAL_SEED_BASE: Final = 10_000
# Steps between updates of the k2 curriculum and between progress reports.
SCHEDULE_EVERY: Final = 100
# Training libraries: stable-baselines3 (torch; the paper's reference) and SBX (JAX).
BACKENDS: Final = ("sb3", "sbx")


def _pos(inst: Any, attribute: attrs.Attribute[float], value: Any) -> None:
    positive(value, f"train.{attribute.name}", ParameterError)


def _nonneg(inst: Any, attribute: attrs.Attribute[float], value: Any) -> None:
    non_negative(value, f"train.{attribute.name}", ParameterError)


def _count(minimum: int) -> Callable[[Any, attrs.Attribute[int], Any], None]:
    def check(inst: Any, attribute: attrs.Attribute[int], value: Any) -> None:
        try:
            n = operator.index(value)
        except TypeError:
            n = minimum - 1
        if isinstance(value, bool) or n < minimum:
            raise ParameterError(
                f"train.{attribute.name} must be an integer >= {minimum}, got {plain(value)}"
            )

    return check


def _backend(inst: Any, attribute: attrs.Attribute[str], value: Any) -> None:
    if not isinstance(value, str) or value not in BACKENDS:
        raise ParameterError(f"train.backend must be one of {BACKENDS}, got {plain(value)}")


def _unit(inst: Any, attribute: attrs.Attribute[float], value: Any) -> None:
    v = positive(value, f"train.{attribute.name}", ParameterError)
    if v > 1.0:
        raise ParameterError(f"train.{attribute.name} must be in (0, 1], got {plain(value)}")


def _net(inst: Any, attribute: attrs.Attribute[tuple[int, ...]], value: Any) -> None:
    if (
        not isinstance(value, tuple)
        or not value
        or not all(isinstance(v, int) and not isinstance(v, bool) and v > 0 for v in value)
    ):
        raise ParameterError(
            f"train.net_arch must be a tuple of positive integers, got {plain(value)}"
        )


def _families(inst: Any, attribute: attrs.Attribute[Any], value: Any) -> None:
    if value is None:
        return
    if not isinstance(value, tuple):
        raise ParameterError(f"train.family_weights must be a tuple or None, got {plain(value)}")
    try:
        family_weights(value)
    except ScenarioError as error:
        raise ParameterError(f"train.family_weights: {error}") from None


def _names(inst: Any, attribute: attrs.Attribute[Any], value: Any) -> None:
    if not isinstance(value, tuple):
        raise ParameterError(f"train.{attribute.name} must be a tuple of names, got {plain(value)}")
    unknown = [n for n in value if n not in BUILTIN_SCENARIOS]
    if unknown:
        raise ParameterError(f"train.{attribute.name}: unknown scenario {plain(unknown[0])}")


def _eval_names(inst: Any, attribute: attrs.Attribute[Any], value: Any) -> None:
    if not isinstance(value, tuple) or not value:
        raise ParameterError(f"train.{attribute.name} must name scenarios, got {plain(value)}")
    _names(inst, attribute, tuple(n for n in value if n != TRAINING_SCENARIO))


def _share(inst: Any, attribute: attrs.Attribute[float], value: Any) -> None:
    unit_interval(value, f"train.{attribute.name}", ParameterError)


@attrs.frozen(kw_only=True)
class TrainConfig:
    """TD3 hyperparameters and the run's schedule (defaults: the paper, docs/rl.md).

    Attributes:
        total_steps: environment steps to train in total (paper: up to 2e6).
        seed: seed of SB3 (networks, exploration noise) and of the episode stream.
        scenario: training scenario (``random``).
        k_dist: k1, weight of the goal-distance term.
        k_div: k2 (1/m), weight of the one-step deviation term: > 0 SRFM-aware,
            0 RL_base.
        k_progress: weight of the potential-based progress term of the reward
            (:class:`srfm.rl.EnvConfig`; 0: the paper's reward). Its γ is ``gamma``.
        success_reward, timeout_penalty: the terminal terms r_term
            (:class:`srfm.rl.EnvConfig`; a collision costs twice the timeout).
        action_repeat: simulation steps per action (:class:`srfm.rl.EnvConfig`; 1:
            the paper's set-up). ``total_steps`` and the other step counts count
            actions (environment steps), not simulation steps.
        k_div_start: curriculum on k2: k2 is 0 up to this step, then
        k_div_ramp: rises linearly to ``k_div`` over this many steps (0: at once).
        learning_rate: Adam learning rate (paper: 1e-4).
        buffer_size: replay buffer capacity (paper: 1e6).
        batch_size: minibatch size.
        learning_starts: random-action warm-up steps before learning.
        train_freq: vectorised environment steps between updates (each collects
            ``n_envs`` transitions).
        gradient_steps: gradient steps per update; the update-to-data ratio is
            gradient_steps / (train_freq · n_envs) (paper: 5 / 5 = 1).
        tau: Polyak factor of the target networks.
        gamma: discount factor.
        policy_delay: critic updates per actor update.
        target_policy_noise: std of the target policy smoothing noise.
        target_noise_clip: clip of that noise.
        action_noise_sigma: std of the Gaussian exploration noise (actions in [−1, 1]).
        net_arch: hidden layer sizes of actor and critics.
        eval_every: steps between evaluations on the evaluation scenarios (0: never).
        eval_seeds: seeds per scenario in an evaluation (from ``EVAL_SEED_BASE``,
            disjoint from the benchmark's seeds 0-99).
        checkpoint_every: steps between checkpoints (0: only at the end).
        counterfactual_twin: step the full counterfactual crowd during training (the
            reward does not need it).
        save_replay_buffer: keep the replay buffer beside ``latest.zip`` for resuming.
        torch_threads: threads of the learner: torch intra-op threads (sb3); for
            sbx, 1 turns XLA's multi-threaded CPU kernels off (set before JAX is
            first imported in the process; other values leave XLA's default).
        backend: ``"sb3"`` (stable-baselines3, torch; the reference) or ``"sbx"``
            (SBX, JAX).
        n_envs: environments stepped together (SB3 ``DummyVecEnv``); each gets its
            own seed (``seed + i``).
        family_weights: relative probabilities of the ``mixed`` layout families, in
            the order of :data:`srfm.scenarios.training.TRAINING_FAMILIES` (walkers,
            streams, crossing, standing, circle); None: each 1/5. Only for ``mixed``.
        library: built-in scenarios run in a share ``library_share`` of the
            training episodes (``mixed`` only; :class:`srfm.rl.SocialNavEnv`), e.g.
            :data:`srfm.scenarios.training.LIBRARY_TRAINING`.
        library_share: the probability of a library scenario per episode, in [0, 1].
        generated_share: the probability of a generated walled layout per episode
            (``mixed`` only; :mod:`srfm.scenarios.generated`), in [0, 1 −
            ``library_share``].
        range_beams: range beams to walls and pillars in the observation
            (:class:`srfm.rl.EnvConfig`; 0: the paper's observation).
        range_max_m: the range of the beams (m).
        eval_scenarios: the scenarios of the periodic evaluations (built-in names;
            ``mixed`` stands for the training layouts of the evaluation seeds).
        select_by_deviation: rank evaluations by success, then collisions, then
            deviation (True); False ranks by success and collisions only (an
            evaluation must be strictly better to replace the best), so that a
            comparison of k2 values is not selected on the quantity under test.
    """

    total_steps: int = attrs.field(default=2_000_000, validator=_count(1))
    seed: int = attrs.field(default=0, validator=_count(0))
    scenario: str = "random"
    k_dist: float = attrs.field(default=0.1, validator=_nonneg)
    k_div: float = attrs.field(default=2.0, validator=_nonneg)
    k_progress: float = attrs.field(default=0.0, validator=_nonneg)
    success_reward: float = attrs.field(default=25.0, validator=_nonneg)
    timeout_penalty: float = attrs.field(default=25.0, validator=_nonneg)
    action_repeat: int = attrs.field(default=1, validator=_count(1))
    k_div_start: int = attrs.field(default=0, validator=_count(0))
    k_div_ramp: int = attrs.field(default=0, validator=_count(0))
    learning_rate: float = attrs.field(default=1e-4, validator=_pos)
    buffer_size: int = attrs.field(default=1_000_000, validator=_count(1))
    batch_size: int = attrs.field(default=256, validator=_count(1))
    learning_starts: int = attrs.field(default=10_000, validator=_count(0))
    train_freq: int = attrs.field(default=5, validator=_count(1))
    gradient_steps: int = attrs.field(default=5, validator=_count(1))
    tau: float = attrs.field(default=0.005, validator=_unit)
    gamma: float = attrs.field(default=0.99, validator=_unit)
    policy_delay: int = attrs.field(default=2, validator=_count(1))
    target_policy_noise: float = attrs.field(default=0.2, validator=_nonneg)
    target_noise_clip: float = attrs.field(default=0.5, validator=_nonneg)
    action_noise_sigma: float = attrs.field(default=0.3, validator=_nonneg)
    net_arch: tuple[int, ...] = attrs.field(default=(256, 256), validator=_net)
    eval_every: int = attrs.field(default=25_000, validator=_count(0))
    eval_seeds: int = attrs.field(default=5, validator=_count(1))
    checkpoint_every: int = attrs.field(default=25_000, validator=_count(0))
    counterfactual_twin: bool = False
    save_replay_buffer: bool = True
    torch_threads: int = attrs.field(default=1, validator=_count(1))
    backend: str = attrs.field(default="sb3", validator=_backend)
    n_envs: int = attrs.field(default=1, validator=_count(1))
    family_weights: tuple[float, ...] | None = attrs.field(default=None, validator=_families)
    library: tuple[str, ...] = attrs.field(default=(), validator=_names)
    library_share: float = attrs.field(default=0.0, validator=_share)
    generated_share: float = attrs.field(default=0.0, validator=_share)
    range_beams: int = attrs.field(default=0, validator=_count(0))
    range_max_m: float = attrs.field(default=4.0, validator=_pos)
    eval_scenarios: tuple[str, ...] = attrs.field(
        default=EVALUATION_SCENARIOS, validator=_eval_names
    )
    select_by_deviation: bool = True

    def __new__(cls, *args: Any, **options: Any) -> TrainConfig:
        # Before attrs' __init__: an unknown option is a ParameterError naming it.
        keyword_options(cls, args, options, ParameterError)
        return super().__new__(cls)


def _a_train_config(inst: Any, attribute: attrs.Attribute[TrainConfig], value: Any) -> None:
    if not isinstance(value, TrainConfig):
        raise ParameterError(f"train.config must be a TrainConfig, got {plain(value)}")


def _as_path(value: Any) -> Any:
    """A path given as text or a path-like as a :class:`Path`; anything else as it is,
    for the validator to name."""
    if isinstance(value, str | os.PathLike) and str(value):
        return Path(value)
    return value


def _path(inst: Any, attribute: attrs.Attribute[Any], value: Any) -> None:
    if not isinstance(value, Path) and not (value is None and attribute.name == "resume"):
        raise ParameterError(f"train.{attribute.name} must be a path, got {plain(value)}")


def _flag(inst: Any, attribute: attrs.Attribute[bool], value: Any) -> None:
    if not isinstance(value, bool):
        raise ParameterError(f"train.{attribute.name} must be true or false, got {plain(value)}")


@attrs.frozen(kw_only=True)
class TrainOptions:
    """One training run as ``srfm train`` runs it, validated when built: what to train,
    where, from which checkpoint, and whether to show its progress.

    The command line builds it from its options with :meth:`from_settings`; Python code
    can build it the same way (for example from the ``train_config`` of a run's
    ``config.json``) or from a :class:`TrainConfig`, and run it with :func:`train`::

        options = TrainOptions.from_settings(run_dir="runs/base", k_div=0.0)
        train(options.config, options.run_dir, resume=options.resume)

    Attributes:
        config: hyperparameters and schedule.
        run_dir: where checkpoints and logs go (created).
        resume: a checkpoint zip to continue from, or None (a new run).
        progress: show a progress bar while training (``srfm train --progress``; on a
            terminal only).
    """

    config: TrainConfig = attrs.field(factory=TrainConfig, validator=_a_train_config)
    run_dir: Path = attrs.field(converter=_as_path, validator=_path)
    resume: Path | None = attrs.field(default=None, converter=_as_path, validator=_path)
    progress: bool = attrs.field(default=True, validator=_flag)

    def __new__(cls, *args: Any, **options: Any) -> TrainOptions:
        keyword_options(cls, args, options, ParameterError)
        return super().__new__(cls)

    @classmethod
    def from_settings(
        cls,
        *,
        run_dir: str | os.PathLike[str],
        resume: str | os.PathLike[str] | None = None,
        progress: bool = True,
        **settings: Any,
    ) -> TrainOptions:
        """The options of a run from :class:`TrainConfig`'s fields by name (a list
        becomes a tuple, as JSON has no tuples), the run directory, the checkpoint to
        resume from and whether to show progress.

        Raises:
            ParameterError: an unknown setting (naming it and the known ones) or a bad
                value (naming the field).
        """
        values: dict[str, Any] = {
            k: tuple(v) if isinstance(v, list) else v for k, v in settings.items()
        }
        return cls(config=TrainConfig(**values), run_dir=run_dir, resume=resume, progress=progress)


@attrs.frozen(kw_only=True)
class EvalResult:
    """A policy's evaluation over scenarios × seeds (full twin episodes).

    Attributes:
        steps: training steps of the evaluated policy.
        episodes: episodes run.
        success_rate, collision_rate, timeout_rate: fractions of episodes.
        mean_deviation_m: mean over episodes of the mean over pedestrians of the largest
            factual-counterfactual distance (m).
        per_scenario: the same four numbers per scenario.
    """

    steps: int
    episodes: int
    success_rate: float
    collision_rate: float
    timeout_rate: float
    mean_deviation_m: float
    per_scenario: dict[str, dict[str, float]]

    def better_than(self, other: EvalResult | None, by_deviation: bool = True) -> bool:
        """Higher success, then fewer collisions, then (with ``by_deviation``) less
        deviation; strictly better only."""
        if other is None:
            return True
        mine: tuple[float, ...] = (-self.success_rate, self.collision_rate)
        theirs: tuple[float, ...] = (-other.success_rate, other.collision_rate)
        if by_deviation:
            mine += (self.mean_deviation_m,)
            theirs += (other.mean_deviation_m,)
        return mine < theirs


@attrs.frozen(kw_only=True)
class TrainResult:
    """What a call of :func:`train` did."""

    run_dir: Path
    steps: int
    wall_time_s: float
    session_wall_time_s: float
    best_eval: EvalResult | None


def evaluate_planner(
    make_planner: Callable[[], Any],
    scenarios: Sequence[str],
    seeds: Sequence[int],
    steps: int = 0,
) -> EvalResult:
    """Run full twin episodes (:func:`srfm.run_episode`) and summarise them.

    A scenario named ``mixed`` runs the training layout of each seed
    (:func:`srfm.scenarios.training.training_layout`)."""
    from srfm.scenarios import load_scenario
    from srfm.scenarios.training import training_layout
    from srfm.sim.episode import run_episode

    outcomes: dict[str, list[str]] = {}
    deviations: dict[str, list[float]] = {}
    for name in scenarios:
        for seed in seeds:
            scenario: Any = name
            if name == TRAINING_SCENARIO:
                scenario = training_layout(load_scenario("random"), seed)
            record = run_episode(scenario, seed, make_planner())
            outcomes.setdefault(name, []).append(record.outcome)
            deviations.setdefault(name, []).append(
                float(record.twin_separation_m().max(axis=0).mean())
            )

    def summary(outs: list[str], devs: list[float]) -> dict[str, float]:
        n = len(outs)
        return {
            "success_rate": outs.count("goal_reached") / n,
            "collision_rate": outs.count("collision") / n,
            "timeout_rate": outs.count("timeout") / n,
            "mean_deviation_m": float(np.mean(devs)),
        }

    per = {name: summary(outcomes[name], deviations[name]) for name in outcomes}
    all_out = [o for name in outcomes for o in outcomes[name]]
    all_dev = [d for name in deviations for d in deviations[name]]
    total = summary(all_out, all_dev)
    return EvalResult(steps=steps, episodes=len(all_out), per_scenario=per, **total)


def k2_schedule(config: TrainConfig, steps: int) -> float:
    """k2 (1/m) at training step ``steps`` under the curriculum: 0 before
    ``config.k_div_start``, then a linear ramp to ``config.k_div`` over
    ``config.k_div_ramp`` steps (at once when that is 0)."""
    if steps < config.k_div_start:
        return 0.0
    if config.k_div_ramp == 0:
        return config.k_div
    return config.k_div * min(1.0, (steps - config.k_div_start) / config.k_div_ramp)


def selectable(config: TrainConfig, steps: int) -> bool:
    """Whether the policy at ``steps`` may become the run's best: once the k2
    curriculum is over (``k_div_start + k_div_ramp``), also for a run with k2 = 0, so
    that runs that differ only in k2 select from the same window of training."""
    return steps >= config.k_div_start + config.k_div_ramp


def _versions() -> dict[str, str]:
    out = {"python": platform.python_version()}
    for mod in ("srfm", "numpy", "numba", "gymnasium", "stable_baselines3", "torch", "sbx", "jax"):
        if mod in ("sbx", "jax") and mod not in sys.modules:
            continue  # not used by this run; importing JAX costs seconds
        try:
            m = importlib.import_module(mod)
            out[mod] = str(getattr(m, "__version__", "?"))
        except ImportError:
            out[mod] = "missing"
    return out


def _require_sbx() -> Any:
    """The sbx module, or MissingDependencyError naming the sbx extra."""
    from srfm._deps import install_hint, require
    from srfm.errors import MissingDependencyError

    try:
        return require("sbx")
    except MissingDependencyError:
        raise MissingDependencyError(
            "the sbx backend needs SBX and JAX: install the sbx extra: " + install_hint("rl,sbx")
        ) from None


def _best_so_far(path: Path, by_deviation: bool = True) -> EvalResult | None:
    """The best evaluation recorded in an ``eval.jsonl`` among those eligible to be
    the run's best (None when there is none)."""
    best: EvalResult | None = None
    if not path.exists():
        return None
    names = {f.name for f in attrs.fields(EvalResult)}
    for line in path.read_text().splitlines():
        if not line.strip():
            continue
        row = json.loads(line)
        if not row.get("eligible", True):
            continue
        result = EvalResult(**{k: v for k, v in row.items() if k in names})
        if result.better_than(best, by_deviation):
            best = result
    return best


def _read_json(path: Path) -> dict[str, Any]:
    if not path.exists():
        return {}
    data = json.loads(path.read_text())
    return data if isinstance(data, dict) else {}


def train(
    config: TrainConfig,
    run_dir: str | Path,
    *,
    resume: str | Path | None = None,
    progress: Callable[[int], None] | None = None,
    log: Callable[[str], None] | None = None,
    command: str | None = None,
) -> TrainResult:
    """Train a TD3 policy on ``srfm/SocialNav-v0``; see the module docstring.

    The shape of stable-baselines3's ``learn``: the set-up (libraries, run directory,
    environments, the model new or resumed, ``config.json``), then the library's
    ``learn`` with srfm's callbacks (:mod:`srfm.rl._callbacks`: the k2 curriculum,
    progress, checkpoints, evaluations, in that order at a step), then the end of the
    run (the last checkpoint, and an evaluation when there is no best yet).

    Args:
        config: hyperparameters and schedule.
        run_dir: where checkpoints and logs go (created).
        resume: a checkpoint zip to continue from (its replay buffer
            ``<stem>_replay_buffer.pkl`` is loaded when it lies beside it); training
            continues until ``config.total_steps`` steps in total.
        progress: called with the number of steps done, every few hundred steps.
        log: called with one-line messages (evaluations, checkpoints).
        command: the command line, recorded in ``config.json``.

    Raises:
        MissingDependencyError: the ``rl`` extra is not installed.
        SrfmError: a bad resume file or run directory.
    """
    lib = _load_libraries(config)
    from stable_baselines3.common.callbacks import CallbackList

    from srfm.rl._callbacks import EveryNSteps, K2Curriculum

    say = log or _silent
    resume = None if resume is None else Path(resume)
    run = _make_run_dir(run_dir)
    env_config = _env_config(config)
    vec_env = _vec_env(config, env_config, run)
    state = _read_json(run / "state.json")
    previous_wall = float(state.get("wall_time_s", 0.0)) if resume is not None else 0.0
    if resume is not None:
        model = _resume_model(lib, config, resume, vec_env, say)
    else:
        model = _new_model(lib, config, vec_env)
    _configure_model(model, env_config, run)
    _write_run_config(run, config, env_config, command, resume)

    session = _Session(
        config=config,
        env_config=env_config,
        run=run,
        model=model,
        say=say,
        previous_wall_s=previous_wall,
    )
    if resume is not None:
        session.best = _best_so_far(run / "eval.jsonl", config.select_by_deviation)
    callback = CallbackList(
        [
            K2Curriculum(SCHEDULE_EVERY, functools.partial(k2_schedule, config)),
            EveryNSteps(SCHEDULE_EVERY, progress or _ignore),
            EveryNSteps(config.checkpoint_every, session.save),
            EveryNSteps(config.eval_every, session.evaluate),
        ]
    )
    remaining = config.total_steps - int(model.num_timesteps)
    if remaining > 0:
        model.learn(
            total_timesteps=remaining,
            callback=callback,
            reset_num_timesteps=resume is None,
            progress_bar=False,
        )

    steps = int(model.num_timesteps)
    if progress is not None:
        progress(steps)
    session.save(steps, final=True)
    if config.eval_every and session.best is None:
        session.evaluate(steps)
    vec_env.close()
    session_wall = time.perf_counter() - session.start
    return TrainResult(
        run_dir=run,
        steps=steps,
        wall_time_s=session.wall(),
        session_wall_time_s=session_wall,
        best_eval=session.best,
    )


def _silent(message: str) -> None:
    """A log that drops its messages."""


def _ignore(steps: int) -> None:
    """A progress report that reports nothing."""


def _load_libraries(config: TrainConfig) -> Any:
    """Import the rl extra (and the sbx one for ``backend="sbx"``) with one learner
    thread when ``config.torch_threads`` is 1; the TD3 library's module (sb3 or sbx)."""
    from srfm._deps import require

    if (
        config.backend == "sbx"
        and config.torch_threads == 1
        and "jax" not in sys.modules
        and "xla_cpu_multi_thread_eigen" not in os.environ.get("XLA_FLAGS", "")
    ):
        # One learner thread, as for torch: XLA reads this once, when JAX starts.
        flags = os.environ.get("XLA_FLAGS", "")
        os.environ["XLA_FLAGS"] = (
            flags + " --xla_cpu_multi_thread_eigen=false intra_op_parallelism_threads=1"
        ).strip()
    require("gymnasium")
    require("stable_baselines3")
    torch = require("torch")
    lib = _require_sbx() if config.backend == "sbx" else require("stable_baselines3")
    torch.set_num_threads(config.torch_threads)
    return lib


def _make_run_dir(run_dir: str | Path) -> Path:
    run = Path(run_dir)
    run.mkdir(parents=True, exist_ok=True)
    (run / "checkpoints").mkdir(exist_ok=True)
    return run


def _env_config(config: TrainConfig) -> Any:
    """The environment's EnvConfig of ``config``, with the scenario's robot kinematics."""
    from srfm.rl import EnvConfig, SocialNavEnv

    env_config = EnvConfig(
        k1=config.k_dist,
        k2=config.k_div,
        counterfactual_twin=config.counterfactual_twin,
        k_progress=config.k_progress,
        success_reward=config.success_reward,
        timeout_penalty=config.timeout_penalty,
        progress_gamma=config.gamma,
        action_repeat=config.action_repeat,
        range_beams=config.range_beams,
        range_max_m=config.range_max_m,
    )
    probe = SocialNavEnv(
        config.scenario,
        env_config,
        family_weights=config.family_weights,
        library=config.library,
        library_share=config.library_share,
        generated_share=config.generated_share,
    )
    return env_config.replace(kinematics=probe.scenario.robot.kinematics)


def _vec_env(config: TrainConfig, env_config: Any, run: Path) -> Any:
    """``config.n_envs`` monitored environments in a ``DummyVecEnv`` (SB3 seeds
    environment i with seed + i); monitor.csv for the first, <i>.monitor.csv after."""
    from stable_baselines3.common.monitor import Monitor
    from stable_baselines3.common.vec_env import DummyVecEnv

    from srfm.rl import SocialNavEnv

    def make_env(i: int) -> Callable[[], Any]:
        name = "monitor.csv" if i == 0 else f"{i}.monitor.csv"

        def make() -> Any:
            env = SocialNavEnv(
                config.scenario,
                env_config,
                family_weights=config.family_weights,
                library=config.library,
                library_share=config.library_share,
                generated_share=config.generated_share,
            )
            return Monitor(env, filename=str(run / name), info_keywords=("outcome",))

        return make

    return DummyVecEnv([make_env(i) for i in range(config.n_envs)])


def _new_model(lib: Any, config: TrainConfig, vec_env: Any) -> Any:
    from stable_baselines3.common.noise import NormalActionNoise

    n_actions = 2
    return lib.TD3(
        "MlpPolicy",
        vec_env,
        learning_rate=config.learning_rate,
        buffer_size=config.buffer_size,
        learning_starts=config.learning_starts,
        batch_size=config.batch_size,
        tau=config.tau,
        gamma=config.gamma,
        train_freq=(config.train_freq, "step"),
        gradient_steps=config.gradient_steps,
        action_noise=NormalActionNoise(
            np.zeros(n_actions), config.action_noise_sigma * np.ones(n_actions)
        ),
        policy_delay=config.policy_delay,
        target_policy_noise=config.target_policy_noise,
        target_noise_clip=config.target_noise_clip,
        policy_kwargs={"net_arch": list(config.net_arch)},
        seed=config.seed,
        device="cpu",
        verbose=0,
    )


def _resume_model(
    lib: Any, config: TrainConfig, resume: Path, vec_env: Any, say: Callable[[str], None]
) -> Any:
    """The model of checkpoint ``resume`` (with its replay buffer when one lies beside
    it), carrying this run's seed and fresh random streams."""
    from srfm.planners.td3 import checkpoint_backend

    if not resume.is_file():
        raise SrfmError(f"checkpoint {str(resume)!r} does not exist")
    written_by = checkpoint_backend(resume)
    if written_by != config.backend:
        raise SrfmError(
            f"checkpoint {str(resume)!r} was written by the {written_by} backend; "
            f"resume it with backend {written_by!r}, not {config.backend!r}"
        )
    model = lib.TD3.load(resume, env=vec_env, device="cpu")
    buffer = resume.with_name(resume.stem + "_replay_buffer.pkl")
    if buffer.is_file():
        model.load_replay_buffer(buffer)
        say(f"resumed from {resume} at step {model.num_timesteps} with its replay buffer")
    else:
        say(f"resumed from {resume} at step {model.num_timesteps} (empty replay buffer)")
    # The checkpoints of this run record its seed, not that of the run it started
    # from (a run may start from another run's checkpoint: tools/rl/train_policies.sh).
    model.seed = config.seed
    # Fresh, deterministic random streams for the continuation (networks'
    # sampling, exploration noise, episodes); the saved states are not restored.
    model.set_random_seed(config.seed + int(model.num_timesteps))
    vec_env.seed(config.seed + int(model.num_timesteps))
    return model


def _configure_model(model: Any, env_config: Any, run: Path) -> None:
    """Record the EnvConfig in the model (its checkpoints carry it) and log to run/logs
    (CSV, and TensorBoard when it is installed)."""
    from stable_baselines3.common.logger import configure

    model.srfm_env_config = attrs.asdict(env_config)
    formats = ["csv"]
    if importlib.util.find_spec("tensorboard") is not None:
        formats.append("tensorboard")
    model.set_logger(configure(str(run / "logs"), formats))


def _write_run_config(
    run: Path,
    config: TrainConfig,
    env_config: Any,
    command: str | None,
    resume: Path | None,
) -> None:
    """config.json (config_resume.json for a resumed session): the TrainConfig, the
    EnvConfig, versions, the command and the checkpoint resumed from."""
    meta = {
        "train_config": {
            k: list(v) if isinstance(v, tuple) else v for k, v in attrs.asdict(config).items()
        },
        "env_config": attrs.asdict(env_config),
        "versions": _versions(),
        "command": command,
        "resumed_from": None if resume is None else str(resume),
    }
    (run / ("config.json" if resume is None else "config_resume.json")).write_text(
        json.dumps(meta, indent=2, sort_keys=True) + "\n"
    )


@attrs.define
class _Session:
    """One call of :func:`train` as its callbacks act on it: the model, the run
    directory, the wall clock and the best evaluation so far."""

    config: TrainConfig
    env_config: Any
    run: Path
    model: Any
    say: Callable[[str], None]
    previous_wall_s: float
    start: float = attrs.field(factory=time.perf_counter)
    best: EvalResult | None = None

    def wall(self) -> float:
        """Seconds of training of the run so far, earlier sessions included."""
        return self.previous_wall_s + time.perf_counter() - self.start

    def save(self, steps: int, final: bool = False) -> None:
        """Checkpoint step ``steps``: checkpoints/step_N.zip, latest.zip (with its replay
        buffer) and state.json."""
        checkpoint = self.run / "checkpoints" / f"step_{steps:09d}.zip"
        # A checkpoint is taken when step N is collected, before that rollout's
        # gradient steps; at the end of a run that already has one for N, keep it, so
        # that step_N.zip is the same whether a run stopped at N or went on.
        if not (final and checkpoint.exists()):
            self.model.save(checkpoint)
        self.model.save(self.run / "latest.zip")
        if self.config.save_replay_buffer:
            self.model.save_replay_buffer(self.run / "latest_replay_buffer.pkl")
        state = {"steps": steps, "wall_time_s": self.wall()}
        (self.run / "state.json").write_text(json.dumps(state, indent=2) + "\n")
        self.say(f"step {steps}: checkpoint saved ({self.wall():.0f} s of training so far)")

    def evaluate(self, steps: int) -> None:
        """Evaluate the current policy (a line of eval.jsonl); best.zip when it is the
        best eligible one."""
        from srfm.planners.td3 import PolicyPlanner

        actor = self._actor()
        eval_seeds = list(range(EVAL_SEED_BASE, EVAL_SEED_BASE + self.config.eval_seeds))
        result = evaluate_planner(
            lambda: PolicyPlanner(actor, self.env_config, "policy"),
            self.config.eval_scenarios,
            eval_seeds,
            steps,
        )
        # Only a policy trained with the final k2 can be the run's best (the k2
        # curriculum's early checkpoints are policies of another reward).
        k2 = k2_schedule(self.config, steps)
        eligible = selectable(self.config, steps)
        row = {**attrs.asdict(result), "wall_time_s": self.wall(), "k2": k2}
        with (self.run / "eval.jsonl").open("a") as fh:
            fh.write(json.dumps({**row, "eligible": eligible}) + "\n")
        if eligible and result.better_than(self.best, self.config.select_by_deviation):
            self.best = result
            self.model.save(self.run / "best.zip")
        self.say(
            f"step {steps}: eval success {result.success_rate:.2f}, collisions "
            f"{result.collision_rate:.2f}, timeouts {result.timeout_rate:.2f}, mean "
            f"deviation {result.mean_deviation_m:.3f} m"
        )

    def _actor(self) -> Any:
        from srfm.planners.td3 import NumpyActor

        if self.config.backend == "sbx":
            return NumpyActor.from_sbx(self.model.policy.actor_state.params)
        return NumpyActor.from_sb3(self.model.actor)


# TD3 attributes copied from a checkpoint's JSON into an exported policy's metadata.
_RECORDED: Final = (
    "learning_rate",
    "buffer_size",
    "learning_starts",
    "batch_size",
    "tau",
    "gamma",
    "gradient_steps",
    "policy_delay",
    "target_policy_noise",
    "target_noise_clip",
    "policy_kwargs",
    "n_envs",
)


def _run_records(checkpoint: Path, steps: int) -> tuple[dict[str, Any], dict[str, Any] | None]:
    """What the run directory of a checkpoint records of it: its configuration files
    and the periodic evaluation at its step (None when there is none)."""
    training: dict[str, Any] = {}
    evaluation: dict[str, Any] | None = None
    for run in (checkpoint.parent, checkpoint.parent.parent):
        found = False
        for name, key in (("config.json", "run_config"), ("config_resume.json", "resume_config")):
            data = _read_json(run / name)
            if data:
                training[key] = data
                found = True
        log = run / "eval.jsonl"
        if log.is_file():
            for line in log.read_text().splitlines():
                row = json.loads(line) if line.strip() else None
                if isinstance(row, dict) and row.get("steps") == steps:
                    evaluation = {
                        "periodic": row,
                        "note": f"srfm train's evaluation at step {steps} (eval.jsonl)",
                    }
            found = True
        if found:
            break
    return training, evaluation


def export_policy(
    checkpoint: str | Path,
    out: str | Path,
    *,
    eval_seeds: int = 0,
    note: str | None = None,
    log: Callable[[str], None] | None = None,
) -> tuple[Path, Path]:
    """Export an SB3 or SBX TD3 checkpoint to a NumPy policy file (``.json`` + ``.npz``).

    The metadata records the checkpoint's EnvConfig, backend, steps and seed, its
    SHA-256, what its run directory holds (``config.json`` / ``config_resume.json``:
    the training configuration and command; the line of ``eval.jsonl`` at its step),
    and, with ``eval_seeds`` > 0, an evaluation of the exported actor on the evaluation
    scenarios with seeds ``EVAL_SEED_BASE`` … (disjoint from the benchmark's 0-99).

    The checkpoint is read with its library's loader, which unpickles: trusted files
    only. The written files load with NumPy only (:func:`srfm.planners.td3.load_numpy_policy`).

    Args:
        checkpoint: the checkpoint zip.
        out: the output name (its suffix is replaced by ``.json`` and ``.npz``).
        eval_seeds: seeds per evaluation scenario for the evaluation at export (0: none).
        note: free text recorded as ``training.note`` (e.g. how the run was made).
        log: called with one-line messages.

    Returns:
        The paths of the JSON and the NPZ written.

    Raises:
        PlannerError: an unreadable checkpoint or one without srfm configuration.
        MissingDependencyError: SB3 (or SBX) is not installed.
    """
    import hashlib
    import zipfile

    from srfm.planners.td3 import PolicyPlanner, load_checkpoint, save_numpy_policy
    from srfm.scenarios import EVALUATION_SCENARIOS

    say = log or (lambda message: None)
    checkpoint = Path(checkpoint)
    actor, config, info = load_checkpoint(checkpoint)
    records, evaluation = _run_records(checkpoint, info["steps"])
    training: dict[str, Any] = {
        **info,
        "source_checkpoint": checkpoint.name,
        "source_sha256": hashlib.sha256(checkpoint.read_bytes()).hexdigest(),
        **records,
    }
    # A checkpoint of a run that started from another run's checkpoint may carry that
    # run's seed (checkpoints written before srfm recorded the resuming run's seed):
    # the seed is that of the run that wrote it, as its config_resume.json says.
    resumed = records.get("resume_config", {}).get("train_config", {})
    if isinstance(resumed, dict) and isinstance(resumed.get("seed"), int):
        training["seed"] = resumed["seed"]
    # The hyperparameters SB3 records as plain JSON in the zip (the pickled ones skipped).
    with zipfile.ZipFile(checkpoint) as archive:
        data = json.loads(archive.read("data"))
    training["checkpoint_hyperparameters"] = {
        key: data[key]
        for key in _RECORDED
        if key in data and ":serialized:" not in json.dumps(data[key])
    }
    if note:
        training["note"] = note
    if eval_seeds > 0:
        seeds = list(range(EVAL_SEED_BASE, EVAL_SEED_BASE + eval_seeds))
        result = evaluate_planner(
            lambda: PolicyPlanner(actor, config, "policy"),
            EVALUATION_SCENARIOS,
            seeds,
            info["steps"],
        )
        evaluation = {
            **(evaluation or {}),
            "at_export": {**attrs.asdict(result), "seeds": [seeds[0], seeds[-1]]},
        }
        say(
            f"evaluation ({result.episodes} episodes, seeds {seeds[0]}-{seeds[-1]}): "
            f"success {result.success_rate:.2f}, collisions {result.collision_rate:.2f}, "
            f"timeouts {result.timeout_rate:.2f}, mean deviation {result.mean_deviation_m:.3f} m"
        )
    paths = save_numpy_policy(actor, config, out, training=training, evaluation=evaluation)
    say(f"exported {checkpoint} to {paths[0]} and {paths[1]}")
    return paths
