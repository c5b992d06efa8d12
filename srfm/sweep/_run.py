"""Running a sweep: every cell of the design a benchmark, into a partitioned Parquet
dataset.

The results folder holds ``sweep.json`` (the spec's identity: scenarios, planners,
seeds, base parameters, cells) and ``data/``, a Hive-partitioned Parquet dataset::

    data/cell=<id>/scenario=<name>/planner=<name>/seeds-<first>-<last>.parquet

one row per episode with the cell's id and factor values, the scenario, planner, seed,
outcome, end step and every episode metric of :data:`srfm.metrics.EPISODE_METRICS`
(NaN stored as null). A partition is one scheduled task (``seeds_per_task`` seeds of
one cell, scenario and planner): the worker simulates its episodes and returns the
file's bytes, and this process writes it atomically (temporary file, then rename), so
readers (pandas, polars, DuckDB, pyarrow) never see half a file, and the workers need
not share a file system with this machine. A re-run on the same folder runs only the
partitions that are missing (or damaged). Every byte depends only on the spec, so two
runs of the same spec give the same files whatever the executor and worker count.
"""

from __future__ import annotations

import collections
import io
import json
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any, Final

import attrs

from srfm._io import (
    MAX_DOCUMENT_BYTES,
    atomic_write_bytes,
    atomic_write_text,
    claim_output_folder,
    folder_lock,
    read_input_bytes,
    remove_stale_temporaries,
)
from srfm.errors import SweepError
from srfm.metrics.episode import EPISODE_METRICS
from srfm.models.params import SRFMParams
from srfm.scenarios import Scenario
from srfm.sim.budget import RunEstimate, check_run, estimate_run
from srfm.sim.episode import check_episode_memory
from srfm.sweep._spec import Cell, SweepSpec, apply_scenario_factors

__all__ = [
    "DATA_DIR",
    "SWEEP_MANIFEST",
    "SWEEP_SCHEMA",
    "SweepSummary",
    "estimate_sweep",
    "partition_path",
    "run_sweep",
]

SWEEP_SCHEMA: Final = "srfm.sweep/1"
SWEEP_MANIFEST: Final = "sweep.json"
DATA_DIR: Final = "data"
ID_COLUMNS: Final = ("cell", "scenario", "planner", "seed", "outcome", "end_step")
# What this process holds per task for the whole run (bytes): the task list, and on
# Dask the futures and the local scheduler's state as well.
_HELD_PER_TASK: Final = {"process": 1_000, "dask": 20_000}


@attrs.frozen
class _SweepTask:
    cell: Cell
    params: SRFMParams
    scenario: Scenario
    planner: str
    seeds: tuple[int, ...]

    @property
    def relative_path(self) -> str:
        return partition_path(self.cell.id, self.scenario.name, self.planner, self.seeds)


@attrs.frozen(kw_only=True)
class SweepSummary:
    """What a sweep run did.

    Attributes:
        out: the results folder.
        episodes: episodes in the sweep.
        simulated: episodes simulated by this run.
        partitions: partition files in the sweep.
        wall_time_s: wall time of the simulation part (s).
        rewritten: damaged partitions found and simulated again.
    """

    out: Path
    episodes: int
    simulated: int
    partitions: int
    wall_time_s: float
    rewritten: tuple[str, ...] = ()


def partition_path(cell: str, scenario: str, planner: str, seeds: tuple[int, ...]) -> str:
    """Path of one partition file, relative to the results folder."""
    return (
        f"{DATA_DIR}/cell={cell}/scenario={scenario}/planner={planner}/"
        f"seeds-{seeds[0]:06d}-{seeds[-1]:06d}.parquet"
    )


def _schema(factors: tuple[str, ...]) -> Any:
    import pyarrow as pa

    fields = [
        pa.field("cell", pa.string(), nullable=False),
        *[
            pa.field(f, pa.int64() if f == "crowd_size" else pa.float64(), nullable=False)
            for f in factors
        ],
        pa.field("scenario", pa.string(), nullable=False),
        pa.field("planner", pa.string(), nullable=False),
        pa.field("seed", pa.int64(), nullable=False),
        pa.field("outcome", pa.string(), nullable=False),
        pa.field("end_step", pa.int64(), nullable=False),
        *[pa.field(m.name, pa.float64()) for m in EPISODE_METRICS],
    ]
    return pa.schema(fields)


