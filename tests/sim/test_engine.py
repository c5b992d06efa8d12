"""The episode engine on its own: what the simulator and the environment both drive."""

from __future__ import annotations

import pickle

import numpy as np
import pytest

import srfm
from srfm.scenarios import episode_setup, load_scenario
from srfm.sim.engine import EpisodeEngine


def _commands(n: int) -> np.ndarray:
    rng = np.random.default_rng(3)
    out = rng.uniform([0.0, -1.0], [0.5, 1.0], (n, 2))
    return out


def _state(engine: EpisodeEngine) -> tuple[bytes, ...]:
    return (
        engine.factual.pos.tobytes(),
        engine.factual.vel.tobytes(),
        engine.factual.goal.tobytes(),
        engine.counterfactual.pos.tobytes(),
        engine.counterfactual.goal.tobytes(),
        engine.robot.tobytes(),
        repr((engine.n_present, engine.robot_active, engine.outcome, engine.end_step)).encode(),
    )


@pytest.mark.parametrize("name", ["crosswalk", "random", "corridor_flow", "blind_corner"])
def test_the_simulator_is_the_engine_with_a_planner_view(name: str) -> None:
    setup = episode_setup(load_scenario(name), 1)
    engine = EpisodeEngine(setup)
    sim = srfm.TwinSimulator(setup)
    for c0, c1 in _commands(200):
        events = engine.advance(c0, c1) if engine.robot_active else engine.advance()
        assert sim.step((c0, c1) if sim.robot_active else None) == events
        assert _state(sim.engine) == _state(engine)
        assert sim.robot == engine.robot_state


@pytest.mark.parametrize("name", ["random", "corridor_flow"])
def test_an_engine_pickled_mid_episode_goes_on_bit_for_bit(name: str) -> None:
    # corridor_flow: pedestrians enter (the kernels see views of the first rows, which
    # pickle copies); random: re-goaling with the goal cache.
    setup = episode_setup(load_scenario(name), 2)
    engine = EpisodeEngine(setup)
    commands = _commands(300)
    for c0, c1 in commands[:150]:
        engine.advance(c0, c1) if engine.robot_active else engine.advance()
    copy = pickle.loads(pickle.dumps(engine))
    for c0, c1 in commands[150:]:
        a = engine.advance(c0, c1) if engine.robot_active else engine.advance()
        b = copy.advance(c0, c1) if copy.robot_active else copy.advance()
        assert a == b
        assert _state(copy) == _state(engine)
    assert engine.n_present > 0


def test_without_the_counterfactual_crowd_it_stays_at_its_start() -> None:
    setup = episode_setup(load_scenario("crosswalk"), 0)
    full = EpisodeEngine(setup)
    factual_only = EpisodeEngine(setup, counterfactual=False)
    start = factual_only.counterfactual.pos.copy()
    for c0, c1 in _commands(100):
        full.advance(c0, c1)
        factual_only.advance(c0, c1)
    np.testing.assert_array_equal(factual_only.counterfactual.pos, start)
    np.testing.assert_array_equal(factual_only.factual.pos, full.factual.pos)
    assert not np.array_equal(full.counterfactual.pos, start)
