"""Convert a dataset, fit the SRFM to it and compare the ADE of the parameter presets.

    python examples/03_dataset_fit.py          # fit both stages, every preset's ADE
    python examples/03_dataset_fit.py --fast   # fewer model evaluations in the fit

The data: NavWareSet tracks of people passing a moving robot (real data, 10 Hz). By
default the 12-track sample in examples/data/navwareset; with SRFM_DATA_DIR set to the
shared data folder, the same folder there (../shared/data next to a checkout).
docs/fitting.md explains the windows, the two-stage least-squares fit and the ADE
table; `srfm data convert`, `srfm fit` and `srfm ade` do the same from the shell.
"""

import os
import sys
from pathlib import Path

from srfm import PRESETS
from srfm.datasets import read_mcap, read_navwareset, write_mcap
from srfm.fitting import WindowConfig, build_windows, evaluate_ade, fit_params
from srfm.models import save_params

FAST = "--fast" in sys.argv or os.environ.get("SRFM_EXAMPLES_FAST") == "1"
OUT = Path(os.environ.get("SRFM_EXAMPLES_OUT", "out/examples")) / "03_dataset_fit"
DATA = Path(os.environ.get("SRFM_DATA_DIR", Path(__file__).parent / "data")) / "navwareset"

# 1. Convert: the raw CSV files become srfm's MCAP layout (one scene per file).
#    Shell: srfm data convert navwareset examples/data/navwareset nav.mcap
OUT.mkdir(parents=True, exist_ok=True)
scenes = read_navwareset(DATA)
write_mcap(OUT / "navwareset.mcap", scenes, dataset="navwareset")
data = read_mcap(OUT / "navwareset.mcap")
print(f"{len(data.scenes)} scenes from {DATA} -> {OUT / 'navwareset.mcap'}")

# 2. Windows: each track is cut into 4.8 s prediction windows; a window is an
#    interaction window when the pedestrian comes within 3 m of the robot.
windows = build_windows(data.scenes, WindowConfig(horizon_s=4.8, stride_s=1.2))
print(f"{windows.n_windows} windows, {int(windows.interaction.sum())} of them interactions")

# 3. Fit: stage 1 the pedestrian part (A_p, B_p, λ, τ) on the windows away from the
#    robot, stage 2 the robot part (A_r, B_r) on the interaction windows.
#    Shell: srfm fit nav.mcap -o fitted.toml
fit = fit_params(windows, max_nfev=20 if FAST else 200, multi_start=not FAST)
for stage in fit.stages:
    if stage.skipped:  # e.g. no windows away from the robot in this sample
        print(f"  {stage.stage}: {stage.message}")
        continue
    fitted = ", ".join(f"{k} = {v:.3g}" for k, v in stage.fitted.items())
    print(f"  {stage.stage}: ADE {stage.ade_start_m:.3f} -> {stage.ade_m:.3f} m  ({fitted})")
save_params(fit.params, OUT / "fitted.toml")  # usable as `srfm simulate --params FILE`

# 4. Compare: the ADE (m) of the SRFM row on the interaction windows, for every preset
#    and the fitted parameters. Shell: srfm ade nav.mcap --params ferrer2013
candidates = {**PRESETS, "fitted here": fit.params}
print(f"\n{'parameters':<16} {'SRFM ADE (m)':>13} {'CV ADE (m)':>11}")
for name, params in candidates.items():
    rows = {(r.model, r.tracks): r for r in evaluate_ade(windows, params)}
    srfm_row, cv_row = rows["SRFM", "interaction"], rows["CV", "interaction"]
    print(f"{name:<16} {srfm_row.ade_m:>13.3f} {cv_row.ade_m:>11.3f}")
