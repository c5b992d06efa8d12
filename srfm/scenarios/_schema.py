"""Scenario classes and the TOML schema (versions 1 and 2) they are read from.

Version 2 adds pedestrian routes, waits, groups, standing pedestrians, speed noise,
entering pedestrians (entry times and sources), wall thickness, doors, named regions
and map points (:mod:`srfm.scenarios._v2`,
``docs/scenarios.md``); version-1 files load as before and refuse those keys. Both
versions get the same checks of a scene that can start (:mod:`srfm.scenarios._checks`).

A scenario file is TOML with these tables (every key is checked; unknown keys and
malformed values raise :class:`srfm.errors.ScenarioError` naming the file and key)::

    schema_version = 1                  # required: 1 or 2
    name = "footpath"                   # required, [a-z0-9][a-z0-9_-]*, <= 100 chars
    description = "one line"            # required
    kind = "fixed"                      # "fixed" (listed pedestrians) or "random"

    [simulation]
    dt_s = 0.06666666666666667          # step (s), in (0, 1], default 1/15
    horizon_steps = 750                 # steps of both twins, 1..MAX_HORIZON_STEPS
    crowd_substeps = 1                  # crowd steps of dt_s / crowd_substeps per step,
                                        # 1..MAX_CROWD_SUBSTEPS (the robot's control rate
                                        # stays 1 / dt_s; 1, the paper's scheme, by default)

    [world]                             # the robot is out of bounds outside it
    x_min = 0.0                         # defaults: [0, 15] x [0, 15] m; |x|, |y| <= 1e7
    x_max = 15.0
    y_min = 0.0
    y_max = 15.0

    [robot]
    start = [2.0, 8.0]                  # kind = "fixed" only (required), inside [world]
    goal = [12.0, 9.0]                  # kind = "fixed" only (required), inside [world]
    heading_rad = 0.0                   # kind = "fixed" only; default: facing the goal
    kinematics = "unicycle"             # and the limits of srfm.RobotConfig:
    radius_m = 0.2                      # max_speed_mps, max_angular_speed_radps,
                                        # max_accel_mps2, max_angular_accel_radps2,
                                        # goal_radius_m

    [robot.recording]                   # version 2, kind = "fixed": a recorded robot
    times_s = [0.0, 0.1, ...]           # for the `recorded` planner to replay: times
    xy = [[2.0, 8.0], [2.03, 8.0], ...] # from 0 and one position each, the first at
                                        # start (`srfm data scenario` writes these)

    [pedestrians]
    starts = [[0.5, 7.4], ...]          # required for kind = "fixed", (N, 2)
    goals = [[8.5, 5.2], ...]           # required for kind = "fixed", (N, 2)
    radius_m = 0.3                      # scalar or one per pedestrian, in [0, 1000]
    desired_speed_mps = 1.25            # scalar or one per pedestrian, in [0, 12.5]
    max_speed_mps = 1.25                # scalar or one per pedestrian, in [0, 12.5]
    goal_radius_m = 0.5                 # arrival distance
    noise_m = 0.5                       # kind = "fixed" only: per-seed offset
                                        # u ~ U(-noise, noise)^2, at most the world size

    [random]                            # only for kind = "random"
    count = 10
    margin_m = 0.5                      # draws stay this far inside the world
    robot_min_start_goal_m = 5.0
    ped_min_robot_start_m = 2.0
    ped_min_start_goal_m = 7.0
    ped_min_robot_goal_m = 2.0
    regoal = true                       # a pedestrian at its goal gets a new one

    [obstacles]
    walls = [[x1, y1, x2, y2], ...]     # segments (m), of non-zero length
    pillars = [[cx, cy, radius], ...]   # circles (m)

Every physical value is bounded by the one rule of :mod:`srfm._validate` (positions
|x| <= 1e7 m, radii <= 1e3 m, pedestrian speeds <= 12.5 m/s, ...). A fixed scenario,
of either version, must also describe a scene that can start
(:mod:`srfm.scenarios._checks`: everyone inside the world, nobody overlapping, no start
or goal in a wall or pillar, every goal reachable). A file is read only if it is a
regular file of at most 16 MiB; a UTF-8 byte-order mark is accepted.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from pathlib import Path
from typing import Any, Final, NamedTuple

import attrs
import numpy as np
from numpy.typing import NDArray

from srfm._io import MAX_TOML_BYTES, parse_toml, read_input_text
from srfm._text import plain
from srfm._validate import MAX_NAME_LENGTH, MAX_PEDESTRIAN_SPEED_MPS
from srfm.errors import ScenarioError, SrfmError
from srfm.models.forces import MAX_DT_S
from srfm.models.robot import KINEMATICS, RobotConfig
from srfm.models.state import MAX_RADIUS_M, Obstacles
from srfm.scenarios import _v2
from srfm.scenarios._checks import check_layout, listed_layout
from srfm.scenarios._reader import TableReader, check_wall_length
from srfm.world import WorldBounds

SCHEMA_VERSION: Final = 2
SCHEMA_VERSIONS: Final = (1, 2)
DEFAULT_SWITCH_RADIUS_M: Final = 0.5
MAX_HORIZON_STEPS: Final = 1_000_000
MAX_CROWD_SUBSTEPS: Final = 64
"""The most crowd substeps per step (``[simulation] crowd_substeps``)."""
DEFAULT_DT_S: Final = 1.0 / 15.0
# [pedestrians] keys of version 2.
_V2_PEDESTRIAN_KEYS: Final = (
    "routes",
    "waits_s",
    "groups",
    "standing",
    "switch_radius_m",
    "speed_noise_mps",
    "enter_s",
    "enter_noise_s",
    "sources",
)
_NAME_RE: Final = re.compile(r"[a-z0-9][a-z0-9_-]*")  # used with fullmatch

FloatArray = NDArray[np.float64]


@attrs.frozen(kw_only=True)
class RandomSpec:
    """Constraints of the random (training) scenario generator (docs/scenarios.md)."""

    count: int = 10
    margin_m: float = 0.5
    robot_min_start_goal_m: float = 5.0
    ped_min_robot_start_m: float = 2.0
    ped_min_start_goal_m: float = 7.0
    ped_min_robot_goal_m: float = 2.0
    regoal: bool = True


@attrs.frozen(kw_only=True, eq=False)
class Scenario:
    """A validated scenario. Build it with :func:`srfm.load_scenario`.

    For ``kind == "fixed"`` the pedestrians and the robot are listed; for
    ``kind == "random"`` they are drawn per seed under ``random``'s constraints. The
    file schema and every bound: docs/scenarios.md.

    Attributes:
        name, description: the scenario's name and one-line description.
        kind: ``"fixed"`` or ``"random"``.
        dt_s: simulation step (s).
        horizon_steps: steps of both twins in every episode.
        crowd_substeps: crowd steps of ``dt_s / crowd_substeps`` per step: the crowd at
            a finer step while the robot's planner keeps its control rate 1 / ``dt_s``
            and the record its samples (1, the paper's scheme, by default;
            docs/metrics.md, "Convergence in the time step").
        world: the world rectangle (m); the robot is out of bounds outside it.
        robot: the robot's body and limits (m, m/s, rad/s, m/s², rad/s²).
        robot_start, robot_goal: (2,) the robot's start and goal (m); None for
            ``random``.
        robot_heading_rad: the robot's start heading (rad); None: facing its goal.
        ped_starts, ped_goals: (N, 2) the listed pedestrians' starts and goals (m),
            before the per-seed noise; None for ``random``.
        ped_radius_m: body radius (m), one for all or (N,).
        ped_desired_speed_mps, ped_max_speed_mps: desired speed v0 and speed cap
            (m/s), one for all or (N,).
        ped_goal_radius_m: arrival distance (m).
        noise_m: half-width (m) of the per-seed offset of starts, waypoints and goals.
        random: the constraints of a ``random`` scenario, else None.
        obstacles: walls (m; thick walls as their outlines, doors cut out) and pillars.
        source: ``builtin:NAME`` or the file's path.
        schema_version: 1 or 2.
        ped_routes: per listed pedestrian, (K, 2) waypoints (m) walked before the goal.
        ped_waits_s: per listed pedestrian, (K,) seconds spent at each waypoint.
        ped_switch_radius_m: a waypoint counts as reached within this distance (m).
        ped_speed_noise_mps: half-width (m/s) of the per-seed change of desired speeds.
        ped_groups: indices of the pedestrians that walk together, per group.
        ped_standing: indices of the pedestrians that stand (goal = start).
        regions: named rectangles (x_min, y_min, x_max, y_max) (m).
        map_points: (M, 2) points of a recorded map (m), or None.
        robot_recording: a recorded robot trajectory (times in s, positions in m).
        ped_enter_s: (N,) entry time of each pedestrian (s), None when all are there
            at the start.
        ped_enter_noise_s: half-width (s) of the per-seed change of entry times > 0.
        ped_sources: streams of pedestrians entering at a rate (per s).
    """

    name: str
    description: str
    kind: str
    dt_s: float
    horizon_steps: int
    world: WorldBounds
    robot: RobotConfig
    robot_start: FloatArray | None
    robot_goal: FloatArray | None
    robot_heading_rad: float | None
    ped_starts: FloatArray | None
    ped_goals: FloatArray | None
    ped_radius_m: FloatArray | float
    ped_desired_speed_mps: FloatArray | float
    ped_max_speed_mps: FloatArray | float
    ped_goal_radius_m: float
    noise_m: float
    random: RandomSpec | None
    obstacles: Obstacles
    source: str
    # Schema version 2 (all optional; version-1 files get these defaults).
    schema_version: int = 1
    ped_routes: tuple[FloatArray, ...] | None = None
    ped_waits_s: tuple[FloatArray, ...] | None = None
    ped_switch_radius_m: float = DEFAULT_SWITCH_RADIUS_M
    ped_speed_noise_mps: float = 0.0
    ped_groups: tuple[tuple[int, ...], ...] = ()
    ped_standing: tuple[int, ...] = ()
    regions: Mapping[str, tuple[float, float, float, float]] = attrs.field(factory=dict)
    map_points: FloatArray | None = None
    robot_recording: _v2.RobotRecording | None = None
    # Entering pedestrians (version 2): each one's scenario-given entry time (s), None
    # when every pedestrian is there at the start; the per-seed noise on the times
    # > 0; the sources (srfm.scenarios.entry_times makes the times of a seed).
    ped_enter_s: FloatArray | None = None
    ped_enter_noise_s: float = 0.0
    ped_sources: tuple[_v2.EntrySource, ...] = ()
    crowd_substeps: int = 1

    def region(self, name: str) -> tuple[float, float, float, float]:
        """The named region (x_min, y_min, x_max, y_max) (m).

        Raises:
            ScenarioError: no region of that name.
        """
        if name not in self.regions:
            known = ", ".join(sorted(self.regions)) or "none"
            raise ScenarioError(f"{self.source}: no region {name!r}; regions: {known}")
        return self.regions[name]

    @property
    def n_pedestrians(self) -> int:
        """Number of pedestrians in every episode of this scenario."""
        if self.random is not None:
            return self.random.count
        assert self.ped_starts is not None
        return int(self.ped_starts.shape[0])


def parse_scenario(data: Mapping[str, Any], source: str) -> Scenario:
    """Validate a parsed TOML document and build the :class:`Scenario`.

    One reader per table, in this order (the first error found is the one raised): the
    top-level keys, ``[simulation]``, ``[world]``, ``[regions]``, ``[robot]``,
    ``[pedestrians]``, ``[random]``, ``[obstacles]``, ``[map]``; then the checks that
    need the geometry of several tables, for every version of a fixed scenario
    (:func:`srfm.scenarios._checks.check_layout`).
    """
    top = TableReader(data, "", source)
    head = _read_head(top)
    dt_s, horizon, substeps = _read_simulation(top)
    world = _read_world(top, source)
    regions = _v2.read_regions(top, world) if head.v2 else {}
    robot = _read_robot(top, head, world)
    peds = _read_pedestrians(top, head, world, horizon * dt_s, regions)
    random_spec = _read_random(top, head, world, source)
    obstacles = _read_obstacles(top, head, source)
    map_points = _read_map(top, head)
    top.finish()
    if head.fixed:
        _check_layout(source, peds, robot, obstacles, world)
    layout = peds.layout
    # A Scenario is shared (built-ins are cached): make its arrays read-only.
    ped_values = (peds.radius_m, peds.desired_speed_mps, peds.max_speed_mps)
    for arr in (robot.start, robot.goal, peds.starts, peds.goals, *ped_values, map_points):
        if isinstance(arr, np.ndarray):
            arr.setflags(write=False)
    return Scenario(
        name=head.name,
        description=head.description,
        kind=head.kind,
        dt_s=dt_s,
        horizon_steps=horizon,
        world=world,
        robot=robot.config,
        robot_start=robot.start,
        robot_goal=robot.goal,
        robot_heading_rad=robot.heading_rad,
        ped_starts=peds.starts,
        ped_goals=peds.goals,
        ped_radius_m=peds.radius_m,
        ped_desired_speed_mps=peds.desired_speed_mps,
        ped_max_speed_mps=peds.max_speed_mps,
        ped_goal_radius_m=peds.goal_radius_m,
        noise_m=peds.noise_m,
        random=random_spec,
        obstacles=obstacles,
        source=source,
        schema_version=head.version,
        ped_routes=None if layout is None else layout.routes,
        ped_waits_s=None if layout is None else layout.waits_s,
        ped_switch_radius_m=peds.switch_radius_m,
        ped_speed_noise_mps=peds.speed_noise_mps,
        ped_groups=() if layout is None else layout.groups,
        ped_standing=() if layout is None else layout.standing,
        regions=regions,
        map_points=map_points,
        robot_recording=robot.recording,
        ped_enter_s=(
            layout.enter_s
            if layout is not None and (layout.enter_s.any() or layout.sources)
            else None
        ),
        ped_enter_noise_s=peds.enter_noise_s,
        ped_sources=() if layout is None else layout.sources,
        crowd_substeps=substeps,
    )


class _Head(NamedTuple):
    """The top-level keys of a scenario file."""

    version: int
    name: str
    description: str
    kind: str

    @property
    def v2(self) -> bool:
        return self.version >= 2

    @property
    def fixed(self) -> bool:
        return self.kind == "fixed"


def _read_head(top: TableReader) -> _Head:
    """``schema_version``, ``name``, ``description`` and ``kind``."""
    version = top.raw("schema_version") if top.has("schema_version") else None
    if type(version) is not int or version not in SCHEMA_VERSIONS:
        raise top.fail(
            "schema_version",
            f"must be one of {', '.join(map(str, SCHEMA_VERSIONS))} (this srfm reads those), "
            f"got {plain(version)}",
        )
    name = top.string("name")
    if not _NAME_RE.fullmatch(name) or len(name) > MAX_NAME_LENGTH:
        raise top.fail(
            "name",
            f"must match [a-z0-9][a-z0-9_-]* (at most {MAX_NAME_LENGTH} characters; it "
            f"names folders and table rows), got {plain(name)}",
        )
    description = top.string("description")
    kind = top.string("kind", "fixed")
    if kind not in ("fixed", "random"):
        raise top.fail("kind", f"must be 'fixed' or 'random', got {plain(kind)}")
    return _Head(version, name, description, kind)


def _read_simulation(top: TableReader) -> tuple[float, int, int]:
    """``[simulation]``: the step (s), the horizon (steps) and the crowd substeps."""
    sim = top.table("simulation")
    dt_s = sim.number("dt_s", DEFAULT_DT_S, minimum=0.0, strict=True, maximum=MAX_DT_S)
    horizon = sim.integer("horizon_steps", 750, minimum=1, maximum=MAX_HORIZON_STEPS)
    substeps = sim.integer("crowd_substeps", 1, minimum=1, maximum=MAX_CROWD_SUBSTEPS)
    sim.finish()
    return dt_s, horizon, substeps


def _read_world(top: TableReader, source: str) -> WorldBounds:
    """``[world]``: the rectangle."""
    w = top.table("world")
    world = WorldBounds(
        x_min=w.number("x_min", 0.0, kind="coordinate"),
        x_max=w.number("x_max", 15.0, kind="coordinate"),
        y_min=w.number("y_min", 0.0, kind="coordinate"),
        y_max=w.number("y_max", 15.0, kind="coordinate"),
    )
    w.finish()
    if world.x_max <= world.x_min or world.y_max <= world.y_min:
        raise ScenarioError(f"{source}: world: x_max > x_min and y_max > y_min needed, got {world}")
    return world


class _Robot(NamedTuple):
    """What ``[robot]`` gives: the limits, and for a fixed scenario the start, goal,
    heading and the recorded trajectory."""

    config: RobotConfig
    start: FloatArray | None
    goal: FloatArray | None
    heading_rad: float | None
    recording: _v2.RobotRecording | None


def _read_robot(top: TableReader, head: _Head, world: WorldBounds) -> _Robot:
    """``[robot]`` (and ``[robot.recording]``, version 2)."""
    r = top.table("robot")
    if not head.fixed:
        for key in ("start", "goal", "heading_rad"):
            if r.has(key):
                raise r.fail(key, "is drawn per seed for kind = 'random'; remove it")
    start = r.array("start", 0, required=head.fixed)
    goal = r.array("goal", 0, required=head.fixed)
    for key, point in (("start", start), ("goal", goal)):
        if point is not None and not world.contains(float(point[0]), float(point[1])):
            raise r.fail(key, f"must lie inside the world {world}, got {point.tolist()}")
    heading = r.number("heading_rad", minimum=-1e3, maximum=1e3) if r.has("heading_rad") else None
    recording: _v2.RobotRecording | None = None
    if r.has("recording"):
        if not head.v2:
            raise r.fail("recording", "needs schema_version = 2")
        if not head.fixed or start is None:
            raise r.fail("recording", "is only allowed with kind = 'fixed'")
        recording = _v2.read_recording(r, world, start)
    config = _robot_config_fields(r)
    r.finish()
    return _Robot(RobotConfig(**config), start, goal, heading, recording)


def _robot_config_fields(r: TableReader) -> dict[str, Any]:
    """``kinematics`` and the limits of :class:`srfm.RobotConfig` (default: its own)."""
    kinematics = r.string("kinematics", "unicycle")
    if kinematics not in KINEMATICS:
        raise r.fail("kinematics", f"must be one of {KINEMATICS}, got {plain(kinematics)}")
    defaults = RobotConfig()
    limits = {
        field: r.number(field, getattr(defaults, field), strict=True, kind=kind)
        for field, kind in (
            ("radius_m", "radius"),
            ("max_speed_mps", "speed"),
            ("max_angular_speed_radps", "angular_speed"),
            ("max_accel_mps2", "acceleration"),
            ("max_angular_accel_radps2", "acceleration"),
            ("goal_radius_m", "radius"),
        )
    }
    return {"kinematics": kinematics, **limits}


class _Pedestrians(NamedTuple):
    """What ``[pedestrians]`` gives: the listed pedestrians (with the version-2 layout,
    those of groups, standing and sources too) and their per-pedestrian values."""

    starts: FloatArray | None
    goals: FloatArray | None
    layout: _v2.PedestrianLayout | None
    radius_m: FloatArray | float
    desired_speed_mps: FloatArray | float
    max_speed_mps: FloatArray | float
    goal_radius_m: float
    noise_m: float
    switch_radius_m: float
    speed_noise_mps: float
    enter_noise_s: float


def _read_pedestrians(
    top: TableReader,
    head: _Head,
    world: WorldBounds,
    horizon_s: float,
    regions: Mapping[str, tuple[float, float, float, float]],
) -> _Pedestrians:
    """``[pedestrians]`` (version 2: routes, groups, standing, entries, sources)."""
    p = top.table("pedestrians")
    if not head.v2:
        for key in _V2_PEDESTRIAN_KEYS:
            if p.has(key):
                raise p.fail(key, "needs schema_version = 2")
    starts, goals = _listed_pedestrians(p, head)
    layout = _pedestrian_layout(p, head, starts, goals, horizon_s, regions)
    if layout is not None:
        starts, goals = layout.starts, layout.goals
    n = None if starts is None else starts.shape[0]
    switch_radius = p.number("switch_radius_m", DEFAULT_SWITCH_RADIUS_M, strict=True, kind="radius")
    speed_noise = p.number("speed_noise_mps", 0.0, kind="speed")
    enter_noise = p.number("enter_noise_s", 0.0, minimum=0.0, maximum=horizon_s)
    radius = p.per_agent("radius_m", 0.3, n, MAX_RADIUS_M)
    desired_speed = p.per_agent("desired_speed_mps", 1.25, n, MAX_PEDESTRIAN_SPEED_MPS)
    max_speed = p.per_agent("max_speed_mps", 1.25, n, MAX_PEDESTRIAN_SPEED_MPS)
    goal_radius = p.number("goal_radius_m", 0.5, strict=True, kind="radius")
    world_size = min(world.x_max - world.x_min, world.y_max - world.y_min)
    if not head.fixed and p.has("noise_m"):
        raise p.fail("noise_m", "is only allowed with kind = 'fixed'")
    noise = p.number("noise_m", 0.5, maximum=world_size, kind="length")
    p.finish()
    if head.kind == "random" and starts is not None:
        raise p.fail("starts", "must not be given for kind = 'random'")
    return _Pedestrians(
        starts=starts,
        goals=goals,
        layout=layout,
        radius_m=radius,
        desired_speed_mps=desired_speed,
        max_speed_mps=max_speed,
        goal_radius_m=goal_radius,
        noise_m=noise,
        switch_radius_m=switch_radius,
        speed_noise_mps=speed_noise,
        enter_noise_s=enter_noise,
    )


def _listed_pedestrians(p: TableReader, head: _Head) -> tuple[FloatArray | None, FloatArray | None]:
    """``starts`` and ``goals``: one goal per start; required for a fixed scenario
    unless groups, standing pedestrians or sources (version 2) give the pedestrians."""
    extra = head.v2 and any(p.has(k) for k in ("groups", "standing", "sources"))
    required = head.fixed and not extra
    starts = p.bounded_array("starts", 2, required=required, kinds=("coordinate",))
    goals = p.bounded_array("goals", 2, required=required, kinds=("coordinate",))
    if starts is not None:
        n = starts.shape[0]
        if n == 0 and not extra:
            raise p.fail("starts", "needs at least one pedestrian")
        if goals is None or goals.shape[0] != n:
            got = "none" if goals is None else goals.shape[0]
            raise p.fail("goals", f"needs one goal per start ({n}), got {got}")
    elif goals is not None:
        raise p.fail("goals", "given without starts")
    return starts, goals


def _pedestrian_layout(
    p: TableReader,
    head: _Head,
    starts: FloatArray | None,
    goals: FloatArray | None,
    horizon_s: float,
    regions: Mapping[str, tuple[float, float, float, float]],
) -> _v2.PedestrianLayout | None:
    """The version-2 layout of a fixed scenario (None for version 1, whose keys are
    refused before); a random scenario must not use its keys."""
    if head.v2 and head.fixed:
        return _v2.read_pedestrians(p, starts, goals, horizon_s, regions)
    if head.v2 and any(p.has(k) for k in _V2_PEDESTRIAN_KEYS):
        key = next(k for k in _V2_PEDESTRIAN_KEYS if p.has(k))
        raise p.fail(key, "is only allowed with kind = 'fixed'")
    return None


def _read_random(
    top: TableReader, head: _Head, world: WorldBounds, source: str
) -> RandomSpec | None:
    """``[random]``: the generator's constraints, for ``kind = "random"`` only."""
    if head.kind != "random":
        if top.has("random"):
            raise top.fail("random", "is only allowed with kind = 'random'")
        return None
    q = top.table("random")
    spec = RandomSpec(
        count=q.integer("count", 10, minimum=1, maximum=10_000),
        margin_m=q.number("margin_m", 0.5, kind="length"),
        robot_min_start_goal_m=q.number("robot_min_start_goal_m", 5.0, kind="length"),
        ped_min_robot_start_m=q.number("ped_min_robot_start_m", 2.0, kind="length"),
        ped_min_start_goal_m=q.number("ped_min_start_goal_m", 7.0, kind="length"),
        ped_min_robot_goal_m=q.number("ped_min_robot_goal_m", 2.0, kind="length"),
        regoal=q.boolean("regoal", True),
    )
    q.finish()
    if 2 * spec.margin_m >= min(world.x_max - world.x_min, world.y_max - world.y_min):
        raise ScenarioError(f"{source}: random.margin_m leaves no room in the world")
    return spec


