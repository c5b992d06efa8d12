"""tools/rl/reward_stats.py: the figures docs/rl.md quotes for the deviation term are
deterministic for a seed and are what its definition says."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from srfm.rl.env import SocialNavEnv
from tools.rl import reward_stats


def test_reward_stats_are_the_steps_r_div(tmp_path: Path) -> None:
    figures = reward_stats.measure(300, 3)
    assert figures == reward_stats.measure(300, 3)  # bit for bit
    env = SocialNavEnv("random")
    env.action_space.seed(3)
    env.reset(seed=3)
    values = []
    for _ in range(300):
        _, _, terminated, truncated, info = env.step(env.action_space.sample())
        values.append(info["r_div"])
        if terminated or truncated:
            env.reset()
    assert figures["nonzero_share"] == float(np.mean(np.array(values) > 0))
    assert figures["mean_m"] == float(np.mean(values))
    assert figures["p99_m"] == float(np.percentile(values, 99))
    out = tmp_path / "stats.json"
    assert reward_stats.main(["--steps", "50", "--json", str(out)]) == 0
    doc = json.loads(out.read_text(encoding="utf-8"))
    assert doc["steps"] == 50
    assert doc["command"].endswith(f"--json {out}")
