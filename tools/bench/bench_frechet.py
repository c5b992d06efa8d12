"""Fréchet distance speed: srfm's kernel against the `similaritymeasures` package.

Pairs are the factual and counterfactual trajectories (751 points each) of every
pedestrian in real twin episodes: the five evaluation scenarios, seeds 0-9, with the
`straight` planner. `similaritymeasures` (pure Python dynamic programme) runs on a
subset of the pairs; srfm runs on all of them, and on the subset for the ratio. A
third column times srfm's recurrence without its exact shortcuts (plain band-free
dynamic programme in numba), to show what the shortcuts add.

Run: .venv/bin/python tools/bench/bench_frechet.py  (needs the bench extra)
"""

from __future__ import annotations

import statistics
import time

import numpy as np

from srfm import EVALUATION_SCENARIOS, run_episode
from srfm.metrics import frechet_distance
from srfm.metrics._kernels import _band_dp

SEEDS = range(10)
SUBSET_EVERY = 10  # similaritymeasures on every 10th pair


def pairs() -> list[tuple[np.ndarray, np.ndarray]]:
    out = []
    for scenario in EVALUATION_SCENARIOS:
        for seed in SEEDS:
            record = run_episode(scenario, seed, "straight", parallel=False)
            for i in range(record.n_pedestrians):
                out.append(
                    (
                        np.ascontiguousarray(record.factual_pos[:, i]),
                        np.ascontiguousarray(record.counterfactual_pos[:, i]),
                    )
                )
    return out


def plain(p: np.ndarray, q: np.ndarray) -> float:
    m = q.shape[0]
    inf = np.full(m, np.inf)  # no suffix is ever "flat" below an infinite value
    big = np.full(m, -np.inf)
    return float(np.sqrt(_band_dp(p, q, 0.0, np.inf, np.empty(m), np.empty(m), big, inf, big, inf)))


def timed(fn, items) -> tuple[list[float], list[float]]:  # type: ignore[no-untyped-def]
    times, values = [], []
    for p, q in items:
        t = time.perf_counter()
        values.append(fn(p, q))
        times.append(time.perf_counter() - t)
    return times, values


def main() -> None:
    import similaritymeasures

    data = pairs()
    subset = data[::SUBSET_EVERY]
    frechet_distance(*data[0])  # load the kernels
    plain(*data[0])
    ours_all, _ = timed(frechet_distance, data)
    ours_sub, ours_vals = timed(frechet_distance, subset)
    plain_sub, plain_vals = timed(plain, subset)
    theirs, their_vals = timed(similaritymeasures.frechet_dist, subset)
    diff = max(abs(a - b) for a, b in zip(ours_vals, their_vals, strict=True))
    assert ours_vals == plain_vals, "shortcuts changed a value"
    print(f"pairs: {len(data)} (751 points each); similaritymeasures on {len(subset)}")
    print(f"largest |srfm - similaritymeasures| on the subset: {diff:.3g} m")
    rows = [
        ("srfm, all pairs", ours_all),
        ("srfm, subset", ours_sub),
        ("srfm without shortcuts, subset", plain_sub),
        ("similaritymeasures 1.x, subset", theirs),
    ]
    print(f"{'':34s} {'median ms':>10s} {'mean ms':>10s} {'max ms':>10s}")
    for name, ts in rows:
        ms = [t * 1e3 for t in ts]
        print(
            f"{name:34s} {statistics.median(ms):10.3f} {statistics.mean(ms):10.3f} {max(ms):10.3f}"
        )
    speedup = sum(theirs) / sum(ours_sub)
    print(f"speed-up on the subset (total time ratio): {speedup:.0f}x")
    print(f"speed-up of the shortcuts over the plain kernel: {sum(plain_sub) / sum(ours_sub):.1f}x")


if __name__ == "__main__":
    main()
