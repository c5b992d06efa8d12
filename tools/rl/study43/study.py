"""The issue-43 study: policies trained on generated walled layouts, chosen on a
validation set with standing crowds and blind corners, and the paper's claim tested
with the penalty acting for most of training. One resumable script.

Every run trains SBX TD3 from scratch with one recipe (``RECIPE`` below; docs/rl.md,
"The issue-43 study: recipe, selection and claim test, fixed before training"); the arms
differ only in k2 (``--k-div``). A run is named ``k<k2>-seed<seed>``.

    python tools/rl/study43/study.py run --arms 0,2 --seeds 1-10 --jobs 2 --commit
    python tools/rl/study43/study.py status                 # what is done
    python tools/rl/study43/study.py collect                # artefacts into git's tree

``run`` keeps at most ``--jobs`` processes busy (``nice -n 10``): training runs and the
validation of finished runs (a finished run's validation goes first, so artefacts are
committed as soon as possible). A run whose ``state.json`` has reached the step count is
done; one with a ``latest.zip`` resumes from it (with the replay buffer beside it), one
with a committed checkpoint in ``tools/rl/study43/checkpoints/`` resumes from that (a
new machine: the replay buffer is lost, the resumed run is deterministic but not
identical to an uninterrupted one). What a later session needs goes into
``tools/rl/study43/`` (``--commit``: committed after every finished run and every
``--collect-every`` seconds):

- ``policies/<run>.{json,npz}``: the run's chosen checkpoint as a NumPy policy: of the
  checkpoints from 100,000 actions on (the end of the k2 ramp), the one with the
  highest success, then the fewest collisions, on the validation set (``SCENES`` and
  the issue-30 validation set, 10 seeds each from 20000 on; the earlier checkpoint on a
  tie); its table in ``validation/<run>.json``;
- ``policies/<run>-final.{json,npz}``: the run's last checkpoint (300,000 actions), for
  the fixed-checkpoint comparison;
- ``evals/<run>.jsonl``: its periodic evaluations (issue-30 validation split, seeds
  10000 on);
- ``checkpoints/<run>.zip``: the latest checkpoint of an unfinished run (to resume);
- ``runs.json``: per run, the steps done, wall time, whether it finished and was
  validated.
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

ROOT: Final = Path(__file__).resolve().parents[3]
STUDY: Final = ROOT / "tools" / "rl" / "study43"
SRFM: Final = str(Path(sys.executable).with_name("srfm"))

sys.path.insert(0, str(ROOT))
from tools.rl import study  # noqa: E402  (issue 30's study: the helpers both use)
from tools.rl.study import run_name, seeds_of, steps_done  # noqa: E402

STEPS: Final = 300_000
VALIDATION_SEEDS: Final = 10
# k2 rises from 0 at K2_START to its arm's value at K2_START + K2_RAMP = 100,000, a
# third of the run; both arms select checkpoints only after it.
K2_START: Final = 40_000
K2_RAMP: Final = 60_000
# The validation scenes of issue 43 (committed before any run), beside the issue-30
# validation set (the mixed layouts and LIBRARY_VALIDATION).
SCENES: Final = tuple(
    sorted(str(p.relative_to(ROOT)) for p in (STUDY / "validation_scenes").glob("*.toml"))
)
RECIPE: Final = (
    "--scenario", "mixed",
    "--library", "train-split",
    "--library-share", "0.3",
    "--generated-share", "0.4",
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
FINAL: Final = f"step_{STEPS:09d}.zip"


def train_command(run: Path, k2: str, seed: int) -> list[str]:
    words = [SRFM, "train", "--run-dir", str(run), "--seed", str(seed), "--k-div", k2, *RECIPE]
    latest = run / "latest.zip"
    committed = STUDY / "checkpoints" / f"{run.name}.zip"
    if latest.is_file():
        words += ["--resume", str(latest)]
    elif committed.is_file():
        shutil.copy(committed, latest)
        words += ["--resume", str(latest)]
    return words


def validate_command(run: Path) -> list[str]:
    """Choose the run's checkpoint on the validation set and export it and the last
    one (tools/rl/study43/finish.py)."""
    return [sys.executable, str(Path(__file__).with_name("finish.py")), str(run)]


def finished(run: Path) -> bool:
    return steps_done(run) >= STEPS


def exported(name: str) -> bool:
    policies = STUDY / "policies"
    return (policies / f"{name}.json").is_file() and (policies / f"{name}-final.json").is_file()


def collect(runs: Path) -> list[str]:
    """Copy every run's evaluations and unfinished checkpoints into tools/rl/study43/
    and write runs.json; the files written."""
    written: list[str] = []
    table: dict[str, dict[str, object]] = {}
    for d in ("policies", "evals", "checkpoints", "validation"):
        (STUDY / d).mkdir(parents=True, exist_ok=True)
    for run in sorted(p for p in runs.glob("k*-seed*") if p.is_dir()):
        steps = steps_done(run)
        state = json.loads((run / "state.json").read_text()) if steps else {}
        table[run.name] = {
            "steps": steps,
            "wall_time_s": state.get("wall_time_s"),
            "finished": steps >= STEPS,
            "validated": exported(run.name),
        }
        evals = run / "eval.jsonl"
        if evals.is_file():
            shutil.copy(evals, STUDY / "evals" / f"{run.name}.jsonl")
            written.append(f"evals/{run.name}.jsonl")
        checkpoint = STUDY / "checkpoints" / f"{run.name}.zip"
        if steps >= STEPS:
            checkpoint.unlink(missing_ok=True)
        elif (run / "latest.zip").is_file():
            shutil.copy(run / "latest.zip", checkpoint)
            written.append(f"checkpoints/{run.name}.zip")
    (STUDY / "runs.json").write_text(json.dumps(table, indent=2, sort_keys=True) + "\n")
    return written


def commit(message: str) -> None:
    study.commit(message, STUDY)


def run(args: argparse.Namespace) -> None:
    runs = Path(args.runs)
    runs.mkdir(parents=True, exist_ok=True)
    names = [(k2, seed) for seed in seeds_of(args.seeds) for k2 in args.arms.split(",")]
    # jobs: ("train", k2, seed) or ("validate", name)
    todo: list[tuple[str, str, int]] = []
    for k2, seed in names:
        name = run_name(k2, seed)
        if not finished(runs / name):
            todo.append(("train", k2, seed))
        elif not exported(name):
            todo.insert(0, ("validate", k2, seed))
    active: dict[str, tuple[subprocess.Popen[bytes], tuple[str, str, int]]] = {}
    last_collect = time.monotonic()
    env = {**os.environ, "NUMBA_NUM_THREADS": "1", "OMP_NUM_THREADS": "1"}
    while todo or active:
        for key, (proc, job) in list(active.items()):
            if proc.poll() is None:
                continue
            del active[key]
            what, k2, seed = job
            name = run_name(k2, seed)
            print(f"{key}: exit {proc.returncode}", flush=True)
            collect(runs)
            if what == "train" and finished(runs / name):
                todo.insert(0, ("validate", k2, seed))
                if args.commit:
                    commit(f"Issue 43: study run {name} trained ({steps_done(runs / name)} steps)")
            elif what == "validate" and args.commit:
                commit(f"Issue 43: study run {name}: validation, chosen and final policies")
        while todo and len(active) < args.jobs:
            job = todo.pop(0)
            what, k2, seed = job
            name = run_name(k2, seed)
            path = runs / name
            path.mkdir(exist_ok=True)
            log = (runs / f"{name}.{what}.log").open("ab")
            words = train_command(path, k2, seed) if what == "train" else validate_command(path)
            words = ["nice", "-n", str(args.nice), *words]
            proc = subprocess.Popen(
                words, stdout=log, stderr=subprocess.STDOUT, env=env, cwd=str(ROOT)
            )
            active[f"{name} {what}"] = (proc, job)
            print(f"{name} {what}: started", flush=True)
        if time.monotonic() - last_collect > args.collect_every:
            collect(runs)
            if args.commit:
                commit("Issue 43: study checkpoints and evaluations")
            last_collect = time.monotonic()
        time.sleep(5)
    collect(runs)
    if args.commit:
        commit("Issue 43: study artefacts")


def status(args: argparse.Namespace) -> None:
    runs = Path(args.runs)
    for run_dir in sorted(p for p in runs.glob("k*-seed*") if p.is_dir()):
        done = "validated" if exported(run_dir.name) else ""
        print(f"{run_dir.name}: {steps_done(run_dir)} / {STEPS} {done}")


def main() -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("--runs", default="runs/study43", help="run folders (default runs/study43)")
    sub = parser.add_subparsers(dest="what", required=True)
    p = sub.add_parser("run")
    p.add_argument("--arms", default="0,2", help="k2 values, comma-separated")
    p.add_argument("--seeds", default="1-10", help="training seeds, e.g. 1-10 or 1,3")
    p.add_argument("--jobs", type=int, default=2)
    p.add_argument("--nice", type=int, default=10, help="niceness of the processes")
    p.add_argument("--collect-every", type=float, default=1200.0, help="seconds")
    p.add_argument("--commit", action="store_true", help="git-commit tools/rl/study43/")
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
