"""The noise floor files of a results folder: ``OUT/floor/<scenario>/seed-NNNNNN.json``,
one per (scenario, seed) (:mod:`srfm.benchmark._floor` writes them; the reports and
``srfm score``, for logs inside a results folder, read them). Each holds the nudged
pedestrian, the nudge, every pedestrian's Fréchet distance between the nudged and the
unnudged crowd and their mean, the floor (:mod:`srfm.metrics.attribution`).
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Final

from srfm import _validate
from srfm._io import MAX_DOCUMENT_BYTES, read_input_bytes
from srfm._validate import path_name
from srfm.errors import BenchmarkError

__all__ = ["FLOOR_DIR", "FLOOR_SCHEMA", "floor_path", "load_floors", "read_floor"]

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
