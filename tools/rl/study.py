"""The walls-aware policies and the study of the paper's claim (issue 30), as one
resumable script.

Every run trains SBX TD3 from scratch with one recipe (``RECIPE`` below: the mixed
training layouts plus the library's training split, range beams to walls and
pillars, checkpoints selected on the validation split by success and collisions only);
the arms differ only in k2 (``--k-div``). A run is named ``k<k2>-seed<seed>``.

    python tools/rl/study.py run --arms 0,2 --seeds 1-10 --jobs 2   # train, resuming
    python tools/rl/study.py status                                  # what is done
    python tools/rl/study.py collect                                 # artefacts into git's tree

``run`` starts at most ``--jobs`` training processes at a time (``nice -n 10``); a run
whose ``state.json`` has reached the step count is done, one with a ``latest.zip``
resumes from it (with its replay buffer when one lies beside it), one with a committed
checkpoint in ``tools/rl/study/checkpoints/`` resumes from that (a new machine: the
replay buffer is lost, the resumed run is deterministic but not identical to an
uninterrupted one). After every finished run, and every ``--collect-every`` seconds,
``collect`` copies what a later session needs into ``tools/rl/study/``:

- ``policies/<run>.{json,npz}``: the run's chosen checkpoint as a NumPy policy: of the
  checkpoints after the k2 curriculum, the one with the highest success, then the
  fewest collisions, on the validation set with 10 seeds per scenario from 20000 on
  (``tools/rl/validate_checkpoints.py``; its table in ``validation/<run>.json``). The
  run's own ``best.zip`` rests on 2 seeds per scenario: too few to tell checkpoints
  apart (docs/rl.md);
- ``evals/<run>.jsonl``: its periodic evaluations (validation split, seeds 10000 on);
- ``checkpoints/<run>.zip``: the latest checkpoint of an unfinished run (to resume);
- ``runs.json``: per run, the steps done, wall time and whether it finished.

Commit that folder (``--commit`` does it after each collection). The evaluation of
finished runs on the report's scenarios and seeds (0-99) and the claim's statistics
are ``tools/rl/study_report.py``.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path
from typing import Final

ROOT: Final = Path(__file__).resolve().parents[2]
STUDY: Final = ROOT / "tools" / "rl" / "study"
SRFM: Final = str(Path(sys.executable).with_name("srfm"))

STEPS: Final = 300_000
VALIDATION_SEEDS: Final = 10
# The curriculum window: k2 rises from 0 at K2_START to its arm's value at
# K2_START + K2_RAMP; both arms select checkpoints only after it (srfm.rl.training.selectable).
K2_START: Final = 100_000
K2_RAMP: Final = 25_000
RECIPE: Final = (
    "--scenario", "mixed",
    "--library", "train-split",
    "--library-share", "0.5",
    "--range-beams", "24",
    "--range-max", "4.0",
    "--action-repeat", "4",
    "--backend", "sbx",
    "--net-arch", "64,64",
    "--train-freq", "50",
    "--gradient-steps", "50",
    "--learning-rate", "3e-4",
    "--k-progress", "10",
    "--steps", str(STEPS),
    "--k-div-start", str(K2_START),
    "--k-div-ramp", str(K2_RAMP),
    "--eval-every", "25000",
    "--eval-seeds", "2",
    "--eval-scenarios", "validation",
    "--select-by-outcome",
    "--checkpoint-every", "25000",
    "--no-progress",
)  # fmt: skip


def run_name(k2: str, seed: int) -> str:
    return f"k{k2}-seed{seed}"


def steps_done(run: Path) -> int:
    try:
        return int(json.loads((run / "state.json").read_text())["steps"])
    except (OSError, ValueError, KeyError):
        return 0


def command(run: Path, k2: str, seed: int) -> list[str]:
    words = [SRFM, "train", "--run-dir", str(run), "--seed", str(seed), "--k-div", k2, *RECIPE]
    latest = run / "latest.zip"
    committed = STUDY / "checkpoints" / f"{run.name}.zip"
    if latest.is_file():
        words += ["--resume", str(latest)]
    elif committed.is_file():
        shutil.copy(committed, latest)
        words += ["--resume", str(latest)]
    return words


def validate(run: Path) -> Path:
    """The run's checkpoint chosen on the validation set (10 seeds per scenario, from
    20000 on; tools/rl/validate_checkpoints.py); its table goes to validation/."""
    table = STUDY / "validation" / f"{run.name}.json"
    table.parent.mkdir(parents=True, exist_ok=True)
    script = ROOT / "tools" / "rl" / "validate_checkpoints.py"
    subprocess.run(
        [
            sys.executable,
            str(script),
            str(run),
            "--seeds",
            str(VALIDATION_SEEDS),
            "--out",
            str(table),
        ],
        check=True,
    )
    best = json.loads(table.read_text())["best"]
    return run / "checkpoints" / str(best["checkpoint"])


def collect(runs: Path) -> list[str]:
    """Copy every run's artefacts into tools/rl/study/; the files written."""
    written: list[str] = []
    table: dict[str, dict[str, object]] = {}
    for d in ("policies", "evals", "checkpoints"):
        (STUDY / d).mkdir(parents=True, exist_ok=True)
    for run in sorted(p for p in runs.glob("k*-seed*") if p.is_dir()):
        steps = steps_done(run)
        state = json.loads((run / "state.json").read_text()) if steps else {}
        finished = steps >= STEPS
        table[run.name] = {
            "steps": steps,
            "wall_time_s": state.get("wall_time_s"),
            "finished": finished,
        }
        evals = run / "eval.jsonl"
        if evals.is_file():
            shutil.copy(evals, STUDY / "evals" / f"{run.name}.jsonl")
            written.append(f"evals/{run.name}.jsonl")
        checkpoint = STUDY / "checkpoints" / f"{run.name}.zip"
        if finished:
            out = STUDY / "policies" / run.name
            if not out.with_suffix(".json").is_file():
                chosen = validate(run)
                subprocess.run(
                    [SRFM, "export-policy", str(chosen), str(out), "--note",
                     f"{run.name}: {chosen.name}, chosen on the validation set by "
                     "tools/rl/validate_checkpoints.py (tools/rl/study.py)"],
                    check=True,
                )  # fmt: skip
                written.append(f"policies/{run.name}")
            checkpoint.unlink(missing_ok=True)
        elif (run / "latest.zip").is_file():
            shutil.copy(run / "latest.zip", checkpoint)
            written.append(f"checkpoints/{run.name}.zip")
    (STUDY / "runs.json").write_text(json.dumps(table, indent=2, sort_keys=True) + "\n")
    return written


