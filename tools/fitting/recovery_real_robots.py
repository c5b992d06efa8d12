"""Identifiability on the real robot trajectories (docs/fitting.md): the 12 recorded
robot trajectories of the NavWareSet excerpt (scenes 21, 34, 47), each pedestrian
replaced by an SRFM pedestrian with known parameters (A_r = 3 m/s², B_r = 0.6 m,
λ_r = 0.4; τ = 0.8 s) started from its observed state toward its observed goal; the
protocol's windows (walking starts, every 0.4 s); the robot part fitted back from the
paper's with the pedestrian part known. The fit of
``tests/datasets/test_protocol.py::test_fit_recovers_robot_part_around_recorded_robots``
(the simulation's goals and desired speeds given to the windows), with a one-sample
velocity, and with the goals and desired speeds estimated from the re-simulated tracks.

    PYTHONPATH=. nice -n 10 .venv/bin/python tools/fitting/recovery_real_robots.py \\
        --out docs/fitting_recovery_real_robots.json

Reads ``$SRFM_DATA_DIR/navwareset`` (the excerpt). Deterministic: no random draws.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from pathlib import Path
from typing import Any

import attrs
import numpy as np

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO))

import srfm  # noqa: E402
from srfm.datasets import navwareset  # noqa: E402
from srfm.fitting import ROBOT_FIELDS, WindowConfig, build_windows, fit_robot_part  # noqa: E402
from tests.datasets._synthetic import resimulate_pedestrian  # noqa: E402
from tests.datasets.test_protocol import TRUE  # noqa: E402
from tools.results.record import run_record, start  # noqa: E402

CASES = (
    ("true goals", 0.4),
    ("true goals", 0.1),
    ("estimated goals", 0.4),
)
"""(the goal and desired speed of each window, velocity span in s) of each row; 0.1 s is
one NavWareSet sample."""


def main() -> None:
    ap = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument("--out", type=Path, default=None, help="JSON results")
    args = ap.parse_args()
    began = start()
    root = Path(os.environ.get("SRFM_DATA_DIR", REPO.parent / "shared" / "data")) / "navwareset"
    truth: dict[str, list[object]] = {}
    scenes = [resimulate_pedestrian(s, TRUE, truth) for s in navwareset.read_navwareset(root)]
    first = TRUE.replace(
        **{f: getattr(srfm.SRFMParams(), f) for f in ("a_robot", "b_robot")}, lambda_robot=1.0
    )
    rows: list[dict[str, Any]] = []
    for goals, span in CASES:
        config = WindowConfig(stride_s=0.4, min_start_speed_mps=0.3, velocity_span_s=span)
        windows = build_windows(scenes, config)
        if goals == "true goals":
            goal = np.array(truth["goal"], dtype=np.float64)[windows.scene]
            v0 = np.array(truth["v0"], dtype=np.float64)[windows.scene]
            windows = attrs.evolve(windows, goal=np.ascontiguousarray(goal), v0=v0, vmax=1.3 * v0)
        fitted = fit_robot_part(windows, first, multi_start=False)
        rows.append(
            {
                "goals": goals,
                "velocity_span_s": span,
                "interaction_windows": int(windows.interaction.sum()),
                "fitted": {f: float(getattr(fitted, f)) for f in ROBOT_FIELDS},
            }
        )
        print(rows[-1], file=sys.stderr, flush=True)
    doc = {
        "true": {f: float(getattr(TRUE, f)) for f in (*ROBOT_FIELDS, "tau")},
        "recordings": len(scenes),
        "rows": rows,
        "run": run_record(*began),
    }
    if args.out:
        args.out.write_text(json.dumps(doc, indent=1) + "\n", encoding="utf-8")


if __name__ == "__main__":
    main()
