"""The ``oracle`` reference: model-predictive control over the twin simulator itself.

A privileged planner, **not** a navigation policy a robot could run: it reads the
episode's own engine (:class:`srfm.sim.engine.EpisodeEngine`), so it knows the crowd
model and its parameters, every pedestrian's position, velocity, goal and route, and
the counterfactual crowd's whole future. It is there to say how little a robot that
still reaches its goal could disturb the crowd of a scenario: the benchmark's
*headroom* (``deviation(straight) − deviation(oracle)``, see
:mod:`srfm.metrics.headroom` and docs/benchmark.md).

Every ``replan_steps`` steps it copies the running episode into a look-ahead engine
(:meth:`EpisodeEngine.look_ahead`, the factual crowd only) and rolls out each candidate
for ``horizon_steps`` steps. A candidate is a steering rule held for the whole
look-ahead: head at ``offset`` from the bearing of the current route waypoint at a
``speed`` fraction of the top speed (offsets × speeds of :class:`OracleConfig`), or
stand still. Its cost is

    predicted deviation + progress_weight · route length left (m),

where the predicted deviation is the mean over pedestrians of the prefix Fréchet
deviation at the end of the look-ahead (:mod:`srfm.planners._oracle_kernels`: the
Fréchet distance between each pedestrian's factual path so far, predicted, and the
best-matching beginning of its counterfactual path; a surrogate of the episode's
``frechet_m`` that, like it, does not charge a pedestrian for being late). A candidate
whose rollout collides (pedestrian, wall) or leaves the world is ruled out; one that
would no longer reach the goal in time (route length left / top speed +
``deadline_margin_s`` beyond the horizon) is ruled out while any candidate can. The
chosen candidate's first ``replan_steps`` commands are then played.

When the candidate "head for the waypoint at top speed" changes the predicted deviation
by less than ``shortcut_m``, it is taken without rolling out the others (nobody is near
enough to gain from anything else), which keeps an episode under a second of CPU.

The oracle draws no randomness and steps only its own engine: an episode with it is
bit-identical for a given seed, in any process. It runs only inside
:func:`srfm.run_episode` (the benchmark, ``srfm simulate``), which hands it the engine
through :meth:`OraclePlanner.attach_episode`.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import attrs
import numpy as np

from srfm.errors import ParameterError, PlannerError
from srfm.models import _robot_kernels as _rk
from srfm.planners._base import FloatArray, Observation, PlannerContext
from srfm.planners._oracle_kernels import extend_prefix_frechet, prefix_frechet_mean

if TYPE_CHECKING:
    from srfm.sim.engine import EpisodeEngine

__all__ = ["OracleConfig", "OraclePlanner"]

_RULED_OUT = 1e6  # cost of a rollout that collides or leaves the world
_LATE = 1e3  # cost added to a rollout that can no longer reach the goal in time


def _positive_int(inst: object, attribute: attrs.Attribute[int], value: int) -> None:
    if isinstance(value, bool) or not isinstance(value, int) or value < 1:
        raise ParameterError(f"oracle {attribute.name} must be an integer >= 1, got {value!r}")


def _non_negative(inst: object, attribute: attrs.Attribute[float], value: float) -> None:
    if isinstance(value, bool) or not isinstance(value, float | int) or not value >= 0.0:
        raise ParameterError(f"oracle {attribute.name} must be a number >= 0, got {value!r}")


def _speeds(inst: object, attribute: attrs.Attribute[tuple[float, ...]], value: object) -> None:
    items = tuple(value) if isinstance(value, tuple | list) else ()
    if not items or not all(isinstance(s, float | int) and 0.0 < s <= 1.0 for s in items):
        raise ParameterError(f"oracle speeds must be fractions in (0, 1], got {value!r}")


def _offsets(inst: object, attribute: attrs.Attribute[tuple[float, ...]], value: object) -> None:
    items = tuple(value) if isinstance(value, tuple | list) else ()
    if not items or not all(isinstance(a, float | int) and abs(a) <= 180.0 for a in items):
        raise ParameterError(f"oracle offsets_deg must be angles in [-180, 180], got {value!r}")


@attrs.frozen(kw_only=True)
class OracleConfig:
    """The oracle's look-ahead (defaults: measured on the paper suite, docs/benchmark.md).

    Attributes:
        horizon_steps: samples each candidate is rolled out for (45: 3 s at 15 Hz).
        replan_steps: samples between two plans (5: 1/3 s at 15 Hz).
        offsets_deg: heading offsets from the waypoint's bearing (degrees).
        speeds: speed fractions of the robot's top speed, each paired with each offset.
        band_s: how far (s) a pedestrian's factual and counterfactual samples may be
            matched apart in the prefix Fréchet deviation.
        progress_weight: cost per metre of route left (m of mean deviation per m).
        deadline_margin_s: a candidate must leave this much time (s) beyond the route
            left at top speed before the horizon.
        shortcut_m: take "straight to the waypoint" without comparing when it adds less
            than this to the predicted mean deviation (m).
        turn_gain: ω = clip(turn_gain · heading error, ±ω_max).
        score_every: a rollout's factual positions enter the prefix Fréchet deviation
            every this many samples (and at its last), a coarser path for a third of
            the cost.
    """

    horizon_steps: int = attrs.field(default=45, validator=_positive_int)
    replan_steps: int = attrs.field(default=5, validator=_positive_int)
    offsets_deg: tuple[float, ...] = attrs.field(
        default=(0.0, 30.0, -30.0, 60.0, -60.0, 90.0, -90.0, 180.0),
        converter=tuple,
        validator=_offsets,
    )
    speeds: tuple[float, ...] = attrs.field(default=(1.0, 0.5), converter=tuple, validator=_speeds)
    band_s: float = attrs.field(default=10.0, validator=_non_negative)
    progress_weight: float = attrs.field(default=0.005, validator=_non_negative)
    deadline_margin_s: float = attrs.field(default=4.0, validator=_non_negative)
    shortcut_m: float = attrs.field(default=2e-4, validator=_non_negative)
    score_every: int = attrs.field(default=3, validator=_positive_int)
    turn_gain: float = attrs.field(default=2.0, validator=_non_negative)

    def candidates(self) -> tuple[tuple[float, float], ...]:
        """(offset rad, speed fraction) of every candidate, "straight to the waypoint
        at top speed" first, standing still (speed 0) last."""
        top = max(self.speeds)
        pairs = [(0.0, top)]
        for speed in self.speeds:
            for deg in self.offsets_deg:
                pair = (math.radians(deg), float(speed))
                if pair not in pairs:
                    pairs.append(pair)
        pairs.append((0.0, 0.0))
        return tuple(pairs)


