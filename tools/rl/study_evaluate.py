"""The issue-30 study's evaluation of its committed policies, kept as committed data.

    PYTHONPATH=. python tools/rl/study_evaluate.py --seeds 1-10 --jobs 2
    python tools/rl/study_report.py tools/rl/study/report/seed*.csv.gz

For every training seed whose file is not written yet, ``srfm benchmark`` of its two
policies (``tools.rl.study_planners:k0_seed<s>`` and ``k2_seed<s>``, the chosen
checkpoints in ``tools/rl/study/policies/``) on seeds 0-99:

- ``report``: the report's 14 scenarios under the default parameters, into
  ``runs/report30/seed<s>``, kept as ``tools/rl/study/report/seed<s>.csv.gz``;
- ``report_ttc``: the five paper scenarios under ``--params navwareset2026_ttc``, into
  ``runs/report30ttc/seed<s>``, kept as ``tools/rl/study/report_ttc/seed<s>.csv.gz``.

Interrupted, the same command resumes (the benchmark skips every finished episode; a
kept file is never re-run). Only the columns the report reads are kept
(``tools/rl/study43/evaluate.py``'s ``COLUMNS``), written whole or not at all; each
kept file's run (command, commit, date, wall time, load) is recorded in ``runs.json``
beside it.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from srfm.scenarios import EVALUATION_SCENARIOS  # noqa: E402
from tools.results.record import run_record, start  # noqa: E402
from tools.rl.study import seeds_of  # noqa: E402
from tools.rl.study43.evaluate import write_columns  # noqa: E402
from tools.rl.study_report import REPORT_SCENARIOS  # noqa: E402

STUDY = ROOT / "tools" / "rl" / "study"
ARMS = ("0", "2")
PARTS: dict[str, tuple[tuple[str, ...], str | None]] = {
    "report": (REPORT_SCENARIOS, None),
    "report_ttc": (tuple(EVALUATION_SCENARIOS), "navwareset2026_ttc"),
}
"""Part -> (its scenarios, its ``--params`` preset or None for the default)."""


def planners(seed: int) -> list[str]:
    """The training seed's two policies as ``srfm benchmark -p`` names."""
    return [f"tools.rl.study_planners:k{k}_seed{seed}" for k in ARMS]


def output(part: str, seed: int) -> Path:
    return STUDY / part / f"seed{seed}.csv.gz"


def command(part: str, seed: int, jobs: int, nice: int) -> list[str]:
    scenarios, params = PARTS[part]
    out = ROOT / "runs" / ("report30" if part == "report" else "report30ttc") / f"seed{seed}"
    cmd = ["nice", "-n", str(nice), sys.executable, "-m", "srfm.cli", "benchmark"]
    cmd += [arg for name in scenarios for arg in ("-s", name)]
    cmd += ["-p", ",".join(planners(seed)), "--seeds", "0-99", "--no-logs", "--no-figures"]
    cmd += ["-j", str(jobs), "--out", str(out)]
    if params is not None:
        cmd += ["--params", params]
    return cmd


def evaluate(part: str, seed: int, jobs: int, nice: int) -> None:
    """Run one part of a training seed (resumable), keep its columns, record the run."""
    started, t0, load = start()
    cmd = command(part, seed, jobs, nice)
    print(f"{part} seed {seed}: {' '.join(cmd[3:])}", flush=True)
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    subprocess.run(cmd, env=env, cwd=ROOT, check=True)
    write_columns(Path(cmd[cmd.index("--out") + 1]) / "episodes.csv", output(part, seed))
    runs_path = STUDY / part / "runs.json"
    runs = json.loads(runs_path.read_text(encoding="utf-8")) if runs_path.is_file() else {}
    runs[f"seed{seed}"] = run_record(started, t0, load)
    tmp = runs_path.with_suffix(".tmp")
    tmp.write_text(json.dumps(dict(sorted(runs.items())), indent=1) + "\n", encoding="utf-8")
    tmp.replace(runs_path)


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=(__doc__ or "").split("\n\n")[0])
    ap.add_argument("--seeds", default="1-10", help="training seeds, e.g. 1-10 or 1,3")
    ap.add_argument("--parts", default="report,report_ttc", help="report and/or report_ttc")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--nice", type=int, default=10)
    args = ap.parse_args(argv)
    parts = args.parts.split(",")
    unknown = [p for p in parts if p not in PARTS]
    if unknown:
        raise SystemExit(f"--parts: unknown part(s) {unknown}; known: {sorted(PARTS)}")
    for seed in seeds_of(args.seeds):
        for part in parts:
            if not output(part, seed).is_file():
                evaluate(part, seed, args.jobs, args.nice)


if __name__ == "__main__":
    main()
