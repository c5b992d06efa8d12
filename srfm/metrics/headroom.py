"""Reference points of a scenario: headroom, normalised scores and the seeds a
comparison needs (issue 29; docs/benchmark.md, "Where the benchmark can tell planners
apart").

Every function takes one value per seed (the episode's ``frechet_m``, or any metric
where lower is better), planners' arrays aligned on the same seeds; seeds where a value
is missing (NaN) are left out of every paired quantity.

- **Headroom** = mean over seeds of ``straight − oracle``: how much less the best plan
  the ``oracle`` reference finds disturbs the crowd than driving straight to the goal.
  Its interval is the paired t-interval over the seeds.
- **Normalised score** of a planner = ``(straight − planner) / (straight − oracle)``
  of the means: 0 is ``straight``, 1 the ``oracle``; negative disturbs more than
  ``straight``. Its interval is the percentile interval of a paired bootstrap over
  seeds (the same resampled seeds for the three planners; ``N_BOOTSTRAP`` resamples,
  a fixed generator seed, so it is reproducible). Undefined (NaN) when the headroom
  is not positive.
- **Standard error** (seed to seed) of a scenario = SD of ``straight``'s values / √n.
- **Seeds needed** to detect a difference δ (0.05 m) between two planners with the
  two-sided paired t-test at α = 0.05 and power 0.8: the least n ≥ 2 with
  ``P(|T| > t_{1−α/2, n−1}) ≥ 0.8`` for T noncentral-t with n − 1 degrees of freedom
  and noncentrality δ √n / σ_d (close to ``((z_{1−α/2} + z_{power}) σ_d / δ)²`` + 1 or 2),
  where σ_d is the SD of the per-seed differences between two planners: the median,
  over every pair of the non-reference planners given, of that pair's SD (the pair
  ``straight``–``oracle`` when no other planner is given).
- A scenario **does not discriminate** when its headroom is below
  ``MIN_HEADROOM_M`` (0.1 m) or below ``MIN_STANDARD_ERRORS`` (3) standard errors: no
  planner can then beat ``straight`` by more than the seed-to-seed noise of a mean.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping, Sequence
from typing import Final

import attrs
import numpy as np
from numpy.typing import ArrayLike, NDArray

from srfm._text import plain
from srfm.errors import MetricError
from srfm.metrics.stats import ALPHA

__all__ = [
    "DETECT_M",
    "MIN_HEADROOM_M",
    "MIN_SCORE_SHARE",
    "MIN_STANDARD_ERRORS",
    "N_BOOTSTRAP",
    "POWER",
    "REFERENCE_PLANNERS",
    "Interval",
    "ScenarioReferences",
    "discriminates",
    "episode_scores",
    "headroom",
    "min_score_seeds",
    "normalised_score",
    "paired_sd",
    "scenario_references",
    "seeds_needed",
    "sigma_d",
    "standard_error",
]

FloatArray = NDArray[np.float64]

MIN_HEADROOM_M: Final = 0.1
"""A scenario whose headroom is below this (m) does not discriminate."""
MIN_STANDARD_ERRORS: Final = 3.0
"""... nor one whose headroom is below this many standard errors."""
DETECT_M: Final = 0.05
"""The difference between two planners (m) :func:`seeds_needed` is asked for."""
POWER: Final = 0.8
"""The power :func:`seeds_needed` is asked for."""
N_BOOTSTRAP: Final = 4000
"""Resamples of the normalised score's paired bootstrap."""
_BOOTSTRAP_SEED: Final = 29
MIN_SCORE_SHARE: Final = 0.5
"""A normalised score needs the planner, ``straight`` and the oracle to reach the goal
on at least this share of the seeds (:func:`min_score_seeds`)."""
REFERENCE_PLANNERS: Final = ("straight", "oracle", "stay")
"""Planners that are reference points, not entries: left out of σ_d's pairs."""


@attrs.frozen
class Interval:
    """An estimate with its two-sided interval (``level``, e.g. 0.95) over ``n`` seeds;
    NaN bounds when undefined."""

    estimate: float
    low: float
    high: float
    n: int
    level: float = 0.95

    def excludes_zero(self) -> bool:
        """The interval lies wholly above or wholly below zero."""
        return bool(self.low > 0.0 or self.high < 0.0)


