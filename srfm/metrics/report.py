"""The report files of a set of scored episodes: tables, CSV and Parquet exports and the
JSON summary.

Written by the benchmark from its episode files and by ``srfm score`` from MCAP logs
alone; one writer, so that both give byte-identical files.
"""

from __future__ import annotations

import csv
import io
import json
import math
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any, Final

import attrs

from srfm._io import atomic_write_text, write_file_set
from srfm.metrics._attribution_report import attribution, suite_dict, suite_markdown
from srfm.metrics.attribution import SPLIT_COLUMNS, deviation_split, felt_robot
from srfm.metrics.episode import (
    EPISODE_METRICS,
    PEDESTRIAN_METRICS,
    EpisodeMetrics,
    MetricParams,
)
from srfm.metrics.suite import SuiteStats, suite_stats
from srfm.metrics.tables import (
    EXTENDED_COLUMNS,
    OUTCOME_COLUMNS,
    TABLE_COLUMNS,
    BenchmarkTable,
    benchmark_table,
    summary_dict,
    to_latex,
    to_latex_extended,
    to_markdown,
    to_markdown_extended,
)
from srfm.models.params import SRFMParams, response_model_name

__all__ = [
    "CORRECTION_OF",
    "FELT_COLUMN",
    "MANIFEST",
    "SUMMARY_SCHEMA",
    "ReportTables",
    "render_tables",
    "write_episodes_csv",
    "write_pedestrians_csv",
    "write_tables",
]

MANIFEST: Final = "manifest.json"
"""The file that marks a benchmark results folder (written by the benchmark)."""
SUMMARY_SCHEMA: Final = "srfm.summary/4"
"""Layout of ``summary.json``; 2: the extended table, n and undefined counts, the rules;
3 (issue 29): columns conditioned on success, outcome counts, adjusted p-values and
each table's correction; 4 (issue 41): ``attribution`` (the noise floor, the direct
and knock-on deviation), ``suite`` (IQMs, probabilities of improvement, performance
profiles), the normalised scores' k/n and whether the oracle is a bound."""

FELT_COLUMN: Final = "felt_robot"
"""``pedestrians.csv``'s column: 1 if the pedestrian felt the robot
(:func:`srfm.metrics.attribution.felt_robot`), else 0."""

CORRECTION_OF: Final = {"table": "holm", "outcomes": "holm", "extended": "bh"}
"""The multiple-comparison correction of each table: Holm's (the family-wise error
rate) for the Table 3 layout and the outcomes, whose marks are the claims a reader
takes away; Benjamini–Hochberg's (the false discovery rate) for the extended table,
a screen of some 60 columns where Holm's would hide nearly everything."""


@attrs.frozen
class ReportTables:
    """The three tables of a report: the paper's layout, the robot outcomes, and every
    metric (extended); and the suite statistics (:mod:`srfm.metrics.suite`)."""

    table: BenchmarkTable
    outcomes: BenchmarkTable
    extended: BenchmarkTable
    suite: SuiteStats


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


_SPLIT_NAMES: Final = tuple(name for name, _, _ in SPLIT_COLUMNS)


def _episodes_csv(results: Sequence[EpisodeMetrics]) -> str:
    header = ["scenario", "planner", "seed", "outcome", "end_step"]
    header += [m.name for m in EPISODE_METRICS]
    header += list(_SPLIT_NAMES)
    rows = (
        [r.scenario, r.planner, r.seed, r.outcome, r.end_step]
        + [_csv_number(r.values[m.name]) for m in EPISODE_METRICS]
        + [_csv_number(split[name]) for name in _SPLIT_NAMES]
        for r, split in ((r, deviation_split(r)) for r in results)
    )
    return _csv_text(header, rows)


def write_pedestrians_csv(path: Path, results: Sequence[EpisodeMetrics]) -> None:
    """One row per (episode, pedestrian) with every :data:`PEDESTRIAN_METRICS` value."""
    atomic_write_text(path, _pedestrians_csv(results))


def _pedestrians_csv(results: Sequence[EpisodeMetrics]) -> str:
    header = ["scenario", "planner", "seed", "pedestrian"]
    header += [m.name for m in PEDESTRIAN_METRICS]
    header.append(FELT_COLUMN)
    rows = (
        [r.scenario, r.planner, r.seed, k]
        + [_csv_number(r.pedestrians[m.name][k]) for m in PEDESTRIAN_METRICS]
        + [int(felt[k])]
        for r, felt in ((r, felt_robot(r)) for r in results)
        for k in range(len(r.pedestrians["frechet_m"]))
    )
    return _csv_text(header, rows)


