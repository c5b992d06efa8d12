"""The noise floor files of a results folder: one per (scenario, seed).

``OUT/floor/<scenario>/seed-NNNNNN.json`` holds the floor of one (scenario, seed) under
the folder's parameters (:func:`srfm.sim.floor.nudged_twins`,
:func:`srfm.metrics.attribution.noise_floor`): the nudged pedestrian, the nudge and
each pedestrian's distance. It does not depend on a planner, so a folder computes it
once per (scenario, seed), beside the planners' episodes (a parameter draw's folder
has its own). Written atomically; a damaged file is computed again.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any, Final

import attrs

from srfm import _validate
from srfm._io import MAX_DOCUMENT_BYTES, atomic_write_text, read_input_bytes
from srfm._validate import path_name
from srfm.errors import BenchmarkError
from srfm.metrics.attribution import noise_floor
from srfm.models.params import SRFMParams
from srfm.scenarios import Scenario
from srfm.sim.floor import nudged_twins

__all__ = [
    "FLOOR_DIR",
    "FloorTask",
    "floor_path",
    "load_floors",
    "pending_floors",
    "read_floor",
    "run_floor_task",
]

FLOOR_DIR: Final = "floor"
FLOOR_SCHEMA: Final = "srfm.noise_floor/1"


def floor_path(out: Path, scenario: str, seed: int) -> Path:
    """Where the floor of one (scenario, seed) lives inside a results folder.

    Raises:
        BenchmarkError: a name that cannot be a folder name, or a bad seed.
    """
    path_name(scenario, "scenario name", BenchmarkError)
    seed = _validate.seed(seed, BenchmarkError)
    return out / FLOOR_DIR / scenario / f"seed-{seed:06d}.json"


def read_floor(path: Path, *, expect: tuple[str, int]) -> float:
    """The floor (m) stored at ``path`` for (scenario, seed) ``expect``.

    Raises:
        BenchmarkError: unreadable, damaged or of another (scenario, seed).
    """
    data = read_input_bytes(
        path, max_bytes=MAX_DOCUMENT_BYTES, error=BenchmarkError, what="noise floor file"
    )
    try:
        doc = json.loads(data.decode("utf-8"))
    except (UnicodeDecodeError, ValueError, RecursionError) as exc:
        raise BenchmarkError(f"{path}: damaged noise floor file ({exc}); delete it") from None
    problem = None
    if not isinstance(doc, dict) or doc.get("schema") != FLOOR_SCHEMA:
        problem = f"schema {doc.get('schema') if isinstance(doc, dict) else None!r}"
    elif (doc.get("scenario"), doc.get("seed")) != tuple(expect):
        problem = f"holds {(doc.get('scenario'), doc.get('seed'))}, not {tuple(expect)}"
    else:
        values = doc.get("frechet_m")
        floor = doc.get("floor_m")
        if (
            not isinstance(values, list)
            or not values
            or not all(isinstance(v, float | int) and math.isfinite(v) for v in values)
            or not isinstance(floor, float | int)
            or not math.isclose(floor, sum(values) / len(values), rel_tol=1e-12, abs_tol=1e-300)
        ):
            problem = "its values do not add up"
    if problem is not None:
        raise BenchmarkError(f"{path}: damaged noise floor file: {problem}; delete it")
    return float(doc["floor_m"])


@attrs.frozen
class FloorTask:
    """The floors of some seeds of one scenario, for a worker."""

    scenario: Scenario
    seeds: tuple[int, ...]
    params: SRFMParams
    out: str


def run_floor_task(task: FloorTask) -> tuple[str, int, bool]:
    """Worker: compute and write the task's floors; returns (scenario, 0, False) like an
    episode task that adds no episode and no figure."""
    out = Path(task.out)
    for seed in task.seeds:
        twins = nudged_twins(task.scenario, seed, task.params)
        values = noise_floor(twins)
        doc: dict[str, Any] = {
            "schema": FLOOR_SCHEMA,
            "scenario": task.scenario.name,
            "seed": seed,
            "nudged": twins.nudged,
            "nudge_m": twins.nudge_m,
            "floor_m": float(values.mean()),
            "frechet_m": [float(v) for v in values],
        }
        atomic_write_text(
            floor_path(out, task.scenario.name, seed), json.dumps(doc, indent=1) + "\n", fsync=False
        )
    return task.scenario.name, 0, False


def pending_floors(
    out: Path, scenarios: Sequence[Scenario], seeds: Sequence[int], params: SRFMParams, chunk: int
) -> list[FloorTask]:
    """The floor tasks a folder still needs (a damaged file is computed again)."""
    tasks = []
    for scenario in scenarios:
        todo = []
        for seed in seeds:
            path = floor_path(out, scenario.name, seed)
            try:
                read_floor(path, expect=(scenario.name, seed))
            except BenchmarkError:
                todo.append(seed)
        for k in range(0, len(todo), chunk):
            tasks.append(FloorTask(scenario, tuple(todo[k : k + chunk]), params, str(out)))
    return tasks


def load_floors(
    out: Path, scenarios: Sequence[str], seeds: Sequence[int]
) -> Mapping[str, list[float]] | None:
    """Per scenario, the floor of each seed in seed order; None when a file is missing
    (a folder from before the floors, or ``srfm score``'s logs)."""
    floors: dict[str, list[float]] = {}
    for scenario in scenarios:
        values = []
        for seed in seeds:
            path = floor_path(out, scenario, seed)
            if not path.is_file():
                return None
            values.append(read_floor(path, expect=(scenario, seed)))
        floors[scenario] = values
    return floors
