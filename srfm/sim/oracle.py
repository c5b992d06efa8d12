"""The ``oracle`` reference: sampling-based optimal control over the twin simulator itself.

A privileged planner, **not** a navigation policy a robot could run: it reads the
episode's own engine (:class:`srfm.sim.engine.EpisodeEngine`), so it knows the crowd
model and its parameters, every pedestrian's position, velocity, goal and route, and
the counterfactual crowd's whole future. It is there to say how little a robot that
still reaches its goal could disturb the crowd of a scenario: the benchmark's
*headroom*, ``deviation(straight) − deviation(oracle)`` (:mod:`srfm.metrics.headroom`,
docs/benchmark.md).

**How it plans.** At the first step it copies the episode into a look-ahead engine of
its own (:meth:`EpisodeEngine.look_ahead`, the factual crowd only; the counterfactual
crowd's path does not depend on the robot and is simulated once) and simulates every
plan of a small family to the episode's horizon:

1. *step aside* to a point ``aside_m`` from the start, at ``aside_deg`` from the bearing
   of the route's first waypoint (or stay at the start);
2. *wait* there, standing, until ``wait_s`` seconds into the episode;
3. *go* to the goal the way ``straight`` does (full speed at the route's waypoints).

The plan with no step aside and no wait **is** ``straight``. Plans whose robot collides,
leaves the world or misses its goal are ruled out. Each remaining plan is scored by
the pedestrians' mean Fréchet deviation at the horizon, computed on the way with the
dynamic programme of :mod:`srfm.sim._oracle_kernels` (factual positions every
``score_every`` samples, a band of ``band_s``); a plan is dropped as soon as its running
lower bound exceeds the best score so far. The ``exact_top`` best plans and
``straight`` are then simulated again and scored with the episode's own metric, the
exact discrete Fréchet distance (the same programme with every sample and no band,
equal to :func:`srfm.metrics.frechet.frechet_distances`); the best of them is played, command
by command. The episode the benchmark records is that simulation: the oracle reaches
its goal whenever one plan of the family does, and its deviation is never above
``straight``'s in the same episode.

Every ``replan_s`` seconds, while the robot has not started its last leg, it plans
again from where the episode is (receding horizon), keeping the remainder of its
current plan as a candidate, so a new plan is taken only when it scores better.

The oracle draws no randomness and steps only its own engine: an episode with it is
bit-identical for a given seed, in any process. It runs only inside
:func:`srfm.run_episode` (the benchmark, ``srfm simulate``), which hands it the engine
through :meth:`OraclePlanner.attach_episode`.
"""

from __future__ import annotations

import math
from typing import Any

import attrs
import numpy as np

from srfm._text import plain
from srfm.errors import ParameterError, PlannerError
from srfm.models import _robot_kernels as _rk
from srfm.planners._base import FloatArray, Observation, PlannerContext
from srfm.sim._oracle_kernels import extend_prefix_frechet, prefix_frechet_mean
from srfm.sim.engine import EpisodeEngine

__all__ = ["OracleConfig", "OraclePlanner"]

Command = tuple[float, float]


def _positive_int(inst: object, attribute: attrs.Attribute[int], value: int) -> None:
    if isinstance(value, bool) or not isinstance(value, int) or value < 1:
        raise ParameterError(f"oracle {attribute.name} must be an integer >= 1, got {plain(value)}")


def _positive(inst: object, attribute: attrs.Attribute[float], value: float) -> None:
    if isinstance(value, bool) or not isinstance(value, float | int) or not value > 0.0:
        raise ParameterError(f"oracle {attribute.name} must be a number > 0, got {plain(value)}")


def _tuple(value: Any) -> Any:
    """A sequence as a tuple; anything else as it is, for the validator to name."""
    try:
        return tuple(value)
    except TypeError:
        return value


