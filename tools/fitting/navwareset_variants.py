"""Two variants of the issue-15 robot-part fit of docs/fitting.md (all 32 scenes, the
ETH/UCY pedestrian part held): the goal at each window's last observed position instead
of the track's, and the relaxation time τ fitted jointly with A_r, B_r, λ_r.

    nice -n 10 .venv/bin/python tools/fitting/navwareset_variants.py \\
        --out docs/fitting_navwareset_variants.json

The pedestrian part is read from ``docs/fitting_ethucy.json`` (tools/fitting/fit_ethucy.py).
Each variant is fitted like the protocol's all-scenes fit (fitting windows every 1.2 s,
walking starts, from the pedestrian part's robot part and the two presets, the lowest
cost kept). Deterministic: no random draws.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

import attrs
import numpy as np

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO))

from srfm.datasets.navwareset import drop_supersets, read_navwareset  # noqa: E402
from srfm.fitting import (  # noqa: E402
    FIT_WINDOWS,
    ROBOT_FIELDS,
    Windows,
    build_windows,
    fit_robot_part,
)
from srfm.models import SRFMParams  # noqa: E402
from tools.fitting.fit_navwareset import data_folder  # noqa: E402
from tools.results.record import run_record, start  # noqa: E402

PEDESTRIAN = REPO / "docs" / "fitting_ethucy.json"


def window_end_goals(w: Windows) -> Windows:
    """The same windows with each goal at the window's last observed position."""
    last = w.out_row + w.steps - 1
    return attrs.evolve(w, goal=np.ascontiguousarray(w.observed[last]))


def main() -> None:
    ap = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument("--data", default=None, help="NavWareSet folder")
    ap.add_argument("--out", type=Path, default=None, help="JSON results")
    args = ap.parse_args()
    began = start()
    ped = SRFMParams().replace(**json.loads(PEDESTRIAN.read_text(encoding="utf-8"))["fitted"])
    scenes, _ = drop_supersets(read_navwareset(data_folder(args.data)))
    w = build_windows(scenes, FIT_WINDOWS)
    variants: dict[str, tuple[Windows, tuple[str, ...]]] = {
        "goal_window_end": (window_end_goals(w), ROBOT_FIELDS),
        "tau_joint": (w, (*ROBOT_FIELDS, "tau")),
    }
    out: dict[str, Any] = {}
    for name, (windows, fields) in variants.items():
        p = fit_robot_part(windows, ped, fields=fields)
        out[name] = {
            "fields": list(fields),
            "fitted": {f: float(getattr(p, f)) for f in fields},
            "interaction_windows": int(windows.interaction.sum()),
        }
        print(name, out[name], file=sys.stderr, flush=True)
    doc = {
        "pedestrian_part": {
            f: float(getattr(ped, f)) for f in ("a_ped", "b_ped", "lambda_ped", "tau")
        },
        "variants": out,
        "run": run_record(*began),
    }
    if args.out:
        args.out.write_text(json.dumps(doc, indent=1) + "\n", encoding="utf-8")


if __name__ == "__main__":
    main()
