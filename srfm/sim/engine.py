"""The episode engine: the state of one twin episode and its advance by one step.

The one implementation of an episode's rules. :class:`srfm.TwinSimulator` (and so
:func:`srfm.run_episode` and the benchmark) and the gymnasium environment
``srfm/SocialNav-v0`` both drive an :class:`EpisodeEngine`; the environment adds only
what is its own (the observation vector, the reward, gymnasium's contract). A new rule
of the episode (an event, a kind of pedestrian) is written here, once.

One step, from sample k to k + 1 (:meth:`EpisodeEngine.advance`):

1. **the kernel's step** (:mod:`srfm.sim._kernels`, one numba call): the robot moves
   under the command (or rests once its episode has ended), both crowds take one SRFM
   step from their own snapshot, the factual one feeling the robot where it was at
   sample k; new arrivals are flagged; the robot event at k + 1 is detected;
2. :meth:`~EpisodeEngine.enter_sample`: the episode is at sample k + 1; pedestrians
   whose entry sample is k + 1 appear at their start (the set-up orders pedestrians by
   entry, so the ones present are always the first ``n_present``: the kernels get
   views of those rows), and the robot event is detected again with them there;
3. :meth:`~EpisodeEngine.apply_events`: arrivals (an arrival at a route's waypoint is
   none; in re-goaling scenarios the pedestrian gets its next goal, else it is marked
   arrived), the pedestrians' and the robot's routes (:mod:`srfm.sim.routes`), and the
   robot event, which ends the robot's episode (the robot then stays where it is, a
   body the factual crowd still feels, while both crowds go on to the horizon).

Both twins get the same pedestrians at the same samples. The environment runs step 1
inside its own fused kernel (the same :func:`srfm.sim._kernels.advance_exact`, followed
by its reward) and then steps 2 and 3 through these methods.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

from srfm._jit import specialize_once
from srfm.errors import SimulationError
from srfm.models import _robot_kernels as _rk
from srfm.models._arrays import ForceContext
from srfm.models._primitives import FALSE, TRUE
from srfm.models.forces import Cutoff, kernel_cutoffs
from srfm.models.params import SRFMParams
from srfm.models.robot import RobotState
from srfm.models.state import CrowdState
from srfm.scenarios import EpisodeSetup, next_goal
from srfm.sim import _kernels as _k
from srfm.sim.record import Event, EventKind, RobotOutcome
from srfm.sim.routes import PedestrianRoutes, RobotRoute

__all__ = ["EVENT_OUTCOMES", "EpisodeEngine"]

FloatArray = NDArray[np.float64]

# The outcome of the robot's episode for each robot event code.
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
_TWINS: Final = ("factual", "counterfactual")


class EpisodeEngine:
    """One twin episode: both crowds, the robot, arrivals, entries and routes.

    Args:
        setup: the episode's start (see :func:`srfm.scenarios.episode_setup`).
        params: SRFM parameters; the ``agrawal2024`` preset when omitted.
        parallel: use the threaded force kernel (for idle cores only). Results are
            identical either way.
        cutoff: interaction cut-off of the crowd steps
            (:func:`srfm.models.forces.kernel_cutoffs`).
        counterfactual: step the counterfactual crowd (else it stays at its start; the
            environment's training set-up, whose reward needs only a one-step
            counterfactual).
        records: return the events as :class:`~srfm.sim.record.Event` records (the
            environment, which needs none, saves their cost).
        robot_felt: the factual crowd feels the robot (False: both crowds are blind
            to it, as for the noise floor, :func:`srfm.sim.floor.nudged_twins`).

    Attributes:
        factual, counterfactual: the two crowds, every pedestrian of the episode (the
            ones not there yet at their start, at rest); updated in place.
        robot: (7,) the robot's state (:mod:`srfm.models._robot_kernels` layout).
        robot_active: the robot's episode goes on.
        outcome: how the robot's episode ended (None while it goes on).
        end_step: the sample at which it ended (the horizon while it goes on).
        step_index: the current sample k.
        n_present: the pedestrians there at sample k (the first ``n_present``).
        has_routes: the robot or some pedestrians follow routes (work after every
            step); False in scenarios without obstacles and given routes.
        initial_events: the robot event at sample 0, if the robot starts in
            collision, out of the world or at its goal (its episode then ends there).
        arrays: the kernels' view of the episode (:class:`srfm.sim._kernels.EpisodeArrays`).
    """

    factual: CrowdState
    counterfactual: CrowdState
    _robot_event: Callable[..., tuple[int, int]]

    def __init__(
        self,
        setup: EpisodeSetup,
        params: SRFMParams | None = None,
        *,
        parallel: bool = False,
        cutoff: Cutoff = "auto",
        counterfactual: bool = True,
        records: bool = True,
        robot_felt: bool = True,
    ) -> None:
        self.params = params if params is not None else SRFMParams()
        self.records = records
        self._robot_felt = robot_felt
        self._parallel = parallel
        self._cutoff: Cutoff = cutoff
        self._counterfactual = counterfactual
        self._obstacles_of: Any = None
        self.reset(setup)

    def reset(self, setup: EpisodeSetup) -> None:
        """Start the episode ``setup`` (the engine's arrays reused where they fit)."""
        scenario = setup.scenario
        self.setup = setup
        self.scenario = scenario
        crowd = setup.crowd
        n = crowd.n
        if self._crowds_fit(n):
            for state in (self.factual, self.counterfactual):
                for name in ("pos", "vel", "goal", "radius", "v0", "vmax"):
                    getattr(state, name)[:] = getattr(crowd, name)
        else:
            self.factual = crowd.copy()
            self.counterfactual = crowd.copy()
            self._arrived = np.zeros((2, n), dtype=np.bool_)
            self._new = np.zeros((2, n), dtype=np.bool_)
            self._goal_count = np.zeros((2, n), dtype=np.int64)
            self._force_buf = np.empty((n, 2))
        # Arrivals, per twin (rows 0, 1 = factual, counterfactual).
        self._arrived[:] = False
        self._new[:] = False
        self._goal_count[:] = 0
        self._regoal = scenario.random is not None and scenario.random.regoal
        self._goal_cache: dict[tuple[int, int], FloatArray] = {}  # both twins draw alike
        self.robot = RobotState(
            x=float(setup.robot_start[0]),
            y=float(setup.robot_start[1]),
            theta=float(setup.robot_heading_rad),
        ).as_array()
        self.task = _rk.robot_task(setup.robot_goal, scenario.world, scenario.horizon_steps)
        self.robot_active = True
        self.outcome: RobotOutcome | None = None
        self.end_step = scenario.horizon_steps
        self.step_index = 0
        # Routes (srfm.sim.routes): the robot's planner and the pedestrians steer to
        # waypoints in scenarios with obstacles or given routes; none otherwise.
        obstacles = scenario.obstacles
        self.robot_route: RobotRoute | None = None
        self._ped_routes: dict[int, PedestrianRoutes] = {}
        if not obstacles.empty:
            self.robot_route = RobotRoute(scenario, setup.robot_start, setup.robot_goal)
            self.robot_route.update(self.robot[_rk.X], self.robot[_rk.Y])
        if not obstacles.empty or setup.ped_routes is not None:
            for side, routes in enumerate(PedestrianRoutes.twins(setup)):
                if routes.any:
                    self.crowd(side).goal[:] = routes.targets()
                    self._ped_routes[side] = routes
        self.has_routes = self.robot_route is not None or bool(self._ped_routes)
        self._enter_step = setup.ped_enter_step
        self.n_present = setup.n_present(0)
        # The kernels' arguments: the same arrays (updated in place) at every step.
        r = self.robot
        self._body = np.array([r[_rk.X], r[_rk.Y], scenario.robot.radius_m, r[_rk.VX], r[_rk.VY]])
        if obstacles is not self._obstacles_of:
            self._obstacles = obstacles.for_kernels()
            self._obstacles_of = obstacles
        self._cut = kernel_cutoffs(self._cutoff, self.params, crowd.radius)
        kernel_params = self.params.for_kernels()
        felt = TRUE if self._robot_felt else FALSE
        self._felt = ForceContext(kernel_params, self._body, felt, self._obstacles, self._cut)
        self._limits = scenario.robot.for_kernels()
        self._options = _k.StepOptions(
            dt_s=float(scenario.dt_s),
            ped_goal_radius_m=float(scenario.ped_goal_radius_m),
            counterfactual=self._counterfactual,
            crowd_substeps=int(scenario.crowd_substeps),
        )
        # The step kernel, and its run of steps with the robot at rest (none threaded).
        self._rest_kernel: Callable[..., tuple[int, int]] | None = None
        if self._parallel:
            self._kernel = _k.advance_parallel
        elif math.isinf(self._cut[0]):
            self._kernel = _k.advance_exact  # no cell list to compile
            self._rest_kernel = _k.rest_exact
        else:
            self._kernel = _k.advance_serial
            self._rest_kernel = _k.rest_serial
        self._pack(self.n_present)
        # The step kernel is specialised at the first step, so that building an engine
        # and observing compiles neither the crowd step nor the robot's motion (the
        # benchmark's warm-up compiles a planner's kernels that way beside them).
        self._advance: Callable[..., tuple[int, int, int]] | None = None
        self._rest: Callable[..., tuple[int, int]] | None = None
        # The engine makes every array and tuple it hands the kernels itself, so their
        # types are the same in every episode (srfm._jit.specialize_once).
        self._robot_event = specialize_once(_rk.robot_event, *self._event_args(), 0)
        code, nearest = self._robot_event(*self._event_args(), 0)
        self.initial_events: list[Event] = self._robot_events(code, nearest)

    def _crowds_fit(self, n: int) -> bool:
        """The crowds' arrays of an earlier episode hold ``n`` pedestrians."""
        factual: CrowdState | None = self.__dict__.get("factual")
        return factual is not None and factual.n == n

    def __getstate__(self) -> dict[str, Any]:
        state = self.__dict__.copy()
        # Compiled functions do not pickle, and pickle copies views: the kernels'
        # arguments are made again on unpickling.
        for name in ("_advance", "_rest", "_robot_event", "arrays"):
            del state[name]
        return state

    def __setstate__(self, state: dict[str, Any]) -> None:
        self.__dict__.update(state)
        self._advance = None
        self._rest = None
        self._pack(self.n_present)
        self._robot_event = specialize_once(_rk.robot_event, *self._event_args(), 0)

    def look_ahead(self, *, counterfactual: bool = False) -> EpisodeEngine:
        """A new engine in this one's state (:meth:`copy_from`), for look-ahead: no event
        records, and the counterfactual crowd left where it is unless asked for. The new
        engine draws nothing from the episode's random streams (re-goaling reads the
        same per-pedestrian streams), so stepping it changes nothing here."""
        engine = EpisodeEngine(
            self.setup,
            self.params,
            cutoff=self._cutoff,
            counterfactual=counterfactual,
            records=False,
        )
        engine.copy_from(self)
        return engine

    def copy_from(self, other: EpisodeEngine) -> None:
        """Put this engine in ``other``'s state at its current sample: both crowds, the
        arrivals, the robot, the routes and the robot's episode.

        For look-ahead: a reference planner (``oracle``) copies the running episode into
        an engine of its own and steps that one; ``other`` is only read. Both engines
        must run the same set-up (the same :class:`~srfm.scenarios.EpisodeSetup` object).

        Raises:
            SimulationError: ``other`` runs another set-up.
        """
        if other.setup is not self.setup:
            raise SimulationError("copy_from needs an engine of the same episode set-up")
        for twin in (0, 1):
            mine, theirs = self.crowd(twin), other.crowd(twin)
            for name in ("pos", "vel", "goal"):
                getattr(mine, name)[:] = getattr(theirs, name)
        self._arrived[:] = other._arrived
        self._new[:] = other._new
        self._goal_count[:] = other._goal_count
        self._goal_cache = dict(other._goal_cache)
        self.robot[:] = other.robot
        self._body[:] = other._body
        self.robot_active = other.robot_active
        self.outcome = other.outcome
        self.end_step = other.end_step
        self.step_index = other.step_index
        if self.robot_route is not None and other.robot_route is not None:
            self.robot_route.copy_from(other.robot_route)
        for twin, routes in self._ped_routes.items():
            routes.copy_from(other._ped_routes[twin])
        if other.n_present != self.n_present:
            self.n_present = other.n_present
            self._pack(self.n_present)

    def crowd(self, twin: int) -> CrowdState:
        """The factual (0) or counterfactual (1) crowd."""
        return self.factual if twin == 0 else self.counterfactual

    @property
    def robot_state(self) -> RobotState:
        """The robot now, as a :class:`srfm.RobotState`."""
        return RobotState.from_array(self.robot)

    @property
    def time_s(self) -> float:
        """Simulated time of the current sample (s)."""
        return self.step_index * self.scenario.dt_s

    @property
    def done(self) -> bool:
        """True once the horizon is reached."""
        return self.step_index >= self.scenario.horizon_steps

    def _pack(self, m: int) -> None:
        """The kernels' view of the first ``m`` pedestrians (views of the crowds' arrays)."""
        self._factual_view = self.factual.for_kernels(m)
        self.arrays = _k.EpisodeArrays(
            factual=self._factual_view,
            counterfactual=self.counterfactual.for_kernels(m),
            factual_arrivals=_k.ArrivalFlags(self._arrived[0, :m], self._new[0, :m]),
            counterfactual_arrivals=_k.ArrivalFlags(self._arrived[1, :m], self._new[1, :m]),
            robot=self.robot,
            felt=self._felt,
            force_buf=self._force_buf[:m],
            limits=self._limits,
            task=self.task,
            options=self._options,
        )

    def _event_args(self) -> tuple[Any, ...]:
        """:func:`robot_event`'s arguments but the sample index."""
        return (self.robot, self._factual_view, self._obstacles, self._limits, self.task)

    def steering_goal(self) -> FloatArray:
        """(2,) what the robot's planner steers to: the route's current waypoint in a
        scenario with obstacles (:class:`srfm.sim.routes.RobotRoute`), else the goal."""
        route = self.robot_route
        if route is None:
            return self.setup.robot_goal.copy()
        return np.array(route.waypoints[route.index], dtype=np.float64)

    def advance(self, c0: float = 0.0, c1: float = 0.0) -> list[Event]:
        """One step with the robot's command (c0, c1), already checked (ignored once the
        robot's episode has ended); the events detected at the new sample."""
        if self._advance is None:
            self._advance = specialize_once(self._kernel, self.arrays, 0.0, 0.0, True, 0)
        n_new, code, nearest = self._advance(
            self.arrays, c0, c1, self.robot_active, self.step_index
        )
        code, nearest = self.enter_sample(code, nearest)
        return self.apply_events(n_new, code, nearest)

    @property
    def can_rest(self) -> bool:
        """:meth:`rest` applies: the robot's episode has ended, everyone is there and
        nobody follows a route (so a step without arrivals needs no Python), and the
        crowd step is not the threaded one."""
        return (
            not self.robot_active
            and not self.has_routes
            and self.n_present == self.factual.n
            and self._rest_kernel is not None
        )

    def prepare_rest(self, samples: _k.Samples) -> None:
        """Compile (or load) :meth:`rest`'s kernel for arrays like ``samples`` now: the
        benchmark's warm-up episodes end before the robot does, and its workers would
        otherwise each compile it (nothing without a kernel for it)."""
        if self._rest is None and self._rest_kernel is not None:
            self._rest = specialize_once(self._rest_kernel, self.arrays, 0, 0, samples)

    def rest(self, stop: int, samples: _k.Samples) -> list[Event]:
        """Steps with the robot at rest, in one kernel call (only where
        :attr:`can_rest`): the same steps as :meth:`advance` without a command, up to
        sample ``stop`` or the first step with new arrivals, whichever comes first.
        The samples before the last one reached are written into ``samples``; the
        last one (at ``stop``, or with its arrivals applied) is the caller's to record.

        Returns:
            The events of the last step reached (its arrivals).
        """
        if not self.can_rest:
            raise SimulationError("rest() needs the robot at rest, no routes, and no entries")
        if not self.step_index < stop <= self.scenario.horizon_steps:
            raise SimulationError(f"rest() to sample {stop} from sample {self.step_index}")
        self.prepare_rest(samples)
        assert self._rest is not None
        k, n_new = self._rest(self.arrays, self.step_index, stop, samples)
        self.step_index = k
        return self.apply_events(n_new, _rk.EVENT_NONE, -1)

    def enter_sample(self, code: int, nearest: int) -> tuple[int, int]:
        """Step 2: the episode is at the next sample, with the pedestrians that enter
        there; the robot event ``code`` (and its ``nearest`` pedestrian) again when
        someone entered."""
        self.step_index += 1
        if self._enter_step is None:
            return code, nearest
        m = self.setup.n_present(self.step_index)
        if m == self.n_present:
            return code, nearest
        self.n_present = m  # new pedestrians at their starts
        self._pack(m)
        if self.robot_active:
            return self._robot_event(*self._event_args(), self.step_index)
        return code, nearest

    def apply_events(self, n_new: int, code: int, nearest: int) -> list[Event]:
        """Step 3: arrivals, routes and the robot event at the current sample; their
        records (pedestrian events first, factual twin first)."""
        events: list[Event] = []
        if n_new:
            events += self._arrivals(0)
            events += self._arrivals(1)
        m = self.n_present
        for twin, routes in self._ped_routes.items():  # after the arrivals on these legs
            crowd = self.crowd(twin)
            routes.advance(crowd.pos, crowd.goal, m)
        if self.robot_route is not None and self.robot_active:
            self.robot_route.update(self.robot[_rk.X], self.robot[_rk.Y])
        if self.robot_active:
            events += self._robot_events(code, nearest)
        return events

    def _arrivals(self, twin: int) -> list[Event]:
        """The twin's new arrivals at its goal (an arrival at a route's waypoint is
        none): new goals (re-goaling) or the arrived mark, and their records."""
        ids = np.flatnonzero(self._new[twin, : self.n_present])
        routes = self._ped_routes.get(twin)
        if routes is not None:
            ids = ids[[routes.at_goal_leg(int(i)) for i in ids]]
        if self._regoal:
            goal = self.crowd(twin).goal
            count = self._goal_count[twin]
            for idx in ids:
                i = int(idx)
                count[i] += 1
                key = (i, int(count[i]))
                new_goal = self._goal_cache.get(key)
                if new_goal is None:
                    new_goal = next_goal(self.setup, i, key[1], goal[i].copy())
                    self._goal_cache[key] = new_goal
                goal[i] = new_goal
        else:
            self._arrived[twin, ids] = True
        if not self.records:
            return []
        t = self.time_s
        k = self.step_index
        name = _TWINS[twin]
        return [Event(step=k, time_s=t, kind="ped_arrival", agent=int(i), twin=name) for i in ids]

    def end_robot(self, outcome: RobotOutcome) -> None:
        """End the robot's episode at the current sample with ``outcome``, no event of
        the world causing it (a planner that failed): from the next step on the robot
        rests where it is, as after any other end. Nothing when it has ended already."""
        if not self.robot_active:
            return
        self.robot_active = False
        self.outcome = outcome
        self.end_step = self.step_index

    def _robot_events(self, code: int, nearest: int) -> list[Event]:
        """The robot event ``code`` at the current sample as a record; it ends the
        robot's episode."""
        if code == _rk.EVENT_NONE:
            return []
        k = self.step_index
        self.robot_active = False
        self.outcome = EVENT_OUTCOMES[code]
        self.end_step = k
        if not self.records:
            return []
        return [Event(step=k, time_s=self.time_s, kind=_EVENT_KINDS[code], agent=int(nearest))]
