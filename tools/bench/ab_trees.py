"""Two source trees of srfm side by side in one process: environment steps, episodes and
crowd steps, in interleaved blocks.

On a shared machine, timings of separate runs drift with the load by more than the
differences worth measuring (±30 % between two runs of the same tree was seen here).
This script copies the ``srfm`` package of each tree into a temporary folder under its
own name (``srfm_a``, ``srfm_b``: the imports in the copy are renamed), imports both
into one process and times them in alternating blocks, so that both see the same load;
the table gives each tree's best and median block and the ratio B / A (below 1: B is
faster). numba compiles or loads each copy's kernels on its own (the copies have their
own caches).

Usage::

    .venv/bin/python tools/bench/ab_trees.py OLD_TREE NEW_TREE
    .venv/bin/python tools/bench/ab_trees.py /tmp/old . --blocks 15 --only env

where a tree is a checkout (a folder with ``srfm/`` in it), e.g. one made by
``git worktree add /tmp/old <commit>``.
"""

from __future__ import annotations

import argparse
import importlib
import re
import shutil
import statistics
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from types import ModuleType
from typing import Any

import numpy as np

_ENV_CASES = (("crosswalk", True), ("crosswalk", False), ("random", True), ("blind_corner", True))
_EPISODE_CASES = (
    ("crosswalk", "straight"),
    ("crosswalk", "dwa"),
    ("random", "dwa"),
    ("corridor_flow", "straight"),
)
_CROWD_SIZES = (10, 100, 1000)


def copy_tree(tree: Path, name: str, into: Path) -> None:
    """``tree/srfm`` as package ``name`` in ``into``, every import of srfm renamed."""
    target = into / name
    shutil.copytree(tree / "srfm", target, ignore=shutil.ignore_patterns("__pycache__"))
    for path in target.rglob("*.py"):
        text = path.read_text(encoding="utf-8")
        text = re.sub(r"\bfrom srfm([. ])", rf"from {name}\1", text)
        text = re.sub(r"\bimport srfm\.([\w.]+)", rf"import {name}.\1", text)
        text = re.sub(r"\bimport srfm\b", f"import {name} as srfm", text)
        text = text.replace('"srfm.', f'"{name}.')
        path.write_text(text, encoding="utf-8")


def env_block(rl: ModuleType, scenario: str, twin: bool) -> Callable[[], float]:
    """µs per environment step over 4,000 random actions, resets included."""
    env = rl.SocialNavEnv(scenario, rl.EnvConfig(counterfactual_twin=twin))
    actions = np.random.default_rng(0).uniform(-1.0, 1.0, (4000, 2)).astype(np.float32)

    def run() -> float:
        env.reset(seed=0)
        t0 = time.perf_counter()
        for action in actions:
            _, _, terminated, truncated, _ = env.step(action)
            if terminated or truncated:
                env.reset()
        return (time.perf_counter() - t0) / len(actions) * 1e6

    return run


def episode_block(srfm: ModuleType, scenario: str, planner: str) -> Callable[[], float]:
    """ms per ``run_episode`` (seeds 0-2)."""

    def run() -> float:
        t0 = time.perf_counter()
        for seed in range(3):
            srfm.run_episode(scenario, seed, planner)
        return (time.perf_counter() - t0) / 3 * 1e3

    return run


def crowd_block(srfm: ModuleType, n: int) -> Callable[[], float]:
    """CPU µs per agent-step of ``step_crowd`` (the crowd-step benchmark's call)."""
    rng = np.random.default_rng(0)
    side = max(5.0, float(np.sqrt(n)) * 1.5)
    pos = rng.uniform(0.0, side, (n, 2))
    start = srfm.CrowdState.create(pos=pos, goal=side - pos, v0=1.3)
    params = srfm.SRFMParams()
    steps = max(20, 20_000 // n)

    def run() -> float:
        crowd = start.copy()
        t0 = time.process_time()
        for _ in range(steps):
            srfm.step_crowd(crowd, 1 / 15, params)
        return (time.process_time() - t0) / steps / n * 1e6

    return run


def compare(cases: dict[str, tuple[Callable[[], float], Callable[[], float]]], blocks: int) -> None:
    print("| case | A best | A median | B best | B median | B / A (best) | B / A (median) |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for label, (a, b) in cases.items():
        a()
        b()  # warm-up: compile or load the kernels, fill caches
        times: dict[str, list[float]] = {"a": [], "b": []}
        for _ in range(blocks):
            times["a"].append(a())
            times["b"].append(b())
        a_best, b_best = min(times["a"]), min(times["b"])
        a_med, b_med = statistics.median(times["a"]), statistics.median(times["b"])
        print(
            f"| {label} | {a_best:.2f} | {a_med:.2f} | {b_best:.2f} | {b_med:.2f} "
            f"| {b_best / a_best:.3f} | {b_med / a_med:.3f} |"
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("tree_a", type=Path, help="checkout A (e.g. the commit before)")
    parser.add_argument("tree_b", type=Path, help="checkout B (e.g. this one)")
    parser.add_argument("--blocks", type=int, default=15, help="timed blocks per tree")
    parser.add_argument("--only", choices=("env", "episode", "crowd"), default=None)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="srfm-ab-") as tmp:
        for tree, name in ((args.tree_a, "srfm_a"), (args.tree_b, "srfm_b")):
            copy_tree(tree.resolve(), name, Path(tmp))
        sys.path.insert(0, tmp)
        pkg: dict[str, Any] = {n: importlib.import_module(n) for n in ("srfm_a", "srfm_b")}
        rl = {n: importlib.import_module(f"{n}.rl") for n in pkg}
        cases: dict[str, tuple[Callable[[], float], Callable[[], float]]] = {}
        if args.only in (None, "env"):
            for scenario, twin in _ENV_CASES:
                label = f"env step µs, {scenario}, {'full twin' if twin else 'no full twin'}"
                cases[label] = (
                    env_block(rl["srfm_a"], scenario, twin),
                    env_block(rl["srfm_b"], scenario, twin),
                )
        if args.only in (None, "episode"):
            for scenario, planner in _EPISODE_CASES:
                cases[f"episode ms, {scenario}, {planner}"] = (
                    episode_block(pkg["srfm_a"], scenario, planner),
                    episode_block(pkg["srfm_b"], scenario, planner),
                )
        if args.only in (None, "crowd"):
            for n in _CROWD_SIZES:
                cases[f"crowd step CPU µs per agent-step, N = {n}"] = (
                    crowd_block(pkg["srfm_a"], n),
                    crowd_block(pkg["srfm_b"], n),
                )
        print(f"A = {args.tree_a}, B = {args.tree_b}, {args.blocks} blocks each, interleaved")
        compare(cases, args.blocks)


if __name__ == "__main__":
    main()
