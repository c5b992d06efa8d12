"""Score a benchmark's logs offline, and what to open in Rerun and Foxglove.

    python examples/05_score_and_view_logs.py          # 2 scenarios × 3 planners × 3 seeds
    python examples/05_score_and_view_logs.py --fast   # 1 scenario × 2 planners × 1 seed

Every benchmark episode can leave an MCAP file (the episode exactly, plus a Foxglove
scene) and, for the first seed of each cell, a Rerun recording (docs/logging.md).
`srfm score` recomputes every metric and the tables from the MCAP files alone and checks
them against the metrics logged at run time, bit for bit: the logs are the results.
"""

import os
import subprocess
import sys
from pathlib import Path

FAST = "--fast" in sys.argv or os.environ.get("SRFM_EXAMPLES_FAST") == "1"
OUT = Path(os.environ.get("SRFM_EXAMPLES_OUT", "out/examples")) / "05_score_and_view_logs"
REPO = Path(__file__).resolve().parents[1]


def srfm(*args: str) -> None:
    """Run the srfm command (as `srfm ...` in a shell) and echo it."""
    print("$ srfm", " ".join(args))
    subprocess.run([sys.executable, "-m", "srfm.cli", *args], check=True)


scenarios, planners = (
    ("crosswalk", "dwa,straight") if FAST else ("crosswalk,circle", "dwa,vo,td3-srfm")
)
# 1. A benchmark with logs: an MCAP file per episode (compact profile: the exact
#    trajectories, the Foxglove scene at 1 Hz) and a Rerun recording per cell's first seed.
srfm(
    "benchmark",
    "-s",
    scenarios,
    "-p",
    planners,
    "--seeds",
    "0" if FAST else "0-2",
    "--out",
    str(OUT / "results"),
    "--no-figures",
    "-j",
    "2",
    "--force",
)

# 2. Score the logs alone, into another folder: the same tables, recomputed.
srfm("score", str(OUT / "results" / "logs"), "--out", str(OUT / "rescored"))
same = (OUT / "results" / "table.md").read_bytes() == (OUT / "rescored" / "table.md").read_bytes()
print(f"table.md recomputed from the logs is identical to the benchmark's: {same}")

# 3. What to open.
logs = OUT / "results" / "logs"
rrd = sorted(logs.rglob("*.rrd"))[0]
mcap = sorted(p for p in logs.rglob("*.mcap") if p.parent.name != "_counterfactual")[0]
print(f"""
Rerun: `srfm view {rrd}` (or `python -m rerun {rrd}`) opens the viewer in srfm's layout:
  the world (blue: pedestrians who feel the robot; grey: their twins who do not; red:
  the robot), the per-pedestrian deviation and the robot's distance over time, the
  episode's metrics and events. Without a display, srfm view prints the command.
Foxglove: open {mcap} (Open local file...; nothing is uploaded), then Layouts ->
  Import from file... -> {REPO / "docs" / "foxglove_layout.json"} once: a top-down 3D
  panel on /foxglove/scene, the metrics, the robot's velocity plot. The exact arrays are
  on the /srfm/... channels (Plot and Raw Messages panels).
The results page {OUT / "results" / "report.html"} links every log.""")
