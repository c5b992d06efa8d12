"""What of a deviation is the robot's doing (issue 41; docs/metrics.md).

- **Noise floor** of a (scenario, seed, parameter set): the deviation an imperceptible
  perturbation produces with no robot acting, :func:`noise_floor` of
  :func:`srfm.sim.floor.nudged_twins` (one start moved 1 mm): the mean over the
  pedestrians of the Fréchet distance between the nudged and the unnudged crowd, the
  same average as an episode's ``frechet_m``.
- **Direct and knock-on deviation** of an episode (:func:`deviation_split`): the
  pedestrians whose largest robot force (``robot_force_max_mps2``) reached
  ``FELT_FORCE_MPS2`` at some step felt the robot; the others' deviation reached them
  only through other people. ``frechet_direct_m`` + ``frechet_knock_on_m`` =
  ``frechet_m`` (up to rounding): each is a sum over its pedestrians divided by the
  number of pedestrians of the episode.
- Which scenarios measure the robot (:func:`floor_verdict`): the floor's share of the
  planners' mean deviation.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Final

import attrs
import numpy as np
from numpy.typing import NDArray

from srfm.errors import MetricError
from srfm.metrics.episode import EpisodeMetrics
from srfm.metrics.frechet import frechet_distances
from srfm.sim.floor import NudgedTwins

__all__ = [
    "CHAOS_SHARE",
    "FELT_FORCE_MPS2",
    "ROBOT_SHARE",
    "SPLIT_COLUMNS",
    "FloorSummary",
    "attributable",
    "deviation_split",
    "felt_robot",
    "floor_summary",
    "floor_verdict",
    "noise_floor",
    "split_table",
]

FloatArray = NDArray[np.float64]

FELT_FORCE_MPS2: Final = 0.02
"""A pedestrian felt the robot when the robot term on it reached this (m/s²) at some
step: 1 % of the goal force that starts a pedestrian of the paper's scenarios
(v0 = 1.25 m/s, agrawal2024's τ = 0.6 s: v0 / τ = 2.08 m/s²), rounded down to 0.02. A
fixed number, so that the split means the same under every parameter set."""

ROBOT_SHARE: Final = 0.1
"""A scenario measures the robot when its noise floor is below this share of the
planners' mean deviation ..."""
CHAOS_SHARE: Final = 0.5
"""... and mostly the crowd's chaos when the floor is at least this share of it
(in between: both)."""

SPLIT_COLUMNS: Final[tuple[tuple[str, str, str], ...]] = (
    ("frechet_direct_m", "m", "the pedestrians who felt the robot (force ≥ threshold)"),
    ("frechet_knock_on_m", "m", "the pedestrians who never did (through other people)"),
    ("pedestrians_felt", "count", "pedestrians who felt the robot"),
)
"""The split's columns: name, unit, what it holds."""


def felt_robot(metrics: EpisodeMetrics) -> NDArray[np.bool_]:
    """(N,) whether each pedestrian's largest robot force reached ``FELT_FORCE_MPS2``
    (False where it is undefined)."""
    peak = np.asarray(metrics.pedestrians["robot_force_max_mps2"], dtype=np.float64)
    with np.errstate(invalid="ignore"):
        return np.asarray(peak >= FELT_FORCE_MPS2, dtype=np.bool_)


def deviation_split(metrics: EpisodeMetrics) -> dict[str, float]:
    """The episode's deviation split into its direct and knock-on part, and the number
    of pedestrians who felt the robot (see the module doc)."""
    frechet = np.asarray(metrics.pedestrians["frechet_m"], dtype=np.float64)
    felt = felt_robot(metrics)
    n = frechet.size
    if n == 0:
        return {
            "frechet_direct_m": math.nan,
            "frechet_knock_on_m": math.nan,
            "pedestrians_felt": 0.0,
        }
    return {
        "frechet_direct_m": float(frechet[felt].sum()) / n,
        "frechet_knock_on_m": float(frechet[~felt].sum()) / n,
        "pedestrians_felt": float(np.count_nonzero(felt)),
    }


def noise_floor(twins: NudgedTwins) -> FloatArray:
    """(N,) each pedestrian's Fréchet distance between the nudged and the unnudged
    crowd; the floor of the (scenario, seed) is their mean."""
    return frechet_distances(twins.nudged_pos, twins.reference_pos)


@attrs.frozen
class FloorSummary:
    """A scenario's noise floor over its seeds.

    Attributes:
        n: seeds.
        mean: mean floor over the seeds (m).
        std: sample SD over the seeds (ddof = 1; NaN for one seed): the floor's spread,
            below which a difference between two planners' mean deviations is not
            attributable to the planners.
        values: the floor of each seed (m), in seed order.
        deviation: the planners' mean deviation in the scenario (m), pooled over the
            planners and seeds given (NaN without any).
        share: mean / deviation.
        verdict: ``"robot"``, ``"both"`` or ``"chaos"`` (:func:`floor_verdict`).
    """

    n: int
    mean: float
    std: float
    values: tuple[float, ...]
    deviation: float
    share: float
    verdict: str


def floor_verdict(share: float) -> str:
    """``"robot"`` when the floor is below ``ROBOT_SHARE`` of the deviation, ``"chaos"``
    when it is at least ``CHAOS_SHARE``, else ``"both"`` (``"–"`` when undefined)."""
    if math.isnan(share):
        return "–"
    if share < ROBOT_SHARE:
        return "robot"
    return "chaos" if share >= CHAOS_SHARE else "both"


def floor_summary(values: Sequence[float], deviations: Sequence[float]) -> FloorSummary:
    """Summarise one scenario's per-seed floors beside the planners' deviations there.

    Raises:
        MetricError: no floor value, or a non-finite one.
    """
    x = np.asarray(values, dtype=np.float64)
    if x.ndim != 1 or x.size == 0 or not np.isfinite(x).all():
        raise MetricError(f"need one finite floor value per seed, got {list(values)[:5]}")
    d = np.asarray(deviations, dtype=np.float64)
    d = d[np.isfinite(d)]
    mean = float(x.mean())
    std = float(x.std(ddof=1)) if x.size >= 2 else math.nan
    deviation = float(d.mean()) if d.size else math.nan
    share = mean / deviation if deviation > 0.0 else math.nan
    return FloorSummary(
        n=int(x.size),
        mean=mean,
        std=std,
        values=tuple(float(v) for v in x),
        deviation=deviation,
        share=share,
        verdict=floor_verdict(share),
    )


def attributable(difference: float, floor: FloorSummary) -> bool:
    """Whether a difference between two planners' mean deviations (m) is at least the
    floor's spread (its SD over seeds; its mean with one seed)."""
    spread = floor.std if not math.isnan(floor.std) else floor.mean
    return bool(abs(difference) >= spread)


def split_table(
    results: Sequence[EpisodeMetrics],
) -> Mapping[tuple[str, str, int], dict[str, float]]:
    """:func:`deviation_split` of every episode, by (scenario, planner, seed)."""
    return {(r.scenario, r.planner, r.seed): deviation_split(r) for r in results}
