"""The cap diagnostic of docs/real_encounters.md (part 4): what the time-to-collision
force's cap does on NavWareSet's encounter windows.

Exploratory and in-sample: every encounter window of the 30 scenes (lead 3 s, 4.8 s,
goal heading, walking starts >= 0.3 m/s), the parameters of ``navwareset2026_ttc``
with the cap ``robot_force_cap`` and the strength ``ttc_k`` varied over a grid; nothing
is held out or fitted. For each point: the mean ADE, FDE, |pass-distance error|,
|path-offset error| and the signed pass-distance bias, and "robot ignored" with the
same pedestrian part.

    nice -n 5 .venv/bin/python tools/fitting/cap_diagnostic.py     # about 1 min

Writes ``cap_diagnostic.json`` (every number, with n) and ``cap_diagnostic.md`` (the
table) into ``--out`` (default docs/real_encounters/) and prints the table.
Deterministic (no random draw).
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from pathlib import Path
from typing import Any

import numpy as np

from srfm.datasets.navwareset import drop_supersets, read_navwareset
from srfm.fitting import WindowConfig, build_windows, window_metrics
from srfm.models import SRFMParams

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO))
from tools.results.record import run_record, start  # noqa: E402

CAPS = (0.25, 0.5, 1.0, 2.0, 5.0, 10.0, 20.0)
KS = (0.15, 1.5)
WINDOWS = WindowConfig(align="encounter", lead_s=3.0, goal="heading", min_start_speed_mps=0.3)


def summary(windows: Any, params: SRFMParams, mode: Any) -> dict[str, float]:
    sel = np.arange(windows.n_windows, dtype=np.int64)
    m = window_metrics(windows, sel, params, mode)
    return {
        "ade_m": float(m.ade.mean()),
        "fde_m": float(m.fde.mean()),
        "abs_pass_m": float(np.nanmean(np.abs(m.pass_distance))),
        "abs_offset_m": float(np.nanmean(np.abs(m.path_offset))),
        "pass_bias_m": float(np.nanmean(m.pass_distance)),
    }


def table_text(payload: dict[str, Any]) -> str:
    """The Markdown table of a saved diagnostic (``cap_diagnostic.json``)."""
    n, rows = payload["n"], payload["rows"]
    lines = [
        f"In-sample, all encounter windows (n = {n['windows']} windows / {n['tracks']} tracks; "
        "parameters of navwareset2026_ttc but the cap and k; nothing fitted or held out):",
        "",
        "| model | k (m²) | cap (m/s²) | ADE (m) | FDE (m) | \\|pass-distance error\\| (m) "
        "| pass bias (m) | \\|path-offset error\\| (m) |",
        "|---|--:|--:|--:|--:|--:|--:|--:|",
    ]
    for r in rows:
        k = f"{r['ttc_k']:g}" if "ttc_k" in r else "–"
        cap = f"{r['cap']:g}" if "cap" in r else "–"
        lines.append(
            f"| {r['model']} | {k} | {cap} | {r['ade_m']:.3f} | {r['fde_m']:.3f} "
            f"| {r['abs_pass_m']:.3f} | {r['pass_bias_m']:+.3f} | {r['abs_offset_m']:.3f} |"
        )
    return "\n".join(lines) + "\n"


def main() -> None:
    ap = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument("--data", type=Path, default=None, help="data root (default $SRFM_DATA_DIR)")
    ap.add_argument("--out", type=Path, default=REPO / "docs" / "real_encounters")
    args = ap.parse_args()
    began = start()
    root = args.data or Path(os.environ.get("SRFM_DATA_DIR", REPO.parent / "shared" / "data"))
    scenes, _ = drop_supersets(read_navwareset(root / "navwareset_quant"))
    enc = build_windows(scenes, WINDOWS)
    base = SRFMParams.preset("navwareset2026_ttc")
    rows: list[dict[str, Any]] = [{"model": "robot ignored", **summary(enc, base, "sfm")}]
    for k in KS:
        for cap in CAPS:
            params = base.replace(ttc_k=k, robot_force_cap=cap)
            rows.append({"model": "ttc", "ttc_k": k, "cap": cap, **summary(enc, params, "srfm")})
    n = {
        "windows": int(enc.n_windows),
        "tracks": int(np.unique(enc.track).size),
        "scenes": len({s.source.get("navwareset_scene", s.scene) for s in scenes}),
    }
    payload = {
        "windows": "encounter, lead 3 s, 4.8 s, goal heading",
        "n": n,
        "rows": rows,
        "run": run_record(*began),
    }
    saved = json.dumps(payload, indent=1, sort_keys=True)
    text = table_text(json.loads(saved))  # what the saved data give: make docs-tables
    print(text)
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "cap_diagnostic.json").write_text(saved + "\n")
    (args.out / "cap_diagnostic.md").write_text(text)


if __name__ == "__main__":
    main()
