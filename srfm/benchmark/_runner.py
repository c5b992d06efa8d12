"""The benchmark runner: scenarios × planners × seeds in worker processes, resumable.

Every finished episode is one small JSON file in ``OUT/episodes/`` written atomically
(temporary file, then rename), so an interrupted run loses at most the episodes that
were being simulated, and a re-run on the same folder skips every valid file that
exists (a damaged one is simulated again). Tables, CSV files and figures are rebuilt
from those files at the end of each run, in a fixed order, so the same request gives
byte-identical tables; they are replaced as a whole (:func:`srfm._io.write_file_set`).

A run holds the folder's lock (:func:`srfm._io.folder_lock`) from before it touches
anything until its reports are written, so a second run on the same folder is refused
instead of deleting the first one's temporaries. It writes only into a new or empty
folder, or one srfm made for a benchmark (unless ``force``).
"""

from __future__ import annotations

import collections
import contextlib
import functools
import json
import multiprocessing
import os
import sys
import time
from collections.abc import Callable, Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any, Final

import attrs

from srfm._io import (
    atomic_write_text,
    claim_output_folder,
    folder_lock,
    recover_file_set,
    remove_stale_temporaries,
    write_file_set,
)
from srfm._text import plain
from srfm.benchmark._dask import check_scheduler, map_on_dask
from srfm.benchmark._draws import ParamDraws, check_param_draws, draw_folder, render_rankings
from srfm.benchmark._floor import (
    FloorTask,
    floor_tasks,
    missing_floors,
    run_floor_task,
    write_floor,
)
from srfm.benchmark._html import REPORT, render_report
from srfm.benchmark._models import (
    ROBUSTNESS_JSON,
    ROBUSTNESS_MD,
    ResponseModels,
    check_models,
    folder_models,
    model_folder,
    robustness,
    robustness_document,
    robustness_markdown,
)
from srfm.benchmark._request import MANIFEST, BenchmarkRequest, check_manifest
from srfm.benchmark._results import episode_path, read_episode, write_episode
from srfm.benchmark._workers import init_worker
from srfm.benchmark.figures import (
    paths_figure_name,
    render_figures,
    render_paths_figure,
    save_figure_episode,
)
from srfm.errors import BenchmarkError, SrfmError
from srfm.metrics import EpisodeMetrics, episode_metrics
from srfm.metrics.floor_files import load_floors
from srfm.metrics.report import render_tables
from srfm.models.params import SRFMParams
from srfm.planners.external import is_external
from srfm.scenarios import Scenario
from srfm.sim.budget import RunEstimate, check_run, estimate_run
from srfm.sim.episode import (
    build_planner,
    check_episode_memory,
    first_command,
    run_episode,
    run_planners,
)
from srfm.sim.floor import nudged_twins
from srfm.sim.record import EpisodeRecord

__all__ = [
    "EXECUTORS",
    "BenchmarkSummary",
    "EpisodeWriter",
    "check_executor",
    "estimate_benchmark",
    "load_results",
    "map_tasks",
    "run_benchmark",
    "write_reports",
]

EXECUTORS: Final = ("process", "dask")
_CHUNK: Final = 5  # episodes per worker task at least: few enough for a smooth progress bar
_HELPER_TIMEOUT_S: Final = 900.0  # the warm-up helper's time limit (_compile_in_parent)
# What this process holds per episode for the whole run (bytes, tracemalloc): its share
# of the task list and, in the report phase, its metrics (plus 2 kB per pedestrian).
_HELD_PER_EPISODE: Final = 5_200
_HELD_PER_PEDESTRIAN: Final = 2_000


@attrs.frozen(kw_only=True)
class BenchmarkSummary:
    """What a run did.

    Attributes:
        out: the results folder.
        episodes: episodes in the request.
        simulated: episodes simulated by this run (the rest were already there).
        wall_time_s: wall time of the simulation part (s).
        files: the files of the results written, relative to ``out``: the report
            files (tables, CSV and Parquet files, summary, figures, report.html), then
            manifest.json (the episode files and logs are in episodes/ and logs/).
        resimulated: damaged episode files found and simulated again.
        jobs: worker processes used at most (fewer than asked when memory is short).
        draws: the number of parameter draws the run added (``param_draws``); their
            episodes are counted in ``episodes`` and ``simulated``.
    """

    out: Path
    episodes: int
    simulated: int
    wall_time_s: float
    files: tuple[str, ...]
    resimulated: tuple[str, ...] = ()
    jobs: int = 1
    draws: int = 0