def _run_sweep_task(task: _SweepTask) -> tuple[str, int, bytes]:
    """Worker: simulate and score the task's episodes; return the partition's path,
    episode count and Parquet bytes."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    from srfm.metrics import episode_metrics
    from srfm.sim.episode import build_planner, run_episode

    values = task.cell.as_dict()
    factors = tuple(values)
    columns: dict[str, list[Any]] = {name: [] for name in _schema(factors).names}
    for seed in task.seeds:
        record = run_episode(
            task.scenario, seed, build_planner(task.planner), task.params, parallel=False
        )
        metrics = episode_metrics(record)
        columns["cell"].append(task.cell.id)
        for f in factors:
            columns[f].append(int(values[f]) if f == "crowd_size" else float(values[f]))
        columns["scenario"].append(task.scenario.name)
        columns["planner"].append(task.planner)
        columns["seed"].append(int(seed))
        columns["outcome"].append(metrics.outcome)
        columns["end_step"].append(int(metrics.end_step))
        for m in EPISODE_METRICS:
            v = float(metrics[m.name])
            columns[m.name].append(None if v != v else v)
    table = pa.table(columns, schema=_schema(factors))
    buffer = io.BytesIO()
    pq.write_table(table, buffer, compression="zstd")
    return task.relative_path, len(task.seeds), buffer.getvalue()


def _partition_ok(path: Path, task: _SweepTask) -> bool:
    """Whether ``path`` holds the task's finished partition (readable, the right rows)."""
    import pyarrow.parquet as pq

    try:
        table = pq.read_table(path)
    except (OSError, ValueError):
        return False
    if table.num_rows != len(task.seeds) or "seed" not in table.column_names:
        return False
    return (
        table.column("seed").to_pylist() == list(task.seeds)
        and set(table.column("cell").to_pylist()) == {task.cell.id}
        and set(table.column("planner").to_pylist()) == {task.planner}
    )


def all_tasks(spec: SweepSpec) -> list[_SweepTask]:
    """The sweep's tasks, in a fixed order (cell, scenario, planner, seed chunk)."""
    tasks = []
    n = spec.seeds_per_task
    for cell in spec.cells:
        params = spec.cell_params(cell)
        values = cell.as_dict()
        for scenario in spec.scenarios:
            cell_scenario = apply_scenario_factors(scenario, values)
            for planner in spec.planners:
                for k in range(0, len(spec.seeds), n):
                    seeds = spec.seeds[k : k + n]
                    tasks.append(_SweepTask(cell, params, cell_scenario, planner, seeds))
    return tasks


def _episode_kinds(spec: SweepSpec) -> Iterator[tuple[Scenario, int]]:
    """Every scenario of the sweep as its episodes run it (a random scenario once per
    crowd size of the design) and how many episodes run it: without building the tasks."""
    per_cell = len(spec.planners) * len(spec.seeds)
    sizes = collections.Counter(
        int(c.as_dict()["crowd_size"]) for c in spec.cells if "crowd_size" in spec.factors
    )
    for scenario in spec.scenarios:
        if sizes and scenario.random is not None:
            for size, cells in sorted(sizes.items()):
                yield apply_scenario_factors(scenario, {"crowd_size": size}), cells * per_cell
        else:
            yield scenario, len(spec.cells) * per_cell


def estimate_sweep(
    spec: SweepSpec, *, executor: str = "process", jobs: int = 1, remote: bool = False
) -> RunEstimate:
    """The time and memory of ``spec`` on ``jobs`` workers (:mod:`srfm.sim.budget`),
    from its size alone: every episode, whether or not a folder already holds it."""
    return estimate_run(
        _episode_kinds(spec),
        jobs=jobs,
        remote=remote,
        held_per_episode=_HELD_PER_TASK.get(executor, 20_000) / spec.seeds_per_task,
    )


def _manifest(spec: SweepSpec) -> dict[str, Any]:
    from srfm.benchmark._request import package_versions

    return {
        "schema": SWEEP_SCHEMA,
        "name": spec.name,
        "spec": str(spec.source),
        "versions": package_versions(),
        "metric_params": _metric_params(),
        **spec.identity(),
    }


def _metric_params() -> dict[str, Any]:
    from srfm.metrics import MetricParams

    return MetricParams().as_dict()


