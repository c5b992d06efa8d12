"""The results folder: per-episode metric files, CSV exports and the manifest."""

from __future__ import annotations

import hashlib
import json
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import attrs
import numpy as np

from srfm._io import atomic_write_text
from srfm.errors import BenchmarkError
from srfm.metrics import EpisodeMetrics
from srfm.scenarios import Scenario

__all__ = [
    "EPISODES_DIR",
    "episode_path",
    "fingerprint",
    "read_episode",
    "write_episode",
]

EPISODES_DIR = "episodes"
EPISODE_SCHEMA = "srfm.episode_metrics/1"


def episode_path(out: Path, scenario: str, planner: str, seed: int) -> Path:
    """Where the metrics of one episode live inside a results folder."""
    return out / EPISODES_DIR / scenario / planner / f"seed-{seed:06d}.json"


def episode_json(metrics: EpisodeMetrics) -> str:
    """The JSON text of one episode's metrics (floats round-trip exactly; NaN is null)."""
    return json.dumps({"schema": EPISODE_SCHEMA, **metrics.to_document()}, indent=1) + "\n"


def write_episode(out: Path, metrics: EpisodeMetrics) -> Path:
    """Write one episode's metrics atomically; return the file's path."""
    path = episode_path(out, metrics.scenario, metrics.planner, metrics.seed)
    atomic_write_text(path, episode_json(metrics), fsync=False)
    return path


def read_episode(path: Path) -> EpisodeMetrics:
    """Read a file written by :func:`write_episode`."""
    try:
        doc = json.loads(path.read_text(encoding="utf-8"))
        if doc.get("schema") != EPISODE_SCHEMA:
            raise BenchmarkError(
                f"{path}: schema {doc.get('schema')!r}, expected {EPISODE_SCHEMA!r}"
            )
        return EpisodeMetrics.from_document(doc)
    except (OSError, ValueError, KeyError, TypeError, AttributeError) as exc:
        if isinstance(exc, BenchmarkError):
            raise
        raise BenchmarkError(f"{path}: not a readable episode metrics file: {exc}") from None


def _plain(value: Any) -> Any:
    """attrs instances, arrays and tuples as JSON-ready plain data."""
    if attrs.has(type(value)):
        return {f.name: _plain(getattr(value, f.name)) for f in attrs.fields(type(value))}
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, list | tuple):
        return [_plain(v) for v in value]
    if isinstance(value, Mapping):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, np.generic):
        return value.item()
    return value


def fingerprint(scenario: Scenario) -> str:
    """SHA-256 of a scenario's content (every field but where it was read from)."""
    data = _plain(scenario)
    data.pop("source", None)
    text = json.dumps(data, sort_keys=True, allow_nan=True)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()
