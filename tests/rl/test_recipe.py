"""The training recipe's parts: the mixed environment, the progress term, the k2
curriculum."""

from __future__ import annotations

import math

import numpy as np
import pytest

from srfm.errors import ParameterError
from srfm.rl import EnvConfig
from srfm.rl.env import SocialNavEnv
from srfm.rl.training import TrainConfig, k2_schedule


def _run(env: SocialNavEnv, seed: int, policy: str = "forward") -> list[tuple[float, dict]]:
    env.reset(seed=seed)
    rng = np.random.default_rng(seed)
    out = []
    done = False
    while not done:
        if policy == "forward":
            action = np.array([1.0, 0.1], dtype=np.float32)
        else:
            action = rng.uniform(-1, 1, 2).astype(np.float32)
        _, reward, terminated, truncated, info = env.step(action)
        out.append((reward, info))
        done = terminated or truncated
    return out


def test_mixed_env_draws_layouts_and_is_reproducible() -> None:
    env = SocialNavEnv("mixed", EnvConfig(counterfactual_twin=False))
    names = set()
    counts = set()
    for seed in range(30):
        env.reset(seed=seed)
        names.add(env.layout.name)
        counts.add(env.factual_pos.shape[0])
    assert len(names) == 5
    assert len(counts) > 3
    a = _run(env, 11, "random")
    b = _run(SocialNavEnv("mixed", EnvConfig(counterfactual_twin=False)), 11, "random")
    assert [r for r, _ in a] == [r for r, _ in b]


@pytest.mark.parametrize("repeat", [1, 4])
def test_progress_term_is_potential_based(repeat: int) -> None:
    """Σ γ^t F_t = γ^T Φ(s_T) − Φ(s_0), with Φ = −k d / d_0 and Φ = 0 when terminal,
    and each F_t equals its definition from the robot's positions; t counts actions
    (with action_repeat = 4, 750 steps end in an action of 2 steps)."""
    k, gamma = 7.0, 0.97
    config = EnvConfig(k2=0.0, k_progress=k, progress_gamma=gamma, action_repeat=repeat)
    for seed, policy in ((3, "forward"), (4, "random"), (8, "forward")):
        env = SocialNavEnv("crosswalk", config)
        env.reset(seed=seed)
        goal = env.robot_goal
        d0 = math.dist(env.robot_state.position, goal)
        before = d0
        total = 0.0
        t = 0
        done = False
        rng = np.random.default_rng(seed)
        while not done:
            if policy == "forward":
                action = np.array([1.0, 0.05], dtype=np.float32)
            else:
                action = rng.uniform(-1, 1, 2).astype(np.float32)
            _, _, terminated, truncated, info = env.step(action)
            done = terminated or truncated
            after = math.dist(env.robot_state.position, goal)
            phi_after = 0.0 if terminated else -k * after / d0
            expected = gamma * phi_after - (-k * before / d0)
            assert info["r_progress"] == pytest.approx(expected, rel=1e-12, abs=1e-12)
            total += gamma**t * info["r_progress"]
            t += 1
            before = after
        end = 0.0 if terminated else gamma**t * (-k * before / d0)
        assert total == pytest.approx(end - (-k), abs=1e-9)


def test_paper_reward_unchanged_without_progress_term() -> None:
    plain = SocialNavEnv("footpath", EnvConfig())
    for reward, info in _run(plain, 2, "random"):
        assert info["r_progress"] == 0.0
        assert reward == info["r_term"] - 0.1 * info["r_dist"] - 2.0 * info["r_div"]


def test_set_k2_changes_the_deviation_weight() -> None:
    env = SocialNavEnv("concert", EnvConfig(k2=0.0, counterfactual_twin=False))
    env.set_k2(3.0)
    assert env.k2 == 3.0
    steps = _run(env, 1)
    assert any(info["r_div"] > 0 for _, info in steps)
    for reward, info in steps:
        assert reward == pytest.approx(info["r_term"] - 0.1 * info["r_dist"] - 3.0 * info["r_div"])
    for bad in (-1.0, math.nan, "2"):
        with pytest.raises(ParameterError, match="k2"):
            env.set_k2(bad)  # type: ignore[arg-type]


def test_k2_curriculum() -> None:
    config = TrainConfig(k_div=2.0, k_div_start=100, k_div_ramp=200)
    assert [k2_schedule(config, s) for s in (0, 99, 100, 200, 300, 10_000)] == [
        0.0,
        0.0,
        0.0,
        1.0,
        2.0,
        2.0,
    ]
    assert k2_schedule(TrainConfig(k_div=2.0), 0) == 2.0
    assert k2_schedule(TrainConfig(k_div=2.0, k_div_start=5), 5) == 2.0


def test_action_repeat_sums_the_steps_of_one_action() -> None:
    """An action repeated k times is k simulation steps of the plain environment under
    that action: the same crowd and robot, bit for bit, and the sum of their reward
    terms (the progress term aside: it telescopes, see above)."""
    base = EnvConfig(k2=2.0, counterfactual_twin=False)
    for name, seed in (("circle", 1), ("mixed", 5), ("mixed", 9)):
        one = SocialNavEnv(name, base)
        three = SocialNavEnv(name, base.replace(action_repeat=3))
        one.reset(seed=seed)
        three.reset(seed=seed)
        rng = np.random.default_rng(seed)
        done = False
        actions = 0
        while not done:
            action = rng.uniform(-1, 1, 2).astype(np.float32)
            action[0] = abs(action[0])
            _, reward, terminated, truncated, info = three.step(action)
            done = terminated or truncated
            sums = dict.fromkeys(("reward", "r_dist", "r_div", "r_term"), 0.0)
            for _ in range(3):
                _, r1, t1, u1, i1 = one.step(action)
                sums["reward"] += r1
                for key in ("r_dist", "r_div", "r_term"):
                    sums[key] += i1[key]
                if t1 or u1:
                    assert (t1, u1, i1["outcome"]) == (terminated, truncated, info["outcome"])
                    break
            assert one.step_index == three.step_index
            assert np.array_equal(one.factual_pos, three.factual_pos)
            assert one.robot_state == three.robot_state
            assert reward == pytest.approx(sums["reward"], rel=1e-12, abs=1e-12)
            for key in ("r_dist", "r_div", "r_term"):
                assert info[key] == pytest.approx(sums[key], rel=1e-12, abs=1e-12)
            actions += 1
        assert actions == math.ceil(three.step_index / 3)


def test_action_repeat_is_validated() -> None:
    assert EnvConfig().action_repeat == 1
    for bad in (0, -2, 101, 2.5, True, "3"):
        with pytest.raises(ParameterError, match=r"env\.action_repeat must be an integer"):
            EnvConfig(action_repeat=bad)  # type: ignore[arg-type]
