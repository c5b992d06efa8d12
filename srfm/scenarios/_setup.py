"""Per-seed episode set-up: noise on fixed scenarios, draws for the random scenario.

Randomness is explicit and keyed by the seed only, so that a set-up never depends on
what ran before it:

- fixed scenarios: ``numpy.random.default_rng(seed)`` draws one offset
  u ~ U(−noise, noise)² per pedestrian, added to its start, its waypoints and its goal;
  then, when ``speed_noise_mps`` = a > 0 (schema 2), one desired-speed change
  U(−a, a) per pedestrian (the result clipped to [0, max speed]);
- random scenario: the same generator draws the robot start and goal, then each
  pedestrian's start and goal, by rejection sampling under the ``[random]`` constraints;
- re-goaling: the k-th new goal of pedestrian i comes from its own stream
  ``SeedSequence(seed, spawn_key=(2, i, k))`` and must lie at least
  ``ped_min_start_goal_m`` from the goal just reached (where the pedestrian stands)
  and ``ped_min_robot_goal_m`` from the robot's goal. Because it depends on (seed, i, k)
  and the previous goal only, both twins draw the same goal sequence.
"""

from __future__ import annotations

import math
from typing import Any, Final

import attrs
import numpy as np
from numpy.typing import NDArray

from srfm import _validate
from srfm.errors import ScenarioError
from srfm.models.state import CrowdState
from srfm.scenarios._schema import RandomSpec, Scenario, WorldBounds

__all__ = ["EpisodeSetup", "episode_setup", "next_goal", "validate_seed"]

MAX_DRAWS: Final = 10_000
_REGOAL_STREAM: Final = 2

FloatArray = NDArray[np.float64]


@attrs.frozen(kw_only=True, eq=False)
class EpisodeSetup:
    """The concrete start of one episode: a scenario and a seed made into numbers."""

    scenario: Scenario
    seed: int
    robot_start: FloatArray
    robot_goal: FloatArray
    robot_heading_rad: float
    crowd: CrowdState
    # Scenario-given waypoints of each pedestrian, before its goal, moved by the
    # pedestrian's per-seed offset (None when the scenario gives none).
    ped_routes: tuple[FloatArray, ...] | None = None


def validate_seed(seed: Any) -> int:
    """A seed is an integer in [0, 2³² − 1] (:data:`srfm._validate.MAX_SEED`)."""
    return _validate.seed(seed, ScenarioError)


def _uniform_point(rng: np.random.Generator, world: WorldBounds, margin: float) -> FloatArray:
    return np.array(
        [
            rng.uniform(world.x_min + margin, world.x_max - margin),
            rng.uniform(world.y_min + margin, world.y_max - margin),
        ]
    )


def _draw(
    rng: np.random.Generator,
    world: WorldBounds,
    margin: float,
    constraints: list[tuple[FloatArray, float]],
    what: str,
    source: str,
) -> FloatArray:
    """A uniform point at least the given distance from each given point."""
    for _ in range(MAX_DRAWS):
        p = _uniform_point(rng, world, margin)
        if all(math.dist(p, q) >= d for q, d in constraints):
            return p
    raise ScenarioError(
        f"{source}: could not draw {what} within {MAX_DRAWS} tries; "
        "the [random] distance constraints do not fit in the world"
    )


def episode_setup(scenario: Scenario, seed: int) -> EpisodeSetup:
    """Make the set-up of episode ``seed`` of ``scenario``."""
    seed = validate_seed(seed)
    rng = np.random.default_rng(seed)
    routes: tuple[FloatArray, ...] | None = None
    if scenario.random is not None:
        spec: RandomSpec = scenario.random
        m = spec.margin_m
        src = scenario.source
        robot_start = _draw(rng, scenario.world, m, [], "the robot start", src)
        robot_goal = _draw(
            rng,
            scenario.world,
            m,
            [(robot_start, spec.robot_min_start_goal_m)],
            "the robot goal",
            src,
        )
        starts = np.zeros((spec.count, 2))
        goals = np.zeros((spec.count, 2))
        for i in range(spec.count):
            starts[i] = _draw(
                rng,
                scenario.world,
                m,
                [(robot_start, spec.ped_min_robot_start_m)],
                f"the start of pedestrian {i}",
                src,
            )
            goals[i] = _draw(
                rng,
                scenario.world,
                m,
                [(starts[i], spec.ped_min_start_goal_m), (robot_goal, spec.ped_min_robot_goal_m)],
                f"the goal of pedestrian {i}",
                src,
            )
    else:
        if (
            scenario.ped_starts is None
            or scenario.ped_goals is None
            or scenario.robot_start is None
            or scenario.robot_goal is None
        ):
            raise ScenarioError(f"{scenario.source}: a fixed scenario needs starts and goals")
        n = scenario.ped_starts.shape[0]
        offsets = rng.uniform(-scenario.noise_m, scenario.noise_m, size=(n, 2))
        starts = scenario.ped_starts + offsets
        goals = scenario.ped_goals + offsets
        if scenario.ped_routes is not None:
            routes = tuple(r + offsets[i] for i, r in enumerate(scenario.ped_routes))
        robot_start = scenario.robot_start.copy()
        robot_goal = scenario.robot_goal.copy()
    if scenario.robot_heading_rad is not None:
        heading = scenario.robot_heading_rad
    else:
        heading = math.atan2(robot_goal[1] - robot_start[1], robot_goal[0] - robot_start[0])
    v0: FloatArray | float = scenario.ped_desired_speed_mps
    if scenario.ped_speed_noise_mps > 0.0:
        # after every draw above, so that version-1 set-ups are unchanged
        n = starts.shape[0]
        a = scenario.ped_speed_noise_mps
        vmax = np.broadcast_to(np.asarray(scenario.ped_max_speed_mps, dtype=np.float64), (n,))
        v0 = np.clip(np.asarray(v0, dtype=np.float64) + rng.uniform(-a, a, size=n), 0.0, vmax)
    crowd = CrowdState.create(
        pos=starts,
        goal=goals,
        radius=scenario.ped_radius_m,
        v0=v0,
        vmax=scenario.ped_max_speed_mps,
    )
    return EpisodeSetup(
        scenario=scenario,
        seed=seed,
        robot_start=robot_start,
        robot_goal=robot_goal,
        robot_heading_rad=heading,
        crowd=crowd,
        ped_routes=routes,
    )


def next_goal(setup: EpisodeSetup, ped: int, k: int, previous_goal: FloatArray) -> FloatArray:
    """The k-th replacement goal (k = 1, 2, ...) of pedestrian ``ped``; see the module doc."""
    scenario = setup.scenario
    if scenario.random is None:
        raise ScenarioError(f"{scenario.source}: only random scenarios re-goal pedestrians")
    spec = scenario.random
    seq = np.random.SeedSequence(setup.seed, spawn_key=(_REGOAL_STREAM, ped, k))
    rng = np.random.default_rng(seq)
    return _draw(
        rng,
        scenario.world,
        spec.margin_m,
        [
            (previous_goal, spec.ped_min_start_goal_m),
            (setup.robot_goal, spec.ped_min_robot_goal_m),
        ],
        f"a new goal for pedestrian {ped}",
        scenario.source,
    )
