"""Fixtures of the log tests: a few real episodes, simulated once per session."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from srfm.metrics import EpisodeMetrics, episode_metrics
from srfm.scenarios import Scenario, load_scenario
from srfm.sim.episode import run_episode
from srfm.sim.record import EpisodeRecord
from tests.conftest import REPO, write_scenario
from tests.logs.node_reader import prefix_or_skip, read_mcap

# A short user scenario with a wall and a pillar, re-goaling off: fast, and it exercises
# obstacles and scenarios that are not built in. The last pedestrian's goal moves 0.6 m
# away from the pillar: 0.01 m from its edge, it is refused (a scenario's checks, since
# issue 33 for version-1 files too).
SHORT = (REPO / "srfm/scenarios/crosswalk.toml").read_text(encoding="utf-8")
SHORT = (
    SHORT.replace('name = "crosswalk"', 'name = "short"')
    .replace("horizon_steps = 750", "horizon_steps = 90")
    .replace("[4.3, 2.5], [2.1, 1.6]]", "[4.3, 2.5], [2.1, 1.0]]")
)
SHORT += """
[obstacles]
walls = [[0.5, 14.5, 14.5, 14.5]]
pillars = [[2.0, 2.0, 0.4]]
"""

Episode = tuple[Scenario, EpisodeRecord, EpisodeMetrics]


@pytest.fixture(scope="session")
def short_scenario(tmp_path_factory: pytest.TempPathFactory) -> Scenario:
    path = write_scenario(tmp_path_factory.mktemp("scn") / "short.toml", SHORT)
    return load_scenario(path)


@pytest.fixture(scope="session")
def episode() -> Callable[..., Episode]:
    """``episode(scenario, seed, planner)``: simulated once, then cached."""
    cache: dict[tuple[Any, ...], Episode] = {}

    def make(scenario: Scenario | str, seed: int = 0, planner: str = "straight") -> Episode:
        sc = scenario if isinstance(scenario, Scenario) else load_scenario(scenario)
        key = (sc.name, sc.source, seed, planner)
        if key not in cache:
            record = run_episode(sc, seed, planner)
            cache[key] = (sc, record, episode_metrics(record))
        return cache[key]

    return make


def same_bits(a: np.ndarray, b: np.ndarray) -> bool:
    """Equal shape, dtype and bytes (NaN payloads included)."""
    return a.shape == b.shape and a.dtype == b.dtype and a.tobytes() == b.tobytes()


def check_json_schema(doc: Any, schema: dict[str, Any], where: str = "$") -> None:
    """A small JSON-schema checker for the keywords srfm's schemas use (type, const,
    enum, properties, required, items, additionalProperties); raises AssertionError."""
    types = schema.get("type")
    if types is not None:
        names = types if isinstance(types, list) else [types]
        py = {
            "object": dict,
            "array": list,
            "string": str,
            "boolean": bool,
            "null": type(None),
            "integer": int,
            "number": (int, float),
        }
        ok = any(
            isinstance(doc, py[t]) and not (t in ("integer", "number") and isinstance(doc, bool))
            for t in names
        )
        assert ok, f"{where}: {doc!r} is not {names}"
    if "const" in schema:
        assert doc == schema["const"], f"{where}: {doc!r} != {schema['const']!r}"
    if "enum" in schema:
        assert doc in schema["enum"], f"{where}: {doc!r} not in {schema['enum']}"
    if "minimum" in schema and isinstance(doc, int | float):
        assert doc >= schema["minimum"], f"{where}: {doc} < {schema['minimum']}"
    if isinstance(doc, dict):
        props = schema.get("properties", {})
        for key in schema.get("required", []):
            assert key in doc, f"{where}: missing {key!r}"
        for key, value in doc.items():
            if key in props:
                check_json_schema(value, props[key], f"{where}.{key}")
            elif isinstance(schema.get("additionalProperties"), dict):
                check_json_schema(value, schema["additionalProperties"], f"{where}.{key}")
    if isinstance(doc, list) and isinstance(schema.get("items"), dict):
        for i, item in enumerate(doc):
            check_json_schema(item, schema["items"], f"{where}[{i}]")


def files_state(root: Path) -> dict[str, tuple[bytes, int]]:
    """Every file under ``root``: bytes and modification time (ns)."""
    return {
        str(p.relative_to(root)): (p.read_bytes(), p.stat().st_mtime_ns)
        for p in sorted(root.rglob("*"))
        if p.is_file()
    }


@pytest.fixture(scope="session")
def mcap_core() -> Callable[[list[Path]], list[dict[str, Any]]]:
    """``mcap_core(paths)``: what the official ``@mcap/core`` indexed reader (under
    Node.js) finds in each file; every file must open. Skips only without Node.js."""
    prefix = prefix_or_skip()

    def read(paths: list[Path]) -> list[dict[str, Any]]:
        results = read_mcap(prefix, paths)
        for r in results:
            assert r["ok"], f"@mcap/core refused {r['file']}: {r['error']}"
        return results

    return read
