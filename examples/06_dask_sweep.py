"""A sweep over the robot force on a local Dask cluster, and its report.

    pip install -e '.[sweep]' -c constraints.txt   # Dask distributed
    python examples/06_dask_sweep.py          # 3 × 2 cells × 2 scenarios × 2 planners × 10 seeds
    python examples/06_dask_sweep.py --fast   # 2 cells × 1 scenario × 2 planners × 2 seeds

A sweep runs one benchmark per cell of a design over SRFM parameters (here A_r and B_r,
the robot force's strength in m/s² and range in m) into a Parquet dataset; its report
shows how each planner's deviation moves with each factor and whether the planners'
ranking holds (docs/sensitivity.md, docs/distributed.md). The same spec runs on a real
cluster with `srfm sweep SPEC --out DIR --scheduler tcp://HOST:8786`.
"""

import os
import sys
from pathlib import Path

from dask.distributed import Client, LocalCluster

from srfm.sweep import load_spec, run_sweep
from srfm.sweep.report import write_sweep_report

FAST = "--fast" in sys.argv or os.environ.get("SRFM_EXAMPLES_FAST") == "1"
OUT = Path(os.environ.get("SRFM_EXAMPLES_OUT", "out/examples")) / "06_dask_sweep"

SPEC = f"""
schema_version = 1
scenarios = {'["crosswalk"]' if FAST else '["crosswalk", "footpath"]'}
planners = ["dwa", "td3-srfm"]
seeds = "{"0-1" if FAST else "0-9"}"

[design]
kind = "grid"                      # every combination of the lists below
[design.factors]
a_robot = {"[0.0, 7.93]" if FAST else "[0.0, 7.93, 15.86]"}   # m/s²; the paper's 7.93
b_robot = {"[1.0]" if FAST else "[0.5, 1.0]"}           # m
"""

if __name__ == "__main__":  # Dask's worker processes import this file: keep work here
    OUT.mkdir(parents=True, exist_ok=True)
    (OUT / "sweep.toml").write_text(SPEC, encoding="utf-8")
    spec = load_spec(OUT / "sweep.toml")
    print(f"{len(spec.cells)} cells, {spec.episodes} episodes")

    # A cluster of two single-threaded worker processes on this machine; on a real
    # cluster, pass its scheduler's address instead.
    with (
        LocalCluster(n_workers=2, threads_per_worker=1, dashboard_address=None) as cluster,
        Client(cluster) as client,
    ):
        print(f"scheduler {cluster.scheduler_address}, {len(client.nthreads())} workers")
        summary = run_sweep(
            spec, OUT / "results", scheduler=cluster.scheduler_address, executor="dask", force=True
        )
    print(f"{summary.episodes} episodes in {OUT / 'results'}")

    # The report: figures per factor and the ranking's stability, as Markdown and PNG.
    for path in write_sweep_report(OUT / "results"):
        print("wrote", path)
