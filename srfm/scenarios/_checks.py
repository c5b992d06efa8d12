"""The physical checks of a fixed scenario, for every schema version.

A scenario whose pedestrians are listed (``kind = "fixed"``) must describe a scene that
can start: every start, waypoint and goal inside the world, no two agents (the robot
and the pedestrians there at the start) overlapping, no start, goal or waypoint closer
to a wall or pillar than the agent's radius, and every waypoint and goal reachable
from the point before it. Version 1 (listed starts and goals) and version 2 (routes,
groups, standing pedestrians, sources) are checked alike: a version-1 file is the
version-2 layout without routes, in which everyone is there at the start. A random
scenario draws its people per seed under its ``[random]`` constraints instead.

The checks of single values (types, bounds, zero-length walls) are where the values are
read (:mod:`srfm.scenarios._schema`, :mod:`srfm.scenarios._reader`).
"""

from __future__ import annotations

from typing import Final

import numpy as np
import shapely
from numpy.typing import NDArray

from srfm.errors import PlannerError, ScenarioError
from srfm.models.state import Obstacles
from srfm.scenarios._v2 import PedestrianLayout
from srfm.world import Router, WorldBounds

__all__ = ["check_layout", "listed_layout"]

FloatArray = NDArray[np.float64]


def listed_layout(starts: FloatArray, goals: FloatArray) -> PedestrianLayout:
    """The layout of listed pedestrians only (a version-1 file): no routes, no waits,
    everyone there at the start, each named by its ``pedestrians.starts[i]`` key."""
    n = starts.shape[0]
    return PedestrianLayout(
        starts=starts,
        goals=goals,
        routes=tuple(np.zeros((0, 2)) for _ in range(n)),
        waits_s=tuple(np.zeros(0) for _ in range(n)),
        groups=(),
        standing=(),
        labels=tuple(f"pedestrians.starts[{i}]" for i in range(n)),
        enter_s=np.zeros(n),
    )


def _goal_key(label: str) -> str:
    """The key naming a pedestrian's goal: ``pedestrians.goals[i]`` for a listed one,
    the group, standing or source key otherwise."""
    return label.replace("starts", "goals") if "starts" in label else label


def _check_inside(source: str, layout: PedestrianLayout, world: WorldBounds) -> None:
    """Every pedestrian's start, waypoints and goal inside the world (as the robot's)."""

    def outside(points: FloatArray) -> NDArray[np.bool_]:
        x, y = points[:, 0], points[:, 1]
        inside = (x >= world.x_min) & (x <= world.x_max) & (y >= world.y_min) & (y <= world.y_max)
        return np.asarray(~inside)

    for q in np.flatnonzero(outside(layout.starts) | outside(layout.goals)):
        p = int(q)
        label = layout.labels[p]
        for key, point in ((label, layout.starts[p]), (_goal_key(label), layout.goals[p])):
            if outside(point[None])[0]:
                raise ScenarioError(
                    f"{source}: {key}: {point.tolist()} lies outside the world {world}"
                )
    for r, route in enumerate(layout.routes):
        away = np.flatnonzero(outside(route)) if route.shape[0] else np.zeros(0, dtype=int)
        if away.size:
            k = int(away[0])
            raise ScenarioError(
                f"{source}: pedestrians.routes[{r}][{k}]: {route[k].tolist()} lies outside "
                f"the world {world}"
            )


_ALL_PAIRS: Final = 256  # discs up to which _worst_overlap measures every pair


