"""How large a run is, before it starts: its time and memory estimated from its size,
against this machine's limits.

A run (a benchmark, a sweep, one episode of ``srfm simulate``) is a list of episodes;
each is estimated from its scenario alone (docs/reliability.md, "Runs too large for the
machine"):

- **time** (CPU seconds of one twin episode on one core, fitted to episodes of the
  built-in scenarios with every planner on the reference machine of
  docs/performance.md; within about a factor of two): with S = horizon_steps + 1
  samples, N pedestrians, K the neighbours of a pedestrian within the interaction
  cut-off (N − 1, at most π (13.5 m)² times the crowd's density over the world) and
  M walls and pillars,

      S · (15 µs + N · (3.3 µs + 5.2 ns · K + 0.4 µs · M))   the crowds, the robot and
                                                              the planner (2 µs of the
                                                              3.3 per pedestrian)
      + N · S · (0.4 µs + 0.5 ns · S)                         the metrics (Fréchet)

  and the run's wall time is the sum over its episodes divided by the workers that run
  side by side (``jobs``, at most this machine's CPUs; unknown on a remote Dask
  cluster, where no time limit applies);
- **memory**: what this process holds for the whole run (the benchmark's reports hold
  every episode's metrics: 5 kB per episode and 2 kB per pedestrian and episode,
  measured with ``tracemalloc``; a sweep holds its tasks: 1 kB each, 20 kB on Dask)
  plus the episodes running side by side
  (:func:`srfm.sim.episode.estimate_episode_memory` each).

A run is refused (:class:`~srfm.errors.ResourceError`, with the estimate and how to go
ahead) when what it holds plus one episode exceeds this machine's memory
(:func:`srfm.sim.episode.memory_room`; fewer workers run when several episodes do not
fit side by side) or its wall time the time limit (:data:`DEFAULT_TIME_LIMIT_S`, or
``SRFM_TIME_LIMIT``), unless forced; a large run that goes ahead
(:attr:`RunEstimate.large`) has its estimate printed by the command line.
"""

from __future__ import annotations

import math
import os
import re
from collections.abc import Iterable, Mapping
from typing import Final

import attrs

from srfm._text import count
from srfm.errors import ResourceError
from srfm.scenarios import Scenario
from srfm.sim.episode import estimate_episode_memory, format_bytes, memory_room

__all__ = [
    "DEFAULT_TIME_LIMIT_S",
    "LARGE_RUN_BYTES",
    "LARGE_RUN_S",
    "TIME_LIMIT_ENV",
    "RunEstimate",
    "check_run",
    "estimate_episode_time",
    "estimate_run",
    "format_duration",
    "time_limit",
    "usable_cpus",
]

TIME_LIMIT_ENV: Final = "SRFM_TIME_LIMIT"
"""Environment variable that sets the time limit: seconds, or with a unit (90m, 48h, 7d)."""
DEFAULT_TIME_LIMIT_S: Final = 24 * 3600.0
"""A run estimated to take longer than this (wall time, one day) is refused unless forced."""
LARGE_RUN_S: Final = 300.0
"""A run estimated to take this long or longer (5 minutes) has its estimate printed."""
LARGE_RUN_BYTES: Final = 2**30
"""A run estimated to need this much memory or more (1 GiB) has its estimate printed."""

# CPU seconds of one twin episode (module docstring): per sample; per pedestrian and
# sample (both crowds 1.3 µs, the planner's view of them 2 µs); per neighbour,
# pedestrian and sample; per wall or pillar, pedestrian and sample; the metrics per
# pedestrian and sample, and per pedestrian and sample squared (the Fréchet table).
_SAMPLE_S: Final = 15e-6
_PED_SAMPLE_S: Final = 3.3e-6
_PAIR_SAMPLE_S: Final = 5.2e-9
_OBSTACLE_PED_SAMPLE_S: Final = 0.4e-6
_METRIC_PED_SAMPLE_S: Final = 0.4e-6
_METRIC_PED_SAMPLE_SQ_S: Final = 0.5e-9
# The interaction cut-off of the agrawal2024 parameters (docs/performance.md).
_CUTOFF_M: Final = 13.5
_UNITS_S: Final = {"": 1.0, "s": 1.0, "m": 60.0, "h": 3600.0, "d": 86400.0}


