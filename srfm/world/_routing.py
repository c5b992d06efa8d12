"""Global routing over the static map: a visibility graph with clearance.

The free space is the world rectangle shrunk by the clearance, minus every wall
(a segment) and pillar (a circle) grown by the clearance; shapely does the geometry.
The graph's nodes are the corners of the obstacles grown a little more than the
clearance (so that paths between them keep the clearance), plus the start and the
goal; two nodes are joined when the straight segment between them lies in the free
space. scipy's Dijkstra gives the shortest path. The route is the list of waypoints
after the start, ending at the goal; a local planner steers to the next one
(:func:`next_waypoint`).

    router = Router(obstacles, world, clearance_m=0.4)
    waypoints = router.route((1.0, 1.0), (9.0, 9.0))   # (K, 2), last row = goal
"""

from __future__ import annotations

import math
from typing import Final

import numpy as np
import shapely
from numpy.typing import NDArray

from srfm._text import plain
from srfm.errors import PlannerError
from srfm.models.state import Obstacles
from srfm.world._bounds import WorldBounds

FloatArray = NDArray[np.float64]

# Nodes sit this much (m) beyond the clearance, so that a segment between two of
# them does not graze the grown obstacle because of the polygon approximation.
NODE_MARGIN_M: Final = 0.02
# Quarter-circle segments of the grown obstacles (shapely's quad_segs).
QUAD_SEGS: Final = 3


class Router:
    """Shortest collision-free paths of a disc of radius ``clearance_m`` among obstacles."""

    def __init__(self, obstacles: Obstacles, world: WorldBounds, *, clearance_m: float) -> None:
        if not (np.isfinite(clearance_m) and clearance_m >= 0.0):
            raise PlannerError(f"clearance_m must be finite and >= 0, got {plain(clearance_m)}")
        self.clearance_m = float(clearance_m)
        shapes = _obstacle_shapes(obstacles)
        box = shapely.box(world.x_min, world.y_min, world.x_max, world.y_max)
        inner = box.buffer(-self.clearance_m, join_style="mitre")
        grown = shapely.union_all([_grow(s, r + self.clearance_m) for s, r in shapes])
        self.free = inner.difference(grown)
        if self.free.is_empty:
            raise PlannerError(f"no free space left with clearance_m = {clearance_m!r}")
        shapely.prepare(self.free)
        corners: list[tuple[float, float]] = []
        for shape, radius in shapes:
            outline = _grow(shape, radius + self.clearance_m + NODE_MARGIN_M)
            corners.extend(tuple(c) for c in shapely.get_coordinates(outline.exterior)[:-1])
        pts = np.array(corners, dtype=np.float64).reshape(-1, 2)
        keep = shapely.covers(self.free, shapely.points(pts)) if len(pts) else np.zeros(0, bool)
        self.nodes: FloatArray = pts[keep]
        # Visibility among the fixed nodes, computed once.
        self._node_edges = self._visible(self.nodes, self.nodes)

    def contains(self, x: float, y: float) -> bool:
        """True when a disc of the clearance at (x, y) is clear of obstacles and edges."""
        return bool(self.free.covers(shapely.Point(x, y)))

    def _visible(self, a: FloatArray, b: FloatArray) -> NDArray[np.bool_]:
        """(len(a), len(b)) mask: the segment a_i b_j lies in the free space."""
        if len(a) == 0 or len(b) == 0:
            return np.zeros((len(a), len(b)), dtype=bool)
        ia, ib = np.meshgrid(np.arange(len(a)), np.arange(len(b)), indexing="ij")
        coords = np.stack([a[ia.ravel()], b[ib.ravel()]], axis=1)
        lines = shapely.linestrings(coords)
        return np.asarray(shapely.covers(self.free, lines)).reshape(len(a), len(b))

    def route(self, start: tuple[float, float], goal: tuple[float, float]) -> FloatArray:
        """Waypoints (K, 2) from ``start`` to ``goal`` (the last row is the goal).

        Raises:
            PlannerError: start or goal not in the free space, or no path joins them.
        """
        s = np.asarray(start, dtype=np.float64).reshape(2)
        g = np.asarray(goal, dtype=np.float64).reshape(2)
        for label, p in (("start", s), ("goal", g)):
            if not self.contains(float(p[0]), float(p[1])):
                raise PlannerError(
                    f"route {label} ({p[0]:g}, {p[1]:g}) is within {self.clearance_m:g} m "
                    "of a wall, pillar or world edge"
                )
        if self._visible(s[None], g[None])[0, 0]:
            return g[None].copy()
        n = len(self.nodes)
        pts = np.vstack([self.nodes, s[None], g[None]])
        vis = np.zeros((n + 2, n + 2), dtype=bool)
        vis[:n, :n] = self._node_edges
        ends = self._visible(pts[n:], pts)
        vis[n:, :] = ends
        vis[:, n:] = ends.T
        np.fill_diagonal(vis, False)
        length = np.linalg.norm(pts[:, None, :] - pts[None, :, :], axis=2)
        from scipy.sparse import csr_array  # here: a scene without walls needs no scipy
        from scipy.sparse.csgraph import dijkstra

        graph = csr_array(np.where(vis, np.maximum(length, 1e-12), 0.0))
        dist, pred = dijkstra(graph, directed=False, indices=n, return_predecessors=True)
        if not np.isfinite(dist[n + 1]):
            raise PlannerError(
                f"no path from ({s[0]:g}, {s[1]:g}) to ({g[0]:g}, {g[1]:g}) "
                f"with clearance {self.clearance_m:g} m"
            )
        order = [n + 1]
        while order[-1] != n:
            order.append(int(pred[order[-1]]))
        return pts[order[::-1][1:]].copy()


def next_waypoint(
    waypoints: FloatArray, index: int, position: FloatArray, switch_radius_m: float
) -> int:
    """Index of the waypoint to steer to: advance past those within ``switch_radius_m``.

    The last waypoint (the goal) is never skipped.
    """
    last = len(waypoints) - 1
    while index < last and float(np.hypot(*(waypoints[index] - position))) <= switch_radius_m:
        index += 1
    return index


def _grow(shape: shapely.Geometry, distance_m: float) -> shapely.Geometry:
    """``shape`` grown by ``distance_m``; the polygon's arcs circumscribe the true ones
    (shapely puts arc vertices on the circle, so its edges would cut inside it)."""
    return shape.buffer(distance_m / math.cos(math.pi / (4 * QUAD_SEGS)), quad_segs=QUAD_SEGS)


def _obstacle_shapes(obstacles: Obstacles) -> list[tuple[shapely.Geometry, float]]:
    """Each wall as a segment (radius 0), each pillar as its centre and radius."""
    shapes: list[tuple[shapely.Geometry, float]] = []
    for x1, y1, x2, y2 in obstacles.segments:
        if (x1, y1) == (x2, y2):
            shapes.append((shapely.Point(x1, y1), 0.0))
        else:
            shapes.append((shapely.LineString([(x1, y1), (x2, y2)]), 0.0))
    for cx, cy, r in obstacles.circles:
        shapes.append((shapely.Point(cx, cy), float(r)))
    return shapes
