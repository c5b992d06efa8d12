"""The parts of scenario schema version 2 that version 1 lacks.

Pedestrians (``[pedestrians]``): per-pedestrian routes (``routes``: one list of
waypoints per listed pedestrian, walked in order before the goal; ``waits_s``: seconds
spent at each waypoint; ``switch_radius_m``: how close a pedestrian comes to a waypoint
before it steers to the next), groups walking side by side (``[[pedestrians.groups]]``),
standing pedestrians (``standing``: goal = start), per-seed speed noise
(``speed_noise_mps``) and pedestrians entering during the run (``enter_s`` per listed
pedestrian or group, ``enter_noise_s``, and ``[[pedestrians.sources]]``: a stream of
``count`` pedestrians entering at ``rate_per_s``; the per-seed times are drawn in
:func:`srfm.scenarios.entry_times`). Obstacles: walls with a thickness (a fifth number per wall),
doors (``doors``: openings cut out of the walls they lie on). Named regions
(``[regions]``) and map points for drawing (``[map] points``).

The checks that need the geometry (walls through a start or goal, overlapping starts,
unreachable waypoints) apply to every schema version: :mod:`srfm.scenarios._checks`.
Every message names the file and the key.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any, Final

import attrs
import numpy as np
import shapely
from numpy.typing import NDArray

from srfm._text import plain
from srfm._validate import BOUNDS
from srfm.scenarios._reader import TableReader, check_wall_length
from srfm.world import WorldBounds

FloatArray = NDArray[np.float64]

MAX_WAYPOINTS: Final = 1_000
MAX_GROUP_SIZE: Final = 100
MAX_SOURCE_COUNT: Final = 10_000
DEFAULT_HEADWAY_S: Final = 1.0
# Walls are drawn as the outline of their rectangle: this thin a wall (m) is one segment.
THIN_WALL_M: Final = 1e-9


@attrs.frozen(kw_only=True)
class EntrySource:
    """``[[pedestrians.sources]]``: ``count`` pedestrians (layout indices ``first`` ..
    ``first + count - 1``) that enter at ``start`` during the run, at ``rate_per_s`` on
    average from ``start_s`` on, at least ``headway_s`` apart (the per-seed times:
    :func:`srfm.scenarios.entry_times`), walking to ``goal`` or to a point of the named
    region ``goal_region`` (:func:`srfm.scenarios.source_goals`)."""

    first: int
    count: int
    rate_per_s: float
    start_s: float
    headway_s: float
    # goal_region: each member's goal is drawn per seed, uniform in this named region
    # (x_min, y_min, x_max, y_max), so that a stream does not crowd onto one point.
    goal_region: str | None = None
    goal_box: tuple[float, float, float, float] | None = None

    @property
    def window_s(self) -> float:
        """The span of the entries: ``count / rate_per_s`` seconds from ``start_s``."""
        return self.count / self.rate_per_s


@attrs.frozen(kw_only=True)
class PedestrianLayout:
    """The pedestrians of a fixed scenario after expanding groups, standing ones and
    sources.

    Order: listed pedestrians, then each group's members, then standing pedestrians,
    then each source's members. ``labels[i]`` names the key that pedestrian i came from
    (for error messages). ``enter_s[i]`` is its scenario-given entry time (0: there at
    the start; a source's members get their source's ``start_s``).
    """

    starts: FloatArray
    goals: FloatArray
    routes: tuple[FloatArray, ...]
    waits_s: tuple[FloatArray, ...]
    groups: tuple[tuple[int, ...], ...]
    standing: tuple[int, ...]
    labels: tuple[str, ...]
    enter_s: FloatArray
    sources: tuple[EntrySource, ...] = ()

    def at_start(self) -> NDArray[np.bool_]:
        """(N,) True for the pedestrians that are there at sample 0 of every seed."""
        out: NDArray[np.bool_] = np.asarray(self.enter_s == 0.0)
        for source in self.sources:
            out[source.first : source.first + source.count] = False
        return out


def _points(reader: TableReader, value: Any, label: str) -> FloatArray:
    """A list of [x, y] coordinates (possibly empty)."""
    if not isinstance(value, list):
        raise reader.fail(label, f"must be a list of [x, y] points, got {plain(value)}")
    if len(value) > MAX_WAYPOINTS:
        raise reader.fail(label, f"has {len(value)} points, more than {MAX_WAYPOINTS}")
    lo, hi, unit = BOUNDS["coordinate"]
    out = np.zeros((len(value), 2))
    for k, row in enumerate(value):
        ok = isinstance(row, list) and len(row) == 2
        ok = ok and all(not isinstance(v, bool) and isinstance(v, int | float) for v in row)
        if not ok or not all(math.isfinite(float(v)) and lo <= v <= hi for v in row):
            raise reader.fail(
                f"{label}[{k}]",
                f"must be [x, y] with finite values in [{lo:g}, {hi:g}] {unit}, got {plain(row)}",
            )
        out[k] = row
    return out


def _seconds(reader: TableReader, value: Any, label: str, count: int) -> FloatArray:
    if not isinstance(value, list) or len(value) != count:
        raise reader.fail(label, f"needs one wait per waypoint ({count}), got {plain(value)}")
    out = np.zeros(count)
    for k, item in enumerate(value):
        if isinstance(item, bool) or not isinstance(item, int | float):
            raise reader.fail(f"{label}[{k}]", f"must be a number of seconds, got {plain(item)}")
        if not 0.0 <= float(item) <= 1e6:  # also false for NaN
            raise reader.fail(f"{label}[{k}]", f"must be in [0, 1e6] s, got {plain(item)}")
        out[k] = float(item)
    return out


def _tables(reader: TableReader, key: str) -> list[dict[str, Any]]:
    """``key`` as an array of tables (``[[pedestrians.groups]]``, ...)."""
    value = reader.raw(key)
    if not isinstance(value, list):
        raise reader.fail(key, f"must be an array of tables, got {plain(value)}")
    for i, table in enumerate(value):
        if not isinstance(table, dict):
            raise reader.fail(f"{key}[{i}]", f"must be a table, got {plain(table)}")
    return value


def _entry_time(reader: TableReader, value: Any, label: str, horizon_s: float) -> float:
    """An entry time (s): a number in [0, horizon)."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise reader.fail(label, f"must be a number of seconds, got {plain(value)}")
    if not 0.0 <= float(value) < horizon_s:  # also false for NaN
        raise reader.fail(
            label, f"must be in [0, {horizon_s:g}) s (before the horizon), got {plain(value)}"
        )
    return float(value)