def estimate_episode_time(scenario: Scenario) -> float:
    """CPU seconds one twin episode of ``scenario`` takes on one core (the module's
    model: an estimate, within about a factor of two on the reference machine)."""
    samples = scenario.horizon_steps + 1
    n = scenario.n_pedestrians
    world = scenario.world
    area = max((world.x_max - world.x_min) * (world.y_max - world.y_min), 1e-9)
    neighbours = min(max(n - 1, 0), math.pi * _CUTOFF_M**2 * n / area)
    obstacles = int(scenario.obstacles.segments.shape[0] + scenario.obstacles.circles.shape[0])
    per_ped = _PED_SAMPLE_S + _PAIR_SAMPLE_S * neighbours + _OBSTACLE_PED_SAMPLE_S * obstacles
    step = _SAMPLE_S + n * per_ped
    metrics = n * (_METRIC_PED_SAMPLE_S + _METRIC_PED_SAMPLE_SQ_S * samples)
    return float(samples * (step + metrics))


def time_limit() -> tuple[float, str]:
    """The longest wall time (s) a run may be estimated to take, and where it comes
    from: ``SRFM_TIME_LIMIT`` when set (seconds, or a number with ``s``, ``m``, ``h``
    or ``d``), else :data:`DEFAULT_TIME_LIMIT_S`.

    Raises:
        ResourceError: ``SRFM_TIME_LIMIT`` is malformed.
    """
    text = os.environ.get(TIME_LIMIT_ENV, "").strip()
    if not text:
        return DEFAULT_TIME_LIMIT_S, "srfm's time limit"
    match = re.fullmatch(r"([0-9]+(?:\.[0-9]+)?)\s*([smhd]?)", text, re.IGNORECASE | re.ASCII)
    if match is None or float(match.group(1)) <= 0.0:
        raise ResourceError(
            f"{TIME_LIMIT_ENV}={text!r} is not a duration such as 3600, 90m, 48h or 7d"
        )
    return float(match.group(1)) * _UNITS_S[match.group(2).lower()], f"{TIME_LIMIT_ENV}={text}"


