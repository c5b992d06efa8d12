"""Training throughput: environment steps per second *with learning*, per configuration.

Every configuration runs ``srfm.rl.training.train`` (what ``srfm train`` calls) in a
fresh process of its own (so that each sets its own thread counts, and JAX / torch
start clean), one after the other, on ``srfm/SocialNav-v0`` with the ``random``
scenario: WARMUP random-action steps, then LEARN learning steps. The rate is taken over
the learning steps after the first SETTLE of them (which include JAX's compilation and
torch's first-call costs), from the training loop's own progress calls; evaluations,
checkpoints and the replay-buffer file are off. With ``--repeats N`` the list is run N
times round-robin and each configuration's best round is kept (on a shared machine the
best round is the least disturbed one). The first row is the paper's set-up
on SB3 + torch ([256, 256], batch 256, 5 gradient steps every 5 environment steps, one
torch thread), the reference of the speed-up column.

    .venv/bin/python tools/bench/bench_train.py                    # every configuration
    .venv/bin/python tools/bench/bench_train.py --only sb3-paper,sbx-paper --learn 2000
    .venv/bin/python tools/bench/bench_train.py --list

Needs the ``rl`` extra, and the ``sbx`` extra for the SBX rows (skipped without it).
Prints a Markdown table (docs/performance.md, "Training throughput") with the projected
wall time of 2,000,000 steps. ``--json PATH`` also writes every round of every
configuration with the options and the run's record (``tools/results/record.py``): the
data that table is generated from (``make docs-tables``)::

    .venv/bin/python tools/bench/bench_train.py --only sb3-paper,sbx-64-tf50,sbx-64-tf50-ar4 \
        --repeats 2 --json docs/results/performance/train.json
"""

from __future__ import annotations

import argparse
import datetime
import importlib.util
import json
import os
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

# name -> (description, TrainConfig overrides). The paper's set-up is TrainConfig's
# defaults: [256, 256], batch 256, train_freq 5, gradient_steps 5, one thread, sb3.
CONFIGS: dict[str, tuple[str, dict[str, Any]]] = {
    "sb3-paper": ("SB3, paper set-up, 1 thread (reference)", {}),
    "sb3-paper-2t": ("SB3, paper set-up, 2 torch threads", {"torch_threads": 2}),
    "sb3-64": ("SB3, [64, 64]", {"net_arch": (64, 64)}),
    "sb3-tf50": ("SB3, 50 gradient steps every 50 steps", {"train_freq": 50, "gradient_steps": 50}),
    "sb3-utd0.5": ("SB3, update-to-data 0.5 (5 every 10)", {"train_freq": 10}),
    "sb3-4env": (
        "SB3, 4 envs, 20 gradient steps every 5 vector steps",
        {"n_envs": 4, "gradient_steps": 20},
    ),
    "sbx-paper": ("SBX, paper set-up, 1 thread", {"backend": "sbx"}),
    "sbx-paper-2t": ("SBX, paper set-up, XLA threads on", {"backend": "sbx", "torch_threads": 2}),
    "sbx-64": ("SBX, [64, 64]", {"backend": "sbx", "net_arch": (64, 64)}),
    "sbx-tf50": (
        "SBX, 50 gradient steps every 50 steps",
        {"backend": "sbx", "train_freq": 50, "gradient_steps": 50},
    ),
    "sbx-tf50-2t": (
        "SBX, 50 every 50, XLA threads on",
        {"backend": "sbx", "train_freq": 50, "gradient_steps": 50, "torch_threads": 2},
    ),
    "sbx-utd0.5": ("SBX, update-to-data 0.5 (5 every 10)", {"backend": "sbx", "train_freq": 10}),
    "sbx-4env": (
        "SBX, 4 envs, 20 gradient steps every 5 vector steps",
        {"backend": "sbx", "n_envs": 4, "gradient_steps": 20},
    ),
    "sbx-64-tf50": (
        "SBX, [64, 64], 50 every 50",
        {"backend": "sbx", "net_arch": (64, 64), "train_freq": 50, "gradient_steps": 50},
    ),
    # The shipped recipe's set-up: its steps are actions of 4 simulation steps each.
    "sbx-64-tf50-ar4": (
        "SBX, [64, 64], 50 every 50, action repeat 4 (steps = actions)",
        {
            "backend": "sbx",
            "net_arch": (64, 64),
            "train_freq": 50,
            "gradient_steps": 50,
            "action_repeat": 4,
        },
    ),
}


