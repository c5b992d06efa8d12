"""The shipped NumPy policy files against the actors of the checkpoints they were
exported from: the largest difference between their actions.

    PYTHONPATH=. python tools/rl/export_match.py --json docs/rl/export_match.json

For each shipped policy (``srfm/policies/td3_srfm.*``, ``td3_base.*``), its training
checkpoint ``tools/rl/policies/<stem>.zip`` (the policy's ``training.source_sha256``;
a mismatch is an error) is loaded with the library that wrote it (SBX or SB3,
``TD3.load``: it unpickles, a trusted file of this repository) and its deterministic
``model.predict`` is set beside the shipped actor's NumPy forward pass
(``NumpyActor.forward``, what the planner runs) on the same float32 observations:

- ``UNIFORM`` observations uniform in [-1, 1];
- ``SPARSE`` sparse ones: uniform, each entry zeroed with probability 0.8;
- ``PER_SCENARIO`` observations of each scenario of ``SCENARIOS``, from the
  environment (``SocialNavEnv`` with the policy's ``EnvConfig``) stepped by the shipped
  actor, episodes 0, 1, ... until that many steps.

Printed: the largest absolute difference per policy; ``--json`` also writes it with the
run's record (``tools/results/record.py``). Deterministic (seed 0).
"""

from __future__ import annotations

import argparse
import hashlib
import json
import sys
import warnings
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from tools.results.record import run_record, start  # noqa: E402

STEMS = {"td3-srfm": "td3_srfm", "td3-base": "td3_base"}
"""Shipped planner -> the stem of its files in srfm/policies/ and tools/rl/policies/."""
UNIFORM = 2000
SPARSE = 800
PER_SCENARIO = 700
SCENARIOS = ("crosswalk", "corridor_flow", "blind_corner")


def random_observations(size: int, seed: int = 0) -> dict[str, np.ndarray]:
    """The uniform and the sparse observations of length ``size``."""
    rng = np.random.default_rng(seed)
    uniform = rng.uniform(-1.0, 1.0, (UNIFORM, size)).astype(np.float32)
    sparse = rng.uniform(-1.0, 1.0, (SPARSE, size)).astype(np.float32)
    sparse[rng.random((SPARSE, size)) < 0.8] = 0.0
    return {"uniform": uniform, "sparse": sparse}


def episode_observations(actor: Any, config: Any, scenario: str, n: int) -> np.ndarray:
    """The first ``n`` observations of the scenario's episodes 0, 1, ... under the actor."""
    from srfm.rl import SocialNavEnv

    env = SocialNavEnv(scenario, config)
    out: list[np.ndarray] = []
    episode = 0
    while len(out) < n:
        obs, _ = env.reset(seed=episode)
        done = False
        while not done and len(out) < n:
            out.append(np.asarray(obs, dtype=np.float32))
            obs, _, terminated, truncated, _ = env.step(actor.forward(out[-1]))
            done = terminated or truncated
        episode += 1
    return np.stack(out)


def compare(planner: str) -> dict[str, Any]:
    """The policy's largest action difference per kind of observation, and overall."""
    from srfm.planners.td3 import load_checkpoint, load_numpy_policy, shipped_policy_path

    policy = load_numpy_policy(shipped_policy_path(planner))
    training = policy.metadata["training"]
    zip_path = ROOT / "tools" / "rl" / "policies" / f"{STEMS[planner]}.zip"
    sha = hashlib.sha256(zip_path.read_bytes()).hexdigest()
    if sha != training["source_sha256"]:
        raise SystemExit(f"{zip_path} is not the checkpoint {planner} was exported from")
    backend = training["backend"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # our own checkpoint: trusted
        load_checkpoint(zip_path)  # the library is installed and the file is a TD3 policy
        lib = __import__("sbx" if backend == "sbx" else "stable_baselines3")
        model = lib.TD3.load(zip_path, device="cpu")
    kinds = random_observations(policy.actor.obs_size)
    for scenario in SCENARIOS:
        kinds[scenario] = episode_observations(policy.actor, policy.config, scenario, PER_SCENARIO)
    diffs = {}
    for kind, obs in kinds.items():
        theirs, _ = model.predict(obs, deterministic=True)
        mine = np.stack([policy.actor.forward(o) for o in obs])
        diffs[kind] = {
            "observations": len(obs),
            "max_abs_diff": float(np.abs(mine - np.asarray(theirs)).max()),
        }
    return {
        "checkpoint": str(zip_path.relative_to(ROOT)),
        "backend": backend,
        "observations": sum(d["observations"] for d in diffs.values()),
        "max_abs_diff": max(d["max_abs_diff"] for d in diffs.values()),
        "by_kind": diffs,
    }


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=(__doc__ or "").split("\n\n")[0])
    ap.add_argument("--json", type=Path, help="also write the figures here")
    args = ap.parse_args(argv)
    started, t0, load = start()
    policies = {planner: compare(planner) for planner in STEMS}
    for planner, found in policies.items():
        print(
            f"{planner}: {found['backend']} checkpoint, {found['observations']} observations, "
            f"largest difference {found['max_abs_diff']:.2g}"
        )
    if args.json is not None:
        doc = {
            "uniform": UNIFORM,
            "sparse": SPARSE,
            "per_scenario": PER_SCENARIO,
            "scenarios": list(SCENARIOS),
            "policies": policies,
            "run": run_record(started, t0, load),
        }
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(doc, indent=1) + "\n", encoding="utf-8")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
