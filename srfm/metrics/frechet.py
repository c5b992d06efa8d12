"""The exact discrete Fréchet distance (Eiter & Mannila 1994), the benchmark's deviation."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from srfm.errors import MetricError
from srfm.metrics._kernels import frechet_sq, frechet_sq_batch

__all__ = ["frechet_distance", "frechet_distances"]


def _curve(value: ArrayLike, name: str) -> NDArray[np.float64]:
    try:
        arr = np.ascontiguousarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise MetricError(f"{name} must be an (n, 2) array of numbers: {exc}") from None
    if arr.ndim != 2 or arr.shape[1] != 2:
        raise MetricError(f"{name} must have shape (n, 2), got {arr.shape}")
    if arr.shape[0] == 0:
        raise MetricError(f"{name} is empty: a curve needs at least one point")
    bad = ~np.isfinite(arr)
    if bad.any():
        row = int(np.argwhere(bad)[0][0])
        raise MetricError(f"{name} has a non-finite value at row {row}: {arr[row].tolist()}")
    return arr


def frechet_distance(p: ArrayLike, q: ArrayLike) -> float:
    """The exact discrete Fréchet distance between two polygonal curves (m).

    The smallest, over all monotone couplings of the points of ``p`` and ``q`` (both
    walks start together, end together and never step back), of the largest Euclidean
    distance between coupled points. Computed with the Eiter–Mannila recurrence
    (docs/metrics.md) in numba with two rows of memory, O(min(n, m)), and pruning that keeps
    the result exact (see ``srfm.metrics._kernels``).

    Args:
        p: (n, 2) points, n ≥ 1.
        q: (m, 2) points, m ≥ 1.

    Returns:
        The distance, in the unit of the points.

    Raises:
        MetricError: (a ``ValueError``) for non-numeric, wrongly shaped, empty or
            non-finite input.
    """
    a = _curve(p, "p")
    b = _curve(q, "q")
    if a.shape[0] < b.shape[0]:  # rows over the longer curve, memory over the shorter
        a, b = b, a
    m = b.shape[0]
    return math.sqrt(frechet_sq(a, b, np.empty(m), np.empty(m)))


def frechet_distances(a: ArrayLike, b: ArrayLike) -> NDArray[np.float64]:
    """Fréchet distance of each agent's pair of trajectories, time-major arrays.

    Args:
        a: (T, N, 2) positions of N agents over T samples (e.g. the factual twin).
        b: (T, N, 2) the same agents' other trajectories (e.g. the counterfactual twin).

    Returns:
        (N,) distances; ``out[k] == frechet_distance(a[:, k], b[:, k])``.
    """
    x = np.asarray(a, dtype=np.float64)
    y = np.asarray(b, dtype=np.float64)
    if x.ndim != 3 or x.shape[2] != 2 or x.shape != y.shape:
        raise MetricError(
            f"trajectories must both have shape (T, N, 2), got {x.shape} and {y.shape}"
        )
    if x.shape[0] == 0:
        raise MetricError("trajectories are empty: T must be at least 1")
    for name, arr in (("a", x), ("b", y)):
        if not np.isfinite(arr).all():
            raise MetricError(f"{name} has non-finite values")
    out = np.empty(x.shape[1])
    frechet_sq_batch(
        np.ascontiguousarray(x.transpose(1, 0, 2)), np.ascontiguousarray(y.transpose(1, 0, 2)), out
    )
    return np.sqrt(out)
