"""Select a run's checkpoint on a larger validation set than its periodic evaluations.

    python tools/rl/validate_checkpoints.py RUN_DIR [--seeds 10] [--out FILE.json] \
        [--scenes FILE.toml ...]

Every checkpoint of the run (``checkpoints/step_N.zip``) that may be its best
(:func:`srfm.rl.training.selectable`: after the k2 curriculum) is run as a planner on
the validation set (the mixed training layouts and
:data:`srfm.scenarios.training.LIBRARY_VALIDATION`) with ``--seeds`` seeds each, from
20000 on (and on the scenario files ``--scenes``, e.g. the validation scenes of
issue 43 in ``tools/rl/study43/validation_scenes/``): seeds that neither the periodic
evaluations (10000 on) nor the report (0-99) use. The checkpoint with the highest
success, then the fewest collisions, wins; a tie keeps the earlier one (deviation
plays no part: the rule of ``--select-by-outcome``). Prints one line per checkpoint and
writes them, with the choice, to ``--out`` (default ``RUN_DIR/validation.json``); a
rerun reuses the lines already written.
"""

from __future__ import annotations

import argparse
import json
import re
import sys
from pathlib import Path

import attrs

from srfm.planners.td3 import PolicyPlanner, load_checkpoint
from srfm.rl.training import EvalResult, TrainConfig, evaluate_planner, selectable
from srfm.scenarios.training import LIBRARY_VALIDATION, TRAINING_SCENARIO

SEED_BASE = 20_000
STEP = re.compile(r"step_(\d+)\.zip")


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run", type=Path)
    parser.add_argument("--seeds", type=int, default=10)
    parser.add_argument("--out", type=Path, default=None)
    parser.add_argument("--scenes", nargs="*", default=[], help="more scenario files")
    args = parser.parse_args(argv)
    out = args.out or args.run / "validation.json"
    meta = json.loads((args.run / "config.json").read_text())
    known = {f.name for f in attrs.fields(TrainConfig)}
    train = {k: v for k, v in meta["train_config"].items() if k in known}
    config = TrainConfig(**{k: tuple(v) if isinstance(v, list) else v for k, v in train.items()})
    done: dict[str, dict[str, object]] = {}
    if out.is_file():
        done = {row["checkpoint"]: row for row in json.loads(out.read_text())["checkpoints"]}
    scenarios = (TRAINING_SCENARIO, *LIBRARY_VALIDATION, *args.scenes)
    seeds = list(range(SEED_BASE, SEED_BASE + args.seeds))
    rows = []
    for path in sorted(args.run.glob("checkpoints/step_*.zip")):
        match = STEP.fullmatch(path.name)
        if match is None or not selectable(config, int(match[1])):
            continue
        if path.name in done:
            rows.append(done[path.name])
            continue
        actor, env_config, _ = load_checkpoint(path)
        result = evaluate_planner(
            lambda actor=actor, env_config=env_config: PolicyPlanner(actor, env_config, "policy"),
            scenarios,
            seeds,
            int(match[1]),
        )
        row = {"checkpoint": path.name, **attrs.asdict(result)}
        rows.append(row)
        print(
            f"{path.name}: success {result.success_rate:.3f}, collisions "
            f"{result.collision_rate:.3f} ({result.episodes} episodes)",
            flush=True,
        )
        out.write_text(json.dumps({"checkpoints": rows}, indent=1) + "\n")
    best: dict[str, object] | None = None
    for row in rows:
        result = EvalResult(**{k: v for k, v in row.items() if k != "checkpoint"})
        if best is None or result.better_than(
            EvalResult(**{k: v for k, v in best.items() if k != "checkpoint"}), by_deviation=False
        ):
            best = row
    doc = {"seeds": seeds, "scenarios": list(scenarios), "checkpoints": rows, "best": best}
    out.write_text(json.dumps(doc, indent=1) + "\n")
    if best is None:
        print("no selectable checkpoint", file=sys.stderr)
        return 1
    print(f"best: {best['checkpoint']}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
