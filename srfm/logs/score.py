"""Re-score runs from their MCAP logs alone: every metric and the benchmark tables.

:func:`score_logs` reads every episode log under the given folders and files, rebuilds
each episode's record from the exact arrays in the file (and the shared counterfactual
file it names, checked against its fingerprint), recomputes the metrics with the same
:func:`srfm.metrics.episode_metrics` the benchmark uses, and compares them bit for bit
with the metrics logged when the episode ran. :func:`write_score_reports` then writes
the same tables, CSV files and summary as the benchmark; on the complete logs of a
benchmark they are byte-identical to the benchmark's own.

Nothing is written before every file has been read and checked, so a corrupt,
truncated or foreign file stops the command with a message naming it and leaves every
existing file as it was.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any, Final

import attrs
import numpy as np

from srfm.errors import BenchmarkError, LogError
from srfm.logs._mcap import LogFile, episode_from_log, read_log
from srfm.logs._writer import LOGS_DIR
from srfm.metrics import EpisodeMetrics, episode_metrics
from srfm.metrics.floor_files import load_floors
from srfm.metrics.report import MANIFEST, write_tables
from srfm.models.params import SRFMParams
from srfm.scenarios import EVALUATION_SCENARIOS

__all__ = [
    "ScoreResult",
    "ScoredEpisode",
    "check_report_folder",
    "find_logs",
    "metrics_identical",
    "score_logs",
    "write_score_reports",
]

_CACHE_SIZE: Final = 8


@attrs.frozen(kw_only=True, eq=False)
class ScoredEpisode:
    """One episode re-scored from its log.

    Attributes:
        path: the episode's ``.mcap`` file.
        metrics: the metrics recomputed from the log.
        online: the metrics logged when the episode ran (None if the file has none).
    """

    path: Path
    metrics: EpisodeMetrics
    online: EpisodeMetrics | None

    @property
    def matches(self) -> bool | None:
        """Whether the recomputed metrics equal the logged ones bit for bit (None: no
        logged metrics)."""
        return None if self.online is None else metrics_identical(self.metrics, self.online)


@attrs.frozen(kw_only=True, eq=False)
class ScoreResult:
    """Re-scored episodes and the table layout they fill.

    Attributes:
        episodes: every episode found, in (scenario, planner, seed) order of the table.
        scenarios, planners, seeds: the table's rows and the seeds every row has; from
            the benchmark the logs came from when they carry one, else sorted.
        reference: the planner the others are tested against (None: no tests).
        params: the SRFM parameters every episode used.
        complete: the logs hold exactly every episode of their benchmark, so the tables
            equal the benchmark's own.
        notes: what was left out of the tables and why.
    """

    episodes: tuple[ScoredEpisode, ...]
    scenarios: tuple[str, ...]
    planners: tuple[str, ...]
    seeds: tuple[int, ...]
    reference: str | None
    params: SRFMParams
    complete: bool
    notes: tuple[str, ...]

    @property
    def mismatches(self) -> list[ScoredEpisode]:
        """Episodes whose recomputed metrics differ from their logged metrics."""
        return [e for e in self.episodes if e.matches is False]


def _same_float(a: float, b: float) -> bool:
    return bool(np.float64(a).tobytes() == np.float64(b).tobytes()) or (
        math.isnan(a) and math.isnan(b)
    )


def metrics_identical(a: EpisodeMetrics, b: EpisodeMetrics) -> bool:
    """Identity, every episode value and every per-pedestrian array equal bit for bit
    (NaN equals NaN)."""
    if (a.scenario, a.planner, a.seed, a.outcome, a.end_step) != (
        b.scenario,
        b.planner,
        b.seed,
        b.outcome,
        b.end_step,
    ):
        return False
    if set(a.values) != set(b.values) or set(a.pedestrians) != set(b.pedestrians):
        return False
    if not all(_same_float(a.values[k], b.values[k]) for k in a.values):
        return False
    for k, x in a.pedestrians.items():
        y = b.pedestrians[k]
        if x.shape != y.shape:
            return False
        nan_x, nan_y = np.isnan(x), np.isnan(y)
        if not np.array_equal(nan_x, nan_y) or x[~nan_x].tobytes() != y[~nan_y].tobytes():
            return False
    return True


def find_logs(paths: Sequence[str | Path]) -> list[Path]:
    """The ``.mcap`` files named or found (recursively) under the given paths.

    Raises:
        LogError: a path does not exist, or a folder holds no ``.mcap`` file.
    """
    found: list[Path] = []
    for raw in paths:
        path = Path(raw)
        if path.is_dir():
            files = sorted(
                p for p in path.rglob("*.mcap") if p.is_file() and not p.name.startswith(".")
            )
            if not files:
                raise LogError(f"{path}: no .mcap files in this folder")
            found.extend(files)
        elif path.is_file():
            found.append(path)
        else:
            raise LogError(f"{path}: no such file or folder")
    unique = list(dict.fromkeys(p.resolve() for p in found))
    # Planners of one seed next to each other, so that a shared counterfactual file is
    # read once and kept in a small cache while it is needed.
    return sorted(unique, key=lambda p: (str(p.parent.parent), p.name, str(p)))


def _cached(cache: dict[Path, LogFile]) -> None:
    while len(cache) > _CACHE_SIZE:
        del cache[next(iter(cache))]


def _order(names: set[str], preferred: Sequence[str]) -> list[str]:
    first = [n for n in preferred if n in names]
    return first + sorted(names - set(first))


def _layout(
    episodes: list[tuple[ScoredEpisode, Mapping[str, Any]]],
) -> tuple[list[str], list[str], list[int], str | None, bool, list[str]]:
    """Rows, seeds and reference of the tables; whether they are the benchmark's own."""
    cells: dict[tuple[str, str], set[int]] = {}
    for ep, _ in episodes:
        m = ep.metrics
        cells.setdefault((m.scenario, m.planner), set()).add(m.seed)
    scenario_names = {s for s, _ in cells}
    planner_names = {p for _, p in cells}
    contexts = {
        json.dumps(info.get("benchmark"), sort_keys=True)
        for _, info in episodes
        if info.get("benchmark") is not None
    }
    notes: list[str] = []
    bench: Mapping[str, Any] | None = None
    if len(contexts) == 1 and all(info.get("benchmark") is not None for _, info in episodes):
        bench = json.loads(next(iter(contexts)))
    elif contexts:
        notes.append("the logs come from different benchmark requests; rows are sorted by name")
    if bench is not None:
        scenarios = _order(scenario_names, [str(s) for s in bench.get("scenarios", [])])
        planners = _order(planner_names, [str(p) for p in bench.get("planners", [])])
        seed_order = [int(s) for s in bench.get("seeds", [])]
        reference = bench.get("reference")
    else:
        scenarios = _order(scenario_names, EVALUATION_SCENARIOS)
        planners = sorted(planner_names)
        seed_order = []
        reference = None
    missing_cells = [(s, p) for s in scenarios for p in planners if (s, p) not in cells]
    if missing_cells:
        notes.append(
            f"no logs for {len(missing_cells)} scenario × planner cells, e.g. "
            f"{missing_cells[0][0]} × {missing_cells[0][1]}: no tables"
        )
        return scenarios, planners, [], None, False, notes
    common = set.intersection(*cells.values())
    all_seeds = set.union(*cells.values())
    seeds = [s for s in seed_order if s in common] + sorted(common - set(seed_order))
    if common != all_seeds:
        notes.append(
            f"{len(all_seeds - common)} seeds are missing from some cells and were left out "
            "of the tables"
        )
    if reference is not None and reference not in planners:
        notes.append(f"the reference planner {reference!r} has no logs: no significance tests")
        reference = None
    complete = bench is not None and (
        list(bench.get("scenarios", [])) == scenarios
        and list(bench.get("planners", [])) == planners
        and [int(s) for s in bench.get("seeds", [])] == seeds
        and common == all_seeds
    )
    return scenarios, planners, seeds, reference, complete, notes