def read_pedestrians(
    p: TableReader,
    starts: FloatArray | None,
    goals: FloatArray | None,
    horizon_s: float,
    regions: Mapping[str, tuple[float, float, float, float]],
) -> PedestrianLayout:
    """Routes, waits, groups, standing pedestrians, entry times and sources of
    ``[pedestrians]`` (version 2); ``horizon_s`` bounds the entry times, ``regions``
    are the scenario's named regions (a source's ``goal_region``)."""
    n_listed = 0 if starts is None else starts.shape[0]
    s_list = [] if starts is None else list(starts)
    g_list = [] if goals is None else list(goals)
    labels = [f"pedestrians.starts[{i}]" for i in range(n_listed)]
    routes: list[FloatArray] = [np.zeros((0, 2)) for _ in range(n_listed)]
    if p.has("routes"):
        value = p.raw("routes")
        if not isinstance(value, list) or len(value) != n_listed:
            got = len(value) if isinstance(value, list) else repr(value)
            raise p.fail(
                "routes", f"needs one waypoint list per listed pedestrian ({n_listed}), got {got}"
            )
        routes = [_points(p, v, f"routes[{i}]") for i, v in enumerate(value)]
    waits = [np.zeros(len(r)) for r in routes]
    if p.has("waits_s"):
        value = p.raw("waits_s")
        if not isinstance(value, list) or len(value) != n_listed:
            raise p.fail(
                "waits_s", f"needs one list per listed pedestrian ({n_listed}), got {plain(value)}"
            )
        waits = [_seconds(p, v, f"waits_s[{i}]", len(routes[i])) for i, v in enumerate(value)]
    enter = [0.0] * n_listed
    if p.has("enter_s"):
        value = p.raw("enter_s")
        if not isinstance(value, list) or len(value) != n_listed:
            raise p.fail(
                "enter_s",
                f"needs one entry time per listed pedestrian ({n_listed}), got {plain(value)}",
            )
        enter = [_entry_time(p, v, f"enter_s[{i}]", horizon_s) for i, v in enumerate(value)]
    groups: list[tuple[int, ...]] = []
    if p.has("groups"):
        for gi, table in enumerate(_tables(p, "groups")):
            members, group_enter = _group(p, table, gi, horizon_s)
            first = len(s_list)
            for start, goal, route in members:
                s_list.append(start)
                g_list.append(goal)
                routes.append(route)
                waits.append(np.zeros(len(route)))
                labels.append(f"pedestrians.groups[{gi}]")
                enter.append(group_enter)
            groups.append(tuple(range(first, len(s_list))))
    standing: list[int] = []
    if p.has("standing"):
        for k, point in enumerate(_points(p, p.raw("standing"), "standing")):
            standing.append(len(s_list))
            s_list.append(point)
            g_list.append(point.copy())
            routes.append(np.zeros((0, 2)))
            waits.append(np.zeros(0))
            labels.append(f"pedestrians.standing[{k}]")
            enter.append(0.0)
    sources: list[EntrySource] = []
    if p.has("sources"):
        for si, table in enumerate(_tables(p, "sources")):
            source, (start, goal, route) = _source(p, table, si, len(s_list), horizon_s, regions)
            for _ in range(source.count):
                s_list.append(start.copy())
                g_list.append(goal.copy())
                routes.append(route)
                waits.append(np.zeros(len(route)))
                labels.append(f"pedestrians.sources[{si}]")
                enter.append(source.start_s)
            sources.append(source)
    if not s_list:
        raise p.fail(
            "starts", "needs at least one pedestrian (starts, groups, standing or sources)"
        )
    for arr in (*routes, *waits):
        arr.setflags(write=False)
    enter_s = np.array(enter, dtype=np.float64)
    enter_s.setflags(write=False)
    return PedestrianLayout(
        starts=np.array(s_list, dtype=np.float64).reshape(-1, 2),
        goals=np.array(g_list, dtype=np.float64).reshape(-1, 2),
        routes=tuple(routes),
        waits_s=tuple(waits),
        groups=tuple(groups),
        standing=tuple(standing),
        labels=tuple(labels),
        enter_s=enter_s,
        sources=tuple(sources),
    )


