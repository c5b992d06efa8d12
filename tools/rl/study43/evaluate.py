"""The issue-43 study's evaluation on the report's scenarios, kept as committed data.

    PYTHONPATH=. python tools/rl/study43/evaluate.py --seeds 1-10 --jobs 2 [--wait]
    python tools/rl/study43/report.py tools/rl/study43/report/seed*.csv.gz

For every training seed whose two runs (k2 = 0 and k2 = 2) are validated
(``tools/rl/study43/runs.json``) and whose ``tools/rl/study43/report/seed<s>.csv.gz`` is
not written yet: ``srfm benchmark`` of the seed's four policies (each arm's chosen and
final checkpoint) on the report's 14 scenarios, evaluation seeds 0-99, into
``runs/report43/seed<s>`` (interrupted, the same command resumes it: the benchmark skips
every finished episode); then the columns the report reads (``COLUMNS``) are written to
``report/seed<s>.csv.gz``, whole or not at all (a temporary file renamed). ``--wait``
keeps polling ``runs.json`` until every requested seed is evaluated, for a study still
training.
"""

from __future__ import annotations

import argparse
import csv
import gzip
import io
import json
import os
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[3]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from tools.rl.study import seeds_of  # noqa: E402
from tools.rl.study_report import REPORT_SCENARIOS  # noqa: E402

STUDY = Path(__file__).resolve().parent
REPORT = STUDY / "report"
ARMS = ("0", "2")
COLUMNS = (
    "scenario",
    "planner",
    "seed",
    "robot_success",
    "robot_collision",
    "robot_out_of_bounds",
    "frechet_m",
)


def planners(seed: int) -> list[str]:
    """The seed's four policies as ``srfm benchmark -p`` names (tools/rl/study43/planners.py)."""
    base = "tools.rl.study43.planners:"
    return [f"{base}k{k}_seed{seed}{tail}" for tail in ("", "_final") for k in ARMS]


def validated(seed: int) -> bool:
    """Both arms of the training seed have their chosen and final policies exported."""
    runs = json.loads((STUDY / "runs.json").read_text(encoding="utf-8"))
    return all(runs.get(f"k{k}-seed{seed}", {}).get("validated", False) for k in ARMS)


def output(seed: int) -> Path:
    return REPORT / f"seed{seed}.csv.gz"


def evaluate(seed: int, jobs: int, nice: int) -> None:
    """Run the seed's benchmark (resumable) and write its committed columns."""
    out = ROOT / "runs" / "report43" / f"seed{seed}"
    cmd = [
        "nice",
        "-n",
        str(nice),
        sys.executable,
        "-m",
        "srfm.cli",
        "benchmark",
        *[arg for name in REPORT_SCENARIOS for arg in ("-s", name)],
        "-p",
        ",".join(planners(seed)),
        "--seeds",
        "0-99",
        "--no-logs",
        "--no-figures",
        "-j",
        str(jobs),
        "--out",
        str(out),
    ]
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    print(f"seed {seed}: {' '.join(cmd[3:])}", flush=True)
    subprocess.run(cmd, env=env, cwd=ROOT, check=True)
    write_columns(out / "episodes.csv", output(seed))


def write_columns(episodes: Path, dest: Path) -> None:
    """The report's columns of a benchmark's episodes.csv, gzip-compressed with a fixed
    header time (the same episodes give the same bytes), written whole or not at all."""
    with episodes.open(newline="", encoding="utf-8") as fh:
        rows = list(csv.DictReader(fh))
    missing = [c for c in COLUMNS if rows and c not in rows[0]]
    if not rows or missing:
        raise SystemExit(f"{episodes}: no episodes or no column {missing}")
    text = io.StringIO()
    writer = csv.writer(text, lineterminator="\n")
    writer.writerow(COLUMNS)
    for row in sorted(rows, key=lambda r: (r["scenario"], r["planner"], int(r["seed"]))):
        writer.writerow([row[c] for c in COLUMNS])
    dest.parent.mkdir(parents=True, exist_ok=True)
    tmp = dest.with_suffix(".tmp")
    with tmp.open("wb") as raw, gzip.GzipFile(fileobj=raw, mode="wb", mtime=0) as gz:
        gz.write(text.getvalue().encode("utf-8"))
    tmp.replace(dest)


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seeds", default="1-10", help="training seeds, e.g. 1-10 or 1,3")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--nice", type=int, default=5)
    ap.add_argument("--wait", action="store_true", help="poll until every seed is done")
    args = ap.parse_args(argv)
    todo = [s for s in seeds_of(args.seeds) if not output(s).is_file()]
    while todo:
        ready = [s for s in todo if validated(s)]
        for seed in ready:
            evaluate(seed, args.jobs, args.nice)
            todo.remove(seed)
        if todo and not ready:
            if not args.wait:
                print(f"not validated yet: seeds {todo}")
                return
            time.sleep(60)


if __name__ == "__main__":
    main()
