"""Sweeps: a design over model parameters and scenario factors, each cell a benchmark,
into a partitioned Parquet dataset (``srfm sweep``); and its analysis
(``srfm sweep report``)."""

from srfm.sweep._run import DATA_DIR, SWEEP_MANIFEST, SweepSummary, partition_path, run_sweep
from srfm.sweep._spec import SCENARIO_FACTORS, Cell, SweepSpec, load_spec

__all__ = [
    "DATA_DIR",
    "SCENARIO_FACTORS",
    "SWEEP_MANIFEST",
    "Cell",
    "SweepSpec",
    "SweepSummary",
    "load_spec",
    "partition_path",
    "run_sweep",
]