def _check_manifest(out: Path, spec: SweepSpec) -> dict[str, Any]:
    """The manifest to write: a new one, or the folder's when it matches the spec."""
    new = _manifest(spec)
    path = out / SWEEP_MANIFEST
    if not path.exists():
        return new
    data = read_input_bytes(
        path, max_bytes=MAX_DOCUMENT_BYTES * 16, error=SweepError, what="sweep manifest"
    )
    try:
        old = json.loads(data.decode("utf-8"))
    except (UnicodeDecodeError, ValueError, RecursionError) as exc:
        raise SweepError(f"{path}: damaged sweep manifest ({exc}); use a new folder") from None
    if not isinstance(old, dict) or old.get("schema") != SWEEP_SCHEMA:
        raise SweepError(f"{path}: not a sweep manifest of this srfm ({SWEEP_SCHEMA})")
    keys = ("versions", "metric_params", *spec.identity())
    for key in keys:
        if old.get(key) != new[key]:
            raise SweepError(
                f"{out} holds a sweep run with other {key} than {spec.source}; resume it "
                "with the spec it was started with, or give a new folder"
            )
    return new


def run_sweep(
    spec: SweepSpec,
    out: str | Path,
    *,
    executor: str = "process",
    jobs: int = 1,
    scheduler: str | None = None,
    scheduler_file: str | Path | None = None,
    on_start: Callable[[RunEstimate], None] | None = None,
    on_progress: Callable[[int], None] | None = None,
    force: bool = False,
) -> SweepSummary:
    """Run (or finish) a sweep into ``out``.

    Before anything is written: the executor and the scheduler are checked, and the
    largest episode's memory and the whole sweep's time and memory are estimated
    (:func:`estimate_sweep`; a sweep too large for this machine is refused unless
    ``force``).

    Args:
        spec: the sweep.
        out: results folder: new, empty, or a sweep folder of the same spec (resumed).
        executor, jobs, scheduler, scheduler_file: where the tasks run (see
            :func:`srfm.benchmark._runner.map_tasks`).
        on_start: called once with the sweep's estimate when every check has passed,
            before the first simulation.
        on_progress: called with the number of episodes finished since the last call
            (first with the number already present).
        force: write into a non-empty folder srfm did not create, and run a sweep too
            large for this machine's memory or the time limit
            (:func:`srfm.sim.budget.check_run`).

    Raises:
        SweepError: a folder of another sweep, or a damaged manifest.
        ResourceError: an episode that cannot fit in memory, or a sweep too large for
            this machine (without ``force``).
        OutputError, FolderInUseError, WriteError: as for ``srfm benchmark``.
    """
    from srfm.benchmark._runner import check_executor, map_tasks

    out = Path(out)
    check_executor(executor, jobs, scheduler, scheduler_file)
    remote = executor == "dask" and (scheduler is not None or scheduler_file is not None)
    kinds = list(_episode_kinds(spec))
    if not remote:
        for scenario, _ in kinds:
            check_episode_memory(scenario)  # one episode alone must fit
    estimate = estimate_sweep(spec, executor=executor, jobs=jobs, remote=remote)
    estimate = check_run(
        estimate,
        what=f"the sweep {spec.name!r}",
        smaller="fewer cells, scenarios, planners or seeds",
        force=force,
    )
    claim_output_folder(out, kind="sweep", force=force)
    with folder_lock(out):
        remove_stale_temporaries(out)
        manifest = _check_manifest(out, spec)
        atomic_write_text(out / SWEEP_MANIFEST, json.dumps(manifest, indent=2) + "\n")
        tasks = all_tasks(spec)
        pending, rewritten = [], []
        for task in tasks:
            path = out / task.relative_path
            if not path.exists():
                pending.append(task)
            elif not _partition_ok(path, task):
                pending.append(task)
                rewritten.append(task.relative_path)
        todo = sum(len(t.seeds) for t in pending)
        if on_start is not None:
            on_start(estimate)
        if on_progress is not None:
            on_progress(spec.episodes - todo)
        start = time.perf_counter()
        for relative, count, data in map_tasks(
            _run_sweep_task,
            pending,
            executor=executor,
            jobs=jobs,
            scheduler=scheduler,
            scheduler_file=scheduler_file,
        ):
            atomic_write_bytes(out / relative, data, fsync=False)
            if on_progress is not None:
                on_progress(count)
        wall = time.perf_counter() - start
    return SweepSummary(
        out=out,
        episodes=spec.episodes,
        simulated=todo,
        partitions=len(tasks),
        wall_time_s=wall,
        rewritten=tuple(rewritten),
    )