def _worst_overlap(points: FloatArray, radii: FloatArray) -> tuple[int, int, float] | None:
    """The pair i < j of discs overlapping most (gap = distance − r_i − r_j < 0; the
    first such pair in (i, j) order among equal gaps), or None. Only pairs closer than
    twice the largest radius are measured (a k-d tree), so 100,000 starts are checked
    in a second instead of a matrix of 10^10 distances; up to ``_ALL_PAIRS`` discs,
    every pair (the same answer: a pair further apart does not overlap), without
    importing scipy."""
    n = points.shape[0]
    if n < 2 or float(radii.max()) <= 0.0:
        return None
    if n <= _ALL_PAIRS:
        i, j = np.triu_indices(n, 1)
    else:
        from scipy.spatial import cKDTree

        pairs = cKDTree(points).query_pairs(2.0 * float(radii.max()), output_type="ndarray")
        if pairs.shape[0] == 0:
            return None
        pairs = np.sort(pairs, axis=1)
        i, j = pairs[:, 0], pairs[:, 1]
    gap = np.linalg.norm(points[i] - points[j], axis=1) - radii[i] - radii[j]
    order = np.lexsort((j, i, gap))  # the smallest gap first, then (i, j)
    k = int(order[0])
    if gap[k] >= 0.0:
        return None
    return int(i[k]), int(j[k]), float(gap[k])


def check_layout(
    source: str,
    layout: PedestrianLayout,
    radius: FloatArray,
    obstacles: Obstacles,
    world: WorldBounds,
    robot_start: FloatArray,
    robot_goal: FloatArray,
    robot_radius: float,
) -> None:
    """Refuse a start, waypoint or goal outside the world, overlapping starts (of the
    robot and the pedestrians there at sample 0; those entering later may come where
    others stood), walls through a start, goal or waypoint, and waypoints that no path
    reaches (the router's free space for a disc of the pedestrian's radius).

    Raises:
        ScenarioError: naming the file and the key.
    """
    _check_inside(source, layout, world)
    there = np.flatnonzero(layout.at_start())
    starts = np.vstack([robot_start[None], layout.starts[there]])
    radii = np.concatenate([[robot_radius], radius[there]])
    overlap = _worst_overlap(starts, radii)
    if overlap is not None:
        i, j, gap = overlap
        names = ["robot.start", *(layout.labels[k] for k in there)]
        raise ScenarioError(
            f"{source}: {names[j]}: overlaps {names[i]} at the start "
            f"({starts[j].tolist()} and {starts[i].tolist()}, {-gap:.3g} m of overlap)"
        )
    if obstacles.empty:
        return
    shapes = [
        shapely.LineString([(a, b), (c, d)]) if (a, b) != (c, d) else shapely.Point(a, b)
        for a, b, c, d in obstacles.segments
    ] + [shapely.Point(cx, cy).buffer(r) for cx, cy, r in obstacles.circles]
    walls = shapely.union_all(shapes)

    def clear(point: FloatArray, r: float, label: str) -> None:
        d = float(shapely.distance(shapely.Point(point), walls))
        if d < r:
            raise ScenarioError(
                f"{source}: {label}: {point.tolist()} is {d:.3g} m from a wall or pillar, "
                f"less than the radius {r:g} m"
            )

    clear(robot_start, robot_radius, "robot.start")
    clear(robot_goal, robot_radius, "robot.goal")
    for si, src in enumerate(layout.sources):
        if src.goal_box is None:
            continue
        r = float(radius[src.first])
        d = float(shapely.distance(shapely.box(*src.goal_box), walls))
        if d < r:
            raise ScenarioError(
                f"{source}: pedestrians.sources[{si}].goal_region: region "
                f"{src.goal_region!r} comes {d:.3g} m from a wall or pillar, less than "
                f"the radius {r:g} m (every point of it may be drawn as a goal)"
            )
    routers: dict[float, Router] = {}
    for p, label in enumerate(layout.labels):
        r = float(radius[p])
        clear(layout.starts[p], r, label)
        key = _goal_key(label)
        clear(layout.goals[p], r, key)
        if r not in routers:
            routers[r] = Router(obstacles, world.grown(r), clearance_m=r)
        points = [layout.starts[p], *layout.routes[p], layout.goals[p]]
        for k in range(1, len(points)):
            where = f"pedestrians.routes[{p}][{k - 1}]" if k < len(points) - 1 else key
            try:
                routers[r].route(tuple(points[k - 1]), tuple(points[k]))
            except PlannerError as exc:
                raise ScenarioError(f"{source}: {where}: unreachable: {exc}") from None
