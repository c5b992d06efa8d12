"""numba kernels of the ``oracle`` reference planner: the prefix Fréchet deviation.

The oracle scores a candidate by the pedestrians' Fréchet deviation so far, predicted
to the end of its look-ahead. For each pedestrian i it keeps one row of the discrete
Fréchet dynamic programme between its factual samples f_0 … f_t and its counterfactual
path c_0 … c_T (known in advance: the counterfactual crowd does not feel the robot):

    D[t, j] = max(|f_t − c_j|, min(D[t−1, j], D[t−1, j−1], D[t, j−1])),

with D[0, j] = max_{j' ≤ j} |f_0 − c_j'|. The prefix deviation at sample t is
min_j D[t, j], the smallest Fréchet distance between the factual path so far and some
beginning of the counterfactual one; it never decreases with t and ends at most at the
episode's Fréchet distance (``frechet_m``, which also ties the two ends). Like that
metric it does not charge a pedestrian for being late, only for being elsewhere.

Rows are updated in place and limited to the band |j − t| ≤ ``band`` (a pedestrian
more than ``band`` samples ahead of or behind its twin is matched no further); cells
never reached hold +inf, so a new table is filled with +inf (row 0 must be computed on
such a table).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = ["extend_prefix_frechet", "prefix_frechet_mean"]


@njit(cache=True)
def extend_prefix_frechet(
    table: np.ndarray, f_pos: np.ndarray, c_path: np.ndarray, t: int, band: int
) -> None:
    """Replace row t − 1 of every pedestrian's table by row t.

    Args:
        table: (N, T + 1) the rows at sample t − 1 (all +inf before sample 0), updated.
        f_pos: (N, 2) the factual positions at sample t.
        c_path: (N, T + 1, 2) each pedestrian's counterfactual positions at every sample.
        t: the sample (0 … T).
        band: the most samples j may be from t.
    """
    n = f_pos.shape[0]
    last = c_path.shape[1] - 1
    lo = max(0, t - band)
    hi = min(last, t + band)
    for i in range(n):
        fx = f_pos[i, 0]
        fy = f_pos[i, 1]
        path = c_path[i]
        row = table[i]
        left = math.inf
        # D[-1, -1] = 0: row 0 (on a table of +inf) is the running max from j = 0.
        diag = row[lo - 1] if lo > 0 else (0.0 if t == 0 else math.inf)
        for j in range(lo, hi + 1):
            dx = fx - path[j, 0]
            dy = fy - path[j, 1]
            d = math.sqrt(dx * dx + dy * dy)
            up = row[j]
            value = max(d, min(up, min(diag, left)))
            diag = up
            row[j] = value
            left = value


@njit(cache=True)
def prefix_frechet_mean(table: np.ndarray, t: int, band: int) -> float:
    """Mean over pedestrians of min_j D[t, j] (the table holding row t)."""
    n = table.shape[0]
    if n == 0:
        return 0.0
    last = table.shape[1] - 1
    lo = max(0, t - band)
    hi = min(last, t + band)
    total = 0.0
    for i in range(n):
        best = math.inf
        for j in range(lo, hi + 1):
            best = min(best, table[i, j])
        total += best
    return float(total / n)