def _source(
    p: TableReader,
    table: dict[str, Any],
    si: int,
    first: int,
    horizon_s: float,
    regions: Mapping[str, tuple[float, float, float, float]],
) -> tuple[EntrySource, tuple[FloatArray, FloatArray, FloatArray]]:
    """Source ``si``: its entry schedule and its members' (start, goal, route); with a
    ``goal_region`` (instead of ``goal``) the goal is the region's centre until a seed
    draws each member's own.

    Its ``count`` entries lie in [start_s, start_s + count / rate_per_s], which must
    end before the horizon, and at least ``headway_s`` apart, which must fit in it.
    """
    q = TableReader(table, p.key(f"sources[{si}]"), p.file)
    start = q.bounded_array("start", 0, required=True, kinds=("coordinate",))
    region = q.string("goal_region") if q.has("goal_region") else None
    goal = q.bounded_array("goal", 0, required=region is None, kinds=("coordinate",))
    box: tuple[float, float, float, float] | None = None
    if region is not None:
        if goal is not None:
            raise q.fail("goal", "give either goal or goal_region, not both")
        if region not in regions:
            known = ", ".join(sorted(regions)) or "none"
            raise q.fail("goal_region", f"no region {region!r} in [regions]; regions: {known}")
        box = regions[region]
        goal = np.array([(box[0] + box[2]) / 2.0, (box[1] + box[3]) / 2.0])
    route = _points(q, q.raw("route"), "route") if q.has("route") else np.zeros((0, 2))
    count = q.integer("count", 1, minimum=1, maximum=MAX_SOURCE_COUNT)
    rate = q.number("rate_per_s", minimum=0.0, strict=True, maximum=1e3)
    start_s = _entry_time(q, q.raw("start_s"), "start_s", horizon_s) if q.has("start_s") else 0.0
    headway = q.number("headway_s", DEFAULT_HEADWAY_S, minimum=0.0, maximum=1e6)
    q.finish()
    assert start is not None
    assert goal is not None
    source = EntrySource(
        first=first,
        count=count,
        rate_per_s=rate,
        start_s=start_s,
        headway_s=headway,
        goal_region=region,
        goal_box=box,
    )
    end = start_s + source.window_s
    if end >= horizon_s:
        raise q.fail(
            "rate_per_s",
            f"{count} entries at {rate:g} per s from {start_s:g} s last until {end:g} s, "
            f"not before the horizon ({horizon_s:g} s); raise the rate or lower count",
        )
    if (count - 1) * headway > source.window_s:
        raise q.fail(
            "headway_s",
            f"{count} entries {headway:g} s apart need {(count - 1) * headway:g} s, more "
            f"than the {source.window_s:g} s that count / rate_per_s gives them",
        )
    return source, (start, goal, route)


