"""CPU cost of scoring an episode (``episode_metrics``) next to simulating it.

For every evaluation scenario × planner × seed the script simulates the twin episode
once (``srfm.run_episode``, one thread) and scores it ``--repeat`` times; it reports
per episode the CPU time (``time.process_time``: the figure least disturbed by other
jobs on a shared machine) of the simulation and the median CPU time of the scoring.
Everything is compiled by a warm-up episode first, so compilation is not counted.

With ``PYTHONPATH`` pointing at an older tree the same script measures that tree's
metrics (before issue 16: the paper's four columns, robot outcomes and the twin
deviation metrics only), which gives what the metrics of issue 16 add per episode.

Usage::

    NUMBA_NUM_THREADS=1 .venv/bin/python tools/bench/bench_metrics.py
    NUMBA_NUM_THREADS=1 .venv/bin/python tools/bench/bench_metrics.py --planners dwa --seeds 2
"""

from __future__ import annotations

import argparse
import platform
import statistics
import time

EVALUATION = ("footpath", "crosswalk", "cross_footpath", "circle", "concert")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--planners", nargs="+", default=["dwa", "straight", "social-force"])
    parser.add_argument("--seeds", type=int, default=3, help="seeds 0..N-1 (default 3)")
    parser.add_argument("--repeat", type=int, default=5, help="scorings per episode")
    args = parser.parse_args()

    import srfm
    from srfm.metrics import episode_metrics

    warm = srfm.run_episode("crosswalk", seed=0, planner=args.planners[0])
    episode_metrics(warm)

    sim_ms: list[float] = []
    score_ms: list[float] = []
    for scenario in EVALUATION:
        for planner in args.planners:
            for seed in range(args.seeds):
                t0 = time.process_time()
                record = srfm.run_episode(scenario, seed=seed, planner=planner)
                sim_ms.append(1e3 * (time.process_time() - t0))
                runs = []
                for _ in range(args.repeat):
                    t0 = time.process_time()
                    episode_metrics(record)
                    runs.append(1e3 * (time.process_time() - t0))
                score_ms.append(statistics.median(runs))
    n = len(sim_ms)
    print(
        f"srfm {srfm.__version__} ({srfm.__file__}), "
        f"python {platform.python_version()}, {n} episodes"
    )
    print(
        f"  planners {', '.join(args.planners)}; seeds 0-{args.seeds - 1}; scenarios {EVALUATION}"
    )
    print("CPU ms per episode        median     mean      max")
    for name, xs in (("simulate (twin episode)", sim_ms), ("episode_metrics", score_ms)):
        print(
            f"  {name:<23} {statistics.median(xs):8.1f} {statistics.mean(xs):8.1f} {max(xs):8.1f}"
        )
    share = 100.0 * sum(score_ms) / (sum(sim_ms) + sum(score_ms))
    print(f"scoring share of simulate + score: {share:.1f} %")


if __name__ == "__main__":
    main()