def _read_obstacles(top: TableReader, head: _Head, source: str) -> Obstacles:
    """``[obstacles]``: walls (version 2: with a thickness, and doors cut out of them)
    and pillars."""
    o = top.table("obstacles")
    walls: FloatArray | None
    if head.v2:
        walls, _ = _v2.read_walls(o)
    else:
        if o.has("doors"):
            raise o.fail("doors", "needs schema_version = 2")
        walls = o.bounded_array("walls", 4, required=False, kinds=("coordinate",))
        for i, row in enumerate(() if walls is None else walls):
            check_wall_length(o, f"walls[{i}]", row)
    pillars = o.bounded_array(
        "pillars", 3, required=False, kinds=("coordinate", "coordinate", "radius")
    )
    o.finish()
    try:
        return Obstacles.create(
            segments=walls if walls is not None else (),
            circles=pillars if pillars is not None else (),
        )
    except SrfmError as exc:
        raise ScenarioError(f"{source}: obstacles: {exc}") from None


def _read_map(top: TableReader, head: _Head) -> FloatArray | None:
    """``[map] points`` (version 2): points drawn as the map."""
    if not (head.v2 and top.has("map")):
        return None
    m = top.table("map")
    points = m.bounded_array("points", 2, required=True, kinds=("coordinate",))
    m.finish()
    return points


def _check_layout(
    source: str,
    peds: _Pedestrians,
    robot: _Robot,
    obstacles: Obstacles,
    world: WorldBounds,
) -> None:
    """The checks of a fixed scenario that need several tables, for every schema
    version (:func:`srfm.scenarios._checks.check_layout`; a version-1 file is checked
    as the layout of its listed pedestrians)."""
    assert robot.start is not None
    assert robot.goal is not None
    layout = peds.layout
    if layout is None:
        assert peds.starts is not None
        assert peds.goals is not None
        layout = listed_layout(peds.starts, peds.goals)
    radius = np.asarray(peds.radius_m, dtype=np.float64)
    check_layout(
        source,
        layout,
        np.broadcast_to(radius, (layout.starts.shape[0],)),
        obstacles,
        world,
        robot.start,
        robot.goal,
        robot.config.radius_m,
    )


def read_scenario_file(path: Path) -> Scenario:
    """Read and validate one scenario file."""
    text = read_input_text(
        path, max_bytes=MAX_TOML_BYTES, error=ScenarioError, what="scenario file"
    )
    return parse_scenario(parse_toml(text, path, ScenarioError), str(path))
