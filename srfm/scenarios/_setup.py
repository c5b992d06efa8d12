"""Per-seed episode set-up: noise on fixed scenarios, draws for the random scenario.

Randomness is explicit and keyed by the seed only, so that a set-up never depends on
what ran before it (the streams and their keys: :mod:`srfm._streams`):

- fixed scenarios: the set-up stream ``numpy.random.default_rng(seed)`` draws one offset
  u ~ U(−noise, noise)² per pedestrian, added to its start, its waypoints and its goal;
  then, when ``speed_noise_mps`` = a > 0 (schema 2), one desired-speed change
  U(−a, a) per pedestrian (the result clipped to [0, max speed]);
- random scenario: the same generator draws the robot start and goal, then each
  pedestrian's start and goal, by rejection sampling under the ``[random]`` constraints;
- entering pedestrians (schema 2, :func:`entry_times`, and the goals of sources with a
  ``goal_region``, :func:`source_goals`): from their own streams (``ENTRY_STREAM``
  and ``SOURCE_GOAL_STREAM``), so that the draws above are those of a
  scenario without entries; the episode's pedestrians are then ordered by entry
  (those there at the start first, in the scenario's order), so that the ones present
  at any sample are always the first ones (:attr:`EpisodeSetup.ped_order`);
- re-goaling: the k-th new goal of pedestrian i comes from its own stream
  (``REGOAL_STREAM``, keyed by (i, k) too) and must lie at least
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

from srfm import _streams, _validate
from srfm.errors import ScenarioError
from srfm.models.state import CrowdState
from srfm.scenarios._schema import RandomSpec, Scenario
from srfm.world import WorldBounds

__all__ = [
    "EpisodeSetup",
    "entry_steps",
    "entry_times",
    "episode_setup",
    "next_goal",
    "source_goals",
    "validate_seed",
]

MAX_DRAWS: Final = 10_000

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
    # Seconds each pedestrian waits at each of those waypoints (None: no waits).
    ped_waits_s: tuple[FloatArray, ...] | None = None
    # The standing pedestrians (goal = start).
    ped_standing: tuple[int, ...] = ()
    # Entering pedestrians: the sample at which each one appears, in increasing order
    # (0: there at the start), and the scenario's index of each episode pedestrian;
    # both None when everyone is there from the start (the scenario's order).
    ped_enter_step: NDArray[np.int64] | None = None
    ped_order: NDArray[np.intp] | None = None

    def n_present(self, sample: int) -> int:
        """How many pedestrians are there at ``sample``: always the first ones."""
        if self.ped_enter_step is None:
            return self.crowd.n
        return int(np.searchsorted(self.ped_enter_step, sample, side="right"))


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


def entry_times(scenario: Scenario, seed: int) -> FloatArray | None:
    """Each pedestrian's entry time (s) in episode ``seed``, in the scenario's order;
    None when everyone is there from the start.

    - a pedestrian with a given ``enter_s`` t > 0 (one draw per group) enters at
      t + u, u ~ U(−a, a) with a = ``enter_noise_s``, clipped to [dt, horizon − dt];
    - the ``count`` members of a source enter at ``start_s`` + the sorted draws of
      ``count`` uniforms on [0, W − (count − 1) h], the k-th (from 0) plus k h, where
      W = count / rate_per_s and h = ``headway_s``: the arrival times of a Poisson
      stream of that rate given ``count`` arrivals in W, at least h apart; clipped
      to [dt, horizon − dt] like the given times.

    Draws come from the entry stream (:func:`srfm._streams.entry_rng`): the given
    times first (in the scenario's order), then each source.
    """
    if scenario.ped_enter_s is None:
        return None
    rng = _streams.entry_rng(seed)
    times = np.array(scenario.ped_enter_s, dtype=np.float64)
    dt = scenario.dt_s
    latest = (scenario.horizon_steps - 1) * dt
    in_source = np.zeros(times.shape[0], dtype=bool)
    for source in scenario.ped_sources:
        in_source[source.first : source.first + source.count] = True
    entering = (times > 0.0) | in_source
    noise = scenario.ped_enter_noise_s
    if noise > 0.0:
        group_of = {i: g for g, members in enumerate(scenario.ped_groups) for i in members}
        drawn: dict[int, float] = {}
        for i in np.flatnonzero((times > 0.0) & ~in_source):
            key = -1 - group_of[int(i)] if int(i) in group_of else int(i)
            if key not in drawn:
                drawn[key] = float(rng.uniform(-noise, noise))
            times[i] += drawn[key]
    for source in scenario.ped_sources:
        h = source.headway_s
        span = source.window_s - (source.count - 1) * h
        offsets = np.sort(rng.uniform(0.0, span, size=source.count))
        stop = source.first + source.count
        times[source.first : stop] = source.start_s + offsets + h * np.arange(source.count)
    times[entering] = np.clip(times[entering], dt, latest)
    return times


def source_goals(scenario: Scenario, seed: int, goals: FloatArray) -> None:
    """Give each member of a source with a ``goal_region`` its goal in episode ``seed``:
    uniform in the region, from the stream :func:`srfm._streams.source_goal_rng` (one
    x and one y per member, source after source); ``goals`` (N, 2) in the scenario's
    order is written in place (no per-seed ``noise_m`` offset on these)."""
    boxed = [s for s in scenario.ped_sources if s.goal_box is not None]
    if not boxed:
        return
    rng = _streams.source_goal_rng(seed)
    for source in boxed:
        assert source.goal_box is not None
        x0, y0, x1, y1 = source.goal_box
        stop = source.first + source.count
        goals[source.first : stop, 0] = rng.uniform(x0, x1, size=source.count)
        goals[source.first : stop, 1] = rng.uniform(y0, y1, size=source.count)


def entry_steps(scenario: Scenario, times: FloatArray) -> NDArray[np.int64]:
    """The sample at which each pedestrian appears: 0 for those there at the start,
    else round(t / dt) kept in [1, horizon − 1]."""
    steps = np.rint(times / scenario.dt_s).astype(np.int64)
    entering = times > 0.0
    steps[entering] = np.clip(steps[entering], 1, max(1, scenario.horizon_steps - 1))
    return steps


def episode_setup(scenario: Scenario, seed: int) -> EpisodeSetup:
    """Make the set-up of episode ``seed`` of ``scenario``: the pedestrians and the robot
    of that episode before its first step, drawn from the seed's own random stream.

    Args:
        scenario: the scenario.
        seed: the episode seed, in [0, 2^32 - 1].

    Returns:
        The robot's start and goal (m) and heading (rad); the crowd (positions and goals
        in m, speeds in m/s, radii in m) after the per-seed noise; waypoints (m), waits
        (s) and entry steps where the scenario has them.
    """
    seed = validate_seed(seed)
    rng = _streams.setup_rng(seed)
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
        source_goals(scenario, seed, goals)
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
    radius: FloatArray | float = scenario.ped_radius_m
    vmax_: FloatArray | float = scenario.ped_max_speed_mps
    waits = scenario.ped_waits_s
    standing = scenario.ped_standing
    times = entry_times(scenario, seed)
    enter_step: NDArray[np.int64] | None = None
    order: NDArray[np.intp] | None = None
    if times is not None:
        # Order by entry (stable: the scenario's order among equal samples).
        steps = entry_steps(scenario, times)
        order = np.argsort(steps, kind="stable")
        enter_step = steps[order]
        starts = starts[order]
        goals = goals[order]
        if isinstance(v0, np.ndarray):
            v0 = v0[order]
        if isinstance(radius, np.ndarray):
            radius = radius[order]
        if isinstance(vmax_, np.ndarray):
            vmax_ = vmax_[order]
        if routes is not None:
            routes = tuple(routes[i] for i in order)
        if waits is not None:
            waits = tuple(waits[i] for i in order)
        place = np.empty_like(order)
        place[order] = np.arange(order.shape[0])
        standing = tuple(sorted(int(place[i]) for i in standing))
        for arr in (enter_step, order):
            arr.setflags(write=False)
    crowd = CrowdState.create(
        pos=starts,
        goal=goals,
        radius=radius,
        v0=v0,
        vmax=vmax_,
    )
    return EpisodeSetup(
        scenario=scenario,
        seed=seed,
        robot_start=robot_start,
        robot_goal=robot_goal,
        robot_heading_rad=heading,
        crowd=crowd,
        ped_routes=routes,
        ped_waits_s=waits,
        ped_standing=standing,
        ped_enter_step=enter_step,
        ped_order=order,
    )


def next_goal(setup: EpisodeSetup, ped: int, k: int, previous_goal: FloatArray) -> FloatArray:
    """The k-th replacement goal (k = 1, 2, ...) of pedestrian ``ped``; see the module doc."""
    scenario = setup.scenario
    if scenario.random is None:
        raise ScenarioError(f"{scenario.source}: only random scenarios re-goal pedestrians")
    spec = scenario.random
    return _draw(
        _streams.regoal_rng(setup.seed, ped, k),
        scenario.world,
        spec.margin_m,
        [
            (previous_goal, spec.ped_min_start_goal_m),
            (setup.robot_goal, spec.ped_min_robot_goal_m),
        ],
        f"a new goal for pedestrian {ped}",
        scenario.source,
    )