def _numbers(low: float, high: float) -> Any:
    def check(inst: object, attribute: attrs.Attribute[tuple[float, ...]], value: Any) -> None:
        ok = isinstance(value, tuple) and all(
            isinstance(x, float | int) and not isinstance(x, bool) and low <= x <= high
            for x in value
        )
        if not ok:
            raise ParameterError(
                f"oracle {attribute.name} must be numbers in [{low}, {high}], got {plain(value)}"
            )

    return check


@attrs.frozen(kw_only=True)
class OracleConfig:
    """The oracle's family of plans and its scoring (see the module doc).

    Attributes:
        aside_m: distances (m) of the points it may step aside to.
        aside_deg: their directions, degrees from the bearing of the first waypoint.
        waits_s: the times (s from the episode's start) it may wait until.
        aside_timeout_s: longest time (s) spent stepping aside.
        arrive_m: a point to step aside to is reached closer than this (m).
        band_s: the largest time shift (s) between matched factual and counterfactual
            samples in the plans' Fréchet score.
        score_every: a plan's factual positions enter its score every this many samples.
        exact_top: the best plans scored again with the exact metric.
        replan_s: time (s) between two plans while the robot has not started to go.
    """

    aside_m: tuple[float, ...] = attrs.field(
        default=(1.0, 2.5), converter=_tuple, validator=_numbers(0.0, 100.0)
    )
    aside_deg: tuple[float, ...] = attrs.field(
        default=(90.0, -90.0, 180.0, 45.0, -45.0, 135.0, -135.0),
        converter=_tuple,
        validator=_numbers(-180.0, 180.0),
    )
    waits_s: tuple[float, ...] = attrs.field(
        default=(0.0, 2.0, 4.0, 7.0, 10.0, 14.0, 18.0, 23.0, 28.0),
        converter=_tuple,
        validator=_numbers(0.0, 1e6),
    )
    aside_timeout_s: float = attrs.field(default=8.0, validator=_positive)
    arrive_m: float = attrs.field(default=0.2, validator=_positive)
    band_s: float = attrs.field(default=10.0, validator=_positive)
    score_every: int = attrs.field(default=3, validator=_positive_int)
    exact_top: int = attrs.field(default=3, validator=_positive_int)
    replan_s: float = attrs.field(default=6.0, validator=_positive)


@attrs.frozen
class _Plan:
    """Step aside to ``via`` (None: stay), wait until sample ``go_at``, then go."""

    via: tuple[float, float] | None
    go_at: int


@attrs.frozen
class _Replay:
    """The rest of the current plan: its commands, and the sample its last leg starts."""

    commands: list[Command]
    go_at: int