def _values(x: ArrayLike, name: str) -> FloatArray:
    a = np.asarray(x, dtype=np.float64)
    if a.ndim != 1:
        raise MetricError(f"{name}: need one value per seed (1-D), got shape {a.shape}")
    return a


def _aligned(*arrays: tuple[ArrayLike, str]) -> list[FloatArray]:
    values = [_values(x, name) for x, name in arrays]
    sizes = {len(v) for v in values}
    if len(sizes) != 1:
        shapes = ", ".join(f"{name} {len(v)}" for v, (_, name) in zip(values, arrays, strict=True))
        raise MetricError(f"need one value per shared seed for each planner, got {shapes}")
    both = np.logical_and.reduce([np.isfinite(v) for v in values])
    return [v[both] for v in values]


def _level(level: float) -> float:
    if not (isinstance(level, float) and 0.0 < level < 1.0):
        raise MetricError(f"interval level must be in (0, 1), got {plain(level)}")
    return level


def headroom(straight: ArrayLike, oracle: ArrayLike, *, level: float = 0.95) -> Interval:
    """Mean of ``straight − oracle`` over the shared seeds, with its paired t-interval
    (NaN bounds for fewer than two seeds)."""
    s, o = _aligned((straight, "straight"), (oracle, "oracle"))
    d = s - o
    n = int(d.size)
    if n == 0:
        return Interval(math.nan, math.nan, math.nan, 0, _level(level))
    mean = float(d.mean())
    if n < 2:
        return Interval(mean, math.nan, math.nan, n, _level(level))
    from scipy import stats  # here: the benchmark's tables import this module, not scipy.stats

    half = (
        float(stats.t.ppf(0.5 + _level(level) / 2.0, n - 1)) * float(d.std(ddof=1)) / math.sqrt(n)
    )
    return Interval(mean, mean - half, mean + half, n, level)


def normalised_score(
    straight: ArrayLike,
    planner: ArrayLike,
    oracle: ArrayLike,
    *,
    level: float = 0.95,
    n_bootstrap: int = N_BOOTSTRAP,
) -> Interval:
    """``(mean straight − mean planner) / (mean straight − mean oracle)`` over the seeds
    all three have, with the percentile interval of a paired bootstrap over seeds
    (resamples whose headroom is not positive are left out; NaN when the headroom
    itself is not positive)."""
    s, p, o = _aligned((straight, "straight"), (planner, "planner"), (oracle, "oracle"))
    n = int(s.size)
    _level(level)
    if n_bootstrap < 1:
        raise MetricError(f"n_bootstrap must be >= 1, got {plain(n_bootstrap)}")
    room = float((s - o).mean()) if n else math.nan
    if not room > 0.0:
        return Interval(math.nan, math.nan, math.nan, n, level)
    estimate = float((s - p).mean()) / room
    if n < 2:
        return Interval(estimate, math.nan, math.nan, n, level)
    rng = np.random.default_rng(_BOOTSTRAP_SEED)
    idx = rng.integers(0, n, size=(n_bootstrap, n))
    gain = (s - p)[idx].mean(axis=1)
    rooms = (s - o)[idx].mean(axis=1)
    ok = rooms > 0.0
    if not ok.any():
        return Interval(estimate, math.nan, math.nan, n, level)
    ratios = gain[ok] / rooms[ok]
    tail = (1.0 - level) / 2.0
    low, high = np.quantile(ratios, [tail, 1.0 - tail])
    return Interval(estimate, float(low), float(high), n, level)


def min_score_seeds(n_seeds: int) -> int:
    """The least number k of seeds on which the planner, ``straight`` and the oracle all
    reached the goal for a normalised score to be shown: max(2, ⌈``MIN_SCORE_SHARE`` ·
    n_seeds⌉); with fewer the score is undefined."""
    return max(2, math.ceil(MIN_SCORE_SHARE * n_seeds - 1e-9))


