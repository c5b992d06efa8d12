"""The noise floor files of a results folder: one per (scenario, seed).

``OUT/floor/<scenario>/seed-NNNNNN.json`` holds the floor of one (scenario, seed) under
the folder's parameters (:func:`srfm.sim.floor.nudged_twins`,
:func:`srfm.metrics.attribution.noise_floor`): the nudged pedestrian, the nudge and
each pedestrian's distance. It does not depend on a planner, so a folder computes it
once per (scenario, seed): in the task that runs the seed's planners, from the
counterfactual crowd their episodes simulate anyway (only the nudged copy is stepped),
or in a floor task of its own when every episode of the seed is done (a parameter
draw's folder has its own). Written atomically; a damaged file is computed again.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import attrs

from srfm._io import atomic_write_text
from srfm.errors import BenchmarkError
from srfm.metrics.attribution import noise_floor
from srfm.metrics.floor_files import FLOOR_SCHEMA, floor_path, read_floor
from srfm.models.params import SRFMParams
from srfm.scenarios import Scenario
from srfm.sim.floor import NudgedTwins, nudged_twins

__all__ = ["FloorTask", "floor_tasks", "missing_floors", "run_floor_task", "write_floor"]


@attrs.frozen
class FloorTask:
    """The floors of some seeds of one scenario, for a worker."""

    scenario: Scenario
    seeds: tuple[int, ...]
    params: SRFMParams
    out: str


def write_floor(out: Path, twins: NudgedTwins) -> None:
    """Write the floor file of one (scenario, seed) from its nudged twins."""
    values = noise_floor(twins)
    doc: dict[str, Any] = {
        "schema": FLOOR_SCHEMA,
        "scenario": twins.scenario,
        "seed": twins.seed,
        "nudged": twins.nudged,
        "nudge_m": twins.nudge_m,
        "floor_m": float(values.mean()),
        "frechet_m": [float(v) for v in values],
    }
    atomic_write_text(
        floor_path(out, twins.scenario, twins.seed), json.dumps(doc, indent=1) + "\n", fsync=False
    )


def run_floor_task(task: FloorTask) -> tuple[str, int, bool]:
    """Worker: compute and write the task's floors; returns (scenario, 0, False) like an
    episode task that adds no episode and no figure."""
    for seed in task.seeds:
        write_floor(Path(task.out), nudged_twins(task.scenario, seed, task.params))
    return task.scenario.name, 0, False


def missing_floors(
    out: Path, scenarios: Sequence[Scenario], seeds: Sequence[int]
) -> dict[str, tuple[int, ...]]:
    """Per scenario, the seeds whose floor file the folder still needs (a damaged file
    is computed again)."""
    missing = {}
    for scenario in scenarios:
        todo = []
        for seed in seeds:
            try:
                read_floor(floor_path(out, scenario.name, seed), expect=(scenario.name, seed))
            except BenchmarkError:
                todo.append(seed)
        missing[scenario.name] = tuple(todo)
    return missing


def floor_tasks(
    out: Path,
    scenarios: Sequence[Scenario],
    missing: dict[str, tuple[int, ...]],
    params: SRFMParams,
    chunk: int,
) -> list[FloorTask]:
    """Floor-only tasks for the ``missing`` seeds, ``chunk`` seeds a task: the seeds
    whose episodes are all done (an episode task computes the floor of its seeds from
    the counterfactual crowd it simulates anyway)."""
    tasks = []
    for scenario in scenarios:
        todo = missing.get(scenario.name, ())
        for k in range(0, len(todo), chunk):
            tasks.append(FloorTask(scenario, tuple(todo[k : k + chunk]), params, str(out)))
    return tasks
