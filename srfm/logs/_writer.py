"""Where logs go in a results folder, and the per-episode writer of the benchmark.

Layout (``OUT`` is the ``--out`` folder of ``srfm simulate`` or ``srfm benchmark``)::

    OUT/logs/<scenario>/<planner>/seed-000042.mcap
    OUT/logs/<scenario>/<planner>/seed-000042.rrd
    OUT/logs/<scenario>/_counterfactual/seed-000042.mcap   (compact logs only)

Every file is written to a temporary file in the same folder and renamed into place,
so a reader never sees half a file; an interrupted run leaves at most hidden
``.*.tmp`` files, which the next run on the folder deletes while holding the folder's
lock (:func:`srfm._io.remove_stale_temporaries`).
"""

from __future__ import annotations

import operator
import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any, Final

import attrs

from srfm._text import plain
from srfm._validate import path_name
from srfm._validate import seed as validate_seed
from srfm.errors import LogError
from srfm.logs._mcap import (
    PROFILES,
    Profile,
    write_counterfactual_mcap,
    write_episode_mcap,
)
from srfm.metrics import EpisodeMetrics
from srfm.scenarios import Scenario, load_scenario
from srfm.sim.record import EpisodeRecord

__all__ = [
    "COUNTERFACTUAL_DIR",
    "LOGS_DIR",
    "EpisodeLogger",
    "LogOptions",
    "counterfactual_log_path",
    "episode_log_path",
    "write_episode_logs",
]

LOGS_DIR: Final = "logs"
COUNTERFACTUAL_DIR: Final = "_counterfactual"
"""Folder of the shared counterfactual files; no planner may have this name."""


def episode_log_path(out: Path, scenario: str, planner: str, seed: int, suffix: str) -> Path:
    """``OUT/logs/<scenario>/<planner>/seed-NNNNNN<suffix>``.

    Raises:
        LogError: a name that cannot be a folder name (:func:`srfm._validate.path_name`:
            no ``/``, ``..``, whitespace or leading ``_``, so never the counterfactual
            folder) or a bad seed; so no log is ever written outside ``OUT/logs``.
    """
    scenario = path_name(scenario, "scenario name", LogError)
    planner = path_name(planner, "planner name", LogError)
    seed = validate_seed(seed, LogError)
    return Path(out) / LOGS_DIR / scenario / planner / f"seed-{seed:06d}{suffix}"


def counterfactual_log_path(out: Path, scenario: str, seed: int) -> Path:
    """``OUT/logs/<scenario>/_counterfactual/seed-NNNNNN.mcap`` (names checked as in
    :func:`episode_log_path`)."""
    scenario = path_name(scenario, "scenario name", LogError)
    seed = validate_seed(seed, LogError)
    return Path(out) / LOGS_DIR / scenario / COUNTERFACTUAL_DIR / f"seed-{seed:06d}.mcap"


def _at_least(value: Any, minimum: int) -> bool:
    """``value`` is an integer (not a bool) >= ``minimum``."""
    try:
        number = operator.index(value)
    except TypeError:
        return False
    return not isinstance(value, bool) and number >= minimum


@attrs.frozen(kw_only=True)
class LogOptions:
    """Which logs to write.

    Attributes:
        mcap: write an MCAP file per episode.
        mcap_profile: ``"full"`` or ``"compact"`` (see :mod:`srfm.logs`).
        rrd: write Rerun recordings.
        rrd_seeds: in a benchmark, only the first this many seeds of each scenario ×
            planner cell get a recording (None: every seed).
        forces: log the SRFM force components in the recordings.
        scene_stride: Foxglove scene (and, in compact logs, the robot messages) every
            this many samples (None: the profile's, 1 for full and 15 for compact).
        share_counterfactual: in a benchmark, store each (scenario, seed)'s
            counterfactual crowd once for all planners (``_counterfactual/``) instead
            of in every episode file.
    """

    mcap: bool = True
    mcap_profile: Profile = "full"
    rrd: bool = True
    rrd_seeds: int | None = attrs.field(default=None)
    forces: bool = False
    scene_stride: int | None = None
    share_counterfactual: bool = False

    @rrd_seeds.validator
    def _rrd_seeds(self, attribute: Any, value: int | None) -> None:
        if value is not None and not _at_least(value, 0):
            raise LogError(f"rrd_seeds must be None (every seed) or >= 0, got {plain(value)}")

    def __attrs_post_init__(self) -> None:
        if not isinstance(self.mcap_profile, str) or self.mcap_profile not in PROFILES:
            raise LogError(
                f"unknown MCAP profile {plain(self.mcap_profile)}; choose from {list(PROFILES)}"
            )
        if self.scene_stride is not None and not _at_least(self.scene_stride, 1):
            raise LogError(f"scene stride must be at least 1, got {plain(self.scene_stride)}")

    @classmethod
    def benchmark_default(cls) -> LogOptions:
        """The benchmark's default: compact MCAP for every episode with the
        counterfactual crowd shared, Rerun for the first seed of each cell."""
        return cls(mcap_profile="compact", rrd_seeds=1, share_counterfactual=True)