def _group(
    p: TableReader, table: dict[str, Any], gi: int, horizon_s: float
) -> tuple[list[tuple[FloatArray, FloatArray, FloatArray]], float]:
    """The members (start, goal, route) of group ``gi`` (side by side across the
    direction of its first leg, ``spacing_m`` apart, sharing the route's shape) and
    the group's entry time."""
    g = TableReader(table, p.key(f"groups[{gi}]"), p.file)
    start = g.bounded_array("start", 0, required=True, kinds=("coordinate",))
    goal = g.bounded_array("goal", 0, required=True, kinds=("coordinate",))
    size = g.integer("size", 2, minimum=1, maximum=MAX_GROUP_SIZE)
    spacing = g.number("spacing_m", 0.8, kind="length")
    route = _points(g, g.raw("route"), "route") if g.has("route") else np.zeros((0, 2))
    enter = _entry_time(g, g.raw("enter_s"), "enter_s", horizon_s) if g.has("enter_s") else 0.0
    g.finish()
    assert start is not None
    assert goal is not None
    towards = route[0] if len(route) else goal
    d = towards - start
    norm = float(np.hypot(*d))
    if norm == 0.0:
        raise g.fail("goal", "must differ from start (the group's direction)")
    across = np.array([-d[1], d[0]]) / norm
    out = []
    for j in range(size):
        offset = (j - (size - 1) / 2.0) * spacing * across
        out.append((start + offset, goal + offset, route + offset))
    return out, enter


