"""Routes through walled scenarios: what the robot's planner and each pedestrian steer to.

The one place where the goal is replaced by a waypoint, shared by the simulator
(:class:`srfm.sim.TwinSimulator`) and the gymnasium environment (:mod:`srfm.rl`):

- **Robot.** In a scenario with walls or pillars, :class:`RobotRoute` asks the global
  router (:class:`srfm.world.Router`, clearance = robot radius +
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

import math
from typing import Final

import numpy as np
import shapely
from numpy.typing import NDArray

from srfm.errors import PlannerError
from srfm.models.state import Obstacles
from srfm.scenarios import EpisodeSetup, Scenario
from srfm.world import Router, WorldBounds

__all__ = [
    "ROBOT_CLEARANCE_MARGIN_M",
    "ROBOT_SWITCH_RADIUS_M",
    "PedestrianRoutes",
    "RobotRoute",
    "pedestrian_waypoints",
    "router_for",
]

FloatArray = NDArray[np.float64]

ROBOT_CLEARANCE_MARGIN_M: Final = 0.3
ROBOT_SWITCH_RADIUS_M: Final = 0.75
# The robot's route is looked at again once it has moved this far (m) since the last
# look (a robot at 0.5 m/s: every third step); a waiting robot costs nothing.
ROBOT_RECHECK_M: Final = 0.1
_CACHE_SIZE: Final = 64
_RouterKey = tuple[int, float, float, float, float, float]
_routers: dict[_RouterKey, tuple[Obstacles, Router]] = {}


def router_for(obstacles: Obstacles, world: WorldBounds, clearance_m: float) -> Router:
    """A :class:`Router` of these obstacles (the same object: a scenario's), world and
    clearance, kept for reuse (building one costs tens of ms)."""
    key = (id(obstacles), world.x_min, world.x_max, world.y_min, world.y_max, clearance_m)
    hit = _routers.get(key)
    if hit is not None and hit[0] is obstacles:
        return hit[1]
    router = Router(obstacles, world, clearance_m=clearance_m)
    if len(_routers) >= _CACHE_SIZE:
        _routers.pop(next(iter(_routers)))
    _routers[key] = (obstacles, router)
    return router


class RobotRoute:
    """The waypoint the robot's planner steers to (see the module doc).

    The router's clearance is the robot radius plus ``ROBOT_CLEARANCE_MARGIN_M``, or a
    third of that margin, or none, the first that finds a path (a narrow door). When no
    path joins the start and the goal, the route is the goal itself: the planner steers
    straight at it, as without routing.

    The robot moves on to the next waypoint when the straight segment to it lies in the
    route's free space, or when it is within ``ROBOT_SWITCH_RADIUS_M`` of the current
    waypoint and that segment keeps at least the robot's radius from every obstacle
    (so that it never cuts a corner into a wall); it looks again each time it has moved
    ``ROBOT_RECHECK_M``.
    """

    def __init__(self, scenario: Scenario, start: FloatArray, goal: FloatArray) -> None:
        radius = scenario.robot.radius_m
        self.router: Router | None = None
        self.tight: Router | None = None
        self.waypoints: FloatArray = np.array(goal, dtype=np.float64).reshape(1, 2)
        margin = ROBOT_CLEARANCE_MARGIN_M
        for clearance in (radius + margin, radius + margin / 3.0, radius):
            try:
                router = router_for(scenario.obstacles, scenario.world, clearance)
                self.waypoints = router.route(tuple(start), tuple(goal))
            except PlannerError:
                continue
            self.router = router
            break
        if self.router is not None:
            self.tight = router_for(scenario.obstacles, scenario.world, radius)
        self.index = 0
        self._checked_at = (math.inf, math.inf)

    def copy_from(self, other: RobotRoute) -> None:
        """Take ``other``'s progress along the route (the same route: same scenario,
        start and goal)."""
        self.index = other.index
        self._checked_at = other._checked_at

    def update(self, x: float, y: float) -> FloatArray:
        """Advance past reached or bypassed waypoints from (x, y); the current one."""
        wps = self.waypoints
        last = len(wps) - 1
        if self.router is None or self.tight is None:
            return np.asarray(wps[self.index], dtype=np.float64)
        cx, cy = self._checked_at
        if (x - cx) ** 2 + (y - cy) ** 2 < ROBOT_RECHECK_M * ROBOT_RECHECK_M:
            return np.asarray(wps[self.index], dtype=np.float64)
        self._checked_at = (x, y)
        while self.index < last:
            k = self.index
            line = shapely.LineString([(x, y), tuple(wps[k + 1])])
            if not self.router.free.covers(line):
                near = float(np.hypot(x - wps[k, 0], y - wps[k, 1])) <= ROBOT_SWITCH_RADIUS_M
                if not (near and self.tight.free.covers(line)):
                    break
            self.index = k + 1
        return np.asarray(wps[self.index], dtype=np.float64)


def pedestrian_waypoints(setup: EpisodeSetup) -> list[FloatArray]:
    """Each pedestrian's waypoints, its goal last (see the module doc)."""
    return [w for w, _ in _pedestrian_plans(setup)]