def episode_scores(straight: ArrayLike, planner: ArrayLike, oracle: ArrayLike) -> FloatArray:
    """Each shared seed's normalised score ``(straight − planner) / H``, H the mean of
    ``straight − oracle`` over the same seeds (the seeds where all three have a value):
    their mean is :func:`normalised_score`'s estimate. Empty when H is not positive."""
    s, p, o = _aligned((straight, "straight"), (planner, "planner"), (oracle, "oracle"))
    room = float((s - o).mean()) if s.size else math.nan
    if not room > 0.0:
        return np.zeros(0)
    return np.asarray((s - p) / room, dtype=np.float64)


def standard_error(values: ArrayLike) -> float:
    """SD / √n of the finite values (NaN for fewer than two)."""
    x = _values(values, "values")
    x = x[np.isfinite(x)]
    return float(x.std(ddof=1)) / math.sqrt(x.size) if x.size >= 2 else math.nan


def paired_sd(a: ArrayLike, b: ArrayLike) -> float:
    """SD of the per-seed differences ``a − b`` over the shared seeds (NaN for fewer
    than two)."""
    x, y = _aligned((a, "a"), (b, "b"))
    return float((x - y).std(ddof=1)) if x.size >= 2 else math.nan


def sigma_d(
    values: Mapping[str, ArrayLike],
    *,
    references: Sequence[str] = REFERENCE_PLANNERS,
    fallback: tuple[str, str] | None = None,
) -> float:
    """σ_d: the median, over every pair of the planners that are not ``references``, of
    the SD of their per-seed differences (:func:`paired_sd`); with fewer than two such
    planners, the SD of the ``fallback`` pair's differences (NaN without one). It does
    not involve the oracle, so it can be measured where the oracle was not run.

    Args:
        values: per planner, its values on the same seeds, in the same order.
        references: planners left out of the pairs.
        fallback: the pair to use when fewer than two planners remain.
    """
    entries = [p for p in values if p not in references]
    pairs = list(itertools.combinations(entries, 2)) or ([fallback] if fallback else [])
    sds = [paired_sd(values[a], values[b]) for a, b in pairs]
    finite = [x for x in sds if math.isfinite(x)]
    return float(np.median(finite)) if finite else math.nan


def seeds_needed(
    sd_diff: float,
    delta: float = DETECT_M,
    *,
    alpha: float = ALPHA,
    power: float = POWER,
    most: int = 1_000_000,
) -> int:
    """The least number of seeds n ≥ 2 for which the two-sided paired t-test at level
    ``alpha`` detects a true mean difference ``delta`` with probability ``power``, the
    per-seed differences having SD ``sd_diff`` (noncentral t; see the module doc).

    Raises:
        MetricError: a non-finite or negative SD, a non-positive delta, alpha or power
            outside (0, 1), or more than ``most`` seeds needed.
    """
    from scipy import stats

    if not (math.isfinite(sd_diff) and sd_diff >= 0.0):
        raise MetricError(f"sd_diff must be a finite number >= 0, got {plain(sd_diff)}")
    if not (math.isfinite(delta) and delta > 0.0):
        raise MetricError(f"delta must be a number > 0, got {plain(delta)}")
    for name, value in (("alpha", alpha), ("power", power)):
        if not 0.0 < value < 1.0:
            raise MetricError(f"{name} must be in (0, 1), got {plain(value)}")
    if sd_diff == 0.0:
        return 2

    def achieved(n: int) -> float:
        crit = float(stats.t.ppf(1.0 - alpha / 2.0, n - 1))
        nc = delta * math.sqrt(n) / sd_diff
        return float(stats.nct.sf(crit, n - 1, nc) + stats.nct.cdf(-crit, n - 1, nc))

    z = float(stats.norm.ppf(1.0 - alpha / 2.0) + stats.norm.ppf(power))
    n = max(2, math.ceil((z * sd_diff / delta) ** 2) - 1)  # the normal guess, then up
    if n > most:
        raise MetricError(f"more than {most} seeds needed (sd_diff {sd_diff}, delta {delta})")
    while n > 2 and achieved(n - 1) >= power:
        n -= 1
    while achieved(n) < power:
        n += 1
        if n > most:
            raise MetricError(f"more than {most} seeds needed (sd_diff {sd_diff}, delta {delta})")
    return n


