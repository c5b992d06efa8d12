"""The shipped policies on the issue-43 validation scenes, kept as committed data.

    PYTHONPATH=. python tools/rl/study43/shipped_scenes.py

``srfm benchmark`` of ``td3-srfm`` and ``td3-base`` on the six scenes of
``tools/rl/study43/validation_scenes/``, validation seeds 20000-20009, into
``runs/val_shipped`` (resumable); the episodes' outcome columns go to
``tools/rl/study43/validation_scenes_shipped.csv.gz`` (``evaluate.py``'s ``COLUMNS``,
whole or not at all) and the run's record (command, commit, date, wall time, load) to
``validation_scenes_shipped.json``. docs/rl.md's table of them is generated from these
(``tools/results/rl_study.py``).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[3]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from tools.results.record import run_record, start  # noqa: E402
from tools.rl.study43.evaluate import write_columns  # noqa: E402

STUDY = Path(__file__).resolve().parent
SCENES = STUDY / "validation_scenes"
OUT = STUDY / "validation_scenes_shipped.csv.gz"
RECORD = STUDY / "validation_scenes_shipped.json"
PLANNERS = ("td3-srfm", "td3-base")
SEEDS = "20000-20009"


def command(out: Path) -> list[str]:
    scenes = sorted(SCENES.glob("*.toml"))
    if not scenes:
        raise SystemExit(f"{SCENES}: no scene files")
    cmd = [sys.executable, "-m", "srfm.cli", "benchmark"]
    cmd += [arg for scene in scenes for arg in ("-s", str(scene.relative_to(ROOT)))]
    cmd += ["-p", ",".join(PLANNERS), "--seeds", SEEDS, "--no-logs", "--no-figures"]
    return [*cmd, "--out", str(out)]


def main() -> None:
    started, t0, load = start()
    out = ROOT / "runs" / "val_shipped"
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    subprocess.run(command(out), env=env, cwd=ROOT, check=True)
    write_columns(out / "episodes.csv", OUT)
    RECORD.write_text(json.dumps(run_record(started, t0, load), indent=1) + "\n")


if __name__ == "__main__":
    main()