class OraclePlanner:
    """Optimal control over the episode's own twin simulator (see the module doc).

    Args:
        config: the plans and their scoring; :class:`OracleConfig`'s defaults when
            omitted.
    """

    name = "oracle"
    detection_range_m: float | None = 0.0  # it reads the engine, not the observation

    def __init__(self, config: OracleConfig | None = None) -> None:
        self.config = config if config is not None else OracleConfig()
        self._engine: EpisodeEngine | None = None
        self._context: PlannerContext | None = None
        self._commands: list[Command] = []

    def reset(self, context: PlannerContext, rng: np.random.Generator) -> None:
        """Forget the last episode; the engine comes with :meth:`attach_episode`."""
        self._context = context
        self._engine = None
        self._commands = []

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
        self._band = max(1, round(self.config.band_s / engine.scenario.dt_s))
        self._full = horizon  # no band: the exact metric
        self._table = np.full((engine.factual.n, horizon + 1), np.inf)
        self._row = -1  # the last sample act() saw
        self._history = np.empty((horizon + 1, engine.factual.n, 2))  # the factual path
        self._commands = []
        self._next_plan = 0
        self._go_at = horizon + 1  # the sample the current plan's last leg starts
        self._scored = -1  # the last sample in the table

    def act(self, observation: Observation) -> FloatArray:
        """The next command of the current plan; a new plan at the start and every
        ``replan_s`` seconds until the robot goes."""
        engine = self._engine
        if engine is None:
            raise PlannerError(
                "the oracle reads the episode's engine: run it with srfm.run_episode "
                "(srfm benchmark, srfm simulate), not step by step"
            )
        k = engine.step_index
        if k != self._row + 1:
            raise PlannerError(f"oracle: asked at sample {k} after sample {self._row}")
        self._history[k] = engine.factual.pos
        if k % self.config.score_every == 0:
            extend_prefix_frechet(self._table, engine.factual.pos, self._c_path, k, self._band)
            self._scored = k
        self._row = k
        if k >= self._next_plan and k < self._go_at:
            self._plan(engine)
            self._next_plan = k + max(1, round(self.config.replan_s / engine.scenario.dt_s))
        if not self._commands:  # the plan ran out (it cannot in the episode it was made for)
            return np.array(self._steer(engine, 1.0))
        return np.array(self._commands.pop(0))

    # ----- planning -------------------------------------------------------------------

    def _plans(self, engine: EpisodeEngine) -> list[_Plan]:
        """The family from the current sample: go now (``straight``) first."""
        cfg = self.config
        dt = engine.scenario.dt_s
        k = engine.step_index
        x, y = float(engine.robot[_rk.X]), float(engine.robot[_rk.Y])
        tx, ty = self._waypoint(engine)
        bearing = math.atan2(ty - y, tx - x)
        vias: list[tuple[float, float] | None] = [None]
        for r in cfg.aside_m:
            for deg in cfg.aside_deg:
                if r > 0.0:
                    a = bearing + math.radians(deg)
                    vias.append((x + r * math.cos(a), y + r * math.sin(a)))
        go_ats = sorted({max(k, round(w / dt)) for w in cfg.waits_s})
        return [_Plan(via, go_at) for via in vias for go_at in go_ats]

    def _plan(self, engine: EpisodeEngine) -> None:
        """Score the family (and the rest of the current plan) and keep the best."""
        scored: list[tuple[float, int, list[Command], int]] = []
        best = math.inf
        if self._commands:
            incumbent = _Replay(list(self._commands), self._go_at)
            score, commands, go_at = self._rollout(engine, incumbent, best)
            if score < math.inf:
                scored.append((score, -1, commands, go_at))
                best = score
        for index, plan in enumerate(self._plans(engine)):
            score, commands, go_at = self._rollout(engine, plan, best)
            if score < math.inf:
                scored.append((score, index, commands, go_at))
                best = min(best, score)
        if not scored:  # every plan collides or misses the goal: go as straight does
            self._commands = []
            self._go_at = engine.step_index
            return
        scored.sort(key=lambda item: (item[0], item[1]))
        top = self.config.exact_top
        finalists = scored[:top] + [s for s in scored[top:] if s[1] in (-1, 0)]
        exact = [(self._exact(engine, c), i, c, g) for _, i, c, g in finalists]
        exact.sort(key=lambda item: (item[0], item[1]))
        _, _, self._commands, self._go_at = exact[0]

    def _rollout(
        self, engine: EpisodeEngine, plan: _Plan | _Replay, bound: float
    ) -> tuple[float, list[Command], int]:
        """Simulate ``plan`` from now to the horizon: its score (inf when ruled out or
        worse than ``bound``), its commands and the sample its last leg starts at."""
        sim = self._scratch
        sim.copy_from(engine)
        table = self._table.copy()
        c_path = self._c_path
        band = self._band
        every = self.config.score_every
        dt = engine.scenario.dt_s
        start = engine.step_index
        played: list[Command] = []
        if isinstance(plan, _Replay):
            phase, go_at = -1, plan.go_at
        else:
            phase, go_at = (0 if plan.via is not None else 1), engine.scenario.horizon_steps + 1
        aside_until = start + round(self.config.aside_timeout_s / dt)
        arrive2 = self.config.arrive_m**2
        scored = self._scored
        while not sim.done:
            k = sim.step_index
            if sim.robot_active:
                if isinstance(plan, _Replay):
                    i = k - start
                    command = plan.commands[i] if i < len(plan.commands) else self._steer(sim, 1.0)
                else:
                    if phase == 0:
                        assert plan.via is not None
                        dx = plan.via[0] - sim.robot[_rk.X]
                        dy = plan.via[1] - sim.robot[_rk.Y]
                        if dx * dx + dy * dy < arrive2 or k >= aside_until:
                            phase = 1
                    if phase == 1 and k >= plan.go_at:
                        phase, go_at = 2, k
                    if phase == 0:
                        assert plan.via is not None
                        command = self._steer_to(sim, plan.via[0], plan.via[1], 1.0)
                    elif phase == 1:
                        command = (0.0, 0.0)
                    else:
                        command = self._steer(sim, 1.0)
                played.append(command)
                sim.advance(command[0], command[1])
                if sim.outcome in ("collision", "out_of_bounds", "timeout"):
                    return math.inf, played, go_at
            else:
                sim.advance()
            t = sim.step_index
            if t % every == 0 or t == sim.scenario.horizon_steps:
                extend_prefix_frechet(table, sim.factual.pos, c_path, t, band)
                scored = t
                if prefix_frechet_mean(table, t, band) > bound:
                    return math.inf, played, go_at
        if sim.outcome != "goal_reached":
            return math.inf, played, go_at
        last = sim.scenario.horizon_steps
        if scored != last:
            return math.inf, played, go_at
        return (float(table[:, last].mean()) if table.shape[0] else 0.0), played, go_at

    def _exact(self, engine: EpisodeEngine, commands: list[Command]) -> float:
        """The episode's mean Fréchet deviation when ``commands`` are played from now
        (every sample, no band: the metric ``frechet_m`` itself)."""
        sim = self._scratch
        sim.copy_from(engine)
        start = engine.step_index
        table = np.full_like(self._table, np.inf)
        for k in range(start + 1):  # the episode so far
            extend_prefix_frechet(table, self._history[k], self._c_path, k, self._full)
        while not sim.done:
            k = sim.step_index
            if sim.robot_active:
                i = k - start
                command = commands[i] if i < len(commands) else self._steer(sim, 1.0)
                sim.advance(command[0], command[1])
            else:
                sim.advance()
            extend_prefix_frechet(table, sim.factual.pos, self._c_path, sim.step_index, self._full)
        return float(table[:, -1].mean()) if table.shape[0] else 0.0

    # ----- steering ---------------------------------------------------------------------

    @staticmethod
    def _waypoint(sim: EpisodeEngine) -> tuple[float, float]:
        route = sim.robot_route
        if route is None:
            goal = sim.setup.robot_goal
            return float(goal[0]), float(goal[1])
        point = route.waypoints[route.index]
        return float(point[0]), float(point[1])

    def _steer(self, sim: EpisodeEngine, speed: float) -> Command:
        """``straight``'s command toward the route's current waypoint."""
        tx, ty = self._waypoint(sim)
        return self._steer_to(sim, tx, ty, speed)

    @staticmethod
    def _steer_to(sim: EpisodeEngine, tx: float, ty: float, speed: float) -> Command:
        """Toward (tx, ty) by the ``straight`` planner's law
        (:class:`srfm.planners.StraightPlanner`) at ``speed`` · v_max."""
        robot = sim.robot
        limits = sim.scenario.robot
        if limits.kinematics == "holonomic":
            dx, dy = tx - robot[_rk.X], ty - robot[_rk.Y]
            dist = math.hypot(dx, dy)
            if dist < 1e-12:
                return 0.0, 0.0
            vmax = speed * limits.max_speed_mps
            return vmax * dx / dist, vmax * dy / dist
        error = math.remainder(
            math.atan2(ty - robot[_rk.Y], tx - robot[_rk.X]) - robot[_rk.THETA], 2.0 * math.pi
        )
        wmax = limits.max_angular_speed_radps
        omega = max(-wmax, min(wmax, 2.0 * error))
        return speed * limits.max_speed_mps * max(math.cos(error), 0.0), omega