def discriminates(headroom_m: float, se_m: float) -> bool:
    """A scenario discriminates when its headroom is at least ``MIN_HEADROOM_M`` and at
    least ``MIN_STANDARD_ERRORS`` standard errors (False when either is NaN)."""
    return bool(headroom_m >= MIN_HEADROOM_M and headroom_m >= MIN_STANDARD_ERRORS * se_m)


@attrs.frozen
class ScenarioReferences:
    """One scenario's reference points (see the module doc).

    Attributes:
        n: seeds with a value for both ``straight`` and ``oracle``.
        standard_error: SD of ``straight``'s values / √n (m).
        headroom: ``straight − oracle`` with its paired t-interval (m).
        scores: each planner's normalised score with its bootstrap interval.
        sd_diff: σ_d, the SD of paired differences :func:`seeds_needed` uses (m).
        seeds_needed: seeds to detect ``DETECT_M`` between two planners.
        discriminates: the scenario's headroom passes :func:`discriminates`.
        n_seeds: the seeds of the run (the n of a score's k/n).
        beats_oracle: the planners whose score exceeds 1 (they disturbed the crowd
            less than the oracle on the seeds where both reached the goal): the
            oracle is then not a bound and the headroom is a lower bound.
    """

    n: int
    standard_error: float
    headroom: Interval
    scores: Mapping[str, Interval]
    sd_diff: float
    seeds_needed: int | None
    discriminates: bool
    n_seeds: int = 0
    beats_oracle: tuple[str, ...] = ()

    @property
    def oracle_is_bound(self) -> bool:
        """No planner scored above the oracle: the headroom is the oracle's."""
        return not self.beats_oracle


def scenario_references(
    values: Mapping[str, ArrayLike],
    *,
    straight: str = "straight",
    oracle: str = "oracle",
    references: Sequence[str] = REFERENCE_PLANNERS,
    n_bootstrap: int = N_BOOTSTRAP,
    success: Mapping[str, ArrayLike] | None = None,
) -> ScenarioReferences:
    """Headroom, normalised scores, standard error and seeds needed of one scenario.

    Args:
        values: per planner, its values (e.g. ``frechet_m``) on the same seeds, in the
            same order; must hold ``straight`` and ``oracle``.
        straight, oracle: the names of the two reference planners.
        references: planners left out of σ_d's pairs (and scored all the same).
        n_bootstrap: resamples of the normalised scores' bootstrap.
        success: per planner, whether it reached the goal on each seed. Given, the
            headroom is taken over the seeds where ``straight`` and the oracle both
            reached it, and each planner's score over the seeds where it did too
            (paired), undefined below :func:`min_score_seeds` of them.

    Raises:
        MetricError: ``straight`` or ``oracle`` missing, or unaligned values.
    """
    for name in (straight, oracle):
        if name not in values:
            raise MetricError(f"need the {name!r} planner's values, got {sorted(values)}")
    raw = {p: _values(v, p) for p, v in values.items()}
    n_seeds = len(raw[straight])
    if success is None:
        kept = raw
    else:
        kept = {}
        for p, v in raw.items():
            ok = np.asarray(success[p], dtype=np.bool_)
            if ok.shape != v.shape:
                raise MetricError(f"{p}: {ok.shape} success flags for {v.shape} values")
            kept[p] = np.where(ok, v, np.nan)
    s = kept[straight]
    o = kept[oracle]
    room = headroom(s, o)
    se = standard_error(raw[straight])
    min_k = min_score_seeds(n_seeds) if success is not None else 1
    scores = {}
    for p, v in kept.items():
        score = normalised_score(s, v, o, n_bootstrap=n_bootstrap)
        if score.n < min_k:
            score = Interval(math.nan, math.nan, math.nan, score.n, score.level)
        scores[p] = score
    sd_diff = sigma_d(raw, references=references, fallback=(straight, oracle))
    needed = seeds_needed(sd_diff) if math.isfinite(sd_diff) else None
    beats = tuple(p for p, x in scores.items() if p not in (straight, oracle) and x.estimate > 1.0)
    return ScenarioReferences(
        n=room.n,
        standard_error=se,
        headroom=room,
        scores=scores,
        sd_diff=sd_diff,
        seeds_needed=needed,
        discriminates=discriminates(room.estimate, se),
        n_seeds=n_seeds,
        beats_oracle=beats,
    )