_SUMMARY: Final = "summary.json"

EpisodeWriter = Callable[[Path, EpisodeRecord, EpisodeMetrics], None]
"""Called in the worker after each episode, before its metrics file is written, with the
results folder, the record and its metrics: the hook for episode logs (.rrd, .mcap).
It must be picklable (a module-level function or an instance of a module-level class)."""


@attrs.frozen
class _Task:
    """Episodes of one scenario for a worker: for each seed, the planners to run (all
    of the request's but those a resumed run has already)."""

    scenario: Scenario
    episodes: tuple[tuple[int, tuple[str, ...]], ...]  # (seed, its planners)
    params: SRFMParams
    out: str
    writer: EpisodeWriter | None
    figure_seed: int | None
    floor_seeds: frozenset[int] = frozenset()  # seeds whose noise floor it computes too

    @property
    def size(self) -> int:
        """The number of episodes."""
        return sum(len(planners) for _, planners in self.episodes)

    @property
    def has_figure(self) -> bool:
        """Whether one of its episodes is a path figure's."""
        return any(seed == self.figure_seed for seed, _ in self.episodes)


@attrs.frozen
class _Start:
    """One planner's first episode of a task, for the warm-up (:func:`_compile_in_parent`)."""

    scenario: Scenario
    planner: str
    seed: int
    params: SRFMParams


def _run_task(task: _Task) -> tuple[str, int, bool]:
    """Worker: simulate and score the task's episodes, one atomic file each. Returns
    the scenario's name, the number of episodes and whether one of them is a path
    figure's (saved for it).

    A seed's planners run through :func:`srfm.sim.episode.run_planners`, which
    simulates the counterfactual crowd (the same for every planner) once for all of
    them: the same records as one :func:`run_episode` each, at less cost."""
    out = Path(task.out)
    for seed, planners in task.episodes:
        # Planners are built by name (also a module:attribute spec), so the record and
        # its metrics file carry the requested name.
        records = run_planners(task.scenario, seed, planners, task.params, parallel=False)
        for k, record in enumerate(records):
            if k == 0 and seed in task.floor_seeds:  # the floor's reference crowd, shared
                twins = nudged_twins(
                    task.scenario, seed, task.params, reference=record.counterfactual_pos
                )
                write_floor(out, twins)
            metrics = episode_metrics(record)
            if task.writer is not None:
                task.writer(out, record, metrics)
            if seed == task.figure_seed:
                save_figure_episode(out, record)
            write_episode(out, metrics)  # last: an episode counts as done once this exists
    return task.scenario.name, task.size, task.has_figure


def _run_any(task: _Task | FloorTask) -> tuple[str, int, bool]:
    """Worker: an episode task (:func:`_run_task`) or a noise floor task
    (:func:`srfm.benchmark._floor.run_floor_task`)."""
    if isinstance(task, FloorTask):
        return run_floor_task(task)
    return _run_task(task)


def _warm_up(task: _Start, *, metrics: bool = True) -> EpisodeRecord | None:
    """One two-step episode of ``task``'s planner on its scenario, with its parameters,
    and (``metrics``) its metrics: compiles (or loads from numba's cache) every kernel
    such an episode calls. Nothing is written. Returns the record (None on an error,
    which is left for the worker to report in its own words)."""
    short = attrs.evolve(task.scenario, horizon_steps=min(2, task.scenario.horizon_steps))
    try:
        record = run_episode(short, task.seed, build_planner(task.planner), task.params)
        if metrics:
            episode_metrics(record)
    except SrfmError:
        return None
    return record


def _warm_up_planner(task: _Start) -> None:
    """Compile (or load) ``task``'s planner's own kernels and the observation's, but not
    the crowd's: the planner's first command on its scenario
    (:func:`srfm.sim.episode.first_command`). Errors are left for the worker."""
    # Any error (a user's planner raises what it likes) is left for the worker, which
    # reports it in its own words; here it only means nothing is compiled.
    with contextlib.suppress(Exception):
        first_command(task.scenario, task.seed, task.planner, task.params)


