"""Aggregates over seeds and significance tests between planners."""

from __future__ import annotations

import functools
import math
import warnings
from typing import Any, Final

import attrs
import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.special import stdtr

from srfm._text import plain
from srfm.errors import MetricError

__all__ = [
    "ALPHA",
    "CORRECTIONS",
    "Comparison",
    "Summary",
    "adjust_p_values",
    "compare",
    "summarize",
    "wilson",
]

ALPHA: Final = 0.05
"""Significance level of every test (the paper's p = 0.05)."""

CORRECTIONS: Final[dict[str, str]] = {
    "holm": "Holm's step-down correction (family-wise error rate)",
    "bh": "the Benjamini–Hochberg correction (false discovery rate)",
    "none": "no correction for multiple comparisons",
}
"""The multiple-comparison corrections :func:`adjust_p_values` knows, with the words
the tables' legends use for them."""


def wilson(successes: float, n: int) -> tuple[float, float, float]:
    """A proportion and its 95 % (1 − :data:`ALPHA`) Wilson score interval.

    Args:
        successes: the count of successes; a fraction is allowed (a share of tied ranks).
        n: the number of trials; 0 gives NaN throughout.

    Returns:
        (proportion, low, high).
    """
    if n == 0:
        return math.nan, math.nan, math.nan
    z = _Z
    p = successes / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z * math.sqrt(max(p * (1 - p), 0.0) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    return p, max(centre - half, 0.0), min(centre + half, 1.0)


_Z: Final = 1.959963984540054
"""The standard normal's 1 − ALPHA / 2 quantile (scipy.stats.norm.ppf(0.975))."""


@attrs.frozen
class Summary:
    """Mean and sample standard deviation of the defined (finite) values.

    Attributes:
        n: number of finite values. Undefined entries (NaN: e.g. a time to goal that
            never happened) are not part of the mean; they are counted in
            ``undefined``, and tables show n wherever it is below the number of seeds.
        mean: their mean (NaN when n = 0).
        std: their sample standard deviation, ddof = 1 (NaN when n < 2).
        undefined: number of entries left out (NaN or infinite).
    """

    n: int
    mean: float
    std: float
    undefined: int = 0


def summarize(values: ArrayLike) -> Summary:
    """:class:`Summary` of the finite entries of ``values``; the others are counted."""
    x = np.asarray(values, dtype=np.float64).ravel()
    finite = x[np.isfinite(x)]
    n = int(finite.size)
    mean = float(finite.mean()) if n else math.nan
    std = float(finite.std(ddof=1)) if n >= 2 else math.nan
    return Summary(n=n, mean=mean, std=std, undefined=int(x.size) - n)


@attrs.frozen
class Comparison:
    """Two significance tests of a planner's metric against a reference planner's.

    Attributes:
        welch_p: two-sided p of Welch's unequal-variance t-test (the paper's
            "independent t-test") over all finite episodes of each planner.
        paired_p: two-sided p of the paired t-test over the seeds both planners have a
            finite value for.
        n_pairs: the number of those seeds.
        welch_p_adjusted, paired_p_adjusted: the same p-values adjusted for multiple
            comparisons over the family of tests of the table they belong to
            (:func:`adjust_p_values`); NaN before a table adjusts them and where the
            test is undefined. The tables' marks use these.
    """

    welch_p: float
    paired_p: float
    n_pairs: int
    welch_p_adjusted: float = math.nan
    paired_p_adjusted: float = math.nan

    @property
    def welch_significant(self) -> bool:
        """Welch's p below :data:`ALPHA` (False when the test is undefined)."""
        return self.welch_p < ALPHA

    @property
    def paired_significant(self) -> bool:
        """Paired p below :data:`ALPHA` (False when the test is undefined)."""
        return self.paired_p < ALPHA


def _finite(p: float) -> float:
    return p if math.isfinite(p) else math.nan


# The two t-tests below are scipy.stats.ttest_ind(equal_var=False) and ttest_rel (scipy
# 1.17) written out, operation for operation, on 1-D float64 arrays: the same bits
# (tests/metrics/test_stats_tables.py compares them with scipy's on random samples), without
# importing scipy.stats (0.5-1 s) or its per-call argument handling (1.3 ms a call).


def _variance(x: NDArray[np.float64]) -> Any:
    """Sample variance (ddof = 1) as scipy's ``_var``: the mean of squared deviations
    times n / (n - 1)."""
    n = np.asarray(x.shape[0], dtype=np.float64)
    return np.mean((x - np.mean(x, axis=0, keepdims=True)) ** 2, axis=0) * (n / (n - 1))


def _t_p_value(t: Any, df: Any) -> float:
    """Two-sided p of a t statistic with ``df`` degrees of freedom."""
    return _finite(float(2 * stdtr(np.asarray(df, dtype=np.float64), -np.abs(t))))


def _welch_p(a: NDArray[np.float64], b: NDArray[np.float64]) -> float:
    """Two-sided p of Welch's unequal-variance t-test."""
    n1, n2 = a.shape[0], b.shape[0]
    vn1 = _variance(a) / n1
    vn2 = _variance(b) / n2
    with np.errstate(divide="ignore", invalid="ignore"):
        df = (vn1 + vn2) ** 2 / (vn1**2 / (n1 - 1) + vn2**2 / (n2 - 1))
    df = np.where(np.isnan(df), 1.0, df)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.divide(np.mean(a, axis=0) - np.mean(b, axis=0), np.sqrt(vn1 + vn2))
    return _t_p_value(t, df)


def _paired_p(a: NDArray[np.float64], b: NDArray[np.float64]) -> float:
    """Two-sided p of the paired t-test (the one-sample test of a - b against 0)."""
    x = a - b
    n = x.shape[0]
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.divide(np.mean(x, axis=0) - np.asarray(0.0), np.sqrt(_variance(x) / n))
    return _t_p_value(t, n - 1)


def compare(
    reference: ArrayLike,
    other: ArrayLike,
) -> Comparison:
    """Welch's and the paired t-test of ``other`` against ``reference``.

    Args:
        reference: (S,) the reference planner's values, one per seed.
        other: (S,) the other planner's values on the same seeds, in the same order.

    Returns:
        Both p-values; NaN where a test is undefined (fewer than two values, or no
        variance at all).
    """
    a = np.asarray(reference, dtype=np.float64).ravel()
    b = np.asarray(other, dtype=np.float64).ravel()
    if a.shape != b.shape:
        raise MetricError(f"need one value per shared seed, got {a.shape} and {b.shape}")
    return _compare(a.tobytes(), b.tobytes())


@functools.lru_cache(maxsize=4096)
def _compare(reference: bytes, other: bytes) -> Comparison:
    """:func:`compare` of two float64 arrays given by their bytes: the tables of a
    benchmark share most columns, so the same pair is tested once (half of the
    tests of ``render_tables``; a :class:`Comparison` is immutable)."""
    a = np.frombuffer(reference, dtype=np.float64)
    b = np.frombuffer(other, dtype=np.float64)
    fa = a[np.isfinite(a)]
    fb = b[np.isfinite(b)]
    both = np.isfinite(a) & np.isfinite(b)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        welch = math.nan
        if fa.size >= 2 and fb.size >= 2 and (_spread(fa) or _spread(fb)):
            welch = _welch_p(fa, fb)
        paired = math.nan
        if np.count_nonzero(both) >= 2 and _spread(a[both] - b[both]):
            paired = _paired_p(a[both], b[both])
    return Comparison(welch_p=welch, paired_p=paired, n_pairs=int(np.count_nonzero(both)))


def _spread(x: NDArray[np.float64]) -> bool:
    return bool(x.size and np.ptp(x) > 0)


def adjust_p_values(p_values: ArrayLike, method: str) -> NDArray[np.float64]:
    """p-values adjusted for multiple comparisons over one family of tests.

    With the m defined (finite) p-values sorted, p_(1) ≤ … ≤ p_(m):

    - ``"holm"`` (Holm 1979): adj_(i) = max over j ≤ i of min(1, (m − j + 1) p_(j));
      rejecting where adj < α keeps the family-wise error rate at α.
    - ``"bh"`` (Benjamini & Hochberg 1995): adj_(i) = min over j ≥ i of
      min(1, m p_(j) / j); rejecting where adj < α keeps the false discovery rate at α
      (for independent or positively dependent tests).
    - ``"none"``: the p-values unchanged.

    Args:
        p_values: the family's p-values, any shape; NaN marks an undefined test, which
            stays NaN and is not counted in m.
        method: one of :data:`CORRECTIONS`.

    Returns:
        The adjusted p-values, same shape.

    Raises:
        MetricError: an unknown method, or a p-value outside [0, 1].
    """
    if method not in CORRECTIONS:
        raise MetricError(f"unknown correction {plain(method)}; known: {', '.join(CORRECTIONS)}")
    p = np.array(p_values, dtype=np.float64)
    flat = p.ravel()
    defined = np.flatnonzero(np.isfinite(flat))
    values = flat[defined]
    outside = ~np.isnan(flat) & ~((flat >= 0.0) & (flat <= 1.0))
    if np.any(outside):
        raise MetricError(f"p-values must lie in [0, 1], got {plain(float(flat[outside][0]))}")
    m = values.size
    if method == "none" or m == 0:
        return p
    order = np.argsort(values, kind="stable")
    ranked = values[order]
    k = np.arange(1, m + 1, dtype=np.float64)
    if method == "holm":
        adjusted = np.maximum.accumulate(np.minimum(1.0, (m - k + 1.0) * ranked))
    else:
        adjusted = np.minimum.accumulate(np.minimum(1.0, m * ranked / k)[::-1])[::-1]
    out = flat.copy()
    out[defined[order]] = adjusted
    return out.reshape(p.shape)
