"""The identifiability table of docs/fitting.md: tracks simulated with known parameters
(none a preset value) are fitted back from `ferrer2013`, without and with position
noise (tests/datasets/_synthetic.py: six 16 m x 14 m two-stream scenes, three with a
robot; windows every 1.2 s).

    nice -n 10 .venv/bin/python tools/fitting/identifiability.py \\
        --out docs/fitting_identifiability.json

Deterministic (the scenes are seeded, the fit draws nothing). Prints the table; the
JSON holds every fitted value and the run's command, commit and date.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO))

import srfm  # noqa: E402
from srfm.fitting import WindowConfig, build_windows, fit_params  # noqa: E402
from tests.datasets._synthetic import simulate_scene  # noqa: E402
from tools.results.record import run_record, start  # noqa: E402

TRUE = srfm.SRFMParams(a_ped=2.0, b_ped=0.5, lambda_ped=0.4, tau=0.6, a_robot=6.0, b_robot=0.8)
FIELDS = ("a_ped", "b_ped", "lambda_ped", "tau", "a_robot", "b_robot")
CASES = ((0.0, 1 / 15), (0.0, 0.4), (0.01, 0.4), (0.02, 0.4), (0.05, 0.4))
"""(position noise sigma in m, velocity span in s) of each row."""


def fit_row(noise_m: float, span_s: float) -> dict[str, float]:
    """The parameters fitted back at one noise level and velocity span."""
    scenes = [simulate_scene(TRUE, s, name=f"p{s}", noise_m=noise_m) for s in range(20, 23)]
    scenes += [
        simulate_scene(TRUE, s, name=f"r{s}", robot=True, noise_m=noise_m) for s in range(30, 33)
    ]
    windows = build_windows(scenes, WindowConfig(stride_s=1.2, velocity_span_s=span_s))
    p = fit_params(windows, start=srfm.SRFMParams.preset("ferrer2013")).params
    return {f: float(getattr(p, f)) for f in FIELDS}


def table_lines(doc: dict[str, Any]) -> list[str]:
    """The Markdown table of a saved run."""
    true, rows = doc["true"], doc["rows"]
    lines = [
        "| σ (m) | velocity span (s) | A_p | B_p (m) | λ | τ (s) | A_r | B_r (m) |",
        "|---|---|---|---|---|---|---|---|",
        "| true | | " + " | ".join(f"{true[f]:g}" for f in FIELDS) + " |",
    ]
    for r in rows:
        span = r["velocity_span_s"]
        label = (
            f"{span:.3f} (one sample)"
            if span < 0.1
            else f"{span:g} (default)"
            if r["noise_m"] == 0
            else f"{span:g}"
        )
        p = r["params"]
        lines.append(
            f"| {r['noise_m']:.2f} | {label} | {p['a_ped']:.2f} | {p['b_ped']:.3f} | "
            f"{p['lambda_ped']:.2f} | {p['tau']:.3f} | {p['a_robot']:.2f} | "
            f"{p['b_robot']:.3f} |"
        )
    return lines


def main() -> None:
    ap = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument("--out", type=Path, default=None, help="JSON results")
    args = ap.parse_args()
    began = start()
    rows = []
    for noise, span in CASES:
        rows.append({"noise_m": noise, "velocity_span_s": span, "params": fit_row(noise, span)})
        print(rows[-1], file=sys.stderr, flush=True)
    doc: dict[str, Any] = {
        "true": {f: float(getattr(TRUE, f)) for f in FIELDS},
        "start": "ferrer2013",
        "rows": rows,
        "run": run_record(*began),
    }
    print("\n".join(table_lines(doc)))
    if args.out:
        args.out.write_text(json.dumps(doc, indent=1) + "\n", encoding="utf-8")


if __name__ == "__main__":
    main()