def _warm_up_shared(
    groups: Sequence[Sequence[_Start]], counter: Any, warm_up: Callable[[_Start], object]
) -> None:
    """``warm_up`` the planner groups whose index this process draws from ``counter``
    (a shared ``multiprocessing.Value``), until none is left."""
    while True:
        with counter.get_lock():
            k = counter.value
            counter.value += 1
        if k >= len(groups):
            return
        for task in groups[k]:
            warm_up(task)


def _compile_in_parent(tasks: Sequence[_Task]) -> None:
    """Compile, before the workers are forked, the kernels the tasks will call.

    :func:`_warm_up` of each planner the tasks name (on the scenario of its first
    task): the crowd, robot, event, planner and metric kernels are then compiled (or
    loaded from numba's cache) once, here, and every forked worker inherits them
    instead of compiling its own copies, which with an empty cache cost each worker as
    much as the whole set. Only the kernels of the requested planners are compiled.
    Nothing is written but numba's cache.

    On two cores at once, from the start: a forked helper process compiles the
    planners' own kernels (:func:`_warm_up_planner`: each planner's first command,
    without stepping the crowd), while this process compiles the crowd, robot and
    metric kernels, which every episode needs, with a two-step episode of the
    ``straight`` planner (which adds no kernel of its own) and its metrics; then this
    process joins in on the planners. Both take the planners' classes (planners of one
    class, such as td3-base and td3-srfm, share their kernels) one at a time from a
    shared counter until none is left. Once the helper is done, this process warms up
    every planner with its metrics, which loads what the helper compiled from numba's
    on-disk cache. Should the helper fail or nothing be cached, this process compiles
    it all itself: slower, never different.

    Measured (docs/performance.md, "First run with an empty numba cache"): the earlier
    order (the crowd kernels first, alone, then the helper) left the second core idle
    for the first 5-6 s of a cold run.
    """
    first: dict[str, _Start] = {}
    for task in tasks:
        for seed, planners in task.episodes:
            for planner in planners:
                if not is_external(planner):  # its process is its own: nothing to compile
                    first.setdefault(planner, _Start(task.scenario, planner, seed, task.params))
    if not tasks:
        return
    some = tasks[0]
    straight = _Start(some.scenario, "straight", some.episodes[0][0], some.params)
    straight = attrs.evolve(next(iter(first.values()), straight), planner="straight")
    groups: dict[type, list[_Start]] = {}
    for name, start in first.items():
        if name != "straight":
            groups.setdefault(type(build_planner(name)), []).append(start)
    ordered = list(groups.values())
    if not ordered:
        _warm_up(straight)
    else:
        context = multiprocessing.get_context("fork")
        counter = context.Value("i", 0)
        helper = context.Process(
            target=_warm_up_shared, args=(ordered, counter, _warm_up_planner), daemon=True
        )
        helper.start()
        try:
            _warm_up(straight)  # the crowd, robot and metric kernels
            _warm_up_shared(ordered, counter, functools.partial(_warm_up, metrics=False))
        finally:
            helper.join(timeout=_HELPER_TIMEOUT_S)
            if helper.is_alive():  # stuck: what it had not compiled, the loop below does
                helper.terminate()
                helper.join()
    for start in (straight, *first.values()):
        _warm_up(start)


class _EarlyFigures:
    """The path figures drawn while the episodes run: this process only waits for the
    workers then, so a scenario's figure is drawn as soon as the last task holding one
    of its figure episodes is done (the report phase draws the others; the same bytes).
    On two cores this takes the figures, 1-1.5 s of CPU each, off the end of the run."""

    def __init__(self, out: Path, request: BenchmarkRequest, tasks: Sequence[_Task]) -> None:
        self.out = out
        self.request = request
        self.figures: dict[str, bytes] = {}
        self._pending = collections.Counter(t.scenario.name for t in tasks if t.has_figure)
        self._scenarios = {s.name: s for s in request.scenarios}

    def task_done(self, scenario: str) -> None:
        """A task with a figure episode of ``scenario`` is done: draw the scenario's
        figure if it was the last. A failure is left to the report phase, which draws
        the figure again and reports it in its own words."""
        self._pending[scenario] -= 1
        if self._pending[scenario] != 0:
            return
        with contextlib.suppress(Exception):
            self.figures[paths_figure_name(scenario)] = render_paths_figure(
                self.out, self.request, self._scenarios[scenario]
            )