def write_episode_logs(
    out: Path,
    record: EpisodeRecord,
    metrics: EpisodeMetrics,
    *,
    scenario: Scenario,
    options: LogOptions,
    rrd: bool | None = None,
    benchmark: Mapping[str, Any] | None = None,
    fsync: bool = True,
) -> list[Path]:
    """Write the logs of one episode into ``OUT/logs`` and return their paths.

    Args:
        out: the results folder.
        record: the finished episode.
        metrics: its metrics (their planner name names the folder).
        scenario: the scenario it ran.
        options: what to write.
        rrd: override ``options.rrd`` for this episode.
        benchmark: the request's scenarios, planners, seeds and reference.
        fsync: flush files to disk before renaming them into place.
    """
    from srfm.logs._rerun import write_rrd

    written: list[Path] = []
    planner = metrics.planner
    if planner == COUNTERFACTUAL_DIR:
        raise LogError(f"a planner named {COUNTERFACTUAL_DIR!r} cannot have a log folder")
    if options.mcap:
        path = episode_log_path(out, record.scenario, planner, record.seed, ".mcap")
        cf_file: str | None = None
        if options.share_counterfactual:
            cf_path = counterfactual_log_path(out, record.scenario, record.seed)
            if not cf_path.exists():  # the same for every planner: written once
                write_counterfactual_mcap(
                    cf_path, record, scenario=scenario, profile=options.mcap_profile, fsync=fsync
                )
                written.append(cf_path)
            cf_file = Path(os.path.relpath(cf_path, path.parent)).as_posix()
        write_episode_mcap(
            path,
            record,
            scenario=scenario,
            metrics=metrics,
            profile=options.mcap_profile,
            scene_stride=options.scene_stride,
            counterfactual_file=cf_file,
            benchmark=benchmark,
            fsync=fsync,
        )
        written.append(path)
    if options.rrd if rrd is None else rrd:
        path = episode_log_path(out, record.scenario, planner, record.seed, ".rrd")
        write_rrd(path, record, scenario=scenario, metrics=metrics, forces=options.forces)
        written.append(path)
    return written


@attrs.frozen(kw_only=True)
class EpisodeLogger:
    """The benchmark's per-episode writer (:data:`srfm.benchmark.EpisodeWriter`).

    Picklable, so that worker processes can call it. Build it with :meth:`create`.

    Attributes:
        options: what to write.
        scenarios: the request's scenarios by name (for world bounds and obstacles).
        rrd_seeds: the seeds that get a Rerun recording.
        benchmark: the request's scenario, planner and seed order and reference.
    """

    options: LogOptions
    scenarios: Mapping[str, Scenario]
    rrd_seeds: frozenset[int]
    benchmark: Mapping[str, Any]

    @classmethod
    def create(
        cls,
        options: LogOptions,
        *,
        scenarios: Sequence[Scenario],
        planners: Sequence[str],
        seeds: Sequence[int],
        reference: str | None,
    ) -> EpisodeLogger:
        """A writer for a benchmark request (the fields of a ``BenchmarkRequest``)."""
        if COUNTERFACTUAL_DIR in planners:
            raise LogError(f"a planner named {COUNTERFACTUAL_DIR!r} cannot have a log folder")
        k = len(seeds) if options.rrd_seeds is None else options.rrd_seeds
        return cls(
            options=options,
            scenarios={s.name: s for s in scenarios},
            rrd_seeds=frozenset(seeds[:k]) if options.rrd else frozenset(),
            benchmark={
                "scenarios": [s.name for s in scenarios],
                "planners": list(planners),
                "seeds": [int(s) for s in seeds],
                "reference": reference,
            },
        )

    def __call__(self, out: Path, record: EpisodeRecord, metrics: EpisodeMetrics) -> None:
        """Write the logs of one finished episode (called in a worker process)."""
        scenario = self.scenarios.get(record.scenario) or load_scenario(record.scenario)
        write_episode_logs(
            out,
            record,
            metrics,
            scenario=scenario,
            options=self.options,
            rrd=record.seed in self.rrd_seeds,
            benchmark=self.benchmark,
            fsync=False,
        )
