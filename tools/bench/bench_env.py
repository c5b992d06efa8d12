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
"""

from __future__ import annotations

import argparse
import statistics
import time
from collections.abc import Callable

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


def _time(run: Callable[[], None], steps: int, repeats: int) -> tuple[float, float]:
    run()  # warm-up (kernel loading, first episode)
    rates = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        run()
        rates.append(steps / (time.perf_counter() - t0))
    return max(rates), statistics.median(rates)


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
    args = parser.parse_args(argv)

    import gymnasium as gym
    from bench_crowd_step import OtherLoad, load_average, machine_info

    import srfm.rl
    from srfm.rl import EnvConfig, SocialNavEnv

    other = OtherLoad()
    rows: list[tuple[str, str, float, float]] = []
    actions = np.random.default_rng(0).uniform(-1.0, 1.0, (args.steps, 2)).astype(np.float32)
    for name in args.scenarios:
        env = SocialNavEnv(name)
        env.reset(seed=0)
        rows.append(
            (
                name,
                "SocialNavEnv, full twin",
                *_time(_env_loop(env, actions), args.steps, args.repeats),
            )
        )
        env = SocialNavEnv(name, EnvConfig(counterfactual_twin=False))
        env.reset(seed=0)
        rows.append(
            (
                name,
                "SocialNavEnv, no full twin (training)",
                *_time(_env_loop(env, actions), args.steps, args.repeats),
            )
        )
        if args.beams:
            env = SocialNavEnv(name, EnvConfig(counterfactual_twin=False, range_beams=args.beams))
            env.reset(seed=0)
            rows.append(
                (
                    name,
                    f"SocialNavEnv, no full twin, {args.beams} range beams",
                    *_time(_env_loop(env, actions), args.steps, args.repeats),
                )
            )
        made = gym.make(srfm.rl.ENV_ID, scenario=name)
        made.reset(seed=0)
        rows.append(
            (
                name,
                "gym.make (default wrappers), full twin",
                *_time(_env_loop(made, actions), args.steps, args.repeats),
            )
        )
        env = SocialNavEnv(name)
        env.reset(seed=0)
        env.action_space.seed(0)
        rows.append(
            (
                name,
                "SocialNavEnv + action_space.sample() per step",
                *_time(_sample_loop(env, args.steps), args.steps, args.repeats),
            )
        )
        rows.append(
            (
                name,
                "core TwinSimulator: observe + step from Python",
                *_time(_simulator_loop(name, args.steps), args.steps, args.repeats),
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
    for name, what, best, median in rows:
        print(f"| {name} | {what} | {best:,.0f} | {median:,.0f} | {1e6 / best:.1f} |")
    print(
        f"\n- load average (1, 5, 15 min) at end: {load_average()}; other processes used"
        f" {other.percent():.1f} % of the machine's CPU time during the measurements"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