def check_executor(
    executor: str, jobs: int, scheduler: str | None, scheduler_file: str | Path | None
) -> None:
    """Refuse an unknown executor, fewer than one job, a scheduler without Dask, or a
    scheduler address or file Dask cannot use (:func:`srfm.benchmark._dask.check_scheduler`):
    before anything is written.

    Raises:
        BenchmarkError: naming the bad value.
        MissingDependencyError: ``dask`` without the ``dask`` extra.
    """
    if jobs < 1:
        raise BenchmarkError(f"jobs must be at least 1, got {jobs}")
    if executor not in EXECUTORS:
        raise BenchmarkError(f"unknown executor {plain(executor)}; known: {', '.join(EXECUTORS)}")
    if executor != "dask" and (scheduler is not None or scheduler_file is not None):
        raise BenchmarkError("--scheduler and --scheduler-file need --executor dask")
    if executor == "dask":
        check_scheduler(scheduler, scheduler_file)


def map_tasks(
    run: Callable[[Any], Any],
    tasks: Sequence[Any],
    *,
    executor: str = "process",
    jobs: int = 1,
    scheduler: str | None = None,
    scheduler_file: str | Path | None = None,
) -> Iterator[Any]:
    """Run ``run(task)`` for every task and yield the results as they complete.

    The one place that chooses where tasks run (the benchmark and the sweep use it):
    ``"process"`` runs them in this process (``jobs == 1``) or on a local process pool
    of one-thread workers; ``"dask"`` on a Dask cluster (:mod:`srfm.benchmark._dask`:
    a ``LocalCluster`` of ``jobs`` workers, or the running one at ``scheduler`` /
    ``scheduler_file``). The order of the results is the order of completion: callers
    must not depend on it.
    """
    check_executor(executor, jobs, scheduler, scheduler_file)
    if not tasks:
        return
    if executor == "dask":
        yield from map_on_dask(
            run,
            tasks,
            workers=min(jobs, len(tasks)),
            scheduler=scheduler,
            scheduler_file=scheduler_file,
        )
    elif jobs == 1:
        for task in tasks:
            yield run(task)
    else:
        context = multiprocessing.get_context("fork" if sys.platform != "win32" else "spawn")
        with context.Pool(min(jobs, len(tasks)), initializer=init_worker) as pool:
            yield from pool.imap_unordered(run, tasks)


def _is_done(path: Path, expect: tuple[str, str, int], damaged: list[str]) -> bool:
    """Whether ``path`` holds the finished episode ``expect``; a damaged file (truncated,
    edited, of another episode) is listed in ``damaged`` and simulated again."""
    if not path.exists():
        return False
    try:
        read_episode(path, expect=expect)
    except BenchmarkError:
        damaged.append(str(path))
        return False
    return True


def _pending_tasks(
    out: Path,
    request: BenchmarkRequest,
    writer: EpisodeWriter | None,
    figures: bool,
    damaged: list[str],
    missing_floors: Mapping[str, Sequence[int]],
) -> list[_Task]:
    """The episode tasks a folder still needs; each also computes the noise floor of
    its seeds that ``missing_floors`` names."""
    figure_seed = request.drawn_seed if figures else None
    tasks = []
    for scenario in request.scenarios:
        todo: list[tuple[int, tuple[str, ...]]] = []
        for seed in request.seeds:
            planners = tuple(
                p
                for p in request.planners
                if not _is_done(
                    episode_path(out, scenario.name, p, seed), (scenario.name, p, seed), damaged
                )
            )
            if planners:
                todo.append((seed, planners))
        # A task: a seed's planners together (they share the counterfactual crowd),
        # seeds added up to _CHUNK episodes.
        chunk: list[tuple[int, tuple[str, ...]]] = []
        for k, item in enumerate(todo):
            chunk.append(item)
            if sum(len(p) for _, p in chunk) >= _CHUNK or k == len(todo) - 1:
                seeds = {seed for seed, _ in chunk}
                floors = frozenset(seeds.intersection(missing_floors.get(scenario.name, ())))
                tasks.append(
                    _Task(
                        scenario, tuple(chunk), request.params, str(out), writer, figure_seed,
                        floors,
                    )
                )  # fmt: skip
                chunk = []
    return tasks