def read_walls(o: TableReader) -> tuple[FloatArray, list[str]]:
    """Wall segments (M, 4) from ``walls`` (4 numbers, or 5 with a thickness) and
    ``doors`` cut out of them; the label of each segment's source key."""
    lines: list[tuple[shapely.Geometry, float, str]] = []
    if o.has("walls"):
        value = o.raw("walls")
        if not isinstance(value, list):
            raise o.fail("walls", f"must be an array, got {plain(value)}")
        lo, hi, _ = BOUNDS["coordinate"]
        for i, row in enumerate(value):
            label = f"walls[{i}]"
            ok = isinstance(row, list) and len(row) in (4, 5)
            ok = ok and all(not isinstance(v, bool) and isinstance(v, int | float) for v in row)
            ok = ok and all(math.isfinite(float(v)) for v in row)
            if not ok:
                raise o.fail(
                    label,
                    f"must be [x1, y1, x2, y2] or [x1, y1, x2, y2, thickness], got {plain(row)}",
                )
            if not all(lo <= v <= hi for v in row[:4]):
                raise o.fail(label, f"coordinates must be in [{lo:g}, {hi:g}] m, got {plain(row)}")
            thick = float(row[4]) if len(row) == 5 else 0.0
            if not 0.0 <= thick <= BOUNDS["length"][1]:
                raise o.fail(label, f"thickness must be >= 0 m, got {plain(row[4])}")
            check_wall_length(o, label, row)
            a, b = (row[0], row[1]), (row[2], row[3])
            lines.append((shapely.LineString([a, b]), thick, o.key(label)))
    doors: list[tuple[shapely.Geometry, str]] = []
    if o.has("doors"):
        value = o.raw("doors")
        if not isinstance(value, list):
            raise o.fail("doors", f"must be an array, got {plain(value)}")
        for i, row in enumerate(value):
            ok = isinstance(row, list) and len(row) == 4
            ok = ok and all(not isinstance(v, bool) and isinstance(v, int | float) for v in row)
            if not ok or not all(math.isfinite(float(v)) for v in row) or row[:2] == row[2:]:
                raise o.fail(
                    f"doors[{i}]",
                    f"must be an opening [x1, y1, x2, y2] of non-zero width, got {plain(row)}",
                )
            doors.append((shapely.LineString([row[:2], row[2:]]), f"doors[{i}]"))
    used = [False] * len(doors)
    segments: list[list[float]] = []
    labels: list[str] = []
    for geom, thick, label in lines:
        shape = geom.buffer(thick / 2.0, cap_style="flat") if thick > THIN_WALL_M else geom
        for k, (door, _) in enumerate(doors):
            # the opening: a rectangle across the wall, as long as the door
            cut = door.buffer(max(thick, 0.01), cap_style="flat")
            if shape.intersects(cut):
                used[k] = True
                shape = shape.difference(cut)
        for seg in _segments(shape):
            segments.append(seg)
            labels.append(label)
    for k, (_, label) in enumerate(doors):
        if not used[k]:
            raise o.fail(label, "lies on no wall (a door is an opening cut out of a wall)")
    return np.array(segments, dtype=np.float64).reshape(-1, 4), labels


def _segments(shape: shapely.Geometry) -> list[list[float]]:
    """The straight pieces of a line, a polygon's outline, or a point (zero length)."""
    out: list[list[float]] = []
    if shape.is_empty:
        return out
    if isinstance(shape, shapely.Point):
        return [[shape.x, shape.y, shape.x, shape.y]]
    if isinstance(shape, shapely.LineString):
        c = shapely.get_coordinates(shape)
        return [[*c[i], *c[i + 1]] for i in range(len(c) - 1)]
    if isinstance(shape, shapely.Polygon):
        return _segments(shape.exterior) + [s for r in shape.interiors for s in _segments(r)]
    if isinstance(shape, shapely.LinearRing):
        return _segments(shapely.LineString(shape.coords))
    for part in getattr(shape, "geoms", ()):
        out.extend(_segments(part))
    return out


def read_regions(
    top: TableReader, world: WorldBounds
) -> dict[str, tuple[float, float, float, float]]:
    """``[regions]``: name = [x_min, y_min, x_max, y_max] inside the world."""
    out: dict[str, tuple[float, float, float, float]] = {}
    if not top.has("regions"):
        return out
    r = top.table("regions")
    for name in list(r.data):
        value = r.raw(name)
        ok = isinstance(value, list) and len(value) == 4
        ok = ok and all(not isinstance(v, bool) and isinstance(v, int | float) for v in value)
        if not ok or not all(math.isfinite(float(v)) for v in value):
            raise r.fail(name, f"must be [x_min, y_min, x_max, y_max], got {plain(value)}")
        x0, y0, x1, y1 = (float(v) for v in value)
        if not (x1 > x0 and y1 > y0):
            raise r.fail(name, f"needs x_max > x_min and y_max > y_min, got {plain(value)}")
        if not (world.contains(x0, y0) and world.contains(x1, y1)):
            raise r.fail(name, f"must lie inside the world, got {plain(value)}")
        out[name] = (x0, y0, x1, y1)
    r.finish()
    return out


