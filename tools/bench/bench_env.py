"""Throughput of the gymnasium environment ``srfm/SocialNav-v0``: env steps per second.

One environment in one process, random actions, episodes reset as they end (the
resets are inside the timed loop). Each configuration runs ``--repeats`` blocks of
``--steps`` steps after an untimed warm-up block; the table gives the best block and
the median. Configurations:

* ``SocialNavEnv`` used directly, actions drawn up front (uniform in [−1, 1]²): the
  cost of the environment itself; with the full counterfactual twin (default) and
  without it (``EnvConfig(counterfactual_twin=False)``, the training set-up), and with
  ``--beams B`` also the training set-up with B range beams to walls and pillars;
* ``gym.make("srfm/SocialNav-v0")``: the same behind gymnasium's default wrappers;
* ``action_space.sample()`` drawn inside the loop, as a random agent would;
* for context, the core ``TwinSimulator`` stepped from Python with ``observe`` each
  step (no observation vector, no reward).

Usage::

    .venv/bin/python tools/bench/bench_env.py
    .venv/bin/python tools/bench/bench_env.py --steps 50000 --repeats 3 --scenarios random
    .venv/bin/python tools/bench/bench_env.py --scenarios random entering_room --beams 24
    .venv/bin/python tools/bench/bench_env.py --json docs/results/performance/env.json

``--json PATH`` also writes every block's rate, per scenario and configuration, with the
run's record (``tools/results/record.py``): the data docs/performance.md's environment
table is generated from (``make docs-tables``).
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np


def _env_loop(env: object, actions: np.ndarray) -> Callable[[], None]:
    step = env.step  # type: ignore[attr-defined]
    reset = env.reset  # type: ignore[attr-defined]

    def run() -> None:
        for a in actions:
            _, _, terminated, truncated, _ = step(a)
            if terminated or truncated:
                reset()

    return run


def _sample_loop(env: object, n: int) -> Callable[[], None]:
    step = env.step  # type: ignore[attr-defined]
    reset = env.reset  # type: ignore[attr-defined]
    sample = env.action_space.sample  # type: ignore[attr-defined]

    def run() -> None:
        for _ in range(n):
            _, _, terminated, truncated, _ = step(sample())
            if terminated or truncated:
                reset()

    return run


def _simulator_loop(scenario: str, n: int) -> Callable[[], None]:
    from srfm.scenarios import episode_setup, load_scenario
    from srfm.sim.simulator import TwinSimulator

    sc = load_scenario(scenario)
    rng = np.random.default_rng(0)
    commands = rng.uniform(-1.0, 1.0, (n, 2)) * [0.5, np.pi]
    state = {"seed": 0, "sim": TwinSimulator(episode_setup(sc, 0))}

    def run() -> None:
        sim = state["sim"]
        for c in commands:
            sim.observe(3.0)  # type: ignore[attr-defined]
            sim.step(c)  # type: ignore[attr-defined]
            if not sim.robot_active:  # type: ignore[attr-defined]
                state["seed"] += 1  # type: ignore[operator]
                sim = TwinSimulator(episode_setup(sc, state["seed"]))  # type: ignore[arg-type]
        state["sim"] = sim

    return run


def _time(run: Callable[[], None], steps: int, repeats: int) -> list[float]:
    """Steps/s of each of ``repeats`` timed blocks, after one untimed block."""
    run()  # warm-up (kernel loading, first episode)
    rates = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        run()
        rates.append(steps / (time.perf_counter() - t0))
    return rates


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        description=__doc__.split("\n\n")[0] if __doc__ else None,
        formatter_class=argparse.ArgumentDefaultsHelpFormatter,
    )
    parser.add_argument("--steps", type=int, default=100_000, help="steps per timed block")
    parser.add_argument("--repeats", type=int, default=5, help="timed blocks per row")
    parser.add_argument("--scenarios", nargs="+", default=["random", "crosswalk"])
    parser.add_argument(
        "--beams",
        type=int,
        default=0,
        help="also time the training set-up with this many range beams (0: not)",
    )
    parser.add_argument("--json", type=Path, default=None, help="also write the figures here")
    args = parser.parse_args(argv)

    sys.path.insert(0, str(Path(__file__).resolve().parents[2]))
    import gymnasium as gym
    from bench_crowd_step import OtherLoad, load_average, machine_info

    import srfm.rl
    from srfm.rl import EnvConfig, SocialNavEnv
    from tools.results import record

    begun = record.start()
    other = OtherLoad()
    rows: list[tuple[str, str, list[float]]] = []
    actions = np.random.default_rng(0).uniform(-1.0, 1.0, (args.steps, 2)).astype(np.float32)
    for name in args.scenarios:
        env = SocialNavEnv(name)
        env.reset(seed=0)
        rows.append(
            (
                name,
                "SocialNavEnv, full twin",
                _time(_env_loop(env, actions), args.steps, args.repeats),
            )
        )
        env = SocialNavEnv(name, EnvConfig(counterfactual_twin=False))
        env.reset(seed=0)
        rows.append(
            (
                name,
                "SocialNavEnv, no full twin (training)",
                _time(_env_loop(env, actions), args.steps, args.repeats),
            )
        )
        if args.beams:
            env = SocialNavEnv(name, EnvConfig(counterfactual_twin=False, range_beams=args.beams))
            env.reset(seed=0)
            rows.append(
                (
                    name,
                    f"SocialNavEnv, no full twin, {args.beams} range beams",
                    _time(_env_loop(env, actions), args.steps, args.repeats),
                )
            )
        made = gym.make(srfm.rl.ENV_ID, scenario=name)
        made.reset(seed=0)
        rows.append(
            (
                name,
                "gym.make (default wrappers), full twin",
                _time(_env_loop(made, actions), args.steps, args.repeats),
            )
        )
        env = SocialNavEnv(name)
        env.reset(seed=0)
        env.action_space.seed(0)
        rows.append(
            (
                name,
                "SocialNavEnv + action_space.sample() per step",
                _time(_sample_loop(env, args.steps), args.steps, args.repeats),
            )
        )
        rows.append(
            (
                name,
                "core TwinSimulator: observe + step from Python",
                _time(_simulator_loop(name, args.steps), args.steps, args.repeats),
            )
        )

    print("## Gymnasium environment throughput (one env, random actions, higher is better)\n")
    print(*machine_info(), sep="\n")
    print(
        f"- {args.repeats} timed blocks of {args.steps} steps per row after one untimed block;"
        " resets inside the loop"
    )
    print("\n| scenario | configuration | best (steps/s) | median (steps/s) | µs per step (best) |")
    print("|---|---|---:|---:|---:|")
    for name, what, rates in rows:
        best, median = max(rates), statistics.median(rates)
        print(f"| {name} | {what} | {best:,.0f} | {median:,.0f} | {1e6 / best:.1f} |")
    other_percent = other.percent()
    print(
        f"\n- load average (1, 5, 15 min) at end: {load_average()}; other processes used"
        f" {other_percent:.1f} % of the machine's CPU time during the measurements"
    )
    if args.json is not None:
        record.write_json(
            args.json,
            {
                "steps": args.steps,
                "repeats": args.repeats,
                "other_cpu_percent": other_percent,
                "rows": [
                    {"scenario": name, "configuration": what, "steps_per_s": rates}
                    for name, what, rates in rows
                ],
            },
            begun,
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