def _log_options(writer: EpisodeWriter | None) -> dict[str, bool]:
    """Which logs ``writer`` writes (an :class:`srfm.logs.EpisodeLogger` says so in its
    ``options``), for the memory estimate."""
    options = getattr(writer, "options", None)
    if options is None:
        return {}
    rrd = bool(getattr(options, "rrd", False))
    return {
        "mcap": bool(getattr(options, "mcap", False)),
        "rrd": rrd,
        "forces": rrd and bool(getattr(options, "forces", False)),
    }


def estimate_benchmark(
    request: BenchmarkRequest,
    *,
    jobs: int,
    remote: bool = False,
    writer: EpisodeWriter | None = None,
    draws: int = 0,
) -> RunEstimate:
    """The time and memory of ``request`` on ``jobs`` workers (:mod:`srfm.sim.budget`):
    every episode of the request, whether or not a folder already holds it, and again
    under each of ``draws`` parameter draws."""
    per_scenario = len(request.planners) * len(request.seeds) * (1 + draws)
    return estimate_run(
        ((s, per_scenario) for s in request.scenarios),
        jobs=jobs,
        remote=remote,
        logs=_log_options(writer),
        held_per_episode=_HELD_PER_EPISODE,
        held_per_pedestrian=_HELD_PER_PEDESTRIAN,
    )


