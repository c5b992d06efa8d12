"""The global router: paths around walls keep the clearance, and are shortest."""

from __future__ import annotations

import numpy as np
import pytest
import shapely

from srfm.errors import PlannerError
from srfm.models.state import Obstacles
from srfm.world import Router, WorldBounds, next_waypoint

WORLD = WorldBounds(x_min=0.0, x_max=10.0, y_min=0.0, y_max=10.0)
# A wall across the middle at x = 5 with a 1.2 m door between y = 6 and y = 7.2.
DOOR_WALLS = Obstacles.create(segments=[[5.0, 0.0, 5.0, 6.0], [5.0, 7.2, 5.0, 10.0]])


def _clear_of(path: np.ndarray, start: tuple[float, float], obstacles: Obstacles) -> float:
    """Smallest distance from the polyline start -> path to any wall or pillar."""
    line = shapely.LineString([start, *map(tuple, path)])
    walls = [shapely.LineString([(a, b), (c, d)]) for a, b, c, d in obstacles.segments]
    pillars = [shapely.Point(x, y).buffer(r) for x, y, r in obstacles.circles]
    return min(line.distance(w) for w in walls + pillars)


def test_open_field_route_is_the_goal() -> None:
    router = Router(Obstacles.create(), WORLD, clearance_m=0.3)
    path = router.route((1.0, 1.0), (9.0, 9.0))
    assert path.tolist() == [[9.0, 9.0]]


def test_route_goes_through_the_door_with_clearance() -> None:
    router = Router(DOOR_WALLS, WORLD, clearance_m=0.4)
    path = router.route((2.0, 2.0), (8.0, 2.0))
    assert path[-1].tolist() == [8.0, 2.0]
    assert len(path) >= 2  # the wall blocks the straight line
    assert _clear_of(path, (2.0, 2.0), DOOR_WALLS) >= 0.4 - 1e-9
    # Passes the wall plane inside the door.
    line = shapely.LineString([(2.0, 2.0), *map(tuple, path)])
    crossing = line.intersection(shapely.LineString([(5.0, 0.0), (5.0, 10.0)]))
    assert 6.0 + 0.4 <= crossing.y <= 7.2 - 0.4
    # Near the shortest: at least the legs via the point 0.4 m above the door's lower jamb.
    length = line.length
    corner = np.array([5.0, 6.4])
    bound = np.hypot(*(corner - (2.0, 2.0))) + np.hypot(*(corner - (8.0, 2.0)))
    assert bound <= length <= bound + 0.5


def test_door_narrower_than_the_disc_is_refused() -> None:
    router = Router(DOOR_WALLS, WORLD, clearance_m=0.7)  # 1.4 m disc, 1.2 m door
    with pytest.raises(PlannerError, match="no path from"):
        router.route((2.0, 2.0), (8.0, 2.0))


def test_start_inside_a_pillar_is_refused() -> None:
    router = Router(Obstacles.create(circles=[[3.0, 3.0, 1.0]]), WORLD, clearance_m=0.2)
    with pytest.raises(PlannerError, match=r"route start \(3, 3\)"):
        router.route((3.0, 3.0), (8.0, 8.0))


def test_route_around_a_pillar_keeps_clearance() -> None:
    obstacles = Obstacles.create(circles=[[5.0, 5.0, 1.5]])
    router = Router(obstacles, WORLD, clearance_m=0.3)
    path = router.route((1.0, 5.0), (9.0, 5.0))
    assert len(path) >= 2
    assert _clear_of(path, (1.0, 5.0), obstacles) >= 0.3 - 1e-9


def test_routes_are_deterministic() -> None:
    a = Router(DOOR_WALLS, WORLD, clearance_m=0.4).route((2.0, 8.0), (8.0, 1.0))
    b = Router(DOOR_WALLS, WORLD, clearance_m=0.4).route((2.0, 8.0), (8.0, 1.0))
    assert a.tobytes() == b.tobytes()


def test_next_waypoint_switches_within_the_radius_and_keeps_the_goal() -> None:
    path = np.array([[1.0, 0.0], [2.0, 0.0], [3.0, 0.0]])
    assert next_waypoint(path, 0, np.array([0.0, 0.0]), 0.5) == 0
    assert next_waypoint(path, 0, np.array([0.9, 0.0]), 0.5) == 1
    assert next_waypoint(path, 0, np.array([2.9, 0.0]), 5.0) == 2  # never past the goal


def test_negative_clearance_is_refused() -> None:
    with pytest.raises(PlannerError, match="clearance_m must be"):
        Router(DOOR_WALLS, WORLD, clearance_m=-1.0)
