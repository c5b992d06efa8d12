"""Routes through walled scenarios: what the robot's planner and each pedestrian steer to.

The one place where the goal is replaced by a waypoint, shared by the simulator
(:class:`srfm.sim.TwinSimulator`) and the gymnasium environment (:mod:`srfm.rl`):

- **Robot.** In a scenario with walls or pillars, :class:`RobotRoute` asks the global
  router (:class:`srfm.planners.routing.Router`, clearance = robot radius +
  ``ROBOT_CLEARANCE_MARGIN_M``) for a path from the start to the goal; every local
  planner then sees the path's current waypoint as ``Observation.robot_goal``. The
  robot moves on to the next waypoint when it comes within ``ROBOT_SWITCH_RADIUS_M``
  of the current one, or as soon as the next one is in sight (the straight segment to
  it lies in the router's free space), so that a robot pushed past a corner does not
  turn back to it. Goal reached, the reward and the metrics still use the goal.
- **Pedestrians.** Each pedestrian walks its scenario-given waypoints (schema 2,
  ``pedestrians.routes``) then its goal; one with only a goal in a scenario with
  obstacles gets the router's path (clearance = its radius) when a wall blocks the
  straight line. It steers to the next waypoint once within the scenario's
  ``switch_radius_m`` of the current one, after waiting there ``waits_s`` seconds when
  asked. The crowd's ``goal`` array holds the current waypoint (the force model's
  goal term steers to it; a record's goals show it); an arrival is counted at the
  goal only.

Scenarios without obstacles and without given routes use none of this: their
episodes are bit-identical to those of earlier versions.
"""

from __future__ import annotations

from typing import Final

import numpy as np
import shapely
from numpy.typing import NDArray

from srfm.errors import PlannerError
from srfm.models.state import Obstacles
from srfm.planners.routing import Router, next_waypoint
from srfm.scenarios import EpisodeSetup, Scenario, WorldBounds

__all__ = [
    "ROBOT_CLEARANCE_MARGIN_M",
    "ROBOT_SWITCH_RADIUS_M",
    "PedestrianRoutes",
    "RobotRoute",
    "pedestrian_waypoints",
    "router_for",
]

FloatArray = NDArray[np.float64]

ROBOT_CLEARANCE_MARGIN_M: Final = 0.1
ROBOT_SWITCH_RADIUS_M: Final = 0.75
_CACHE_SIZE: Final = 64
_routers: dict[tuple[int, int, float], tuple[Obstacles, WorldBounds, Router]] = {}


def router_for(obstacles: Obstacles, world: WorldBounds, clearance_m: float) -> Router:
    """A :class:`Router` of these obstacles, kept for reuse (building one costs ms)."""
    key = (id(obstacles), id(world), float(clearance_m))
    hit = _routers.get(key)
    if hit is not None and hit[0] is obstacles and hit[1] is world:
        return hit[2]
    router = Router(obstacles, world, clearance_m=clearance_m)
    if len(_routers) >= _CACHE_SIZE:
        _routers.pop(next(iter(_routers)))
    _routers[key] = (obstacles, world, router)
    return router


def _open_world(world: WorldBounds, margin: float) -> WorldBounds:
    """The world grown by ``margin``: its edge is no wall for pedestrians."""
    return WorldBounds(
        x_min=world.x_min - margin,
        x_max=world.x_max + margin,
        y_min=world.y_min - margin,
        y_max=world.y_max + margin,
    )


class RobotRoute:
    """The waypoint the robot's planner steers to (see the module doc).

    When no path joins the start and the goal (the router's clearance is the robot
    radius plus a margin, then the radius alone), the route is the goal itself: the
    planner steers straight at it, as without routing.
    """

    def __init__(self, scenario: Scenario, start: FloatArray, goal: FloatArray) -> None:
        radius = scenario.robot.radius_m
        self.router: Router | None = None
        self.waypoints: FloatArray = np.array(goal, dtype=np.float64).reshape(1, 2)
        for clearance in (radius + ROBOT_CLEARANCE_MARGIN_M, radius):
            try:
                router = router_for(scenario.obstacles, scenario.world, clearance)
                self.waypoints = router.route(tuple(start), tuple(goal))
            except PlannerError:
                continue
            self.router = router
            break
        self.index = 0

    def update(self, x: float, y: float) -> FloatArray:
        """Advance past reached or bypassed waypoints from (x, y); the current one."""
        pos = np.array([x, y])
        wps = self.waypoints
        last = len(wps) - 1
        while self.index < last:
            index = next_waypoint(wps, self.index, pos, ROBOT_SWITCH_RADIUS_M)
            if index == self.index:
                if self.router is None:
                    break
                line = shapely.LineString([(x, y), tuple(wps[index + 1])])
                if not self.router.free.covers(line):
                    break
                index += 1
            self.index = index
        return wps[self.index]