def run_benchmark(
    request: BenchmarkRequest,
    out: str | Path,
    *,
    jobs: int | None = None,
    on_start: Callable[[RunEstimate], None] | None = None,
    on_progress: Callable[[int], None] | None = None,
    figures: bool = True,
    writer: EpisodeWriter | None = None,
    force: bool = False,
    command: str | None = None,
    executor: str = "process",
    scheduler: str | None = None,
    scheduler_file: str | Path | None = None,
    param_draws: ParamDraws | None = None,
    models: ResponseModels | None = None,
) -> BenchmarkSummary:
    """Run (or finish) a benchmark into ``out`` and write its reports.

    Before anything is written: the executor and the scheduler are checked, the
    episodes' memory is estimated (the pool is made smaller when ``jobs`` episodes
    would not fit side by side), and so are the whole run's time and memory
    (:func:`estimate_benchmark`; a run too large for this machine is refused unless
    ``force``). Then, before any simulation: the folder is claimed (new, empty, or
    srfm's benchmark folder; any other non-empty folder only with ``force``) and
    locked, a report set cut short by a kill is completed, stale temporaries are
    removed and the manifest is checked.

    Args:
        request: scenarios, planners, seeds and parameters.
        out: results folder; created if missing, resumed if it holds an earlier run.
        jobs: worker processes (default: the number of CPUs; 1 runs in this process).
        on_start: called once with the run's estimate when every check has passed,
            before the first simulation (where the command line starts its output).
        on_progress: called with the number of episodes finished since the last call
            (first with the number already present).
        figures: also draw the PNG figures.
        writer: optional per-episode hook (see :data:`EpisodeWriter`), e.g. log files.
        force: write into a non-empty folder srfm did not create, and run a request
            too large for this machine's memory or the time limit
            (:func:`srfm.sim.budget.check_run`).
        command: the command line that asked for this run, kept in the manifest and
            shown on the results page.
        executor: ``"process"`` (a local process pool of ``jobs`` workers) or
            ``"dask"`` (a Dask cluster: a ``distributed.LocalCluster`` of ``jobs``
            workers, or the running one at ``scheduler`` / ``scheduler_file``; see
            :mod:`srfm.benchmark._dask`). The results are the same bytes either way.
        scheduler: address of a running Dask scheduler (``executor="dask"``).
        scheduler_file: scheduler file of a running Dask scheduler (``executor="dask"``).
        param_draws: run every episode again under each of these parameter sets
            (:mod:`srfm.benchmark._draws`), each draw into a results folder of its own,
            ``out/draws/draw-NNN`` (no logs, no figures), and add the planners' rank
            probabilities over the draws to the reports (``rankings.md``,
            ``rankings.json``, ``report.html``).
        models: response models (:mod:`srfm.benchmark._models`): the first must be
            ``request.params`` (the folder's own results); every episode runs again
            under each other model, into ``out/models/<name>`` (no logs, no figures),
            and the reports add which orderings of planners hold under every model
            (``robustness.md``, ``robustness.json``, ``summary.json``, ``report.html``).

    Returns:
        A :class:`BenchmarkSummary`.

    Raises:
        BenchmarkError: a folder of another run (parameters, versions, scenario content)
            or a damaged manifest.
        OutputError: a non-empty folder srfm did not create (without ``force``).
        FolderInUseError: another srfm process is running on ``out``.
        ResourceError: one episode would not fit in memory, or the run is too large
            for this machine (without ``force``).
        WriteError: the folder cannot be written.
        UserCodeError: a user's planner raised.
    """
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise BenchmarkError(f"--out {out} exists and is not a folder")
    if jobs is None:
        jobs = os.cpu_count() or 1
    check_executor(executor, jobs, scheduler, scheduler_file)
    logs = _log_options(writer)
    for scenario in request.scenarios:
        jobs = check_episode_memory(scenario, jobs=jobs, **logs)
    remote = executor == "dask" and (scheduler is not None or scheduler_file is not None)
    n_draws = 0 if param_draws is None else len(param_draws.params)
    others = () if models is None else tuple(zip(models.names, models.params, strict=True))[1:]
    if models is not None and models.params[0] != request.params:
        raise BenchmarkError("the first response model must be the request's parameters")
    estimate = estimate_benchmark(
        request, jobs=jobs, remote=remote, writer=writer, draws=n_draws + len(others)
    )
    estimate = check_run(
        estimate, what="the benchmark", smaller="fewer scenarios, planners or seeds", force=force
    )
    claim_output_folder(out, kind="benchmark", force=force, legacy_markers=(MANIFEST,))
    with folder_lock(out):
        recover_file_set(out)  # a report set cut short by a kill: finish it first
        remove_stale_temporaries(out)
        manifest = check_manifest(out, request, command)
        if param_draws is not None:  # other draws are refused before anything is written
            check_param_draws(out, param_draws)
        if models is not None:  # so are other models
            check_models(out, models)
        drawn_params = param_draws.params if param_draws is not None else ()
        folders = [
            *((draw_folder(out, k), p) for k, p in enumerate(drawn_params)),
            *((model_folder(out, name), p) for name, p in others),
        ]
        for folder, params in folders:
            # each draw's (model's) folder as its own run below checks it, before on_start
            claim_output_folder(folder, kind="benchmark", force=force, legacy_markers=(MANIFEST,))
            check_manifest(folder, attrs.evolve(request, params=params), command)
        atomic_write_text(out / MANIFEST, json.dumps(manifest, indent=2, sort_keys=True) + "\n")
        damaged: list[str] = []
        missing = missing_floors(out, request.scenarios, request.seeds)
        tasks = _pending_tasks(out, request, writer, figures, damaged, missing)
        for task in tasks:  # what the episode tasks compute is left for floor tasks no more
            name = task.scenario.name
            missing[name] = tuple(s for s in missing[name] if s not in task.floor_seeds)
        floors = floor_tasks(out, request.scenarios, missing, request.params, _CHUNK)
        cells = len(request.scenarios) * len(request.planners) * len(request.seeds)
        total = cells * (1 + n_draws + len(others))
        pending = sum(t.size for t in tasks)
        if on_start is not None:
            on_start(estimate)
        if on_progress is not None:
            on_progress(cells - pending)
        start = time.perf_counter()
        drawn = _EarlyFigures(out, request, tasks)
        if tasks or floors:
            if tasks and executor == "process" and jobs > 1 and sys.platform != "win32":
                _compile_in_parent(tasks)  # the forked workers (map_tasks) inherit them
            for scenario, done, figure in map_tasks(
                _run_any,
                [*tasks, *floors],
                executor=executor,
                jobs=jobs,
                scheduler=scheduler,
                scheduler_file=scheduler_file,
            ):
                if on_progress is not None:
                    on_progress(done)
                if figure:
                    drawn.task_done(scenario)
        for folder, params in folders:
            draw = run_benchmark(
                attrs.evolve(request, params=params),
                folder,
                jobs=jobs,
                on_progress=on_progress,
                figures=False,
                force=force,  # each draw is smaller than the whole, checked above
                command=command,
                executor=executor,
                scheduler=scheduler,
                scheduler_file=scheduler_file,
            )
            pending += draw.simulated
            damaged += draw.resimulated
        wall = time.perf_counter() - start
        files = _write_reports(out, request, figures=figures, drawn=drawn.figures)
    return BenchmarkSummary(
        out=out,
        episodes=total,
        simulated=pending,
        wall_time_s=wall,
        files=(*files, MANIFEST),
        resimulated=tuple(damaged),
        jobs=jobs,
        draws=n_draws,
    )


