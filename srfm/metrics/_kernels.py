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

from srfm.models._primitives import ZERO

__all__ = ["coupling_bound_sq", "frechet_sq", "frechet_sq_batch", "hausdorff_lower_sq"]


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
    i = ZERO  # not literals (srfm.models._primitives.ZERO)
    j = ZERO
    greedy = _dist_sq(p, ZERO, q, ZERO)
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
def _order_decreasing(values: np.ndarray) -> np.ndarray:
    """Indices of ``values`` in decreasing order of value (heapsort; the order of ties
    is unspecified). Written out because numba's ``np.argsort`` costs seconds of
    compilation on a first run; the callers' results do not depend on the order of ties.
    """
    m = values.shape[0]
    idx = np.empty(m, dtype=np.int64)  # np.arange would compile an overload of its own
    for k in range(m):
        idx[k] = k
    # a min-heap on values: popping the smallest to the end leaves them in decreasing order
    for start in range(m // 2 - 1, -1, -1):
        _sift_down(values, idx, start, m)
    for end in range(m - 1, 0, -1):
        idx[0], idx[end] = idx[end], idx[0]
        _sift_down(values, idx, 0, end)
    return idx


@njit(cache=True, inline="always")
def _sift_down(values: np.ndarray, idx: np.ndarray, root: int, size: int) -> None:
    """Restore the min-heap property of ``idx[:size]`` (keyed by ``values``) below ``root``."""
    while True:
        child = 2 * root + 1
        if child >= size:
            return
        if child + 1 < size and values[idx[child + 1]] < values[idx[child]]:
            child += 1
        if values[idx[child]] < values[idx[root]]:
            idx[root], idx[child] = idx[child], idx[root]
            root = child
        else:
            return


@njit(cache=True)
def hausdorff_lower_sq(p: np.ndarray, q: np.ndarray) -> float:
    """max over j of min over i of the squared distance from q_j to p_i (m = len(q)).

    Every coupling visits each q_j with some p_i, so this directed Hausdorff distance
    is a lower bound on the (squared) Fréchet distance. Points are taken in decreasing
    order of their distance to the proportional partner; the scan for each stops as soon
    as it finds a p_i within the current maximum, and the whole search stops once no
    remaining point can raise it.
    """
    n = p.shape[0]
    m = q.shape[0]
    partner = np.empty(m)
    for j in range(m):
        i0 = (j * (n - 1)) // (m - 1) if m > 1 else 0
        partner[j] = _dist_sq(p, i0, q, j)
    order = _order_decreasing(partner)
    h = 0.0
    for k in range(m):
        j = order[k]
        best = partner[j]
        if best <= h:
            break
        i0 = (j * (n - 1)) // (m - 1) if m > 1 else 0
        for off in range(1, n):
            a = i0 - off
            b = i0 + off
            if a < 0 and b >= n:
                break
            if a >= 0:
                d = _dist_sq(p, a, q, j)
                if d < best:
                    best = d
            if b < n:
                d = _dist_sq(p, b, q, j)
                if d < best:
                    best = d
            if best <= h:
                break
        if best > h:
            h = best
    return h


@njit(cache=True)
def frechet_sq(p: np.ndarray, q: np.ndarray, prev: np.ndarray, cur: np.ndarray) -> float:
    """Squared discrete Fréchet distance between ``p`` (n, 2) and ``q`` (m, 2), n ≥ m ≥ 1.

    ``prev`` and ``cur`` are scratch rows of length ≥ m; with four suffix bounding-box
    arrays of length m they are the only memory used, O(min(n, m)). Rows run over the
    longer curve, columns over the shorter.

    Exact shortcuts (each keeps the result equal to the plain recurrence):

    - a lower bound L (end points, directed Hausdorff) and an upper bound U (two
      couplings) bracket the answer; when they meet, it is returned at once;
    - cells with d > U are unreachable (their value would exceed the answer);
    - values are clamped from below at L, which changes nothing at the end;
    - a row whose values from column f to the end are all one value V (a "flat"
      suffix, kept implicit) stays flat in the next row when every point of q[f:] lies
      within V of the row's point (checked against the bounding box of q[f:]): then
      only the columns before the flat part, and until the value reaches V again, are
      computed. This is what makes long stretches of standing or converged twins cheap.
    """
    n = p.shape[0]
    m = q.shape[0]
    lower = max(_dist_sq(p, ZERO, q, ZERO), _dist_sq(p, n - 1, q, m - 1))
    bound = coupling_bound_sq(p, q)
    if bound <= lower:  # the answer lies in [lower, bound]
        return bound
    lower = max(lower, hausdorff_lower_sq(p, q))
    if n == m:  # the other direction needs memory of the longer curve's length
        lower = max(lower, hausdorff_lower_sq(q, p))
    if bound <= lower:
        return bound
    # Bounding boxes of the suffixes q[j:].
    bx0 = np.empty(m)
    bx1 = np.empty(m)
    by0 = np.empty(m)
    by1 = np.empty(m)
    bx0[m - 1] = bx1[m - 1] = q[m - 1, 0]
    by0[m - 1] = by1[m - 1] = q[m - 1, 1]
    for j in range(m - 2, -1, -1):
        bx0[j] = min(bx0[j + 1], q[j, 0])
        bx1[j] = max(bx1[j + 1], q[j, 0])
        by0[j] = min(by0[j + 1], q[j, 1])
        by1[j] = max(by1[j + 1], q[j, 1])
    # Often the lower bound is the answer: a cheap pass over the narrow band of cells
    # within it decides that; otherwise the full pass within the upper bound.
    if _band_dp(p, q, lower, lower, prev, cur, bx0, bx1, by0, by1) <= lower:
        return lower
    return _band_dp(p, q, lower, bound, prev, cur, bx0, bx1, by0, by1)


@njit(cache=True)
def _band_dp(
    p: np.ndarray,
    q: np.ndarray,
    lower: float,
    bound: float,
    prev: np.ndarray,
    cur: np.ndarray,
    bx0: np.ndarray,
    bx1: np.ndarray,
    by0: np.ndarray,
    by1: np.ndarray,
) -> float:
    """The recurrence with values clamped below at ``lower`` and cells farther than
    ``bound`` unreachable; inf when the end cannot be reached within ``bound``."""
    n = p.shape[0]
    m = q.shape[0]
    inf = np.inf
    # Row 0: a running maximum along q, reachable while it stays within the bound.
    hi = -1
    running = lower
    for j in range(m):
        d = _dist_sq(p, ZERO, q, j)
        if d > running:
            running = d
        if running > bound:
            break
        prev[j] = running
        hi = j
    lo = ZERO
    flat = m  # prev[j] == flat_value for flat <= j <= hi (implicit); m: no flat part
    flat_value = inf
    if hi == m - 1:
        flat = m - 1
        flat_value = prev[m - 1]
        while flat > 0 and prev[flat - 1] == flat_value:
            flat -= 1
    for i in range(1, n):
        px = p[i, 0]
        py = p[i, 1]
        free = False
        if flat <= hi:
            fx = max(abs(px - bx0[flat]), abs(px - bx1[flat]))
            fy = max(abs(py - by0[flat]), abs(py - by1[flat]))
            free = fx * fx + fy * fy <= flat_value
        new_lo = -1
        new_hi = -1
        new_flat = m
        left = inf  # value of (i, j - 1)
        j = lo
        while j < m:
            best = left
            if j <= hi:
                up = flat_value if j >= flat else prev[j]
                if up < best:
                    best = up
            if lo <= j - 1 <= hi:
                diag = flat_value if j - 1 >= flat else prev[j - 1]
                if diag < best:
                    best = diag
            value = inf
            if best < inf:
                d = _dist_sq(p, i, q, j)
                if d <= bound:
                    value = best
                    if d > value:
                        value = d
            cur[j] = value
            if value < inf:
                if new_lo < 0:
                    new_lo = j
                new_hi = j
                if free and j >= flat and value == flat_value:
                    new_flat = j  # every later cell of this row equals flat_value
                    new_hi = m - 1
                    break
            elif j > hi:
                break  # past the previous row only the left neighbour leads on
            left = value
            j += 1
        if new_lo < 0:
            return inf  # nothing of this row is reachable within the bound
        if new_flat < m:
            new_value = flat_value
        else:
            new_value = inf
            if new_hi == m - 1:
                new_value = cur[m - 1]
                new_flat = m - 1
                while new_flat > new_lo and cur[new_flat - 1] == new_value:
                    new_flat -= 1
        lo = new_lo
        hi = new_hi
        flat = new_flat
        flat_value = new_value
        prev, cur = cur, prev
    if hi < m - 1:
        return inf
    result: float = flat_value if m - 1 >= flat else prev[m - 1]
    return result


@njit(cache=True)
def frechet_sq_batch(a: np.ndarray, b: np.ndarray, out: np.ndarray) -> None:
    """Squared Fréchet distance of each pair ``a[k]``, ``b[k]``; a, b are (K, T, 2)."""
    t = a.shape[1]
    prev = np.empty(t)
    cur = np.empty(t)
    for k in range(a.shape[0]):
        out[k] = frechet_sq(a[k], b[k], prev, cur)