def _parquet(columns: dict[str, Any]) -> bytes:
    """A Parquet file (zstd) of ``columns``: name -> (pyarrow type, values); NaN as null."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    arrays = {}
    for name, (kind, values) in columns.items():
        if kind == "float":
            arrays[name] = pa.array(
                [None if math.isnan(v) else float(v) for v in values], type=pa.float64()
            )
        elif kind == "int":
            arrays[name] = pa.array(values, type=pa.int64())
        else:
            arrays[name] = pa.array(values, type=pa.string())
    buf = io.BytesIO()
    pq.write_table(pa.table(arrays), buf, compression="zstd")
    return buf.getvalue()


def _episodes_parquet(results: Sequence[EpisodeMetrics]) -> bytes:
    """episodes.csv as Parquet: the same rows and columns, typed; undefined as null."""
    columns: dict[str, Any] = {
        "scenario": ("str", [r.scenario for r in results]),
        "planner": ("str", [r.planner for r in results]),
        "seed": ("int", [r.seed for r in results]),
        "outcome": ("str", [r.outcome for r in results]),
        "end_step": ("int", [r.end_step for r in results]),
    }
    for m in EPISODE_METRICS:
        columns[m.name] = ("float", [r.values[m.name] for r in results])
    splits = [deviation_split(r) for r in results]
    for name in _SPLIT_NAMES:
        columns[name] = ("float", [x[name] for x in splits])
    return _parquet(columns)


def _pedestrians_parquet(results: Sequence[EpisodeMetrics]) -> bytes:
    """pedestrians.csv as Parquet."""
    rows = [(r, k) for r in results for k in range(len(r.pedestrians["frechet_m"]))]
    columns: dict[str, Any] = {
        "scenario": ("str", [r.scenario for r, _ in rows]),
        "planner": ("str", [r.planner for r, _ in rows]),
        "seed": ("int", [r.seed for r, _ in rows]),
        "pedestrian": ("int", [k for _, k in rows]),
    }
    for m in PEDESTRIAN_METRICS:
        columns[m.name] = ("float", [float(r.pedestrians[m.name][k]) for r, k in rows])
    felt = {id(r): felt_robot(r) for r in results}
    columns[FELT_COLUMN] = ("int", [int(felt[id(r)][k]) for r, k in rows])
    return _parquet(columns)


def write_tables(
    out: Path,
    results: Sequence[EpisodeMetrics],
    *,
    scenarios: Sequence[str],
    planners: Sequence[str],
    seeds: Sequence[int],
    params: SRFMParams,
    reference: str | None,
    floors: Mapping[str, Sequence[float]] | None = None,
) -> tuple[list[str], BenchmarkTable]:
    """Write the tables, CSV files and JSON summary of ``results`` (every scenario ×
    planner × seed) into ``out`` as a whole (:func:`srfm._io.write_file_set`: all old
    or all new, also when the disk fills); also used by ``srfm score``. ``floors``: as
    :func:`render_tables`.

    Returns:
        The files written (relative to ``out``) and the Table 3 layout table.
    """
    files, tables = render_tables(
        results,
        scenarios=scenarios,
        planners=planners,
        seeds=seeds,
        params=params,
        reference=reference,
        floors=floors,
    )
    write_file_set(out, files)
    return list(files), tables.table


def render_tables(
    results: Sequence[EpisodeMetrics],
    *,
    scenarios: Sequence[str],
    planners: Sequence[str],
    seeds: Sequence[int],
    params: SRFMParams,
    reference: str | None,
    metric_params: MetricParams | None = None,
    floors: Mapping[str, Sequence[float]] | None = None,
) -> tuple[dict[str, bytes], ReportTables]:
    """The tables, CSV and Parquet files and JSON summary of ``results`` (every scenario
    × planner × seed), nothing written.

    ``floors``: per scenario, the noise floor of each seed in seed order
    (:mod:`srfm.metrics.attribution`), shown beside each scenario when given.

    Returns:
        The file contents by name (relative to the results folder, in a fixed order)
        and the tables.
    """
    names = list(scenarios)
    table, outcomes, extended = (
        benchmark_table(
            results,
            scenarios=names,
            planners=planners,
            seeds=seeds,
            reference=reference,
            columns=columns,
            correction=CORRECTION_OF[key],
            with_references=key == "table",
        )
        for key, columns in (
            ("table", TABLE_COLUMNS),
            ("outcomes", OUTCOME_COLUMNS),
            ("extended", EXTENDED_COLUMNS),
        )
    )
    blocks, attribution_doc = attribution(
        results, scenarios=names, planners=planners, seeds=seeds, floors=floors
    )
    stats = suite_stats(results, scenarios=names, planners=planners, seeds=seeds)
    summary = {
        "schema": SUMMARY_SCHEMA,
        "request": {
            "scenarios": names,
            "planners": list(planners),
            "seeds": list(seeds),
            "params": params.as_dict(),
            "metric_params": (metric_params or MetricParams()).as_dict(),
        },
        "table": summary_dict(table),
        "outcomes": summary_dict(outcomes),
        "extended": summary_dict(extended),
        "attribution": attribution_doc,
        "suite": suite_dict(stats),
    }
    model = response_model_name(params)
    texts = {
        "episodes.csv": _episodes_csv(results),
        "pedestrians.csv": _pedestrians_csv(results),
        "table.md": to_markdown(table, model=model),
        "table.tex": to_latex(table, model=model),
        "outcomes.md": to_markdown(outcomes, model=model),
        "table_extended.md": to_markdown_extended(extended, blocks, model=model),
        "table_extended.tex": to_latex_extended(extended, blocks, model=model),
        "suite.md": suite_markdown(stats, len(seeds)),
        "summary.json": json.dumps(summary, indent=1) + "\n",
    }
    files = {name: text.encode("utf-8") for name, text in texts.items()}
    files["episodes.parquet"] = _episodes_parquet(results)
    files["pedestrians.parquet"] = _pedestrians_parquet(results)
    return files, ReportTables(table, outcomes, extended, stats)
