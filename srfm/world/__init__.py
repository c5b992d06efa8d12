"""The static world of a scenario: its rectangle and the global router round its walls
and pillars (the walls and pillars themselves are :class:`srfm.models.state.Obstacles`,
the force kernels' input).

Below the scenarios, which check with the router that every waypoint can be reached,
and below the planners and the simulator, which route the robot and the pedestrians::

    from srfm.world import Router, WorldBounds

    router = Router(obstacles, WorldBounds(x_max=10.0, y_max=10.0), clearance_m=0.4)
    waypoints = router.route((1.0, 1.0), (9.0, 9.0))   # (K, 2), last row = goal
"""

from srfm.world._bounds import WorldBounds
from srfm.world._routing import Router, next_waypoint

__all__ = ["Router", "WorldBounds", "next_waypoint"]
