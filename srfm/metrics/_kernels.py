"""numba kernels for the metrics: the exact discrete Fréchet distance.

The dynamic programme works on squared distances and takes one square root at the end:
``sqrt`` is monotone and correctly rounded, so ``sqrt(max(a, b)) == max(sqrt(a),
sqrt(b))`` exactly and the result equals the textbook recurrence on distances bit for
bit, with one ``sqrt`` instead of n·m.

Pruning keeps it exact. Any monotone coupling of the two curves gives an upper bound U
on the answer (for equal lengths the time-aligned diagonal gives the largest pointwise
distance). A cell farther apart than U has c(i, j) ≥ d_ij > U, so no optimal coupling
passes through it: it is treated as unreachable, and each row only visits the columns
that a reachable cell of the previous row (or of the same row, to its left) can reach.
For two nearby twin trajectories that band is narrow and the cost close to linear.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["coupling_bound_sq", "frechet_sq", "frechet_sq_batch"]


@njit(cache=True)
def _dist_sq(p: np.ndarray, i: int, q: np.ndarray, j: int) -> float:
    dx = p[i, 0] - q[j, 0]
    dy = p[i, 1] - q[j, 1]
    d: float = dx * dx + dy * dy
    return d


@njit(cache=True)
def coupling_bound_sq(p: np.ndarray, q: np.ndarray) -> float:
    """An upper bound on the squared Fréchet distance from two monotone couplings.

    ``p`` is (n, 2), ``q`` is (m, 2) with n ≥ m ≥ 1. The first coupling walks the
    longer curve and advances on the shorter in proportion (the diagonal when n = m);
    the second is greedy (always the cheapest of the three moves). Both are valid
    couplings, so the larger squared distance along each is an upper bound; the
    smaller of the two is returned.
    """
    n = p.shape[0]
    m = q.shape[0]
    proportional = 0.0
    for i in range(n):
        j = (i * (m - 1)) // (n - 1) if n > 1 else 0
        d = _dist_sq(p, i, q, j)
        if d > proportional:
            proportional = d
    i = 0
    j = 0
    greedy = _dist_sq(p, 0, q, 0)
    while i < n - 1 or j < m - 1:
        if i == n - 1:
            j += 1
        elif j == m - 1:
            i += 1
        else:
            d_diag = _dist_sq(p, i + 1, q, j + 1)
            d_down = _dist_sq(p, i + 1, q, j)
            d_right = _dist_sq(p, i, q, j + 1)
            if d_diag <= d_down and d_diag <= d_right:
                i += 1
                j += 1
            elif d_down <= d_right:
                i += 1
            else:
                j += 1
        d = _dist_sq(p, i, q, j)
        if d > greedy:
            greedy = d
    return min(proportional, greedy)


@njit(cache=True)
def frechet_sq(p: np.ndarray, q: np.ndarray, prev: np.ndarray, cur: np.ndarray) -> float:
    """Squared discrete Fréchet distance between ``p`` (n, 2) and ``q`` (m, 2), n ≥ m ≥ 1.

    ``prev`` and ``cur`` are scratch rows of length ≥ m (the only memory used,
    O(min(n, m))). Rows run over the longer curve, columns over the shorter.
    """
    n = p.shape[0]
    m = q.shape[0]
    start = _dist_sq(p, 0, q, 0)
    end = _dist_sq(p, n - 1, q, m - 1)
    lower = max(start, end)
    bound = coupling_bound_sq(p, q)
    if bound <= lower:  # the answer lies in [lower, bound]
        return bound
    inf = np.inf
    # Row 0: a running maximum along q, reachable while it stays within the bound.
    hi = -1
    running = 0.0
    for j in range(m):
        d = _dist_sq(p, 0, q, j)
        if d > running:
            running = d
        if running > bound:
            break
        prev[j] = running
        hi = j
    lo = 0
    for i in range(1, n):
        new_lo = -1
        new_hi = -1
        left = inf  # c(i, j - 1)
        j = lo
        while j < m:
            best = left
            if j <= hi:
                up = prev[j]
                if up < best:
                    best = up
            if lo <= j - 1 <= hi:
                diag = prev[j - 1]
                if diag < best:
                    best = diag
            value = inf
            if best < inf:
                d = _dist_sq(p, i, q, j)
                if d <= bound:
                    value = d if d > best else best
            cur[j] = value
            if value < inf:
                if new_lo < 0:
                    new_lo = j
                new_hi = j
            elif j > hi:
                break  # past the previous row only the left neighbour leads on
            left = value
            j += 1
        if new_lo < 0:
            return inf  # unreachable with a valid bound
        lo = new_lo
        hi = new_hi
        prev, cur = cur, prev
    result: float = prev[m - 1] if hi == m - 1 else inf
    return result


@njit(cache=True)
def frechet_sq_batch(a: np.ndarray, b: np.ndarray, out: np.ndarray) -> None:
    """Squared Fréchet distance of each pair ``a[k]``, ``b[k]``; a, b are (K, T, 2)."""
    t = a.shape[1]
    prev = np.empty(t)
    cur = np.empty(t)
    for k in range(a.shape[0]):
        out[k] = frechet_sq(a[k], b[k], prev, cur)
