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
from srfm.sim.floor import nudged_twins

__all__ = ["FloorTask", "pending_floors", "run_floor_task"]


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