def score_logs(paths: Sequence[str | Path]) -> ScoreResult:
    """Re-score every episode log under ``paths`` (folders and ``.mcap`` files).

    Raises:
        LogError: naming the file, when a file is unreadable, truncated, corrupt, foreign
            or inconsistent, when two files hold the same episode, when the episodes
            were run with different parameters, or when no episode log is found.
    """
    files = find_logs(paths)
    cache: dict[Path, LogFile] = {}
    scored: list[tuple[ScoredEpisode, Mapping[str, Any]]] = []
    seen: dict[tuple[str, str, int], Path] = {}
    params: dict[str, Any] | None = None
    params_from: Path | None = None
    for path in files:
        if path in cache:
            continue  # a shared counterfactual file already read (and checked)
        log = read_log(path)
        if log.kind == "counterfactual":
            cache[path] = log
            _cached(cache)
            continue
        episode = episode_from_log(log, counterfactuals=cache)
        _cached(cache)
        metrics = episode_metrics(episode.record)
        online = episode.online_metrics
        if online is not None and online.planner != metrics.planner:
            metrics = attrs.evolve(metrics, planner=online.planner)
        key = (metrics.scenario, metrics.planner, metrics.seed)
        if key in seen:
            raise LogError(f"{path}: the same episode {key} as {seen[key]}")
        seen[key] = path
        p = episode.record.params.as_dict()
        if params is None:
            params, params_from = p, path
        elif p != params:
            raise LogError(
                f"{path}: run with other SRFM parameters than {params_from}; "
                "score the runs separately"
            )
        scored.append((ScoredEpisode(path=path, metrics=metrics, online=online), episode.info))
    if not scored:
        raise LogError(
            "no episode logs among " + ", ".join(str(p) for p in paths) + " (only shared "
            "counterfactual files)"
        )
    scenarios, planners, seeds, reference, complete, notes = _layout(scored)
    rank_s = {s: i for i, s in enumerate(scenarios)}
    rank_p = {p: i for i, p in enumerate(planners)}
    seed_rank = {s: i for i, s in enumerate(seeds)}
    episodes = sorted(
        (e for e, _ in scored),
        key=lambda e: (
            rank_s[e.metrics.scenario],
            rank_p[e.metrics.planner],
            seed_rank.get(e.metrics.seed, len(seed_rank)),
            e.metrics.seed,
        ),
    )
    assert params is not None
    return ScoreResult(
        episodes=tuple(episodes),
        scenarios=tuple(scenarios),
        planners=tuple(planners),
        seeds=tuple(seeds),
        reference=reference,
        params=SRFMParams(**params),
        complete=complete,
        notes=tuple(notes),
    )