def commit(message: str, folder: Path = STUDY) -> None:
    """git-commit ``folder`` (a study's artefacts) alone, if anything in it changed."""
    subprocess.run(["git", "-C", str(ROOT), "add", str(folder)])
    staged = subprocess.run(
        ["git", "-C", str(ROOT), "diff", "--cached", "--quiet", "--", str(folder)]
    )
    if staged.returncode:  # a failed commit (another git command running) waits for the next
        subprocess.run(["git", "-C", str(ROOT), "commit", "-q", "-m", message, "--", str(folder)])


def seeds_of(text: str) -> list[int]:
    out: list[int] = []
    for part in text.split(","):
        lo, _, hi = part.partition("-")
        out += range(int(lo), int(hi or lo) + 1)
    return out


def run(args: argparse.Namespace) -> None:
    runs = Path(args.runs)
    runs.mkdir(parents=True, exist_ok=True)
    todo = [(k2, seed) for seed in seeds_of(args.seeds) for k2 in args.arms.split(",")]
    active: dict[str, subprocess.Popen[bytes]] = {}
    last_collect = time.monotonic()
    env = {**os.environ, "NUMBA_NUM_THREADS": "1", "OMP_NUM_THREADS": "1"}
    while todo or active:
        for name, proc in list(active.items()):
            if proc.poll() is not None:
                del active[name]
                print(f"{name}: exit {proc.returncode}", flush=True)
                collect(runs)
                if args.commit:
                    commit(f"Issue 30: study run {name} ({steps_done(runs / name)} steps)")
        while todo and len(active) < args.jobs:
            k2, seed = todo.pop(0)
            name = run_name(k2, seed)
            path = runs / name
            if steps_done(path) >= STEPS:
                continue
            path.mkdir(exist_ok=True)
            log = (runs / f"{name}.log").open("ab")
            words = ["nice", "-n", str(args.nice), *command(path, k2, seed)]
            active[name] = subprocess.Popen(words, stdout=log, stderr=subprocess.STDOUT, env=env)
            print(f"{name}: started", flush=True)
        if time.monotonic() - last_collect > args.collect_every:
            collect(runs)
            if args.commit:
                commit("Issue 30: study checkpoints and evaluations")
            last_collect = time.monotonic()
        time.sleep(5)


def status(args: argparse.Namespace) -> None:
    runs = Path(args.runs)
    for run in sorted(p for p in runs.glob("k*-seed*") if p.is_dir()):
        print(f"{run.name}: {steps_done(run)} / {STEPS}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", default="runs/study", help="run folders (default runs/study)")
    sub = parser.add_subparsers(dest="what", required=True)
    p = sub.add_parser("run")
    p.add_argument("--arms", default="0,2", help="k2 values, comma-separated")
    p.add_argument("--seeds", default="1-10", help="training seeds, e.g. 1-10 or 1,3")
    p.add_argument("--jobs", type=int, default=2)
    p.add_argument("--nice", type=int, default=10, help="niceness of the training processes")
    p.add_argument("--collect-every", type=float, default=1800.0, help="seconds")
    p.add_argument("--commit", action="store_true", help="git-commit tools/rl/study/")
    sub.add_parser("status")
    sub.add_parser("collect")
    args = parser.parse_args()
    if args.what == "run":
        run(args)
    elif args.what == "status":
        status(args)
    else:
        print("\n".join(collect(Path(args.runs))))


if __name__ == "__main__":
    main()
