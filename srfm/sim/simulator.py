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
3. events are detected at sample k + 1: pedestrian arrivals (and new goals in
   re-goaling scenarios), then robot collision, out of bounds, goal reached, and a
   timeout when k + 1 is the horizon.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from srfm.errors import PlannerError, SimulationError
from srfm.models import _kernels
from srfm.models.forces import PARALLEL_MIN_AGENTS
from srfm.models.params import SRFMParams
from srfm.models.robot import RobotState, apply_command, stopped
from srfm.models.state import CrowdState
from srfm.planners._base import Observation, PlannerContext
from srfm.scenarios import EpisodeSetup, next_goal
from srfm.sim.record import Event, RobotOutcome

__all__ = ["TwinSimulator"]

FloatArray = NDArray[np.float64]


class TwinSimulator:
    """Steps the factual and counterfactual crowds and the robot of one episode.

    Args:
        setup: the episode's start (see :func:`srfm.scenarios.episode_setup`).
        params: SRFM parameters; the ``agrawal2024`` preset when omitted.
        parallel: use the threaded force kernel; by default for crowds of at least
            ``PARALLEL_MIN_AGENTS``. Results are identical either way.
    """

    def __init__(
        self,
        setup: EpisodeSetup,
        params: SRFMParams | None = None,
        *,
        parallel: bool | None = None,
    ) -> None:
        self.setup = setup
        self.scenario = setup.scenario
        self.params = params if params is not None else SRFMParams()
        self._param_vec = self.params.as_array()
        self.factual: CrowdState = setup.crowd.copy()
        self.counterfactual: CrowdState = setup.crowd.copy()
        n = self.factual.n
        use_parallel = n >= PARALLEL_MIN_AGENTS if parallel is None else parallel
        self._twin_step = _kernels.twin_step_parallel if use_parallel else _kernels.twin_step_serial
        self._force_buf = np.empty((n, 2))
        self._robot_body = np.array([0.0, 0.0, self.scenario.robot.radius_m])
        self.robot = RobotState(
            x=float(setup.robot_start[0]),
            y=float(setup.robot_start[1]),
            theta=float(setup.robot_heading_rad),
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
        self._pillar_xy = np.ascontiguousarray(self._obstacles.circles[:, :2])
        self._pillar_r = np.ascontiguousarray(self._obstacles.circles[:, 2])
        self._ped_radius = self.factual.radius
        # A robot that starts in collision, out of bounds or at its goal ends at sample 0.
        self.initial_events: list[Event] = self._robot_events()

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
        )

    def observe(self, detection_range_m: float | None) -> Observation:
        """The planner's view of the current sample: factual pedestrians closer than
        ``detection_range_m`` (all of them for None)."""
        pos = self.factual.pos
        if detection_range_m is None:
            ids = self._all_ids.copy()
        else:
            k = _kernels.within_range(
                pos, self.robot.x, self.robot.y, float(detection_range_m), self._range_ids
            )
            ids = self._range_ids[:k].copy()
        return Observation(
            step=self.step_index,
            time_s=self.time_s,
            robot=self.robot,
            robot_goal=self.setup.robot_goal.copy(),
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
        if self.robot_active:  # validate before anything moves
            next_robot = apply_command(robot, command, self.scenario.robot, dt)
        elif robot.vx or robot.vy or robot.v or robot.omega:
            next_robot = stopped(robot)  # once, in the step after the episode ended
        else:
            next_robot = robot
        body = self._robot_body
        body[0] = robot.x
        body[1] = robot.y
        f = self.factual
        c = self.counterfactual
        arrived = self._arrived
        new = self._new_arrivals
        n_new = self._twin_step(
            f.pos,
            f.vel,
            f.goal,
            c.pos,
            c.vel,
            c.goal,
            f.radius,
            f.v0,
            f.vmax,
            self._param_vec,
            body,
            self._obstacles.segments,
            self._obstacles.circles,
            dt,
            self._force_buf,
            self.scenario.ped_goal_radius_m,
            arrived["factual"],
            arrived["counterfactual"],
            new["factual"],
            new["counterfactual"],
        )
        self.robot = next_robot
        self.step_index += 1
        events: list[Event] = []
        if n_new:
            events += self._pedestrian_events("factual", f)
            events += self._pedestrian_events("counterfactual", c)
        if self.robot_active:
            events += self._robot_events()
        return events

    def _pedestrian_events(self, twin: str, crowd: CrowdState) -> list[Event]:
        arrived = self._arrived[twin]
        new = self._new_arrivals[twin]
        events = []
        t = self.time_s
        for i in np.flatnonzero(new):
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
        robot = self.robot
        cfg = self.scenario.robot
        t = self.time_s
        k = self.step_index
        clearance, nearest = _kernels.nearest_clearance(
            self.factual.pos, self._ped_radius, robot.x, robot.y
        )
        events: list[Event] = []
        if clearance < cfg.radius_m:
            events.append(Event(step=k, time_s=t, kind="robot_collision", agent=int(nearest)))
            outcome: RobotOutcome | None = "collision"
        elif self._hits_obstacle(robot.x, robot.y, cfg.radius_m):
            events.append(Event(step=k, time_s=t, kind="robot_collision", agent=-1))
            outcome = "collision"
        elif not self.scenario.world.contains(robot.x, robot.y):
            events.append(Event(step=k, time_s=t, kind="robot_out_of_bounds"))
            outcome = "out_of_bounds"
        elif (
            math.hypot(robot.x - self.setup.robot_goal[0], robot.y - self.setup.robot_goal[1])
            < cfg.goal_radius_m
        ):
            events.append(Event(step=k, time_s=t, kind="robot_goal_reached"))
            outcome = "goal_reached"
        elif self.done:
            events.append(Event(step=k, time_s=t, kind="robot_timeout"))
            outcome = "timeout"
        else:
            outcome = None
        if outcome is not None:
            self.robot_active = False
            self.outcome = outcome
            self.end_step = k
        return events

    def _hits_obstacle(self, x: float, y: float, radius: float) -> bool:
        """True when a disc of ``radius`` at (x, y) overlaps a wall or a pillar."""
        obs = self._obstacles
        if obs.empty:
            return False
        clearance, _ = _kernels.nearest_clearance(self._pillar_xy, self._pillar_r, x, y)
        if clearance < radius:
            return True
        return bool(_kernels.segment_distance(obs.segments, x, y) < radius)
