"""The results folder: per-episode metric files and the scenario fingerprints.

An episode file is JSON ending with the CRC-32 of its text; :func:`read_episode`
validates every file against its schema and checksum, so a hand-edited, truncated or
bit-flipped file is an error naming it, never a silently different table.
"""

from __future__ import annotations

import hashlib
import json
import math
import zlib
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import attrs
import numpy as np

from srfm import _validate
from srfm._io import MAX_DOCUMENT_BYTES, atomic_write_text, read_input_bytes
from srfm._text import plain
from srfm._validate import path_name
from srfm.errors import BenchmarkError, SrfmError
from srfm.metrics import EpisodeMetrics
from srfm.metrics.episode import EPISODE_METRICS, PEDESTRIAN_METRICS
from srfm.scenarios import Scenario
from srfm.sim.record import ROBOT_OUTCOMES

__all__ = [
    "EPISODES_DIR",
    "episode_path",
    "fingerprint",
    "read_episode",
    "write_episode",
]

EPISODES_DIR = "episodes"
EPISODE_SCHEMA = "srfm.episode_metrics/2"
"""2 (issue 16): the metrics of docs/metrics.md; files of schema 1 are refused."""
_CHECKSUM = "crc32"


def episode_path(out: Path, scenario: str, planner: str, seed: int) -> Path:
    """Where the metrics of one episode live inside a results folder.

    Raises:
        BenchmarkError: a name that cannot be a folder name, or a seed out of range
            (nothing can land outside ``out``).
    """
    path_name(scenario, "scenario name", BenchmarkError)
    path_name(planner, "planner name", BenchmarkError)
    seed = _validate.seed(seed, BenchmarkError)
    return out / EPISODES_DIR / scenario / planner / f"seed-{seed:06d}.json"


def _text(doc: Mapping[str, Any]) -> str:
    return json.dumps(doc, indent=1)


def episode_json(metrics: EpisodeMetrics) -> str:
    """The JSON text of one episode's metrics (floats round-trip exactly; NaN is null),
    ending with the CRC-32 of the text before it, so that any change is seen on read."""
    text = _text({"schema": EPISODE_SCHEMA, **metrics.to_document()})
    return _with_checksum(text, f"{zlib.crc32(text.encode('utf-8')):08x}")


def _with_checksum(text: str, crc: str) -> str:
    """A document's text with the checksum entry appended, as ``_text`` of the document
    with that last key would print it (``json.dumps`` with an indent is pure Python:
    printing the document once instead of twice saves 0.3 ms an episode)."""
    return f'{text[:-2]},\n "{_CHECKSUM}": "{crc}"\n}}\n'


def _checksum_matches(raw: str, doc: Mapping[str, Any]) -> bool:
    """Whether the file's text ``raw`` is what :func:`episode_json` wrote for a document
    with this checksum: the text before the checksum entry is checked directly, without
    printing the document again. False also for a file laid out otherwise (then the
    document is printed again and checked, as before)."""
    stored = doc.get(_CHECKSUM)
    if not isinstance(stored, str):
        return False
    tail = f',\n "{_CHECKSUM}": "{stored}"\n}}\n'
    if not raw.endswith(tail):
        return False
    head = raw[: -len(tail)] + "\n}"  # the document's text without the checksum
    return f"{zlib.crc32(head.encode('utf-8')):08x}" == stored


def write_episode(out: Path, metrics: EpisodeMetrics) -> Path:
    """Write one episode's metrics atomically; return the file's path."""
    path = episode_path(out, metrics.scenario, metrics.planner, metrics.seed)
    atomic_write_text(path, episode_json(metrics), fsync=False)
    return path


def _number_or_null(value: Any) -> bool:
    return value is None or (
        not isinstance(value, bool) and isinstance(value, int | float) and math.isfinite(value)
    )