class OraclePlanner:
    """Sampling-based MPC over the episode's own twin simulator (see the module doc).

    Args:
        config: the look-ahead; :class:`OracleConfig`'s defaults when omitted.
    """

    name = "oracle"
    detection_range_m: float | None = 0.0  # it reads the engine, not the observation

    def __init__(self, config: OracleConfig | None = None) -> None:
        self.config = config if config is not None else OracleConfig()
        self._candidates = self.config.candidates()
        self._engine: EpisodeEngine | None = None
        self._context: PlannerContext | None = None

    def reset(self, context: PlannerContext, rng: np.random.Generator) -> None:
        """Forget the last episode; the engine comes with :meth:`attach_episode`."""
        self._context = context
        self._engine = None

    def attach_episode(self, engine: EpisodeEngine) -> None:
        """Take the running episode's engine (read only; called by
        :func:`srfm.run_episode` after :meth:`reset`): make the look-ahead engine and
        the counterfactual crowd's path over the whole horizon."""
        if self._context is None:
            raise PlannerError("oracle: attach_episode() before reset()")
        self._engine = engine
        twin = engine.look_ahead(counterfactual=True)
        horizon = engine.scenario.horizon_steps
        path = np.empty((horizon + 1, engine.counterfactual.n, 2))
        path[twin.step_index] = twin.counterfactual.pos
        while not twin.done:
            twin.advance(0.0, 0.0)
            path[twin.step_index] = twin.counterfactual.pos
        self._c_path = np.ascontiguousarray(path.transpose(1, 0, 2))
        self._scratch = engine.look_ahead()
        dt = engine.scenario.dt_s
        self._band = max(1, round(self.config.band_s / dt))
        self._table = np.full((engine.factual.n, horizon + 1), np.inf)
        self._work = np.empty_like(self._table)
        self._row = -1  # the sample the table holds
        self._queue: list[tuple[float, float]] = []

    def act(self, observation: Observation) -> FloatArray:
        """The next command of the current plan; a new plan every ``replan_steps``."""
        engine = self._engine
        if engine is None:
            raise PlannerError(
                "the oracle reads the episode's engine: run it with srfm.run_episode "
                "(srfm benchmark, srfm simulate), not step by step"
            )
        k = engine.step_index
        if k != self._row + 1 and not (k == 0 and self._row == -1):
            raise PlannerError(f"oracle: asked at sample {k} after sample {self._row}")
        extend_prefix_frechet(self._table, engine.factual.pos, self._c_path, k, self._band)
        self._row = k
        if not self._queue:
            self._queue = self._plan(engine)
        c0, c1 = self._queue.pop(0)
        return np.array([c0, c1])

    def _plan(self, engine: EpisodeEngine) -> list[tuple[float, float]]:
        """The first ``replan_steps`` commands of the cheapest candidate."""
        now = prefix_frechet_mean(self._table, engine.step_index, self._band)
        best_cost = math.inf
        best: list[tuple[float, float]] = []
        for index, candidate in enumerate(self._candidates):
            cost, deviation, commands = self._rollout(engine, candidate)
            if cost < best_cost:
                best_cost, best = cost, commands
            if index == 0 and cost < _LATE and deviation - now < self.config.shortcut_m:
                break
        if not best:  # cannot happen while the robot is active: one step at least
            best = [(0.0, 0.0)]
        return best[: self.config.replan_steps]

    def _rollout(
        self, engine: EpisodeEngine, candidate: tuple[float, float]
    ) -> tuple[float, float, list[tuple[float, float]]]:
        """(cost, predicted mean deviation, commands) of holding ``candidate``."""
        sim = self._scratch
        sim.copy_from(engine)
        table = self._work
        table[:] = self._table
        robot = sim.robot
        limits = engine.scenario.robot
        vmax = limits.max_speed_mps
        wmax = limits.max_angular_speed_radps
        gain = self.config.turn_gain
        offset, speed = candidate
        every = self.config.score_every
        last = every - 1
        band = self._band
        scored = sim.step_index
        commands: list[tuple[float, float]] = []
        for h in range(self.config.horizon_steps):
            if sim.done:
                break
            if sim.robot_active:
                if speed == 0.0:
                    c0 = c1 = 0.0
                else:
                    tx, ty = self._waypoint(sim)
                    bearing = math.atan2(ty - robot[_rk.Y], tx - robot[_rk.X]) + offset
                    error = math.remainder(bearing - robot[_rk.THETA], 2.0 * math.pi)
                    c1 = max(-wmax, min(wmax, gain * error))
                    c0 = speed * vmax * max(math.cos(error), 0.0)
                commands.append((c0, c1))
                sim.advance(c0, c1)
                if sim.outcome in ("collision", "out_of_bounds"):
                    return _RULED_OUT - h, math.inf, commands
            else:
                sim.advance()
            if h % every == last:
                scored = sim.step_index
                extend_prefix_frechet(table, sim.factual.pos, self._c_path, scored, band)
        if sim.step_index != scored:  # the last sample counts
            extend_prefix_frechet(table, sim.factual.pos, self._c_path, sim.step_index, band)
        deviation = prefix_frechet_mean(table, sim.step_index, band)
        left = self._route_left(sim)
        cost = deviation + self.config.progress_weight * left
        if sim.robot_active:
            need_s = left / vmax + self.config.deadline_margin_s
            if need_s > (sim.scenario.horizon_steps - sim.step_index) * sim.scenario.dt_s:
                cost += _LATE + left
        return cost, deviation, commands

    @staticmethod
    def _waypoint(sim: EpisodeEngine) -> tuple[float, float]:
        route = sim.robot_route
        if route is None:
            goal = sim.setup.robot_goal
            return float(goal[0]), float(goal[1])
        point = route.waypoints[route.index]
        return float(point[0]), float(point[1])

    @staticmethod
    def _route_left(sim: EpisodeEngine) -> float:
        """The length (m) of the robot's route from where it is to its goal (0 once the
        goal is reached)."""
        if sim.outcome == "goal_reached":
            return 0.0
        x, y = float(sim.robot[_rk.X]), float(sim.robot[_rk.Y])
        route = sim.robot_route
        if route is None:
            goal = sim.setup.robot_goal
            return math.hypot(float(goal[0]) - x, float(goal[1]) - y)
        points = route.waypoints[route.index :]
        length = math.hypot(float(points[0, 0]) - x, float(points[0, 1]) - y)
        if len(points) > 1:
            length += float(np.hypot(*np.diff(points, axis=0).T).sum())
        return length