def load_results(out: Path, request: BenchmarkRequest) -> list[EpisodeMetrics]:
    """The request's episode metrics from ``out``, in (scenario, planner, seed) order.

    Raises:
        BenchmarkError: a missing or damaged episode file (the message names it).
    """
    results = []
    for scenario in request.scenarios:
        for planner in request.planners:
            for seed in request.seeds:
                path = episode_path(out, scenario.name, planner, seed)
                if not path.exists():
                    raise BenchmarkError(f"{path} is missing: run the benchmark to finish it")
                results.append(read_episode(path, expect=(scenario.name, planner, seed)))
    return results


def write_reports(out: Path, request: BenchmarkRequest, *, figures: bool = True) -> tuple[str, ...]:
    """Write the tables, CSV and Parquet files, JSON summary, figures and results page
    from the episode files, as a whole, holding the folder's lock."""
    out = Path(out)
    with folder_lock(out):
        recover_file_set(out)
        return _write_reports(out, request, figures=figures)


def _write_reports(
    out: Path,
    request: BenchmarkRequest,
    *,
    figures: bool,
    drawn: Mapping[str, bytes] | None = None,
) -> tuple[str, ...]:
    """Every report rendered in memory first, then replaced as one set: a full disk or
    a kill never leaves tables of one run beside CSV files of another. ``drawn``: the
    path figures already rendered (:class:`_EarlyFigures`)."""
    results = load_results(out, request)
    names = [s.name for s in request.scenarios]
    files, tables = render_tables(
        results,
        scenarios=names,
        planners=request.planners,
        seeds=request.seeds,
        params=request.params,
        reference=request.reference,
        floors=load_floors(out, names, request.seeds),
    )
    if figures:
        files.update(
            render_figures(
                out, request, tables.table, tables.extended, drawn=drawn, suite=tables.suite
            )
        )
    files.update(
        render_rankings(out, [s.name for s in request.scenarios], request.planners, request.seeds)
    )
    files.update(render_robustness(out, request, results, files))
    files[REPORT] = render_report(out, files)
    write_file_set(out, files)
    return tuple(files)


def render_robustness(
    out: Path,
    request: BenchmarkRequest,
    results: Sequence[EpisodeMetrics],
    files: Mapping[str, bytes],
) -> dict[str, bytes]:
    """``robustness.md``, ``robustness.json`` and ``summary.json`` with its
    ``robustness`` entry, once every response model of the folder is finished for this
    request (:mod:`srfm.benchmark._models`); nothing for a folder of one model or while
    one is unfinished."""
    names = folder_models(out)
    if names is None:
        return {}
    per_model = [results]
    for name in names[1:]:
        try:
            per_model.append(load_results(model_folder(out, name), request))
        except BenchmarkError:  # not finished: the reports of the run's own model only
            return {}
    table = robustness(
        per_model,
        models=names,
        scenarios=[s.name for s in request.scenarios],
        planners=request.planners,
        n_seeds=len(request.seeds),
    )
    doc = robustness_document(table)
    summary = json.loads(files[_SUMMARY])
    summary["robustness"] = doc
    return {
        ROBUSTNESS_MD: robustness_markdown(table).encode("utf-8"),
        ROBUSTNESS_JSON: (json.dumps(doc, indent=1) + "\n").encode("utf-8"),
        _SUMMARY: (json.dumps(summary, indent=1) + "\n").encode("utf-8"),
    }
