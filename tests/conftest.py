"""Shared test helpers."""

from __future__ import annotations

import hashlib
from pathlib import Path

import numpy as np

from srfm.sim.record import EpisodeRecord

REPO = Path(__file__).resolve().parents[1]
# The tables and data files every finished benchmark or score run writes.
RESULT_TABLES = (
    "table.md",
    "table.tex",
    "outcomes.md",
    "table_extended.md",
    "table_extended.tex",
    "suite.md",
    "summary.json",
    "episodes.csv",
    "pedestrians.csv",
    "episodes.parquet",
    "pedestrians.parquet",
)


def record_digest(record: EpisodeRecord) -> str:
    """SHA-256 over every array (bytes, dtype, shape), the outcome and the events."""
    h = hashlib.sha256()
    for name, arr in sorted(record.arrays().items()):
        h.update(name.encode())
        h.update(str(arr.dtype).encode())
        h.update(str(arr.shape).encode())
        h.update(np.ascontiguousarray(arr).tobytes())
    h.update(record.outcome.encode())
    h.update(repr(record.end_step).encode())
    h.update(repr(record.events).encode())
    return h.hexdigest()


def write_scenario(path: Path, body: str) -> Path:
    """Write a scenario TOML file and return its path."""
    path.write_text(body, encoding="utf-8")
    return path