def check_report_folder(out: Path) -> None:
    """Raise :class:`LogError` if re-scored reports may not be written into ``out``: it
    is a file, or a benchmark results folder (whose own reports are never overwritten)."""
    if out.exists() and not out.is_dir():
        raise LogError(f"--out {out} exists and is not a folder")
    if (out / MANIFEST).exists():
        raise LogError(
            f"{out} is a benchmark results folder; write the re-scored reports elsewhere "
            "(srfm score never overwrites a benchmark's own reports)"
        )


def write_score_reports(out: str | Path, result: ScoreResult) -> list[str]:
    """Write the benchmark's tables, CSV files and summary for the re-scored episodes.

    Only the episodes of the table's seeds are used, in table order, exactly as the
    benchmark writes them. Returns the files written (relative to ``out``).

    Raises:
        LogError: ``out`` is a benchmark results folder (its own reports are never
            overwritten) or the logs give no table (see ``result.notes``).
    """
    out = Path(out)
    check_report_folder(out)
    if not result.seeds:
        raise LogError("the logs give no table: " + "; ".join(result.notes))
    seeds = set(result.seeds)
    results = [e.metrics for e in result.episodes if e.metrics.seed in seeds]
    out.mkdir(parents=True, exist_ok=True)
    files, _ = write_tables(
        out,
        results,
        scenarios=result.scenarios,
        planners=result.planners,
        seeds=result.seeds,
        params=result.params,
        reference=result.reference,
        floors=_floors_beside(result),
    )
    return files


def _floors_beside(result: ScoreResult) -> Mapping[str, list[float]] | None:
    """The noise floors of the results folder the logs lie in (``OUT/logs/<scenario>/
    <planner>/seed-N.mcap`` beside ``OUT/floor/``), when every one of the table's is
    there: a floor needs a simulation, not a log, so the logs cannot give it."""
    folders = {
        e.path.parents[3]
        for e in result.episodes
        if len(e.path.parents) > 3 and e.path.parents[2].name == LOGS_DIR
    }
    if len(folders) != 1:
        return None
    try:
        return load_floors(folders.pop(), result.scenarios, result.seeds)
    except BenchmarkError:
        return None