def _pedestrian_plans(setup: EpisodeSetup) -> list[tuple[FloatArray, NDArray[np.bool_]]]:
    """Each pedestrian's waypoints (goal last) and which of them the router computed
    (those may be skipped once the next one is in sight; given ones may not)."""
    scenario = setup.scenario
    crowd = setup.crowd
    given = setup.ped_routes
    out: list[tuple[FloatArray, NDArray[np.bool_]]] = []
    for i in range(crowd.n):
        goal = crowd.goal[i]
        if given is not None and len(given[i]):
            wps = np.vstack([given[i], goal[None]])
            out.append((wps, np.zeros(len(wps), dtype=bool)))
        elif scenario.obstacles.empty or i in setup.ped_standing:
            out.append((goal[None].copy(), np.zeros(1, dtype=bool)))
        else:
            wps = _computed_route(scenario, crowd.pos[i], goal, float(crowd.radius[i]))
            skip = np.ones(len(wps), dtype=bool)
            skip[-1] = False
            out.append((wps, skip))
    return out


def _ped_routers(scenario: Scenario, r: float) -> tuple[Router, ...]:
    """The routers a pedestrian of radius ``r`` uses: clearance r, then r / 2."""
    world = scenario.world.grown(r)
    out = []
    for clearance in (r, 0.5 * r):
        try:
            out.append(router_for(scenario.obstacles, world, clearance))
        except PlannerError:
            continue
    return tuple(out)


def _computed_route(
    scenario: Scenario, start: FloatArray, goal: FloatArray, r: float
) -> FloatArray:
    """The router's path for a pedestrian (clearance its radius, then half of it; the
    straight line to the goal when neither finds one: the wall force then acts)."""
    for router in _ped_routers(scenario, r):
        try:
            return router.route(tuple(start), tuple(goal))
        except PlannerError:
            continue
    return goal[None].copy()


