"""The run-size time model (``srfm.sim.budget``) against measured episodes, and its refit.

For every built-in scenario and every large crowd, with every default planner, seeds
``0 .. --seeds − 1``: one twin episode (``srfm.run_episode``, serial kernels, as a
benchmark worker runs it) and its metrics (``srfm.metrics.episode_metrics``), each timed
with ``time.process_time`` (CPU time of this one process, after a warm-up episode of
each scenario and planner that compiles and loads everything), beside the model's
estimate (``estimate_episode_time``) and the model's terms (S samples, N pedestrians,
K neighbours, M walls and pillars).

The refit: the episode's simulation time by non-negative least squares on S, S·N,
S·N·K and S·N·M, its metrics time on N·S and N·S², both in relative terms (each episode
weighted by 1 / its measured time, so the 10-pedestrian episodes count as much as the
400-pedestrian ones); the shipped coefficients are written beside it.

The memory a benchmark's report phase holds per episode (the run-size model's
``held_per_episode`` and ``held_per_pedestrian``, ``srfm/benchmark/_runner.py``):
``--memory-seeds`` episodes of each of three scenarios of 10, 27 and 400 pedestrians
are written as a benchmark writes them and read back as its report phase does
(``write_episode``, ``read_episode``); the bytes the read metrics hold
(``tracemalloc``, after garbage collection) per episode, fitted as a + b · N.

It also writes the estimate line ``srfm benchmark`` prints for two requests on two
workers (``--suite large``, and the paper's full benchmark), as the model gives them.

Usage::

    .venv/bin/python tools/bench/bench_time_model.py
    .venv/bin/python tools/bench/bench_time_model.py --json docs/results/performance/time_model.json
"""

from __future__ import annotations

import argparse
import gc
import json
import math
import sys
import tempfile
import time
import tracemalloc
from pathlib import Path
from typing import Any

import numpy as np
from scipy.optimize import nnls

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from srfm.benchmark import BenchmarkRequest, default_planners
from srfm.benchmark._runner import _HELD_PER_EPISODE, _HELD_PER_PEDESTRIAN, estimate_benchmark
from srfm.metrics import episode_metrics
from srfm.scenarios import Scenario, load_scenario, scenario_names
from srfm.scenarios.suites import SUITES
from srfm.sim import budget
from srfm.sim.episode import run_episode
from tools.results.record import run_record, start

SIMULATION_TERMS = ("S", "S·N", "S·N·K", "S·N·M")
METRICS_TERMS = ("N·S", "N·S²")
SHIPPED = {
    "S": budget._SAMPLE_S,
    "S·N": budget._PED_SAMPLE_S,
    "S·N·K": budget._PAIR_SAMPLE_S,
    "S·N·M": budget._OBSTACLE_PED_SAMPLE_S,
    "N·S": budget._METRIC_PED_SAMPLE_S,
    "N·S²": budget._METRIC_PED_SAMPLE_SQ_S,
}
"""The shipped model's coefficients (s per unit of each term)."""


def terms(scenario: Scenario) -> dict[str, float]:
    """The model's S, N, K, M of ``scenario`` (as ``estimate_episode_time`` computes them)."""
    s = scenario.horizon_steps + 1
    n = scenario.n_pedestrians
    world = scenario.world
    area = max((world.x_max - world.x_min) * (world.y_max - world.y_min), 1e-9)
    k = min(max(n - 1, 0), math.pi * budget._CUTOFF_M**2 * n / area)
    m = int(scenario.obstacles.segments.shape[0] + scenario.obstacles.circles.shape[0])
    return {"S": s, "N": n, "K": k, "M": m}


def features(t: dict[str, float]) -> dict[str, float]:
    """Each term of the model for one scenario."""
    s, n, k, m = t["S"], t["N"], t["K"], t["M"]
    return {
        "S": s,
        "S·N": s * n,
        "S·N·K": s * n * k,
        "S·N·M": s * n * m,
        "N·S": n * s,
        "N·S²": n * s * s,
    }


def fit(rows: list[dict[str, Any]], names: tuple[str, ...], column: str) -> dict[str, float]:
    """Non-negative least squares of ``column`` on the terms ``names``, relative errors."""
    a = np.array([[r["features"][n] for n in names] for r in rows], dtype=float)
    y = np.array([r[column] for r in rows], dtype=float)
    w = 1.0 / y
    scale = np.where(a.max(axis=0) > 0, a.max(axis=0), 1.0)
    coef, _ = nnls(a * w[:, None] / scale, y * w)
    return {n: float(c / s) for n, c, s in zip(names, coef, scale, strict=True)}


