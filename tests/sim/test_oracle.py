"""The ``oracle`` reference planner and what it stands on: the engine's look-ahead copy
and the prefix Fréchet programme."""

from __future__ import annotations

import numpy as np
import pytest

import srfm
from srfm.errors import ParameterError, PlannerError, SimulationError
from srfm.metrics.episode import episode_metrics
from srfm.metrics.frechet import frechet_distances
from srfm.planners import PlannerContext
from srfm.scenarios import episode_setup, load_scenario
from srfm.sim import OracleConfig, OraclePlanner
from srfm.sim._oracle_kernels import extend_prefix_frechet, prefix_frechet_mean
from srfm.sim.engine import EpisodeEngine
from srfm.sim.record import EpisodeRecord


def _same(a: EpisodeRecord, b: EpisodeRecord) -> None:
    for name in ("factual_pos", "counterfactual_pos", "robot_pose", "robot_cmd"):
        assert np.array_equal(getattr(a, name), getattr(b, name), equal_nan=True), name
    assert (a.outcome, a.end_step) == (b.outcome, b.end_step)


def test_oracle_reaches_its_goal_below_straight_and_is_deterministic() -> None:
    for seed in (0, 1):
        oracle = srfm.run_episode("cross_footpath", seed, planner="oracle")
        straight = srfm.run_episode("cross_footpath", seed, planner="straight")
        assert oracle.outcome == "goal_reached"
        dev_o = episode_metrics(oracle).values["frechet_m"]
        dev_s = episode_metrics(straight).values["frechet_m"]
        assert dev_o <= dev_s  # straight is one of its plans, scored exactly
        assert dev_o < dev_s - 0.1  # and it finds a much gentler one here
    again = srfm.run_episode("cross_footpath", 1, planner="oracle")
    _same(oracle, again)


class _Replay:
    """Plays given commands: the oracle's episode without the oracle."""

    name = "replay"
    detection_range_m = 0.0

    def __init__(self, commands: np.ndarray) -> None:
        self.commands = commands

    def reset(self, context: PlannerContext, rng: np.random.Generator) -> None:
        pass

    def act(self, observation: srfm.planners.Observation) -> np.ndarray:
        return self.commands[observation.step]


def test_the_oracles_look_ahead_leaves_the_episode_alone() -> None:
    oracle = srfm.run_episode("crosswalk", 2, planner="oracle")
    replayed = srfm.run_episode("crosswalk", 2, planner=_Replay(oracle.robot_cmd))
    _same(oracle, replayed)


def test_look_ahead_engine_follows_the_episode_with_routes() -> None:
    setup = episode_setup(load_scenario("intersection"), 4)
    engine = EpisodeEngine(setup)
    for _ in range(40):
        engine.advance(0.4, 0.3)
    copy = engine.look_ahead(counterfactual=True)
    assert copy.step_index == engine.step_index
    for k in range(60):
        engine.advance(0.5, -0.2 if k % 2 else 0.1)
        copy.advance(0.5, -0.2 if k % 2 else 0.1)
    for twin in (0, 1):
        assert np.array_equal(engine.crowd(twin).pos, copy.crowd(twin).pos)
        assert np.array_equal(engine.crowd(twin).goal, copy.crowd(twin).goal)
    assert np.array_equal(engine.robot, copy.robot)
    assert engine.outcome == copy.outcome
    other = EpisodeEngine(episode_setup(load_scenario("intersection"), 5))
    with pytest.raises(SimulationError, match="same episode set-up"):
        other.copy_from(engine)


def test_prefix_frechet_programme() -> None:
    rng = np.random.default_rng(3)
    steps, n = 40, 3
    f = np.cumsum(rng.normal(size=(steps + 1, n, 2)), axis=0)
    c = np.cumsum(rng.normal(size=(steps + 1, n, 2)), axis=0)
    c_path = np.ascontiguousarray(c.transpose(1, 0, 2))
    table = np.full((n, steps + 1), np.inf)
    previous = 0.0
    for t in range(steps + 1):
        extend_prefix_frechet(table, np.ascontiguousarray(f[t]), c_path, t, steps)
        now = prefix_frechet_mean(table, t, steps)
        assert now >= previous  # the prefix deviation never decreases
        previous = now
    # with no band the last cell is the metric itself
    np.testing.assert_allclose(table[:, steps], frechet_distances(f, c), rtol=1e-12)
    # the prefix deviation of a curve against itself is zero
    same = np.full((n, steps + 1), np.inf)
    for t in range(steps + 1):
        extend_prefix_frechet(same, np.ascontiguousarray(c[t]), c_path, t, 5)
    assert prefix_frechet_mean(same, steps, 5) == 0.0


def test_oracle_misuse() -> None:
    planner = OraclePlanner()
    with pytest.raises(PlannerError, match="reads the episode's engine"):
        planner.act(None)  # type: ignore[arg-type]
    with pytest.raises(ParameterError, match="score_every"):
        OracleConfig(score_every=0)
    with pytest.raises(ParameterError, match="waits_s"):
        OracleConfig(waits_s=(-1.0,))
    with pytest.raises(ParameterError, match="band_s"):
        OracleConfig(band_s=0.0)