class PedestrianRoutes:
    """One twin's progress along the pedestrians' routes.

    Every ``REPLAN_STEPS`` steps, a walking pedestrian that has lost sight of its
    current waypoint behind a wall (pushed off its path by others) gets the router's
    path to that waypoint in front of the rest of its route; a router-made waypoint is
    skipped once the next one is in sight (looked at every ``SKIP_CHECK_STEPS`` steps).

    Args:
        setup: the episode's set-up (its scenario, starts, goals and given routes).
    """

    REPLAN_STEPS: Final = 15
    SKIP_CHECK_STEPS: Final = 5

    def __init__(
        self,
        setup: EpisodeSetup,
        plans: list[tuple[FloatArray, NDArray[np.bool_]]] | None = None,
    ) -> None:
        scenario = setup.scenario
        if plans is None:
            plans = _pedestrian_plans(setup)
        self.waypoints = [w for w, _ in plans]
        self.skippable = [k for _, k in plans]
        self.switch_radius_m = float(scenario.ped_switch_radius_m)
        n = len(plans)
        self.index = np.zeros(n, dtype=np.int64)
        self.wait_steps: list[NDArray[np.int64]] = []
        waits = setup.ped_waits_s
        for i, wps in enumerate(self.waypoints):
            w = np.zeros(len(wps), dtype=np.int64)
            if waits is not None and len(waits[i]) == len(wps) - 1:
                w[:-1] = np.round(np.asarray(waits[i]) / scenario.dt_s).astype(np.int64)
            self.wait_steps.append(w)
        self.left = np.full(n, -1, dtype=np.int64)  # steps still to wait (-1: not there)
        # The pedestrians still on their way to an intermediate waypoint.
        self.active = [i for i, wps in enumerate(self.waypoints) if len(wps) > 1]
        # Replanning needs obstacles; standing pedestrians never replan.
        standing = set(setup.ped_standing)
        self._walkers = (
            [] if scenario.obstacles.empty else [i for i in range(n) if i not in standing]
        )
        self._routers = {
            r: _ped_routers(scenario, r) for r in {float(x) for x in setup.crowd.radius}
        }
        self._radius = setup.crowd.radius.copy()
        self._steps = 0

    @classmethod
    def twins(cls, setup: EpisodeSetup) -> tuple[PedestrianRoutes, PedestrianRoutes]:
        """The factual and the counterfactual twin's routes (planned once)."""
        plans = _pedestrian_plans(setup)
        return cls(setup, plans), cls(setup, plans)

    @property
    def any(self) -> bool:
        """True when some pedestrian has an intermediate waypoint or may get one."""
        return bool(self.active or self._walkers)

    def targets(self) -> FloatArray:
        """(N, 2) the current waypoint of each pedestrian."""
        return np.array([w[k] for w, k in zip(self.waypoints, self.index, strict=True)])

    def at_goal_leg(self, i: int) -> bool:
        """True when pedestrian i steers to its goal (its last waypoint)."""
        return bool(self.index[i] == len(self.waypoints[i]) - 1)

    def copy_from(self, other: PedestrianRoutes) -> None:
        """Take ``other``'s state (the routes of the same set-up and twin): waypoints
        replanned so far, progress, waits. Waypoint arrays are replaced, never changed in
        place, so the lists are copied and their arrays shared."""
        self.waypoints = list(other.waypoints)
        self.skippable = list(other.skippable)
        self.wait_steps = list(other.wait_steps)
        self.index[:] = other.index
        self.left[:] = other.left
        self.active = list(other.active)
        self._steps = other._steps

    def _visible(self, i: int, a: FloatArray, b: FloatArray) -> bool:
        routers = self._routers[float(self._radius[i])]
        if not routers:
            return True
        line = shapely.LineString([tuple(a), tuple(b)])
        return bool(routers[-1].free.covers(line))

    def advance(self, pos: FloatArray, goal: FloatArray, present: int | None = None) -> None:
        """Move each pedestrian within the switch radius of its waypoint on to the next
        one (after its wait), replan where a wall hides the waypoint; write the current
        waypoints into ``goal`` (N, 2). Only the first ``present`` pedestrians (all for
        None) are there yet (:meth:`srfm.scenarios.EpisodeSetup.n_present`)."""
        self._steps += 1
        n = len(self.waypoints) if present is None else present
        if self._walkers and self._steps % self.REPLAN_STEPS == 0:
            for i in self._walkers:
                if i >= n:
                    break
                if not self._visible(i, pos[i], goal[i]):
                    self._replan(i, pos[i], goal)
        r2 = self.switch_radius_m * self.switch_radius_m
        check_skips = self._steps % self.SKIP_CHECK_STEPS == 0
        done = []
        for i in self.active:
            if i >= n:
                break  # sorted: the rest are not there yet
            k = int(self.index[i])
            wp = self.waypoints[i][k]
            dx = pos[i, 0] - wp[0]
            dy = pos[i, 1] - wp[1]
            if self.left[i] < 0:
                if dx * dx + dy * dy > r2:
                    if not (
                        check_skips
                        and self.skippable[i][k]
                        and self._visible(i, pos[i], self.waypoints[i][k + 1])
                    ):
                        continue
                    self.left[i] = 0
                else:
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

    def _replan(self, i: int, at: FloatArray, goal: FloatArray) -> None:
        """Put the router's path from ``at`` to pedestrian i's current waypoint in front
        of the rest of its route (unchanged when no path is found)."""
        k = int(self.index[i])
        wps = self.waypoints[i]
        for router in self._routers[float(self._radius[i])]:
            try:
                path = router.route(tuple(at), tuple(wps[k]))
            except PlannerError:
                continue
            if len(path) == 1:
                return  # in sight with this clearance: the wall force will do
            self.waypoints[i] = np.vstack([path[:-1], wps[k:]])
            skip = np.ones(len(path) - 1, dtype=bool)
            self.skippable[i] = np.concatenate([skip, self.skippable[i][k:]])
            self.wait_steps[i] = np.concatenate(
                [np.zeros(len(path) - 1, dtype=np.int64), self.wait_steps[i][k:]]
            )
            self.index[i] = 0
            self.left[i] = -1
            goal[i] = self.waypoints[i][0]
            if i not in self.active:
                self.active.append(i)
                self.active.sort()
            return
