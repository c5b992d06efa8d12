"""Twin counterfactual simulator (DESIGN §5).

Two crowds start from the same state and are stepped in lockstep: the *factual* crowd
feels the robot force, the *counterfactual* crowd does not perceive the robot at all.
Both run for the scenario's full horizon whatever the robot does, so every pedestrian
has two trajectories of equal length and equal timestamps. The planner observes the
factual crowd only. When the robot's episode ends (goal reached, collision, out of
bounds) it stops where it is and stays there as a body that the factual crowd still
perceives.

One step, from sample k to k + 1:

1. both crowds take one SRFM step from their own snapshot; the factual crowd sees the
   robot where it is at sample k;
2. the robot moves under the planner's command (clipped to its limits), or stays put
   once its episode has ended;
3. pedestrians whose entry sample is k + 1 appear at their start (schema 2 entries);
4. events are detected at sample k + 1: pedestrian arrivals (and new goals in
   re-goaling scenarios), then robot collision, out of bounds, goal reached, and a
   timeout when k + 1 is the horizon.

Entering pedestrians: the set-up orders the pedestrians by entry
(:func:`srfm.scenarios.episode_setup`), so the ones present at a sample are the first
``n_present``; the kernels get those rows (views of the same arrays, so no copy and no
other kernel), and a pedestrian not there yet neither moves nor is felt or seen. Both
twins get the same pedestrians at the same samples.

The robot's motion and checks are the robot kernels of
:mod:`srfm.models._robot_kernels` (the ones :func:`srfm.apply_command` and the RL
environment call), the crowd step the SRFM kernels; each is called through
:func:`srfm._jit.specialize` so that a step pays no per-call type resolution.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

from srfm._jit import specialize
from srfm.errors import PlannerError, SimulationError
from srfm.models import _kernels
from srfm.models import _robot_kernels as _rk
from srfm.models.forces import Cutoff, kernel_cutoffs
from srfm.models.params import SRFMParams
from srfm.models.robot import RobotState, command_pair, stopped
from srfm.models.state import CrowdState
from srfm.planners._base import Observation, PlannerContext
from srfm.scenarios import EpisodeSetup, next_goal
from srfm.sim.record import Event, EventKind, RobotOutcome
from srfm.sim.routes import PedestrianRoutes, RobotRoute

__all__ = ["TwinSimulator"]

FloatArray = NDArray[np.float64]

# The outcome of the robot's episode for each robot event code (also the environment's).
EVENT_OUTCOMES: Final[dict[int, RobotOutcome]] = {
    _rk.EVENT_COLLISION: "collision",
    _rk.EVENT_OBSTACLE: "collision",
    _rk.EVENT_OUT_OF_BOUNDS: "out_of_bounds",
    _rk.EVENT_GOAL: "goal_reached",
    _rk.EVENT_TIMEOUT: "timeout",
}
_EVENT_KINDS: Final[dict[int, EventKind]] = {
    _rk.EVENT_COLLISION: "robot_collision",
    _rk.EVENT_OBSTACLE: "robot_collision",
    _rk.EVENT_OUT_OF_BOUNDS: "robot_out_of_bounds",
    _rk.EVENT_GOAL: "robot_goal_reached",
    _rk.EVENT_TIMEOUT: "robot_timeout",
}


class TwinSimulator:
    """Steps the factual and counterfactual crowds and the robot of one episode.

    Args:
        setup: the episode's start (see :func:`srfm.scenarios.episode_setup`).
        params: SRFM parameters; the ``agrawal2024`` preset when omitted.
        parallel: use the threaded force kernel (for idle cores only; serial by
            default). Results are identical either way.
        cutoff: interaction cut-off of the crowd steps (:func:`srfm.models.forces.kernel_cutoffs`):
            "auto" (exact below ``CELL_LIST_MIN_AGENTS`` pedestrians), "exact", or a
            pedestrian cut-off in m.
    """

    def __init__(
        self,
        setup: EpisodeSetup,
        params: SRFMParams | None = None,
        *,
        parallel: bool = False,
        cutoff: Cutoff = "auto",
    ) -> None:
        self.setup = setup
        self.scenario = setup.scenario
        self.params = params if params is not None else SRFMParams()
        self._kernel_params = self.params.for_kernels()
        self.factual: CrowdState = setup.crowd.copy()
        self.counterfactual: CrowdState = setup.crowd.copy()
        n = self.factual.n
        self._cut = kernel_cutoffs(cutoff, self.params, self.factual.radius)
        self._force_buf = np.empty((n, 2))
        self._robot_body = np.array([0.0, 0.0, self.scenario.robot.radius_m])
        self.robot = RobotState(
            x=float(setup.robot_start[0]),
            y=float(setup.robot_start[1]),
            theta=float(setup.robot_heading_rad),
        )
        # The robot in the kernels' layout (self.robot is its RobotState view).
        self._robot = self.robot.as_array()
        self._limits = self.scenario.robot.for_kernels()
        self._task = _rk.robot_task(
            setup.robot_goal, self.scenario.world, self.scenario.horizon_steps
        )
        self.robot_active = True
        self.outcome: RobotOutcome | None = None
        self.end_step = self.scenario.horizon_steps
        self.step_index = 0
        self._regoal = self.scenario.random is not None and self.scenario.random.regoal
        self._goal_count = {
            "factual": np.zeros(n, dtype=np.int64),
            "counterfactual": np.zeros(n, dtype=np.int64),
        }
        self._arrived = {"factual": np.zeros(n, bool), "counterfactual": np.zeros(n, bool)}
        self._new_arrivals = {"factual": np.zeros(n, bool), "counterfactual": np.zeros(n, bool)}
        self._all_ids = np.arange(n)
        self._range_ids = np.zeros(n, dtype=np.intp)
        self._obstacles = self.scenario.obstacles
        # The kernels' copies of the obstacles: writable and C-contiguous whatever the
        # scenario's arrays are. numba compiles a kernel once per argument type, and
        # read-only is part of an array's type: a scenario's arrays are read-only where
        # it was built but writable where it was unpickled (a benchmark worker), which
        # made every worker compile the crowd step and the robot events again (with an
        # empty cache, seconds of CPU each).
        self._segments = np.array(self._obstacles.segments, dtype=np.float64, order="C")
        self._circles = np.array(self._obstacles.circles, dtype=np.float64, order="C")
        self._pillar_xy = np.array(self._circles[:, :2], order="C")
        self._pillar_r = np.array(self._circles[:, 2], order="C")
        self._ped_radius = self.factual.radius
        # Routes (srfm.sim.routes): the robot's planner and the pedestrians steer to
        # waypoints in scenarios with obstacles or given routes; none otherwise.
        self._robot_route: RobotRoute | None = None
        self._ped_routes: dict[str, PedestrianRoutes] = {}
        if not self._obstacles.empty:
            self._robot_route = RobotRoute(self.scenario, setup.robot_start, setup.robot_goal)
            self._robot_route.update(self.robot.x, self.robot.y)
        if not self._obstacles.empty or setup.ped_routes is not None:
            twins = PedestrianRoutes.twins(setup)
            crowds = (("factual", self.factual), ("counterfactual", self.counterfactual))
            for (twin, crowd), routes in zip(crowds, twins, strict=True):
                if routes.any:
                    crowd.goal[:] = routes.targets()
                    self._ped_routes[twin] = routes
        # The pedestrians there at the current sample are the first n_present.
        self._enter_step = setup.ped_enter_step
        self.n_present = setup.n_present(0)
        # The per-step kernels, their argument types resolved once (srfm._jit.specialize),
        # and their arguments, the same arrays (updated in place) at every step.
        self._pack(self.n_present)
        if parallel:
            twin_kernel = _kernels.twin_step_parallel
        elif math.isinf(self._cut[0]):
            twin_kernel = _kernels.twin_step_exact  # no cell list to compile
        else:
            twin_kernel = _kernels.twin_step_serial
        # The step's kernels are specialised at the first step, so that building a
        # simulator and observing compiles neither the crowd step nor the robot's motion
        # (the benchmark's warm-up compiles a planner's kernels that way beside them).
        self._twin_kernel = twin_kernel
        self._twin_step: Callable[..., Any] | None = None
        self._move_robot: Callable[..., Any] | None = None
        self._robot_event = specialize(_rk.robot_event, *self._event_args, 0)
        # A robot that starts in collision, out of bounds or at its goal ends at sample 0.
        self.initial_events: list[Event] = self._robot_events()

    def _pack(self, m: int) -> None:
        """The twin step's and the robot events' arguments for the first ``m``
        pedestrians (views of the crowds' arrays: the kernels update them in place)."""
        f = self.factual
        c = self.counterfactual
        self._twin_step_args = (
            f.pos[:m],
            f.vel[:m],
            f.goal[:m],
            c.pos[:m],
            c.vel[:m],
            c.goal[:m],
            f.radius[:m],
            f.v0[:m],
            f.vmax[:m],
            self._kernel_params,
            self._robot_body,
            self._segments,
            self._circles,
            float(self.scenario.dt_s),
            self._force_buf[:m],
            float(self.scenario.ped_goal_radius_m),
            self._arrived["factual"][:m],
            self._arrived["counterfactual"][:m],
            self._new_arrivals["factual"][:m],
            self._new_arrivals["counterfactual"][:m],
            self._cut,
        )
        # robot_event's arguments but the sample index
        self._event_args = (
            self._robot,
            f.pos[:m],
            self._ped_radius[:m],
            self._segments,
            self._pillar_xy,
            self._pillar_r,
            self._limits,
            self._task,
        )

    @property
    def time_s(self) -> float:
        """Simulated time of the current sample (s)."""
        return self.step_index * self.scenario.dt_s

    @property
    def done(self) -> bool:
        """True once the horizon is reached."""
        return self.step_index >= self.scenario.horizon_steps

    def planner_context(self) -> PlannerContext:
        """What a planner is told at reset."""
        return PlannerContext(
            scenario=self.scenario.name,
            seed=self.setup.seed,
            dt_s=self.scenario.dt_s,
            horizon_steps=self.scenario.horizon_steps,
            robot=self.scenario.robot,
            robot_goal=self.setup.robot_goal.copy(),
            world=self.scenario.world,
            obstacles=self._obstacles,
            robot_recording=self.scenario.robot_recording,
        )

    def steering_goal(self) -> FloatArray:
        """(2,) what the planner steers to: the route's current waypoint in a scenario
        with obstacles (:class:`srfm.sim.routes.RobotRoute`), else the goal."""
        if self._robot_route is None:
            return self.setup.robot_goal.copy()
        route = self._robot_route
        return np.array(route.waypoints[route.index], dtype=np.float64)

    def observe(self, detection_range_m: float | None) -> Observation:
        """The planner's view of the current sample: factual pedestrians closer than
        ``detection_range_m`` (all of them for None)."""
        pos = self.factual.pos[: self.n_present]
        if detection_range_m is None:
            ids = self._all_ids[: self.n_present].copy()
        else:
            k = _kernels.within_range(
                pos, self.robot.x, self.robot.y, float(detection_range_m), self._range_ids
            )
            ids = self._range_ids[:k].copy()
        return Observation(
            step=self.step_index,
            time_s=self.time_s,
            robot=self.robot,
            robot_goal=self.steering_goal(),
            ped_ids=ids,
            ped_pos=pos[ids],
            ped_vel=self.factual.vel[ids],
            ped_radius=self._ped_radius[ids],
            obstacles=self._obstacles,
        )

    def step(self, command: Any = None) -> list[Event]:
        """Advance both crowds and the robot by one step; return the events detected.

        Args:
            command: the planner's command while the robot is active (ignored after
                its episode has ended).

        Raises:
            SimulationError: the horizon has been reached.
            PlannerError: an active robot got no command or an unusable one.
        """
        if self.done:
            raise SimulationError(
                f"the episode is over: horizon of {self.scenario.horizon_steps} steps reached"
            )
        if self.robot_active and command is None:
            raise PlannerError("the robot is active and needs a command")
        dt = self.scenario.dt_s
        robot = self.robot
        if self.robot_active:
            c0, c1 = command_pair(command)  # validate before anything moves
        if self._twin_step is None or self._move_robot is None:
            self._twin_step = specialize(self._twin_kernel, *self._twin_step_args)
            self._move_robot = specialize(
                _rk.move_robot, self._robot, 0.0, 0.0, self._limits, float(dt)
            )
        body = self._robot_body
        body[0] = robot.x
        body[1] = robot.y
        if self.robot_active:
            self._move_robot(self._robot, c0, c1, self._limits, dt)
            next_robot = RobotState.from_array(self._robot)
        elif robot.vx or robot.vy or robot.v or robot.omega:
            next_robot = stopped(robot)  # once, in the step after the episode ended
            self._robot[_rk.VX :] = 0.0
        else:
            next_robot = robot
        n_new = self._twin_step(*self._twin_step_args) if self.n_present else 0  # body at k
        self.robot = next_robot
        self.step_index += 1
        if self._enter_step is not None:
            m = self.setup.n_present(self.step_index)
            if m != self.n_present:  # new pedestrians at their starts
                self.n_present = m
                self._pack(m)
        events: list[Event] = []
        if n_new:
            events += self._pedestrian_events("factual", self.factual)
            events += self._pedestrian_events("counterfactual", self.counterfactual)
        if self._ped_routes:  # after the arrivals, which were flagged on these legs
            for twin, routes in self._ped_routes.items():
                crowd = self.factual if twin == "factual" else self.counterfactual
                routes.advance(crowd.pos, crowd.goal, self.n_present)
        if self._robot_route is not None and self.robot_active:
            self._robot_route.update(next_robot.x, next_robot.y)
        if self.robot_active:
            events += self._robot_events()
        return events

    def _pedestrian_events(self, twin: str, crowd: CrowdState) -> list[Event]:
        arrived = self._arrived[twin]
        new = self._new_arrivals[twin]
        events = []
        t = self.time_s
        routes = self._ped_routes.get(twin)
        for i in np.flatnonzero(new):
            if routes is not None and not routes.at_goal_leg(int(i)):
                continue  # near a waypoint on the way, not at the goal
            events.append(
                Event(step=self.step_index, time_s=t, kind="ped_arrival", agent=int(i), twin=twin)
            )
            if self._regoal:
                count = self._goal_count[twin]
                count[i] += 1
                crowd.goal[i] = next_goal(self.setup, int(i), int(count[i]), crowd.goal[i])
            else:
                arrived[i] = True
        return events

    def _robot_events(self) -> list[Event]:
        """The robot event at the current sample (robot kernel), as records; ends the
        robot's episode when there is one."""
        code, nearest = self._robot_event(*self._event_args, self.step_index)
        if code == _rk.EVENT_NONE:
            return []
        k = self.step_index
        event = Event(step=k, time_s=self.time_s, kind=_EVENT_KINDS[code], agent=int(nearest))
        self.robot_active = False
        self.outcome = EVENT_OUTCOMES[code]
        self.end_step = k
        return [event]