def measure(names: list[str], planners: tuple[str, ...], seeds: int) -> list[dict[str, Any]]:
    """Every episode's CPU seconds (simulation, metrics) beside the model's estimate."""
    rows: list[dict[str, Any]] = []
    for name in names:
        scenario = load_scenario(name)
        t = terms(scenario)
        f = features(t)
        estimate = budget.estimate_episode_time(scenario)
        for planner in planners:
            episode_metrics(run_episode(scenario, 99, planner, parallel=False))  # warm-up
            for seed in range(seeds):
                c0 = time.process_time()
                record = run_episode(scenario, seed, planner, parallel=False)
                c1 = time.process_time()
                episode_metrics(record)
                c2 = time.process_time()
                rows.append(
                    {
                        "scenario": name,
                        "planner": planner,
                        "seed": seed,
                        **t,
                        "features": f,
                        "simulation_s": round(c1 - c0, 5),
                        "metrics_s": round(c2 - c1, 5),
                        "estimate_s": round(estimate, 5),
                    }
                )
            print(
                f"{name:28s} {planner:14s} {rows[-1]['simulation_s'] + rows[-1]['metrics_s']:.3f} s"
            )
    return rows


MEMORY_SCENARIOS = ("crosswalk", "corridor_flow", "concert_crowd")


def held_memory(seeds: int) -> list[dict[str, Any]]:
    """Bytes the report phase holds per episode of each of :data:`MEMORY_SCENARIOS`."""
    from srfm.benchmark._results import read_episode, write_episode

    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp)
        for name in MEMORY_SCENARIOS:
            scenario = load_scenario(name)
            paths = [
                write_episode(out, episode_metrics(run_episode(scenario, seed, "straight")))
                for seed in range(seeds)
            ]
            gc.collect()
            tracemalloc.start()
            before = tracemalloc.get_traced_memory()[0]
            held = [read_episode(p) for p in paths]
            gc.collect()
            after = tracemalloc.get_traced_memory()[0]
            tracemalloc.stop()
            rows.append(
                {
                    "scenario": name,
                    "pedestrians": scenario.n_pedestrians,
                    "episodes": len(held),
                    "bytes_per_episode": round((after - before) / len(held)),
                }
            )
            print(f"{name:16s} {rows[-1]['bytes_per_episode']:>9,} bytes held per episode")
            del held
    return rows


def fit_memory(rows: list[dict[str, Any]]) -> dict[str, float]:
    """``held_per_episode`` and ``held_per_pedestrian`` (bytes) by least squares."""
    a = np.array([[1.0, r["pedestrians"]] for r in rows])
    y = np.array([float(r["bytes_per_episode"]) for r in rows])
    coef, _ = nnls(a, y)
    return {"per_episode": float(coef[0]), "per_pedestrian": float(coef[1])}


def estimates(jobs: int) -> dict[str, str]:
    """The estimate line ``srfm benchmark`` prints, for ``--suite large`` and the paper's
    full benchmark (default logs), on ``jobs`` workers."""
    from srfm.logs import EpisodeLogger, LogOptions

    options = LogOptions(  # the defaults of ``srfm benchmark --out DIR``
        mcap=True,
        mcap_profile="compact",
        rrd=True,
        rrd_seeds=1,
        forces=False,
        share_counterfactual=True,
    )
    out = {}
    for label, scenarios in (("large", SUITES["large"]), ("paper", SUITES["paper"])):
        request = BenchmarkRequest.create(scenarios=list(scenarios))
        logger = EpisodeLogger.create(
            options,
            scenarios=request.scenarios,
            planners=request.planners,
            seeds=request.seeds,
            reference=request.reference,
        )
        e = estimate_benchmark(request, jobs=jobs, writer=logger)
        out[label] = e.describe()
        out[f"{label}_wall_s"] = f"{e.wall_s:.1f}" if e.wall_s is not None else "unknown"
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seeds", type=int, default=1, help="seeds 0 .. N-1 per cell")
    parser.add_argument("--scenarios", nargs="+", default=list(scenario_names()))
    parser.add_argument("--memory-seeds", type=int, default=20, help="episodes per scenario")
    parser.add_argument("--json", type=Path, default=None, help="also write the data here")
    args = parser.parse_args()
    started, t0, load0 = start()
    lines = estimates(2)  # first: a mistake here costs no measurement
    memory = held_memory(args.memory_seeds)
    planners = default_planners()
    rows = measure(args.scenarios, planners, args.seeds)
    simulation = fit(rows, SIMULATION_TERMS, "simulation_s")
    metrics = fit(rows, METRICS_TERMS, "metrics_s")
    ratios = [(r["simulation_s"] + r["metrics_s"]) / r["estimate_s"] for r in rows]
    print(f"measured / estimated: {min(ratios):.2f}–{max(ratios):.2f} over {len(rows)} episodes")
    for name in SHIPPED:
        fitted = {**simulation, **metrics}[name]
        print(f"{name:6s} shipped {SHIPPED[name]:.3g} s, refit {fitted:.3g} s")
    print(f"estimate: {lines['large']}")
    if args.json is not None:
        doc = {
            "planners": list(planners),
            "seeds": list(range(args.seeds)),
            "episodes": rows,
            "shipped": SHIPPED,
            "refit": {**simulation, **metrics},
            "estimates_on_2_workers": lines,
            "held_memory": {
                "scenarios": memory,
                "fit": fit_memory(memory),
                "shipped": {
                    "per_episode": _HELD_PER_EPISODE,
                    "per_pedestrian": _HELD_PER_PEDESTRIAN,
                },
            },
            "run": run_record(started, t0, load0),
        }
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(doc, indent=1) + "\n", encoding="utf-8")
        print(f"-> {args.json}")


if __name__ == "__main__":
    main()
