"""Scenario classes and the TOML schema (versions 1 and 2) they are read from.

Version 2 adds pedestrian routes, waits, groups, standing pedestrians, speed noise,
entering pedestrians (entry times and sources), wall thickness, doors, named regions
and map points (:mod:`srfm.scenarios._v2`,
``docs/scenarios.md``); version-1 files load as before and refuse those keys.

A scenario file is TOML with these tables (every key is checked; unknown keys and
malformed values raise :class:`srfm.errors.ScenarioError` naming the file and key)::

    schema_version = 1                  # required: 1 or 2
    name = "footpath"                   # required, [a-z0-9][a-z0-9_-]*, <= 100 chars
    description = "one line"            # required
    kind = "fixed"                      # "fixed" (listed pedestrians) or "random"

    [simulation]
    dt_s = 0.06666666666666667          # step (s), in (0, 1], default 1/15
    horizon_steps = 750                 # steps of both twins, 1..MAX_HORIZON_STEPS

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
    desired_speed_mps = 1.25            # scalar or one per pedestrian, in [0, 1000]
    max_speed_mps = 1.25                # scalar or one per pedestrian, in [0, 1000]
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
    walls = [[x1, y1, x2, y2], ...]     # segments (m)
    pillars = [[cx, cy, radius], ...]   # circles (m)

Every physical value is bounded by the one rule of :mod:`srfm._validate` (positions
|x| <= 1e7 m, radii <= 1e3 m, speeds <= 1e3 m/s, ...). A file is read only if it is a
regular file of at most 16 MiB; a UTF-8 byte-order mark is accepted.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from pathlib import Path
from typing import Any, Final

import attrs
import numpy as np
from numpy.typing import NDArray

from srfm._io import MAX_TOML_BYTES, read_input_text
from srfm._validate import MAX_NAME_LENGTH
from srfm.errors import ScenarioError, SrfmError
from srfm.models.forces import MAX_DT_S
from srfm.models.robot import KINEMATICS, RobotConfig
from srfm.models.state import MAX_RADIUS_M, MAX_SPEED_MPS, Obstacles
from srfm.scenarios import _v2
from srfm.scenarios._reader import TableReader
from srfm.world import WorldBounds

SCHEMA_VERSION: Final = 2
SCHEMA_VERSIONS: Final = (1, 2)
DEFAULT_SWITCH_RADIUS_M: Final = 0.5
MAX_HORIZON_STEPS: Final = 1_000_000
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
    ``kind == "random"`` they are drawn per seed under ``random``'s constraints.
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
    """Validate a parsed TOML document and build the :class:`Scenario`."""
    top = TableReader(data, "", source)
    version = top.raw("schema_version") if top.has("schema_version") else None
    if type(version) is not int or version not in SCHEMA_VERSIONS:
        raise top.fail(
            "schema_version",
            f"must be one of {', '.join(map(str, SCHEMA_VERSIONS))} (this srfm reads those), "
            f"got {version!r}",
        )
    v2 = version >= 2
    name = top.string("name")
    if not _NAME_RE.fullmatch(name) or len(name) > MAX_NAME_LENGTH:
        raise top.fail(
            "name",
            f"must match [a-z0-9][a-z0-9_-]* (at most {MAX_NAME_LENGTH} characters; it "
            f"names folders and table rows), got {name!r}",
        )
    description = top.string("description")
    kind = top.string("kind", "fixed")
    if kind not in ("fixed", "random"):
        raise top.fail("kind", f"must be 'fixed' or 'random', got {kind!r}")

    sim = top.table("simulation")
    dt_s = sim.number("dt_s", DEFAULT_DT_S, minimum=0.0, strict=True, maximum=MAX_DT_S)
    horizon = sim.integer("horizon_steps", 750, minimum=1, maximum=MAX_HORIZON_STEPS)
    sim.finish()

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
    regions: dict[str, tuple[float, float, float, float]] = {}
    if v2:
        regions = _v2.read_regions(top, world)

    r = top.table("robot")
    fixed = kind == "fixed"
    if not fixed:
        for key in ("start", "goal", "heading_rad"):
            if r.has(key):
                raise r.fail(key, "is drawn per seed for kind = 'random'; remove it")
    robot_start = r.array("start", 0, required=fixed)
    robot_goal = r.array("goal", 0, required=fixed)
    for key, point in (("start", robot_start), ("goal", robot_goal)):
        if point is not None and not world.contains(float(point[0]), float(point[1])):
            raise r.fail(key, f"must lie inside the world {world}, got {point.tolist()}")
    heading = r.number("heading_rad", minimum=-1e3, maximum=1e3) if r.has("heading_rad") else None
    recording: _v2.RobotRecording | None = None
    if r.has("recording"):
        if not v2:
            raise r.fail("recording", "needs schema_version = 2")
        if not fixed or robot_start is None:
            raise r.fail("recording", "is only allowed with kind = 'fixed'")
        recording = _v2.read_recording(r, world, robot_start)
    kin = r.string("kinematics", "unicycle")
    if kin not in KINEMATICS:
        raise r.fail("kinematics", f"must be one of {KINEMATICS}, got {kin!r}")
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
    r.finish()
    robot = RobotConfig(kinematics=kin, **limits)

    p = top.table("pedestrians")
    if not v2:
        for key in _V2_PEDESTRIAN_KEYS:
            if p.has(key):
                raise p.fail(key, "needs schema_version = 2")
    extra = v2 and any(p.has(k) for k in ("groups", "standing", "sources"))
    starts = p.bounded_array("starts", 2, required=fixed and not extra, kinds=("coordinate",))
    goals = p.bounded_array("goals", 2, required=fixed and not extra, kinds=("coordinate",))
    n: int | None = None
    if starts is not None:
        n = starts.shape[0]
        if n == 0 and not extra:
            raise p.fail("starts", "needs at least one pedestrian")
        if goals is None or goals.shape[0] != n:
            got = "none" if goals is None else goals.shape[0]
            raise p.fail("goals", f"needs one goal per start ({n}), got {got}")
    elif goals is not None:
        raise p.fail("goals", "given without starts")
    layout: _v2.PedestrianLayout | None = None
    if v2 and fixed:
        layout = _v2.read_pedestrians(p, starts, goals, horizon * dt_s, regions)
        starts, goals = layout.starts, layout.goals
        n = starts.shape[0]
    elif v2 and any(p.has(k) for k in _V2_PEDESTRIAN_KEYS):
        key = next(k for k in _V2_PEDESTRIAN_KEYS if p.has(k))
        raise p.fail(key, "is only allowed with kind = 'fixed'")
    switch_radius = p.number("switch_radius_m", DEFAULT_SWITCH_RADIUS_M, strict=True, kind="radius")
    speed_noise = p.number("speed_noise_mps", 0.0, kind="speed")
    enter_noise = p.number("enter_noise_s", 0.0, minimum=0.0, maximum=horizon * dt_s)
    ped_radius = p.per_agent("radius_m", 0.3, n, MAX_RADIUS_M)
    ped_v0 = p.per_agent("desired_speed_mps", 1.25, n, MAX_SPEED_MPS)
    ped_vmax = p.per_agent("max_speed_mps", 1.25, n, MAX_SPEED_MPS)
    ped_goal_radius = p.number("goal_radius_m", 0.5, strict=True, kind="radius")
    world_size = min(world.x_max - world.x_min, world.y_max - world.y_min)
    if not fixed and p.has("noise_m"):
        raise p.fail("noise_m", "is only allowed with kind = 'fixed'")
    noise = p.number("noise_m", 0.5, maximum=world_size, kind="length")
    p.finish()

    random_spec: RandomSpec | None = None
    if kind == "random":
        if starts is not None:
            raise p.fail("starts", "must not be given for kind = 'random'")
        q = top.table("random")
        random_spec = RandomSpec(
            count=q.integer("count", 10, minimum=1, maximum=10_000),
            margin_m=q.number("margin_m", 0.5, kind="length"),
            robot_min_start_goal_m=q.number("robot_min_start_goal_m", 5.0, kind="length"),
            ped_min_robot_start_m=q.number("ped_min_robot_start_m", 2.0, kind="length"),
            ped_min_start_goal_m=q.number("ped_min_start_goal_m", 7.0, kind="length"),
            ped_min_robot_goal_m=q.number("ped_min_robot_goal_m", 2.0, kind="length"),
            regoal=q.boolean("regoal", True),
        )
        q.finish()
        if 2 * random_spec.margin_m >= min(world.x_max - world.x_min, world.y_max - world.y_min):
            raise ScenarioError(f"{source}: random.margin_m leaves no room in the world")
    elif top.has("random"):
        raise top.fail("random", "is only allowed with kind = 'random'")

    o = top.table("obstacles")
    walls: FloatArray | None
    if v2:
        walls, _ = _v2.read_walls(o)
    else:
        if o.has("doors"):
            raise o.fail("doors", "needs schema_version = 2")
        walls = o.bounded_array("walls", 4, required=False, kinds=("coordinate",))
    pillars = o.bounded_array(
        "pillars", 3, required=False, kinds=("coordinate", "coordinate", "radius")
    )
    o.finish()
    try:
        obstacles = Obstacles.create(
            segments=walls if walls is not None else (),
            circles=pillars if pillars is not None else (),
        )
    except SrfmError as exc:
        raise ScenarioError(f"{source}: obstacles: {exc}") from None
    map_points: FloatArray | None = None
    if v2 and top.has("map"):
        m = top.table("map")
        map_points = m.bounded_array("points", 2, required=True, kinds=("coordinate",))
        m.finish()
    top.finish()
    if layout is not None:
        assert robot_start is not None
        assert robot_goal is not None
        assert n is not None
        _v2.check_layout(
            source,
            layout,
            np.broadcast_to(np.asarray(ped_radius, dtype=np.float64), (n,)),
            obstacles,
            world,
            robot_start,
            robot_goal,
            robot.radius_m,
        )

    # A Scenario is shared (built-ins are cached): make its arrays read-only.
    for arr in (robot_start, robot_goal, starts, goals, ped_radius, ped_v0, ped_vmax, map_points):
        if isinstance(arr, np.ndarray):
            arr.setflags(write=False)
    return Scenario(
        name=name,
        description=description,
        kind=kind,
        dt_s=dt_s,
        horizon_steps=horizon,
        world=world,
        robot=robot,
        robot_start=robot_start,
        robot_goal=robot_goal,
        robot_heading_rad=heading,
        ped_starts=starts,
        ped_goals=goals,
        ped_radius_m=ped_radius,
        ped_desired_speed_mps=ped_v0,
        ped_max_speed_mps=ped_vmax,
        ped_goal_radius_m=ped_goal_radius,
        noise_m=noise,
        random=random_spec,
        obstacles=obstacles,
        source=source,
        schema_version=version,
        ped_routes=None if layout is None else layout.routes,
        ped_waits_s=None if layout is None else layout.waits_s,
        ped_switch_radius_m=switch_radius,
        ped_speed_noise_mps=speed_noise,
        ped_groups=() if layout is None else layout.groups,
        ped_standing=() if layout is None else layout.standing,
        regions=regions,
        map_points=map_points,
        robot_recording=recording,
        ped_enter_s=(
            layout.enter_s
            if layout is not None and (layout.enter_s.any() or layout.sources)
            else None
        ),
        ped_enter_noise_s=enter_noise,
        ped_sources=() if layout is None else layout.sources,
    )


def read_scenario_file(path: Path) -> Scenario:
    """Read and validate one scenario file."""
    import tomllib

    text = read_input_text(
        path, max_bytes=MAX_TOML_BYTES, error=ScenarioError, what="scenario file"
    )
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ScenarioError(f"{path}: not valid TOML: {exc}") from None
    return parse_scenario(data, str(path))