def usable_cpus() -> int:
    """The CPUs this process may run on (its affinity where known)."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):
        return max(1, os.cpu_count() or 1)


def format_duration(seconds: float) -> str:
    """A duration for a message: ``45 s``, ``12 min``, ``3.5 h``, ``9 days``, ``1.2e+03 years``."""
    if seconds < 90:
        return f"{seconds:.0f} s"
    if seconds < 90 * 60:
        return f"{seconds / 60:.0f} min"
    if seconds < 48 * 3600:
        return f"{seconds / 3600:.1f} h"
    if seconds < 730 * 86400:
        return f"{seconds / 86400:.0f} days"
    return f"{seconds / (365 * 86400):.3g} years"


@attrs.frozen(kw_only=True)
class RunEstimate:
    """The estimated size of a run (:func:`estimate_run`).

    Attributes:
        episodes: the run's episodes.
        cpu_s: their CPU time on one core (s).
        workers: episodes run side by side on this machine (None: on a remote cluster
            of unknown size).
        memory_bytes: the most memory the run needs at once on this machine.
        held_bytes: of it, what this process holds for the whole run.
        episode_bytes: one episode's memory (the largest).
        beyond: the limits of this machine the run exceeds (:func:`check_run` fills it;
            a run that goes ahead anyway was forced).
    """

    episodes: int
    cpu_s: float
    workers: int | None
    memory_bytes: int
    held_bytes: int
    episode_bytes: int
    beyond: tuple[str, ...] = ()

    @property
    def wall_s(self) -> float | None:
        """The estimated wall time (s) on ``workers`` workers (None: unknown)."""
        return None if self.workers is None else self.cpu_s / self.workers

    @property
    def large(self) -> bool:
        """Long or big enough for the command line to print the estimate (or beyond a
        limit, run by force)."""
        wall = self.cpu_s if self.wall_s is None else self.wall_s
        return bool(self.beyond) or wall >= LARGE_RUN_S or self.memory_bytes >= LARGE_RUN_BYTES

    def describe(self) -> str:
        """``2,000 episodes: about 3.5 h on 2 workers (7.0 h of CPU time), 1.20 GB of
        memory``."""
        if self.workers is None:
            where = f"about {format_duration(self.cpu_s)} of CPU time on the cluster"
        else:
            assert self.wall_s is not None
            where = f"about {format_duration(self.wall_s)} on {count(self.workers, 'worker')}"
            if self.workers > 1:
                where += f" ({format_duration(self.cpu_s)} of CPU time)"
        episodes = f"{self.episodes:,} episode" + ("" if self.episodes == 1 else "s")
        text = f"{episodes}: {where}, {format_bytes(self.memory_bytes)} of memory"
        return text + (f"; {' and '.join(self.beyond)}" if self.beyond else "")


def estimate_run(
    parts: Iterable[tuple[Scenario, int]],
    *,
    jobs: int = 1,
    remote: bool = False,
    logs: Mapping[str, bool] | None = None,
    held_per_episode: float = 0.0,
    held_per_pedestrian: float = 0.0,
) -> RunEstimate:
    """The estimate of a run of ``count`` episodes of each ``(scenario, count)``.

    Args:
        parts: the run's scenarios and how many episodes of each.
        jobs: workers asked for (at most :func:`usable_cpus` run side by side).
        remote: the episodes run on a remote Dask cluster: no workers here.
        logs: the logs written per episode (``mcap``, ``rrd``, ``forces``), for the
            episode's memory.
        held_per_episode, held_per_pedestrian: bytes this process holds for the whole
            run per episode, and per episode and pedestrian.
    """
    items = [(s, int(k)) for s, k in parts if k > 0]
    episodes = sum(k for _, k in items)
    cpu = sum(k * estimate_episode_time(s) for s, k in items)
    held = sum(k * (held_per_episode + held_per_pedestrian * s.n_pedestrians) for s, k in items)
    one = max((estimate_episode_memory(s, **(logs or {})) for s, _ in items), default=0)
    workers = None if remote else max(1, min(jobs, usable_cpus(), max(episodes, 1)))
    memory = int(held) + (workers or 0) * one
    return RunEstimate(
        episodes=episodes,
        cpu_s=cpu,
        workers=workers,
        memory_bytes=memory,
        held_bytes=int(held),
        episode_bytes=one,
    )


def check_run(
    estimate: RunEstimate, *, what: str, smaller: str, force: bool = False
) -> RunEstimate:
    """Refuse a run that cannot fit this machine's memory or would take longer than the
    time limit (:func:`time_limit`), unless ``force``.

    Args:
        estimate: the run's estimate.
        what: the run, for the message (``"the benchmark"``).
        smaller: how to ask for less (``"fewer scenarios, planners or seeds"``).
        force: go ahead anyway (``--force``).

    Returns:
        ``estimate`` with the limits it exceeds (``beyond``; empty unless forced).

    Raises:
        ResourceError: the estimate, the limit it exceeds, and how to go ahead.
    """
    beyond = []
    found = memory_room()
    if found is not None:
        room, source = found
        least = estimate.held_bytes + (0 if estimate.workers is None else estimate.episode_bytes)
        if least > room:
            beyond.append(f"more memory than the {format_bytes(max(room, 0))} of {source}")
    limit, source = time_limit()
    if estimate.wall_s is not None and estimate.wall_s > limit:
        beyond.append(f"longer than the limit of {format_duration(limit)} ({source})")
    estimate = attrs.evolve(estimate, beyond=tuple(beyond))
    if beyond and not force:
        raise ResourceError(
            f"{what} is too large for this machine: {estimate.describe()}. Ask for {smaller}, "
            "or give --force to run it anyway"
        )
    return estimate
