"""The mixed training layouts (srfm.scenarios.training)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from srfm.errors import ScenarioError
from srfm.scenarios import EVALUATION_SCENARIOS, episode_setup, load_scenario
from srfm.scenarios.training import TRAINING_FAMILIES, training_layout

BASE = load_scenario("random")


def test_same_seed_same_layout_and_every_family_drawn() -> None:
    seen = set()
    for seed in range(200):
        a = episode_setup(training_layout(BASE, seed), seed)
        b = episode_setup(training_layout(BASE, seed), seed)
        assert a.scenario.name == b.scenario.name
        assert np.array_equal(a.crowd.pos, b.crowd.pos)
        assert np.array_equal(a.crowd.goal, b.crowd.goal)
        assert np.array_equal(a.robot_start, b.robot_start)
        assert a.robot_heading_rad == b.robot_heading_rad
        seen.add(a.scenario.name)
    assert seen == {f"mixed/{f}" for f in TRAINING_FAMILIES}


@pytest.mark.parametrize("family", TRAINING_FAMILIES)
def test_layout_rules(family: str) -> None:
    w = BASE.world
    for seed in range(60):
        layout = training_layout(BASE, seed, family)
        assert layout.name == f"mixed/{family}"
        assert layout.world == BASE.world
        assert layout.robot == BASE.robot
        setup = episode_setup(layout, seed)
        pos = setup.crowd.pos
        assert pos.shape[0] >= 1
        assert np.all(pos[:, 0] >= w.x_min)
        assert np.all(pos[:, 0] <= w.x_max)
        assert np.all(pos[:, 1] >= w.y_min)
        assert np.all(pos[:, 1] <= w.y_max)
        length = math.dist(setup.robot_start, setup.robot_goal)
        assert length >= 5.99
        if family == "walkers":
            continue
        assert length <= 13.01
        gaps = np.linalg.norm(pos[:, None] - pos[None], axis=-1) + np.eye(len(pos)) * 99
        assert gaps.min() >= 0.7 - 1e-9
        assert np.linalg.norm(pos - setup.robot_start, axis=1).min() >= 1.0 - 1e-9
        bearing = math.atan2(*(setup.robot_goal - setup.robot_start)[::-1])
        off = math.remainder(setup.robot_heading_rad - bearing, 2 * math.pi)
        assert abs(off) <= math.pi / 4 + 1e-9
        speeds = np.asarray(setup.crowd.v0)
        assert np.all((speeds >= 0.8) & (speeds <= 1.5))
        if family == "standing":
            standing = np.all(setup.crowd.goal == pos, axis=1)
            assert standing.sum() >= 1
            near_goal = np.linalg.norm(pos[standing] - setup.robot_goal, axis=1)
            assert near_goal.min() >= 1.0 - 1e-9


def test_no_layout_is_an_evaluation_scenario() -> None:
    """Training never sees the exact layouts of the five evaluation scenarios."""
    evaluation = [load_scenario(name) for name in EVALUATION_SCENARIOS]
    for seed in range(300):
        setup = episode_setup(training_layout(BASE, seed), seed)
        for scenario in evaluation:
            assert scenario.robot_start is not None
            same_robot = np.allclose(setup.robot_start, scenario.robot_start, atol=0.05)
            same_goal = np.allclose(setup.robot_goal, scenario.robot_goal, atol=0.05)
            assert not (same_robot and same_goal)


def test_bad_family_and_seed() -> None:
    with pytest.raises(ScenarioError, match="'corridor'"):
        training_layout(BASE, 0, "corridor")
    with pytest.raises(ScenarioError):
        training_layout(BASE, -1)


def test_family_weights_change_the_mix_and_none_keeps_the_uniform_draw() -> None:
    from collections import Counter

    from srfm.scenarios.training import family_weights

    seeds = range(400)
    uniform = [training_layout(BASE, s).name for s in seeds]
    # None is the uniform draw of earlier versions, layout for layout
    assert uniform == [training_layout(BASE, s, weights=None).name for s in seeds]
    weighted = Counter(training_layout(BASE, s, weights=(1, 1, 1, 6, 1)).name for s in seeds)
    assert weighted["mixed/standing"] > 0.5 * len(seeds)  # expected 0.6
    assert Counter(uniform)["mixed/standing"] < 0.3 * len(seeds)  # expected 0.2
    only = {training_layout(BASE, s, weights=(0, 0, 0, 2.5, 0)).name for s in range(50)}
    assert only == {"mixed/standing"}
    # the same seed and weights give the same layout
    a = episode_setup(training_layout(BASE, 7, weights=(1, 1, 1, 6, 1)), 7)
    b = episode_setup(training_layout(BASE, 7, weights=(1, 1, 1, 6, 1)), 7)
    assert np.array_equal(a.crowd.pos, b.crowd.pos)
    assert family_weights(None) is None
    assert family_weights([1, 2, 3, 4, 5]) == (1.0, 2.0, 3.0, 4.0, 5.0)


@pytest.mark.parametrize(
    ("weights", "message"),
    [
        ((1, 1, 1, 1), "need 5 values"),
        ((1, 1, 1, -1, 1), "'standing' must be finite and >= 0, got -1.0"),
        ((1, 1, math.nan, 1, 1), "'crossing' must be finite"),
        ((0, 0, 0, 0, 0), "must not all be 0"),
        ("11131", "sequence of numbers"),
        ((1, 1, "x", 1, 1), "must be numbers"),
    ],
)
def test_bad_family_weights(weights: object, message: str) -> None:
    with pytest.raises(ScenarioError, match=message):
        training_layout(BASE, 0, weights=weights)  # type: ignore[arg-type]
