"""Varied training layouts: one new crowd layout per episode seed (``"mixed"``).

The paper trains on one scenario, ``random``: ten pedestrians walking between random
points. A policy trained there never meets a standing crowd, two streams passing each
other or a ring of people crossing, and the shipped policies of the first release
failed exactly there (docs/rl.md). :func:`training_layout` draws, from an episode seed
alone, one of five layout families with random geometry, density and walking speeds:

- ``walkers``: 4–14 walkers between random points, re-goaled on arrival (the
  ``random`` scenario's rules); the robot's start and goal at least 6 m apart.
- ``streams``: 6–16 walkers in a band 2–6 m wide along a random axis, in both
  directions; the robot walks along the band (half the episodes) or across it.
- ``crossing``: two streams of 3–8 walkers each, crossing at 50°–130°; the robot
  crosses near the crossing point.
- ``standing``: 1–3 groups of 3–8 people standing still (goal = start), on the
  robot's line, plus 0–4 walkers.
- ``circle``: 6–14 walkers on a ring of radius 3.5–6.5 m, each walking to the
  opposite point; the robot crosses the ring, or leaves it from inside.

In the other families than ``walkers`` the robot's start and goal are 6–13 m apart.
Every family uses the world, time step, horizon, robot and pedestrian radius of a base
scenario (``random``: 15 m × 15 m, dt = 1/15 s, 750 steps), so the observation's
scales are those of the evaluation scenarios. Desired speeds are drawn per pedestrian
in [0.8, 1.5] m/s (the evaluation scenarios use 1.25). The robot's start heading is
the goal bearing plus U(−π/4, π/4). Rejection sampling keeps every pedestrian start at
least 0.7 m from the others and 1 m from the robot's start, and standing people 1 m
from the robot's goal; a pedestrian that cannot be placed in 200 draws is left out.

The layouts are drawn from random geometry, never from the coordinates of the five
evaluation scenarios, and the benchmark's episodes are not used: training draws its
episode seeds from its own stream (docs/rl.md, "Training scenarios").

By default each family has probability 1/5; ``weights`` (``srfm train
--family-weights``) draws them in other proportions, for example more ``standing``
layouts for a policy that fails to cross standing crowds (docs/rl.md).

Randomness is keyed by the seed only (the training stream,
:func:`srfm._streams.training_rng`), so a layout never depends on what ran before it.

**Library scenarios in training.** The layouts above have no walls. A policy that is to
go anywhere also trains on built-in library scenarios with walls, doors, rooms, pillars
and entering people: ``SocialNavEnv("mixed", library=LIBRARY_TRAINING,
library_share=p)`` runs a library scenario in a share p of the episodes
(:func:`pool_scenario`, keyed by the episode seed). The library is split once, before
any training (issue 30), and the split is fixed here:

- :data:`LIBRARY_TRAINING`: the scenarios training may use; those of
  :data:`LIBRARY_VALIDATION` (all but ``corridor_flow``, which is reported) also select
  checkpoints, on seeds 10000 on.
- :data:`LIBRARY_HELDOUT`: never used for training, selection or tuning; they are
  reported only (seeds 0-99). Each held-out scenario has a sibling of its kind in
  training (a corridor encounter, a crowd in a corridor, a corner, a door, a room, an
  open crossing, the NavWareSet room), so the held-out set tests generalisation to new
  geometry, not to a kind of scene never seen.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

from srfm._streams import pool_rng, training_rng
from srfm._text import plain
from srfm.errors import ScenarioError
from srfm.scenarios._schema import RandomSpec, Scenario
from srfm.scenarios._setup import validate_seed
from srfm.world import WorldBounds

__all__ = [
    "GENERATED",
    "LIBRARY_HELDOUT",
    "LIBRARY_TRAINING",
    "LIBRARY_VALIDATION",
    "TRAINING_FAMILIES",
    "TRAINING_SCENARIO",
    "family_weights",
    "pool_scenario",
    "training_layout",
]

FloatArray = NDArray[np.float64]

TRAINING_SCENARIO: Final = "mixed"  # the environment's name for these layouts
GENERATED: Final = "generated"  # pool_scenario's answer for a generated walled layout

# The split of the scenario library (the Francis, NavWareSet and flow suites), fixed on
# 2026-11-27 before any policy was trained on it (issue 30; docs/rl.md).
LIBRARY_TRAINING: Final = (
    "frontal_approach",
    "pedestrian_obstruction",
    "robot_overtaking",
    "parallel_traffic",
    "robot_crowding",
    "intersection",
    "intersection_open",
    "narrow_hallway",
    "entering_room",
    "perpendicular_traffic",
    "crowd_navigation",
    "navwareset_frontal_approach",
    "navwareset_obstruction",
    "navwareset_perpendicular_crossing",
    "corridor_flow",
)
"""Library scenarios a policy may train on."""
LIBRARY_HELDOUT: Final = (
    "pedestrian_overtaking",
    "down_path",
    "blind_corner",
    "narrow_doorway",
    "exiting_room",
    "circular_crossing",
    "navwareset_blind_corner",
    "navwareset_circular_crossing",
)
"""Library scenarios never used for training, checkpoint selection or tuning."""
LIBRARY_VALIDATION: Final = tuple(n for n in LIBRARY_TRAINING if n != "corridor_flow")
"""Library scenarios that select checkpoints (on seeds 10000 on; ``corridor_flow`` is
reported, so it does not select)."""
TRAINING_FAMILIES: Final = ("walkers", "streams", "crossing", "standing", "circle")
_MARGIN_M: Final = 0.5  # everything at least this far inside the world
_PED_GAP_M: Final = 0.7  # pedestrian starts at least this far apart (centres)
_ROBOT_GAP_M: Final = 1.0  # pedestrian starts at least this far from the robot start
_ROBOT_MIN_M: Final = 6.0  # robot start-goal distance range (m)
_ROBOT_MAX_M: Final = 13.0
_SPEED_MPS: Final = (0.8, 1.5)  # desired speed range of the pedestrians
_TRIES: Final = 200


class _Layout:
    """Pedestrians placed one by one under the spacing rules."""

    def __init__(
        self, rng: np.random.Generator, world: WorldBounds, start: FloatArray, goal: FloatArray
    ) -> None:
        self.rng = rng
        self.world = world
        self.robot_start = start
        self.robot_goal = goal
        self.starts: list[FloatArray] = []
        self.goals: list[FloatArray] = []

    def inside(self, p: FloatArray) -> bool:
        w = self.world
        m = _MARGIN_M
        return bool(w.x_min + m <= p[0] <= w.x_max - m and w.y_min + m <= p[1] <= w.y_max - m)

    def clip(self, p: FloatArray) -> FloatArray:
        w = self.world
        m = _MARGIN_M
        return np.array(
            [min(max(p[0], w.x_min + m), w.x_max - m), min(max(p[1], w.y_min + m), w.y_max - m)]
        )

    def free(self, p: FloatArray, *, standing: bool) -> bool:
        if not self.inside(p):
            return False
        if math.dist(p, self.robot_start) < _ROBOT_GAP_M:
            return False
        if standing and math.dist(p, self.robot_goal) < _ROBOT_GAP_M:
            return False
        return all(math.dist(p, q) >= _PED_GAP_M for q in self.starts)

    def place(self, draw: Callable[[], tuple[FloatArray, FloatArray]], *, standing: bool) -> None:
        """Add one pedestrian from ``draw() -> (start, goal)``; skipped if no draw fits."""
        for _ in range(_TRIES):
            start, goal = draw()
            if self.free(start, standing=standing):
                self.starts.append(start)
                self.goals.append(start.copy() if standing else self.clip(goal))
                return


def _unit(angle: float) -> FloatArray:
    return np.array([math.cos(angle), math.sin(angle)])


def _robot_line(
    rng: np.random.Generator, world: WorldBounds, through: FloatArray | None
) -> tuple[FloatArray, FloatArray]:
    """A robot start and goal 6–13 m apart inside the world (margin 1 m), passing
    within 1.5 m of ``through`` when given."""
    cx = 0.5 * (world.x_min + world.x_max)
    cy = 0.5 * (world.y_min + world.y_max)
    for _ in range(10 * _TRIES):
        length = rng.uniform(_ROBOT_MIN_M, _ROBOT_MAX_M)
        u = _unit(rng.uniform(-math.pi, math.pi))
        if through is None:
            mid = np.array([cx, cy]) + rng.uniform(-3.5, 3.5, size=2)
        else:
            side = np.array([-u[1], u[0]])
            mid = through + rng.uniform(-1.5, 1.5) * side + rng.uniform(-2.0, 2.0) * u
        start = mid - 0.5 * length * u
        goal = mid + 0.5 * length * u
        if all(
            world.x_min + 1.0 <= p[0] <= world.x_max - 1.0
            and world.y_min + 1.0 <= p[1] <= world.y_max - 1.0
            for p in (start, goal)
        ):
            return start, goal
    raise ScenarioError("training layout: no robot start and goal fit the world")


def _stream(
    lay: _Layout, centre: FloatArray, u: FloatArray, half_width: float, count: int, both: bool
) -> None:
    """``count`` walkers in a band of half-width ``half_width`` around the line
    through ``centre`` along ``u``, walking along it (both directions if ``both``),
    each to the far end of the band inside the world."""
    rng = lay.rng
    side = np.array([-u[1], u[0]])

    def draw() -> tuple[FloatArray, FloatArray]:
        sign = 1.0 if not both or rng.uniform() < 0.5 else -1.0
        lateral = rng.uniform(-half_width, half_width)
        start = centre + rng.uniform(-7.0, 7.0) * u + lateral * side
        goal = centre + sign * 10.0 * u + lateral * side
        return start, goal

    for _ in range(count):
        lay.place(draw, standing=False)


def _walkers(lay: _Layout, count: int) -> None:
    rng = lay.rng
    w = lay.world

    def draw() -> tuple[FloatArray, FloatArray]:
        start = np.array([rng.uniform(w.x_min, w.x_max), rng.uniform(w.y_min, w.y_max)])
        for _ in range(_TRIES):
            goal = np.array([rng.uniform(w.x_min, w.x_max), rng.uniform(w.y_min, w.y_max)])
            if math.dist(start, goal) >= 7.0:
                break
        return start, goal

    for _ in range(count):
        lay.place(draw, standing=False)


def _centre(world: WorldBounds, rng: np.random.Generator, spread: float) -> FloatArray:
    return np.array(
        [0.5 * (world.x_min + world.x_max), 0.5 * (world.y_min + world.y_max)]
    ) + rng.uniform(-spread, spread, size=2)


def _streams(rng: np.random.Generator, world: WorldBounds) -> _Layout:
    centre = _centre(world, rng, 3.0)
    axis = rng.uniform(0.0, math.pi)
    u = _unit(axis)
    half = rng.uniform(1.0, 3.0)
    if rng.uniform() < 0.5:  # along the band
        along = u if rng.uniform() < 0.5 else -u
        side = np.array([-u[1], u[0]])
        length = rng.uniform(_ROBOT_MIN_M, _ROBOT_MAX_M)
        offset = rng.uniform(-half, half) * side
        start = centre + offset - 0.5 * length * along
        goal = centre + offset + 0.5 * length * along
        start, goal = _fit_line(world, start, goal)
    else:
        start, goal = _robot_line(rng, world, centre)
    lay = _Layout(rng, world, start, goal)
    _stream(lay, centre, u, half, int(rng.integers(6, 17)), both=True)
    return lay


def _fit_line(
    world: WorldBounds, start: FloatArray, goal: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """Clip a robot line into the world (margin 1 m); keep it at least 6 m long by
    shifting it back along its direction when one end left the world."""
    lo = np.array([world.x_min + 1.0, world.y_min + 1.0])
    hi = np.array([world.x_max - 1.0, world.y_max - 1.0])
    start = np.clip(start, lo, hi)
    goal = np.clip(goal, lo, hi)
    if math.dist(start, goal) < _ROBOT_MIN_M:
        direction = (goal - start) / max(math.dist(start, goal), 1e-9)
        goal = np.clip(start + _ROBOT_MIN_M * direction, lo, hi)
        start = np.clip(goal - _ROBOT_MIN_M * direction, lo, hi)
    return start, goal


def _crossing(rng: np.random.Generator, world: WorldBounds) -> _Layout:
    centre = _centre(world, rng, 2.5)
    a = rng.uniform(0.0, math.pi)
    b = a + rng.uniform(math.radians(50.0), math.radians(130.0))
    start, goal = _robot_line(rng, world, centre)
    lay = _Layout(rng, world, start, goal)
    for axis in (a, b):
        both = bool(rng.uniform() < 0.5)
        _stream(lay, centre, _unit(axis), rng.uniform(0.8, 2.0), int(rng.integers(3, 9)), both)
    return lay


def _standing(rng: np.random.Generator, world: WorldBounds) -> _Layout:
    start, goal = _robot_line(rng, world, None)
    lay = _Layout(rng, world, start, goal)
    for _ in range(int(rng.integers(1, 4))):
        t = rng.uniform(0.25, 0.75)
        u = (goal - start) / math.dist(start, goal)
        side = np.array([-u[1], u[0]])
        centre = start + t * (goal - start) + rng.uniform(-1.5, 1.5) * side
        radius = rng.uniform(1.0, 2.5)

        def draw(c: FloatArray = centre, r: float = radius) -> tuple[FloatArray, FloatArray]:
            p = c + r * math.sqrt(rng.uniform()) * _unit(rng.uniform(-math.pi, math.pi))
            return p, p

        for _ in range(int(rng.integers(3, 9))):
            lay.place(draw, standing=True)
    _walkers(lay, int(rng.integers(0, 5)))
    return lay


def _circle(rng: np.random.Generator, world: WorldBounds) -> _Layout:
    centre = _centre(world, rng, 1.5)
    radius = rng.uniform(3.5, 6.5)
    count = int(rng.integers(6, 15))
    if rng.uniform() < 0.3:  # from inside the ring outwards
        direction = _unit(rng.uniform(-math.pi, math.pi))
        start = centre + rng.uniform(0.0, 1.5) * _unit(rng.uniform(-math.pi, math.pi))
        goal = start + rng.uniform(_ROBOT_MIN_M, _ROBOT_MAX_M) * direction
        start, goal = _fit_line(world, start, goal)
    else:
        start, goal = _robot_line(rng, world, centre)
    lay = _Layout(rng, world, start, goal)
    phase = rng.uniform(-math.pi, math.pi)
    slots = iter(range(10 * count))

    def draw() -> tuple[FloatArray, FloatArray]:
        k = next(slots, 0)
        angle = phase + 2.0 * math.pi * (k % count) / count + rng.uniform(-0.15, 0.15)
        p = centre + radius * _unit(angle)
        q = centre - radius * _unit(angle) + rng.uniform(-0.5, 0.5, size=2)
        return lay.clip(p), q

    for _ in range(count):
        lay.place(draw, standing=False)
    return lay


_FAMILIES: Final[dict[str, Callable[[np.random.Generator, WorldBounds], _Layout]]] = {
    "streams": _streams,
    "crossing": _crossing,
    "standing": _standing,
    "circle": _circle,
}


def family_weights(weights: Sequence[float] | None) -> tuple[float, ...] | None:
    """Validate relative family weights, one per :data:`TRAINING_FAMILIES` entry.

    Args:
        weights: non-negative finite numbers with a positive sum, in the order of
            :data:`TRAINING_FAMILIES`, or None (every family 1/5).

    Returns:
        The weights as a tuple of floats (not normalised), or None.

    Raises:
        ScenarioError: a wrong count, a negative, non-finite or non-numeric weight, or
            all weights zero.
    """
    if weights is None:
        return None
    if isinstance(weights, (str, bytes)):
        raise ScenarioError(f"family weights must be a sequence of numbers, got {plain(weights)}")
    try:
        values = tuple(float(w) for w in weights)
    except (TypeError, ValueError):
        raise ScenarioError(f"family weights must be numbers, got {plain(weights)}") from None
    names = ", ".join(TRAINING_FAMILIES)
    if len(values) != len(TRAINING_FAMILIES):
        raise ScenarioError(
            f"family weights need {len(TRAINING_FAMILIES)} values ({names}), got {len(values)}: "
            f"{plain(weights)}"
        )
    for name, value in zip(TRAINING_FAMILIES, values, strict=True):
        if not math.isfinite(value) or value < 0.0:
            raise ScenarioError(
                f"family weight of {name!r} must be finite and >= 0, got {plain(value)}"
            )
    if sum(values) <= 0.0:
        raise ScenarioError(f"family weights must not all be 0, got {plain(weights)}")
    return values


def pool_scenario(
    seed: int, library: Sequence[str], share: float, generated_share: float = 0.0
) -> str | None:
    """The library scenario that training episode ``seed`` runs, ``"generated"`` for a
    generated walled layout (:func:`srfm.scenarios.generated.generated_scenario` of
    the episode seed), or None for a training layout (:func:`training_layout`).

    One uniform draw u of the pool's stream decides: a library scenario when u <
    ``share``, a generated layout when ``share`` <= u < ``share + generated_share``,
    else a training layout; without a generated share the draws are those of earlier
    versions.

    Args:
        seed: the episode seed.
        library: the library scenarios of the pool (each equally likely).
        share: the probability of a library scenario, in [0, 1].
        generated_share: the probability of a generated layout, in [0, 1 − share].
    """
    if (not library or share <= 0.0) and generated_share <= 0.0:
        return None
    rng = pool_rng(validate_seed(seed))
    u = rng.random()
    if library and u < share:
        return library[int(rng.integers(len(library)))]
    if u < max(share, 0.0) + generated_share:
        return GENERATED
    return None


def training_layout(
    base: Scenario,
    seed: int,
    family: str | None = None,
    weights: Sequence[float] | None = None,
) -> Scenario:
    """The training layout of episode ``seed``: a scenario of one of
    :data:`TRAINING_FAMILIES`, drawn from the seed alone (see the module doc).

    Args:
        base: the scenario whose world, time step, horizon, robot and pedestrian
            radius and goal radius every layout keeps (the ``random`` scenario).
        seed: the episode seed, an integer in [0, 2³² − 1].
        family: one family (default: drawn from the seed).
        weights: relative probabilities of the families in the order of
            :data:`TRAINING_FAMILIES` (:func:`family_weights`); None: uniform. The
            uniform draw is kept as it always was, so None reproduces every layout
            of earlier versions.

    Returns:
        A ``fixed`` scenario without noise (``walkers``: a ``random`` scenario with its
        own count), named ``mixed/<family>``; ``episode_setup(layout, seed)`` gives the
        episode.

    Raises:
        ScenarioError: a bad seed or an unknown family.
    """
    seed = validate_seed(seed)
    rng = training_rng(seed)
    probabilities = family_weights(weights)
    if probabilities is None:
        drawn = TRAINING_FAMILIES[int(rng.integers(len(TRAINING_FAMILIES)))]
    else:
        cumulative = np.cumsum(probabilities)
        index = int(np.searchsorted(cumulative, rng.random() * cumulative[-1], side="right"))
        last = max(i for i, w in enumerate(probabilities) if w > 0.0)  # rounding at 1
        drawn = TRAINING_FAMILIES[min(index, last)]
    family = drawn if family is None else family
    if family not in TRAINING_FAMILIES:
        known = ", ".join(TRAINING_FAMILIES)
        raise ScenarioError(f"unknown training family {plain(family)}; known: {known}")
    common: dict[str, Any] = {
        "description": f"training layout ({family}) of seed {seed}",
        "dt_s": base.dt_s,
        "horizon_steps": base.horizon_steps,
        "world": base.world,
        "robot": base.robot,
        "ped_radius_m": base.ped_radius_m,
        "ped_goal_radius_m": base.ped_goal_radius_m,
        "obstacles": base.obstacles,
        "source": f"mixed(seed={seed}, family={family})",
        "name": f"mixed/{family}",
    }
    if family == "walkers":
        count = int(rng.integers(4, 15))
        speed = rng.uniform(*_SPEED_MPS)
        spec = RandomSpec(count=count, robot_min_start_goal_m=_ROBOT_MIN_M)
        return Scenario(
            kind="random",
            robot_start=None,
            robot_goal=None,
            robot_heading_rad=None,
            ped_starts=None,
            ped_goals=None,
            ped_desired_speed_mps=speed,
            ped_max_speed_mps=speed,
            noise_m=0.0,
            random=spec,
            **common,
        )
    lay = _FAMILIES[family](rng, base.world)
    if not lay.starts:  # nobody fitted: one walker far from the robot
        _walkers(lay, 1)
    n = len(lay.starts)
    speeds = rng.uniform(*_SPEED_MPS, size=n)
    bearing = math.atan2(
        lay.robot_goal[1] - lay.robot_start[1], lay.robot_goal[0] - lay.robot_start[0]
    )
    heading = bearing + rng.uniform(-0.25 * math.pi, 0.25 * math.pi)
    return Scenario(
        kind="fixed",
        robot_start=lay.robot_start,
        robot_goal=lay.robot_goal,
        robot_heading_rad=math.remainder(heading, 2.0 * math.pi),
        ped_starts=np.array(lay.starts),
        ped_goals=np.array(lay.goals),
        ped_desired_speed_mps=speeds,
        ped_max_speed_mps=speeds.copy(),
        noise_m=0.0,
        random=None,
        **common,
    )
