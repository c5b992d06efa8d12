"""The random streams of an episode: every key in one list.

An episode's randomness is keyed by its seed alone; there is no global random state. Each
consumer draws from a stream of its own, derived from the seed and the consumer's key, so
that draws added to one stream never shift another's: the same seed gives the same
pedestrians whatever the planner draws, and a scenario with entering pedestrians draws
its set-up exactly as the same scenario without them.

- **set-up** (no key), ``default_rng(seed)``: the episode's set-up
  (:func:`srfm.scenarios.episode_setup`): a fixed scenario's offsets of the starts,
  waypoints and goals, then its speed noise; the random scenario's robot and
  pedestrian starts and goals.
- ``PLANNER_STREAM`` = 1, ``SeedSequence(seed, spawn_key=(1,))``: the generator handed
  to the planner's ``reset`` (:func:`planner_rng`; :func:`srfm.run_episode`).
- ``REGOAL_STREAM`` = 2, ``SeedSequence(seed, spawn_key=(2, i, k))``: the k-th new goal
  of pedestrian i of the random scenario (:func:`srfm.scenarios.next_goal`), so that
  both twins draw the same goals.
- ``ENTRY_STREAM`` = 3, ``SeedSequence(seed, spawn_key=(3,))``: the entry times of
  entering pedestrians (:func:`srfm.scenarios.entry_times`).
- ``SOURCE_GOAL_STREAM`` = 4, ``SeedSequence(seed, spawn_key=(4,))``: the goals of a
  source's members in its ``goal_region`` (:func:`srfm.scenarios.source_goals`).
- ``POOL_STREAM`` = 5, ``SeedSequence(seed, spawn_key=(5,))``: which scenario of a
  training pool episode ``seed`` runs (:func:`srfm.scenarios.training.pool_scenario`).
- ``GENERATED_STREAM`` = 6, ``SeedSequence(seed, spawn_key=(6,))``: the generated walled
  layout of seed ``seed`` (:func:`srfm.scenarios.generated.generated_scenario`).
- ``TRAINING_STREAM`` = 7, ``default_rng((seed, 7))``: the RL training layouts
  (:func:`srfm.scenarios.training.training_layout`); here 7 is the second word of the
  generator's entropy, not a spawn key.

A new stream takes a new key here (8 is free). The values are part of the results:
changing one changes every episode that draws from that stream.
"""

from __future__ import annotations

from typing import Final

import numpy as np

__all__ = [
    "ENTRY_STREAM",
    "GENERATED_STREAM",
    "PLANNER_STREAM",
    "POOL_STREAM",
    "REGOAL_STREAM",
    "SOURCE_GOAL_STREAM",
    "TRAINING_STREAM",
    "entry_rng",
    "generated_rng",
    "planner_rng",
    "pool_rng",
    "regoal_rng",
    "setup_rng",
    "source_goal_rng",
    "training_rng",
]

PLANNER_STREAM: Final = 1
REGOAL_STREAM: Final = 2
ENTRY_STREAM: Final = 3
SOURCE_GOAL_STREAM: Final = 4
POOL_STREAM: Final = 5
GENERATED_STREAM: Final = 6
TRAINING_STREAM: Final = 7


def _spawned(seed: int, *key: int) -> np.random.Generator:
    return np.random.default_rng(np.random.SeedSequence(seed, spawn_key=key))


def setup_rng(seed: int) -> np.random.Generator:
    """The set-up stream of episode ``seed``."""
    return np.random.default_rng(seed)


def planner_rng(seed: int) -> np.random.Generator:
    """The planner's own generator for episode ``seed``."""
    return _spawned(seed, PLANNER_STREAM)


def regoal_rng(seed: int, ped: int, k: int) -> np.random.Generator:
    """The stream of the k-th new goal (k = 1, 2, ...) of pedestrian ``ped``."""
    return _spawned(seed, REGOAL_STREAM, ped, k)


def entry_rng(seed: int) -> np.random.Generator:
    """The stream of the entry times of episode ``seed``."""
    return _spawned(seed, ENTRY_STREAM)


def source_goal_rng(seed: int) -> np.random.Generator:
    """The stream of the goals drawn in the sources' goal regions of episode ``seed``."""
    return _spawned(seed, SOURCE_GOAL_STREAM)


def pool_rng(seed: int) -> np.random.Generator:
    """The stream that picks the scenario of training episode ``seed`` from a pool."""
    return _spawned(seed, POOL_STREAM)


def generated_rng(seed: int) -> np.random.Generator:
    """The stream of generated walled layout ``seed``."""
    return _spawned(seed, GENERATED_STREAM)


def training_rng(seed: int) -> np.random.Generator:
    """The stream of training layout ``seed``."""
    return np.random.default_rng((seed, TRAINING_STREAM))