def pedestrian_waypoints(setup: EpisodeSetup) -> list[FloatArray]:
    """Each pedestrian's waypoints, its goal last (see the module doc)."""
    scenario = setup.scenario
    crowd = setup.crowd
    n = crowd.n
    given = setup.ped_routes
    out: list[FloatArray] = []
    for i in range(n):
        goal = crowd.goal[i]
        if given is not None and len(given[i]):
            out.append(np.vstack([given[i], goal[None]]))
        elif scenario.obstacles.empty or i in scenario.ped_standing:
            out.append(goal[None].copy())
        else:
            out.append(_computed_route(scenario, crowd.pos[i], goal, float(crowd.radius[i])))
    return out


def _computed_route(scenario: Scenario, start: FloatArray, goal: FloatArray, r: float) -> FloatArray:
    """The router's path for a pedestrian (clearance its radius, then half of it; the
    straight line to the goal when neither finds one: the wall force then acts)."""
    world = _open_world(scenario.world, r)
    for clearance in (r, 0.5 * r):
        try:
            return router_for(scenario.obstacles, world, clearance).route(tuple(start), tuple(goal))
        except PlannerError:
            continue
    return goal[None].copy()


class PedestrianRoutes:
    """One twin's progress along the pedestrians' routes.

    Args:
        waypoints: per pedestrian (K_i, 2), goal last (:func:`pedestrian_waypoints`).
        waits_s: per pedestrian (K_i − 1,) seconds to wait at each waypoint, or None.
        switch_radius_m: distance at which a waypoint counts as reached (m).
        dt_s: the step (s).
    """

    def __init__(
        self,
        waypoints: list[FloatArray],
        waits_s: tuple[FloatArray, ...] | None,
        switch_radius_m: float,
        dt_s: float,
    ) -> None:
        self.waypoints = waypoints
        self.switch_radius_m = float(switch_radius_m)
        n = len(waypoints)
        self.index = np.zeros(n, dtype=np.int64)
        self.wait_steps: list[NDArray[np.int64]] = []
        for i, wps in enumerate(waypoints):
            w = np.zeros(len(wps), dtype=np.int64)
            if waits_s is not None and len(waits_s[i]) == len(wps) - 1:
                w[:-1] = np.round(np.asarray(waits_s[i]) / dt_s).astype(np.int64)
            self.wait_steps.append(w)
        self.left = np.full(n, -1, dtype=np.int64)  # steps still to wait (-1: not there)
        # The pedestrians still on their way to an intermediate waypoint.
        self.active = [i for i, wps in enumerate(waypoints) if len(wps) > 1]

    @property
    def any(self) -> bool:
        """True when some pedestrian has an intermediate waypoint."""
        return bool(self.active)

    def targets(self) -> FloatArray:
        """(N, 2) the current waypoint of each pedestrian."""
        return np.array([w[k] for w, k in zip(self.waypoints, self.index, strict=True)])

    def at_goal_leg(self, i: int) -> bool:
        """True when pedestrian i steers to its goal (its last waypoint)."""
        return bool(self.index[i] == len(self.waypoints[i]) - 1)

    def advance(self, pos: FloatArray, goal: FloatArray) -> None:
        """Move each pedestrian within the switch radius of its waypoint on to the next
        one (after its wait); write the new waypoints into ``goal`` (N, 2)."""
        r2 = self.switch_radius_m * self.switch_radius_m
        done = []
        for i in self.active:
            k = int(self.index[i])
            wp = self.waypoints[i][k]
            dx = pos[i, 0] - wp[0]
            dy = pos[i, 1] - wp[1]
            if self.left[i] < 0:
                if dx * dx + dy * dy > r2:
                    continue
                self.left[i] = self.wait_steps[i][k]
            if self.left[i] > 0:
                self.left[i] -= 1
                continue
            self.left[i] = -1
            self.index[i] = k + 1
            goal[i] = self.waypoints[i][k + 1]
            if k + 1 == len(self.waypoints[i]) - 1:
                done.append(i)
        for i in done:
            self.active.remove(i)
