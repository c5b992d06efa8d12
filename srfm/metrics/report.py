"""The report files of a set of scored episodes: tables, CSV exports and the JSON summary.

Written by the benchmark from its episode files and by ``srfm score`` from MCAP logs
alone; one writer, so that both give byte-identical files.
"""

from __future__ import annotations

import csv
import io
import json
import math
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Any, Final

from srfm._io import atomic_write_text, write_file_set
from srfm.metrics.episode import EPISODE_METRICS, PEDESTRIAN_METRICS, EpisodeMetrics
from srfm.metrics.tables import (
    OUTCOME_COLUMNS,
    TABLE_COLUMNS,
    BenchmarkTable,
    benchmark_table,
    summary_dict,
    to_latex,
    to_markdown,
)
from srfm.models.params import SRFMParams

__all__ = [
    "MANIFEST",
    "render_tables",
    "write_episodes_csv",
    "write_pedestrians_csv",
    "write_tables",
]

MANIFEST: Final = "manifest.json"
"""The file that marks a benchmark results folder (written by the benchmark)."""


def _csv_number(x: float) -> str:
    return "" if math.isnan(x) else repr(float(x))


def _csv_text(header: Sequence[str], rows: Iterable[Sequence[Any]]) -> str:
    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="\n")
    writer.writerow(header)
    writer.writerows(rows)
    return buf.getvalue()


def write_episodes_csv(path: Path, results: Sequence[EpisodeMetrics]) -> None:
    """One row per episode: identity, outcome and every :data:`EPISODE_METRICS` value
    (empty cell for NaN)."""
    atomic_write_text(path, _episodes_csv(results))


def _episodes_csv(results: Sequence[EpisodeMetrics]) -> str:
    header = ["scenario", "planner", "seed", "outcome", "end_step"]
    header += [m.name for m in EPISODE_METRICS]
    rows = (
        [r.scenario, r.planner, r.seed, r.outcome, r.end_step]
        + [_csv_number(r.values[m.name]) for m in EPISODE_METRICS]
        for r in results
    )
    return _csv_text(header, rows)


def write_pedestrians_csv(path: Path, results: Sequence[EpisodeMetrics]) -> None:
    """One row per (episode, pedestrian) with every :data:`PEDESTRIAN_METRICS` value."""
    atomic_write_text(path, _pedestrians_csv(results))


def _pedestrians_csv(results: Sequence[EpisodeMetrics]) -> str:
    header = ["scenario", "planner", "seed", "pedestrian"]
    header += [m.name for m in PEDESTRIAN_METRICS]
    rows = (
        [r.scenario, r.planner, r.seed, k]
        + [_csv_number(r.pedestrians[m.name][k]) for m in PEDESTRIAN_METRICS]
        for r in results
        for k in range(len(r.pedestrians["frechet_m"]))
    )
    return _csv_text(header, rows)


def write_tables(
    out: Path,
    results: Sequence[EpisodeMetrics],
    *,
    scenarios: Sequence[str],
    planners: Sequence[str],
    seeds: Sequence[int],
    params: SRFMParams,
    reference: str | None,
) -> tuple[list[str], BenchmarkTable]:
    """Write the tables, CSV files and JSON summary of ``results`` (every scenario ×
    planner × seed) into ``out`` as a whole (:func:`srfm._io.write_file_set`: all old
    or all new, also when the disk fills); also used by ``srfm score``.

    Returns:
        The files written (relative to ``out``) and the Table 3 layout table.
    """
    files, table = render_tables(
        results,
        scenarios=scenarios,
        planners=planners,
        seeds=seeds,
        params=params,
        reference=reference,
    )
    write_file_set(out, files)
    return list(files), table


def render_tables(
    results: Sequence[EpisodeMetrics],
    *,
    scenarios: Sequence[str],
    planners: Sequence[str],
    seeds: Sequence[int],
    params: SRFMParams,
    reference: str | None,
) -> tuple[dict[str, bytes], BenchmarkTable]:
    """The tables, CSV files and JSON summary of ``results`` (every scenario × planner ×
    seed), nothing written.

    Returns:
        The file contents by name (relative to the results folder, in a fixed order)
        and the Table 3 layout table.
    """
    names = list(scenarios)
    table, outcomes = (
        benchmark_table(
            results,
            scenarios=names,
            planners=planners,
            seeds=seeds,
            reference=reference,
            columns=columns,
        )
        for columns in (TABLE_COLUMNS, OUTCOME_COLUMNS)
    )
    summary = {
        "request": {
            "scenarios": names,
            "planners": list(planners),
            "seeds": list(seeds),
            "params": params.as_dict(),
        },
        "table": summary_dict(table),
        "outcomes": summary_dict(outcomes),
    }
    texts = {
        "episodes.csv": _episodes_csv(results),
        "pedestrians.csv": _pedestrians_csv(results),
        "table.md": to_markdown(table),
        "table.tex": to_latex(table),
        "outcomes.md": to_markdown(outcomes),
        "summary.json": json.dumps(summary, indent=1) + "\n",
    }
    return {name: text.encode("utf-8") for name, text in texts.items()}, table