def _check_document(doc: Any, raw: str | None = None) -> str | None:
    """What is wrong with an episode document (None when nothing): its schema, the
    types of every entry, one value per pedestrian in every per-pedestrian list, its
    checksum (against the file's text ``raw`` when it is laid out as written)."""
    if not isinstance(doc, dict):
        return "not a JSON object"
    if doc.get("schema") != EPISODE_SCHEMA:
        return f"schema {doc.get('schema')!r}, expected {EPISODE_SCHEMA!r}"
    if raw is not None and _checksum_matches(raw, doc):
        doc.pop(_CHECKSUM)
    elif _CHECKSUM in doc:
        stored = doc.pop(_CHECKSUM)
        crc = f"{zlib.crc32(_text(doc).encode('utf-8')):08x}"
        if stored != crc:
            return f"checksum mismatch (stored {stored!r}, content {crc!r}): the file was changed"
    for key in ("scenario", "planner", "outcome"):
        if not isinstance(doc.get(key), str):
            return f"{key!r} must be a string, got {plain(doc.get(key))}"
    if doc["outcome"] not in ROBOT_OUTCOMES:
        return f"unknown outcome {doc['outcome']!r}"
    for key in ("seed", "end_step"):
        value = doc.get(key)
        if isinstance(value, bool) or not isinstance(value, int) or value < 0:
            return f"{key!r} must be a non-negative integer, got {plain(value)}"
    metrics, peds = doc.get("metrics"), doc.get("pedestrians")
    if not isinstance(metrics, dict) or not isinstance(peds, dict):
        return "'metrics' and 'pedestrians' must be objects"
    for m in EPISODE_METRICS:
        if m.name not in metrics:
            return f"metrics: {m.name!r} is missing"
        if not _number_or_null(metrics[m.name]):
            return (
                f"metrics: {m.name!r} must be a finite number or null, got {plain(metrics[m.name])}"
            )
    lengths = set()
    for m in PEDESTRIAN_METRICS:
        values = peds.get(m.name)
        if not isinstance(values, list):
            return f"pedestrians: {m.name!r} must be a list, got {plain(values)}"
        bad = next((v for v in values if not _number_or_null(v)), "ok")
        if bad != "ok":
            return f"pedestrians: {m.name!r} must hold finite numbers or null, got {plain(bad)}"
        lengths.add(len(values))
    if len(lengths) > 1:
        return f"pedestrians: lists of different lengths {sorted(lengths)} (cut short?)"
    return None


def read_episode(path: Path, *, expect: tuple[str, str, int] | None = None) -> EpisodeMetrics:
    """Read and validate a file written by :func:`write_episode`.

    The document is checked against its schema (types, one value per pedestrian in
    every list, its CRC-32), and, with ``expect`` = (scenario, planner, seed), that it
    is the episode its path says.

    Raises:
        BenchmarkError: unreadable, damaged or misplaced; the message names the file and
            says to delete it (a benchmark run re-simulates damaged episodes itself).
    """
    hint = "delete it and run the benchmark again to re-simulate it"
    data = read_input_bytes(
        path, max_bytes=MAX_DOCUMENT_BYTES, error=BenchmarkError, what="episode metrics file"
    )
    try:
        raw = data.decode("utf-8")
        doc = json.loads(raw)
    except (UnicodeDecodeError, ValueError, RecursionError) as exc:
        raise BenchmarkError(f"{path}: damaged episode metrics file ({exc}); {hint}") from None
    problem = _check_document(doc, raw)
    if problem is None and expect is not None:
        got = (doc["scenario"], doc["planner"], doc["seed"])
        if got != tuple(expect):
            problem = f"holds episode {got}, not {tuple(expect)}"
    if problem is not None:
        raise BenchmarkError(f"{path}: damaged episode metrics file: {problem}; {hint}")
    try:
        return EpisodeMetrics.from_document(doc)
    except (SrfmError, KeyError, TypeError, ValueError) as exc:
        raise BenchmarkError(f"{path}: damaged episode metrics file: {exc}; {hint}") from None


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
    """SHA-256 of a scenario's content (every field but where it was read from; the
    crowd substeps only when not 1, so a folder of the paper's scheme keeps its
    fingerprints)."""
    data = _plain(scenario)
    data.pop("source", None)
    if data.get("crowd_substeps") == 1:  # the default: the fingerprints of before it
        data.pop("crowd_substeps")
    text = json.dumps(data, sort_keys=True, allow_nan=True)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()
