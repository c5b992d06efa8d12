"""How far the interaction cut-off moves the built-in scenarios from the exact kernel.

For every built-in scenario, the large ones included (or those named), and seeds
0..k-1, one full twin episode is run twice with the ``straight`` planner: with
``cutoff="exact"`` (every pair) and
with the cut-off of ``srfm.models.forces.interaction_cutoffs`` (tolerance
``FORCE_TOLERANCE_MPS2``) forced on through the cell list, whatever the crowd size.
Reported per scenario:

* force: the largest difference of the total pedestrian + obstacle force (m/s², per
  component) between the two kernels on the same states (every 10th sample of the
  exact run's factual crowd) — what the cut-off leaves out in one step;
* position: the largest distance (m) between a pedestrian's positions in the two runs,
  over all samples, both twins and all seeds — how that grows over a full episode
  (crowds amplify small differences, so this is the upper figure).

Usage::

    .venv/bin/python tools/bench/check_cutoff.py
    .venv/bin/python tools/bench/check_cutoff.py --seeds 1 --scenarios concert_large
    .venv/bin/python tools/bench/check_cutoff.py --large-seeds 1 \
        --json docs/results/performance/cutoff.json

``--large-seeds K`` runs only seeds 0..K-1 of the scenarios with at least
``CELL_LIST_MIN_AGENTS`` pedestrians (where ``cutoff="auto"`` uses the cut-off; their
exact runs are the slow ones). ``--json PATH`` also writes every row, the cut-off
distances and tolerance, with the run's record (``tools/results/record.py``): the data
docs/performance.md's cut-off table is generated from (``make docs-tables``).
"""

from __future__ import annotations

import argparse
import datetime
import sys
import time
from pathlib import Path

import numpy as np

import srfm
from srfm.models.forces import (
    CELL_LIST_MIN_AGENTS,
    FORCE_TOLERANCE_MPS2,
    force_components,
    interaction_cutoffs,
)
from srfm.scenarios import BUILTIN_SCENARIOS, LARGE_SCENARIOS, load_scenario

SCENARIOS = (*BUILTIN_SCENARIOS, *LARGE_SCENARIOS)


def force_deviation(record: srfm.EpisodeRecord, scenario: srfm.Scenario, cut: float) -> float:
    """Largest |F_cut − F_exact| (m/s²) over every 10th sample of the factual crowd."""
    worst = 0.0
    crowd0 = srfm.episode_setup(scenario, record.seed).crowd
    for k in range(0, record.horizon_steps + 1, 10):
        c = srfm.CrowdState.create(
            pos=record.factual_pos[k],
            vel=record.factual_vel[k],
            goal=record.factual_goal[k],
            radius=crowd0.radius,
            v0=crowd0.v0,
            vmax=crowd0.vmax,
        )
        a = force_components(c, record.params, obstacles=scenario.obstacles, cutoff="exact")
        b = force_components(c, record.params, obstacles=scenario.obstacles, cutoff=cut)
        diff = (a.pedestrians + a.obstacles) - (b.pedestrians + b.obstacles)
        worst = max(worst, float(np.abs(diff).max(initial=0.0)))
    return worst


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0] if __doc__ else None)
    parser.add_argument("--seeds", type=int, default=3, help="seeds 0..k-1 per scenario")
    parser.add_argument("--scenarios", nargs="+", default=list(SCENARIOS))
    parser.add_argument(
        "--large-seeds",
        type=int,
        default=None,
        help=f"seeds 0..k-1 for scenarios of at least {CELL_LIST_MIN_AGENTS} pedestrians"
        " (default: --seeds)",
    )
    parser.add_argument("--json", type=Path, default=None, help="also write the rows here")
    args = parser.parse_args(argv)
    unknown = sorted(set(args.scenarios) - set(SCENARIOS))
    if unknown:
        parser.error(f"unknown scenarios {unknown}; built-in: {list(SCENARIOS)}")
    sys.path.insert(0, str(Path(__file__).resolve().parents[2]))
    from tools.results import record

    begun = record.start()
    rows: list[dict[str, object]] = []
    params = srfm.SRFMParams()
    print(f"# cut-off vs exact kernel ({datetime.date.today()}, seeds 0-{args.seeds - 1})\n")
    print(
        "| scenario | N | cut-off (m) | largest force difference (m/s²)"
        " | largest position difference (m) | wall time (s) |"
    )
    print("|---|---:|---:|---:|---:|---:|")
    for name in args.scenarios:
        scenario = load_scenario(name)
        t0 = time.perf_counter()
        n = scenario.n_pedestrians
        r_max = float(np.max(scenario.ped_radius_m))
        cut = interaction_cutoffs(params, r_max, FORCE_TOLERANCE_MPS2)[0]
        f_dev = 0.0
        x_dev = 0.0
        large = args.large_seeds is not None and n >= CELL_LIST_MIN_AGENTS
        seeds = args.large_seeds if large else args.seeds
        for seed in range(seeds):
            exact = srfm.run_episode(scenario, seed, "straight", params, cutoff="exact")
            cells = srfm.run_episode(scenario, seed, "straight", params, cutoff=cut)
            for a, b in (
                (exact.factual_pos, cells.factual_pos),
                (exact.counterfactual_pos, cells.counterfactual_pos),
            ):
                x_dev = max(x_dev, float(np.linalg.norm(a - b, axis=-1).max(initial=0.0)))
            f_dev = max(f_dev, force_deviation(exact, scenario, cut))
        print(
            f"| {name} | {n} | {cut:.2f} | {f_dev:.2e} | {x_dev:.2e}"
            f" | {time.perf_counter() - t0:.1f} |"
        )
        rows.append(
            {
                "scenario": name,
                "pedestrians": n,
                "obstacles": int(
                    scenario.obstacles.segments.shape[0] + scenario.obstacles.circles.shape[0]
                ),
                "seeds": seeds,
                "r_max_m": r_max,
                "cutoff_m": cut,
                "force_difference_mps2": f_dev,
                "position_difference_m": x_dev,
            }
        )
    if args.json is not None:
        r = 0.3  # the pedestrians' radius of the page's sentence
        d_ped, d_obs = interaction_cutoffs(params, r, FORCE_TOLERANCE_MPS2)
        record.write_json(
            args.json,
            {
                "tolerance_mps2": FORCE_TOLERANCE_MPS2,
                "cell_list_min_agents": CELL_LIST_MIN_AGENTS,
                "radius_m": r,
                "d_ped_m": d_ped,
                "d_obs_m": d_obs,
                "rows": rows,
            },
            begun,
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