def _child(name: str, warmup: int, learn: int, settle: int) -> dict[str, Any]:
    """Run one configuration in this process and return its measurement."""
    from srfm.rl.training import TrainConfig, train

    _, overrides = CONFIGS[name]
    total = warmup + learn
    config = TrainConfig(
        total_steps=total,
        learning_starts=warmup,
        buffer_size=total,
        eval_every=0,
        checkpoint_every=0,
        save_replay_buffer=False,
        seed=0,
        **overrides,
    )
    marks: list[tuple[int, float]] = []
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory() as run:
        train(config, run, progress=lambda n: marks.append((n, time.perf_counter())))
    start = next((m for m in marks if m[0] >= warmup + settle), None)
    end = marks[-1]
    if start is None or end[0] <= start[0]:
        raise SystemExit(f"{name}: too few progress marks {marks}")
    warm = next(m for m in marks if m[0] >= warmup)
    return {
        "name": name,
        "steps_per_s": (end[0] - start[0]) / (end[1] - start[1]),
        "measured_steps": end[0] - start[0],
        "settle_s": start[1] - warm[1],
        "warmup_steps_per_s": warm[0] / (warm[1] - t0),
        "backend": config.backend,
        "net_arch": list(config.net_arch),
        "batch": config.batch_size,
        "train_freq": config.train_freq,
        "gradient_steps": config.gradient_steps,
        "n_envs": config.n_envs,
        "threads": config.torch_threads,
        "utd": config.gradient_steps / (config.train_freq * config.n_envs),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--only", help="comma-separated configuration names")
    parser.add_argument("--warmup", type=int, default=1000, help="random-action steps")
    parser.add_argument("--learn", type=int, default=3000, help="learning steps")
    parser.add_argument("--settle", type=int, default=500, help="learning steps not timed")
    parser.add_argument(
        "--repeats", type=int, default=1, help="rounds over the configurations (best kept)"
    )
    parser.add_argument("--list", action="store_true", help="list the configurations")
    parser.add_argument("--child", help=argparse.SUPPRESS)
    parser.add_argument("--json", help="also write the results to this JSON file")
    args = parser.parse_args()
    if args.list:
        for name, (text, overrides) in CONFIGS.items():
            print(f"{name:14s} {text}  {overrides}")
        return
    if args.child:
        print(json.dumps(_child(args.child, args.warmup, args.learn, args.settle)))
        return
    sys.path.insert(0, str(Path(__file__).resolve().parents[2]))
    from tools.results import record

    begun = record.start()
    names = args.only.split(",") if args.only else list(CONFIGS)
    unknown = [n for n in names if n not in CONFIGS]
    if unknown:
        raise SystemExit(f"unknown configurations {unknown}; see --list")
    has_sbx = importlib.util.find_spec("sbx") is not None
    env = {**os.environ, "OMP_NUM_THREADS": "1", "NUMBA_NUM_THREADS": "1"}
    print(
        f"# {datetime.date.today()} {platform.node()} {os.cpu_count()} CPUs, python "
        f"{platform.python_version()}; warm-up {args.warmup}, learning {args.learn} "
        f"(first {args.settle} not timed)",
        file=sys.stderr,
    )
    best: dict[str, dict[str, Any]] = {}
    rounds: dict[str, list[float]] = {}
    for name in [n for _ in range(args.repeats) for n in names]:
        overrides = CONFIGS[name][1]
        if overrides.get("backend") == "sbx" and not has_sbx:
            print(f"{name}: skipped (sbx not installed)", file=sys.stderr)
            continue
        load = os.getloadavg()[0]
        out = subprocess.run(
            [
                sys.executable,
                __file__,
                "--child",
                name,
                "--warmup",
                str(args.warmup),
                "--learn",
                str(args.learn),
                "--settle",
                str(args.settle),
            ],
            env=env,
            capture_output=True,
            text=True,
            check=False,
        )
        if out.returncode != 0:
            print(f"{name}: failed\n{out.stderr[-2000:]}", file=sys.stderr)
            continue
        row = json.loads(out.stdout.strip().splitlines()[-1])
        row["load_before"] = load
        rounds.setdefault(name, []).append(row["steps_per_s"])
        if name not in best or row["steps_per_s"] > best[name]["steps_per_s"]:
            best[name] = row
        print(
            f"{name}: {row['steps_per_s']:.0f} steps/s (load {load:.2f})",
            file=sys.stderr,
            flush=True,
        )
    results = [{**best[n], "rounds_steps_per_s": rounds[n]} for n in names if n in best]
    if args.json:
        record.write_json(
            args.json,
            {
                "warmup": args.warmup,
                "learn": args.learn,
                "settle": args.settle,
                "repeats": args.repeats,
                "action_repeat": {n: CONFIGS[n][1].get("action_repeat", 1) for n in best},
                "configurations": results,
            },
            begun,
        )
    ref = next((r["steps_per_s"] for r in results if r["name"] == "sb3-paper"), None)
    print(
        "| configuration | backend | net | batch | grad. steps / env steps | envs | threads "
        "| steps/s | × paper SB3 | 2M steps |"
    )
    print("|---|---|---|---:|---|---:|---:|---:|---:|---:|")
    for r in results:
        rate = r["steps_per_s"]
        speed = f"{rate / ref:.2f}" if ref else "–"
        hours = 2_000_000 / rate / 3600
        print(
            f"| `{r['name']}` | {r['backend']} | {r['net_arch']} | {r['batch']} | "
            f"{r['gradient_steps']} / {r['train_freq'] * r['n_envs']} | {r['n_envs']} | "
            f"{r['threads']} | {rate:.0f} | {speed} | {hours:.2f} h |"
        )


if __name__ == "__main__":
    main()