MAX_RECORDING_SAMPLES: Final = 1_000_000
# How far the recording's first position may be from robot.start (m): a recording
# that starts elsewhere would make the replay jump at its first step.
RECORDING_START_TOLERANCE_M: Final = 1e-6


@attrs.frozen(eq=False)
class RobotRecording:
    """A recorded robot trajectory (``[robot.recording]``), replayed by the ``recorded``
    planner (:class:`srfm.planners.recorded.RecordedRobotPlanner`).

    Attributes:
        times_s: (n,) times (s) from 0, strictly increasing, n >= 2.
        xy: (n, 2) positions (m), the first at the robot's start.
    """

    times_s: FloatArray
    xy: FloatArray


def read_recording(robot: TableReader, world: WorldBounds, start: FloatArray) -> RobotRecording:
    """``[robot.recording]``: ``times_s`` (s, from 0, strictly increasing) and ``xy``
    (one [x, y] per time, inside the world, the first at ``robot.start``)."""
    rec = robot.table("recording")
    times = rec.raw("times_s") if rec.has("times_s") else None
    if not isinstance(times, list) or not 2 <= len(times) <= MAX_RECORDING_SAMPLES:
        raise rec.fail(
            "times_s",
            f"must be a list of 2 to {MAX_RECORDING_SAMPLES} times (s), got {plain(times)}",
        )
    t = np.zeros(len(times))
    for k, item in enumerate(times):
        if isinstance(item, bool) or not isinstance(item, int | float):
            raise rec.fail(f"times_s[{k}]", f"must be a number of seconds, got {plain(item)}")
        if not 0.0 <= float(item) <= 1e7:  # also false for NaN
            raise rec.fail(f"times_s[{k}]", f"must be in [0, 1e7] s, got {plain(item)}")
        t[k] = float(item)
        if k == 0 and t[0] != 0.0:
            raise rec.fail("times_s[0]", f"must be 0 (the episode's start), got {plain(item)}")
        if k > 0 and t[k] <= t[k - 1]:
            raise rec.fail(
                f"times_s[{k}]",
                f"must be later than times_s[{k - 1}] = {t[k - 1]!r}, got {plain(item)}",
            )
    points = rec.raw("xy") if rec.has("xy") else None
    if not isinstance(points, list) or len(points) != len(times):
        got = len(points) if isinstance(points, list) else repr(points)
        raise rec.fail("xy", f"needs one [x, y] per time ({len(times)}), got {got}")
    xy = np.zeros((len(points), 2))
    for k, row in enumerate(points):
        ok = isinstance(row, list) and len(row) == 2
        ok = ok and all(not isinstance(v, bool) and isinstance(v, int | float) for v in row)
        if not ok or not all(math.isfinite(float(v)) for v in row):
            raise rec.fail(f"xy[{k}]", f"must be [x, y] with finite numbers, got {plain(row)}")
        if not world.contains(float(row[0]), float(row[1])):
            raise rec.fail(f"xy[{k}]", f"must lie inside the world {world}, got {plain(row)}")
        xy[k] = row
    rec.finish()
    gap = float(np.hypot(*(xy[0] - start)))
    if gap > RECORDING_START_TOLERANCE_M:
        raise rec.fail(
            "xy[0]",
            f"must be robot.start {start.tolist()} (the replay starts there), got "
            f"{xy[0].tolist()}, {gap:.3g} m away",
        )
    t.setflags(write=False)
    xy.setflags(write=False)
    return RobotRecording(t, xy)
