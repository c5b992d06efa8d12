"""Statistics over a whole suite run (issue 41; Agarwal et al., "Deep Reinforcement
Learning at the Edge of the Statistical Precipice", NeurIPS 2021).

Over every (scenario, seed) of a run, per planner:

- the **interquartile mean** (IQM, the mean of the middle 50 % of the values,
  ``scipy.stats.trim_mean(x, 0.25)``) of the episodes' deviation ``frechet_m`` and,
  with ``straight`` and ``oracle`` in the run, of their normalised score
  (:func:`srfm.metrics.headroom.episode_scores`: on the seeds where the planner,
  ``straight`` and the oracle all reached the goal, in the scenarios where the score
  is defined);
- the **probability of improvement** P(A < B) of every pair of planners: the chance
  that planner A deviates a person less than planner B does the same person (same
  scenario, seed and pedestrian), ties counting one half; averaged over the seeds of a
  scenario, then over the scenarios (each scenario weighs the same);
- **performance profiles**: the share of a planner's episodes whose deviation is at
  most τ, for every τ (:func:`profile`).

Every interval is a percentile interval of a **stratified bootstrap**: the seeds of
each scenario are resampled within that scenario (a seed keeps its pedestrians
together), ``N_RESAMPLES`` times, from a fixed generator seed, so the same run gives
the same interval. It is ``scipy.stats.bootstrap`` with one sample per scenario
(``paired=False``: each sample is resampled on its own, which is the stratification):
scipy is a dependency already and maintained, and its multi-sample form is exactly
this resampling; rliable, the reference implementation of the paper, would add a
dependency (and arch's) for the same percentile interval and expects as many runs
in every task, which the success-filtered scores do not have.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Mapping, Sequence
from typing import Any, Final

import attrs
import numpy as np
from numpy.typing import NDArray

from srfm.errors import MetricError
from srfm.metrics.episode import EpisodeMetrics
from srfm.metrics.headroom import Interval, episode_scores, min_score_seeds

__all__ = [
    "LEVEL",
    "N_RESAMPLES",
    "PROFILE_POINTS",
    "SuiteStats",
    "improvement_probabilities",
    "improvement_probability",
    "iqm",
    "iqm_interval",
    "profile",
    "suite_stats",
]

FloatArray = NDArray[np.float64]

N_RESAMPLES: Final = 2000
"""Bootstrap resamples of every suite interval."""
LEVEL: Final = 0.95
"""Their level."""
_SEED: Final = 41
PROFILE_POINTS: Final = 64
"""τ values of a performance profile (log-spaced over the run's deviations)."""
_TRIM: Final = 0.25


def iqm(values: Sequence[float] | FloatArray) -> float:
    """The interquartile mean of ``values`` (NaN when empty)."""
    from scipy import stats

    x = np.asarray(values, dtype=np.float64)
    return float(stats.trim_mean(x, _TRIM)) if x.size else math.nan


def _strata(strata: Sequence[Sequence[float] | FloatArray]) -> list[FloatArray]:
    out = []
    for s in strata:
        x = np.asarray(s, dtype=np.float64)
        if x.ndim != 1 or not np.isfinite(x).all():
            raise MetricError("every stratum must be a 1-D array of finite values")
        if x.size:
            out.append(x)
    return out


def _bootstrap_rows(
    strata: list[FloatArray], statistic: Callable[..., Any], estimates: FloatArray
) -> list[Interval]:
    """The stratified percentile interval of ``statistic`` for each row of the strata
    (each stratum (R, n_i): R quantities, n_i seeds), all rows from the same resampled
    seeds, one ``scipy.stats.bootstrap`` call: row r's interval is the one a call on
    row r alone gives. NaN bounds when a stratum has fewer than two seeds."""
    rows = len(estimates)
    n = sum(x.shape[-1] for x in strata)
    if not strata or any(x.shape[-1] < 2 for x in strata):
        return [Interval(float(e), math.nan, math.nan, n, LEVEL) for e in estimates]
    from scipy import stats

    constant = [bool(all(np.all(x[r] == strata[0][r, 0]) for x in strata)) for r in range(rows)]
    if all(constant):  # nothing varies: nothing to resample
        return [Interval(float(e), float(e), float(e), n, LEVEL) for e in estimates]
    res = stats.bootstrap(
        tuple(strata),
        statistic,
        n_resamples=N_RESAMPLES,
        confidence_level=LEVEL,
        method="percentile",
        vectorized=True,
        paired=False,
        axis=-1,
        rng=np.random.default_rng(_SEED),
    )
    low = np.atleast_1d(res.confidence_interval.low)
    high = np.atleast_1d(res.confidence_interval.high)
    return [
        Interval(float(e), float(e), float(e), n, LEVEL)
        if constant[r]
        else Interval(float(e), float(low[r]), float(high[r]), n, LEVEL)
        for r, e in enumerate(estimates)
    ]


def _bootstrap(
    strata: list[FloatArray], statistic: Callable[..., Any], estimate: float
) -> Interval:
    """:func:`_bootstrap_rows` of one quantity (1-D strata)."""
    return _bootstrap_rows([x[None, :] for x in strata], statistic, np.array([estimate]))[0]


def _iqm_stat(*samples: FloatArray, axis: int = -1) -> FloatArray:
    from scipy import stats

    joined = np.concatenate(samples, axis=axis)
    return np.asarray(stats.trim_mean(joined, _TRIM, axis=axis), dtype=np.float64)


def iqm_interval(strata: Sequence[Sequence[float] | FloatArray]) -> Interval:
    """The IQM of all values pooled, with its stratified bootstrap interval (one stratum
    per scenario, its values one per seed; empty strata are left out)."""
    kept = _strata(strata)
    pooled = np.concatenate(kept) if kept else np.zeros(0)
    return _bootstrap(kept, _iqm_stat, iqm(pooled))


def _mean_of_means(*samples: FloatArray, axis: int = -1) -> FloatArray:
    return np.asarray(np.mean([np.mean(x, axis=axis) for x in samples], axis=0), dtype=np.float64)


def _wins(a: Sequence[FloatArray], b: Sequence[FloatArray]) -> FloatArray:
    """Per seed, the share of the pedestrians whom A deviated less than B (ties one
    half; over the pedestrians both have a value for, 0.5 when none)."""
    if len(a) != len(b):
        raise MetricError(f"need the same seeds for both planners, got {len(a)} and {len(b)}")
    out = np.empty(len(a))
    for k, (x, y) in enumerate(zip(a, b, strict=True)):
        x = np.asarray(x, dtype=np.float64)
        y = np.asarray(y, dtype=np.float64)
        if x.shape != y.shape:
            raise MetricError(f"need the same pedestrians, got {x.shape} and {y.shape}")
        ok = np.isfinite(x) & np.isfinite(y)
        out[k] = float(np.mean((x[ok] < y[ok]) + 0.5 * (x[ok] == y[ok]))) if ok.any() else 0.5
    return out


def improvement_probabilities(
    pairs: Sequence[tuple[Sequence[Sequence[FloatArray]], Sequence[Sequence[FloatArray]]]],
) -> list[Interval]:
    """:func:`improvement_probability` of several pairs at once (one bootstrap call,
    the same resampled seeds for every pair; each pair's interval is the one it gets
    alone)."""
    if not pairs:
        return []
    n_scenarios = len(pairs[0][0])
    strata = []
    for c in range(n_scenarios):
        rows = []
        for a, b in pairs:
            if len(a) != n_scenarios or len(b) != n_scenarios:
                raise MetricError(
                    f"need the same scenarios for both planners, got {len(a)} and {len(b)}"
                )
            rows.append(_wins(a[c], b[c]))
        if rows[0].size:
            strata.append(np.vstack(rows))
    estimates = (
        np.mean([x.mean(axis=-1) for x in strata], axis=0)
        if strata
        else np.full(len(pairs), math.nan)
    )
    return _bootstrap_rows(strata, _mean_of_means, np.asarray(estimates, dtype=np.float64))


def improvement_probability(
    a: Sequence[Sequence[FloatArray]], b: Sequence[Sequence[FloatArray]]
) -> Interval:
    """P(A < B): per scenario (the outer sequences) and seed (the inner ones), the
    share of the pedestrians whom A deviated less than B (ties one half); the mean
    over the seeds, then over the scenarios, with its stratified bootstrap interval.

    Raises:
        MetricError: ``a`` and ``b`` of other shapes.
    """
    return improvement_probabilities([(a, b)])[0]


def profile(values: Sequence[float] | FloatArray, taus: FloatArray) -> FloatArray:
    """The share of ``values`` at most each τ of ``taus`` (a performance profile)."""
    x = np.sort(np.asarray(values, dtype=np.float64))
    if not x.size:
        return np.full(taus.shape, np.nan)
    return np.searchsorted(x, taus, side="right") / x.size


@attrs.frozen
class SuiteStats:
    """The suite statistics of one run (see the module doc).

    Attributes:
        planners: in the run's order.
        scenarios: in the run's order.
        deviation_iqm: per planner, the IQM of ``frechet_m`` over (scenario, seed).
        score_iqm: per planner, the IQM of its normalised scores (empty without
            ``straight`` and ``oracle``), over the scenarios where the score is
            defined; ``score_scenarios`` names them.
        improvement: ``improvement[(a, b)]``, P(a < b), for every ordered pair a ≠ b.
        taus: the profile's τ (m). profiles: per planner, the share ≤ each τ.
    """

    planners: tuple[str, ...]
    scenarios: tuple[str, ...]
    deviation_iqm: Mapping[str, Interval]
    score_iqm: Mapping[str, Interval]
    score_scenarios: Mapping[str, tuple[str, ...]]
    improvement: Mapping[tuple[str, str], Interval]
    taus: FloatArray
    profiles: Mapping[str, FloatArray]


def suite_stats(
    results: Sequence[EpisodeMetrics],
    *,
    scenarios: Sequence[str],
    planners: Sequence[str],
    seeds: Sequence[int],
) -> SuiteStats:
    """IQMs, probabilities of improvement and performance profiles of a run.

    Raises:
        MetricError: a missing (scenario, planner, seed).
    """
    found = {(r.scenario, r.planner, r.seed): r for r in results}

    def episodes(scenario: str, planner: str) -> list[EpisodeMetrics]:
        try:
            return [found[(scenario, planner, s)] for s in seeds]
        except KeyError as exc:
            raise MetricError(f"no result for {exc.args[0]}") from None

    cells = {(c, p): episodes(c, p) for c in scenarios for p in planners}
    deviation = {
        p: [np.array([r["frechet_m"] for r in cells[(c, p)]]) for c in scenarios] for p in planners
    }
    if all(np.isfinite(x).all() for p in planners for x in deviation[p]):
        strata = [np.vstack([deviation[p][c] for p in planners]) for c in range(len(scenarios))]
        strata = [x for x in strata if x.shape[-1]]
        by_planner = [np.concatenate([x[r] for x in strata]) for r in range(len(planners))]
        estimates = np.array([iqm(x) for x in by_planner])
        dev_iqm = dict(zip(planners, _bootstrap_rows(strata, _iqm_stat, estimates), strict=True))
    else:
        dev_iqm = {p: iqm_interval([x[np.isfinite(x)] for x in deviation[p]]) for p in planners}
    score_iqm: dict[str, Interval] = {}
    score_scenarios: dict[str, tuple[str, ...]] = {}
    if "straight" in planners and "oracle" in planners:
        min_k = min_score_seeds(len(seeds))
        for p in planners:
            strata, named = [], []
            for c in scenarios:
                masked = {
                    q: np.array(
                        [
                            r["frechet_m"] if r.outcome == "goal_reached" else math.nan
                            for r in cells[(c, q)]
                        ]
                    )
                    for q in ("straight", "oracle", p)
                }
                scores = episode_scores(masked["straight"], masked[p], masked["oracle"])
                if scores.size >= min_k:
                    strata.append(scores)
                    named.append(c)
            score_iqm[p] = iqm_interval(strata)
            score_scenarios[p] = tuple(named)
    per_ped = {
        p: [[r.pedestrians["frechet_m"] for r in cells[(c, p)]] for c in scenarios]
        for p in planners
    }
    improvement: dict[tuple[str, str], Interval] = {}
    pairs = list(itertools.combinations(planners, 2))
    found_pairs = improvement_probabilities([(per_ped[a], per_ped[b]) for a, b in pairs])
    for (a, b), x in zip(pairs, found_pairs, strict=True):  # P(b < a) = 1 − P(a < b)
        improvement[(a, b)] = x
        improvement[(b, a)] = Interval(1.0 - x.estimate, 1.0 - x.high, 1.0 - x.low, x.n, x.level)
    pooled = np.concatenate([np.concatenate(deviation[p]) for p in planners])
    pooled = pooled[np.isfinite(pooled) & (pooled > 0.0)]
    if pooled.size:
        low, high = float(pooled.min()), float(pooled.max())
        taus = np.geomspace(low, high, PROFILE_POINTS) if high > low else np.array([low])
    else:
        taus = np.zeros(0)
    profiles = {p: profile(np.concatenate(deviation[p]), taus) for p in planners}
    return SuiteStats(
        planners=tuple(planners),
        scenarios=tuple(scenarios),
        deviation_iqm=dev_iqm,
        score_iqm=score_iqm,
        score_scenarios=score_scenarios,
        improvement=improvement,
        taus=taus,
        profiles=profiles,
    )
