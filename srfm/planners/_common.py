"""Shared parts of the classical planners: config validators, static geometry, and
the per-episode set-up every kernel-backed planner does at reset."""

from __future__ import annotations

import math
from typing import Any, Generic, TypeVar

import attrs
import numpy as np

from srfm._text import plain
from srfm._validate import finite_float, non_negative, positive, unit_interval
from srfm.errors import PlannerError
from srfm.models.robot import RobotConfig
from srfm.models.state import Obstacles
from srfm.planners._base import FloatArray, PlannerContext
from srfm.planners._geometry import CommonParams
from srfm.world import WorldBounds

__all__ = [
    "DEFAULT_DT_S",
    "KernelPlanner",
    "check_bool",
    "check_detection_range",
    "check_finite",
    "check_non_negative",
    "check_optional_positive",
    "check_positive",
    "check_positive_int",
    "check_unit_interval",
    "check_unit_open",
    "static_geometry",
]

DEFAULT_DT_S = 1.0 / 15.0

P = TypeVar("P", bound=tuple[Any, ...])


def _field(inst: Any, attribute: attrs.Attribute[Any]) -> str:
    return f"{type(inst).__name__}.{attribute.name}"


def check_positive(inst: Any, attribute: attrs.Attribute[Any], value: Any) -> None:
    """attrs validator: a finite number > 0."""
    positive(value, _field(inst, attribute), PlannerError)


def check_non_negative(inst: Any, attribute: attrs.Attribute[Any], value: Any) -> None:
    """attrs validator: a finite number >= 0."""
    non_negative(value, _field(inst, attribute), PlannerError)


def check_finite(inst: Any, attribute: attrs.Attribute[Any], value: Any) -> None:
    """attrs validator: a finite number."""
    finite_float(value, _field(inst, attribute), PlannerError)


def check_unit_open(inst: Any, attribute: attrs.Attribute[Any], value: Any) -> None:
    """attrs validator: a number in (0, 1]."""
    out = finite_float(value, _field(inst, attribute), PlannerError)
    if not 0.0 < out <= 1.0:
        raise PlannerError(f"{_field(inst, attribute)} must be in (0, 1], got {plain(value)}")


def check_unit_interval(inst: Any, attribute: attrs.Attribute[Any], value: Any) -> None:
    """attrs validator: a number in [0, 1]."""
    unit_interval(value, _field(inst, attribute), PlannerError)


def check_positive_int(inst: Any, attribute: attrs.Attribute[Any], value: Any) -> None:
    """attrs validator: an integer >= 1 (and at most 10,000: a per-step sample count)."""
    if isinstance(value, bool) or not isinstance(value, int | np.integer):
        raise PlannerError(f"{_field(inst, attribute)} must be an integer, got {plain(value)}")
    if not 1 <= value <= 10_000:
        raise PlannerError(f"{_field(inst, attribute)} must be in [1, 10000], got {plain(value)}")


def check_bool(inst: Any, attribute: attrs.Attribute[Any], value: Any) -> None:
    """attrs validator: True or False."""
    if not isinstance(value, bool):
        raise PlannerError(f"{_field(inst, attribute)} must be True or False, got {plain(value)}")


def check_detection_range(inst: Any, attribute: attrs.Attribute[Any], value: Any) -> None:
    """attrs validator: None (observe everyone) or a finite number >= 0 (m)."""
    if value is not None:
        non_negative(value, _field(inst, attribute), PlannerError)


def check_optional_positive(inst: Any, attribute: attrs.Attribute[Any], value: Any) -> None:
    """attrs validator: None or a finite number > 0."""
    if value is not None:
        positive(value, _field(inst, attribute), PlannerError)


def static_geometry(obstacles: Obstacles) -> tuple[FloatArray, FloatArray]:
    """Writable, C-contiguous copies (segments (M, 4), circles (K, 3)) for the kernels."""
    segments = np.ascontiguousarray(obstacles.segments, dtype=np.float64).copy()
    circles = np.ascontiguousarray(obstacles.circles, dtype=np.float64).copy()
    return segments, circles


class KernelPlanner(Generic[P]):
    """Base of the planners whose step is one numba kernel call.

    Subclasses set ``name``, build their own kernel parameters in :meth:`_own_params`
    and implement ``act``. Everything a planner knows about an episode is rebuilt by
    :meth:`reset`; nothing carries over between episodes and no randomness is drawn.

    Attributes:
        common: the robot and world part of the kernel parameters of the episode.
        params: the planner's own kernel parameters (a NamedTuple per planner).
    """

    name: str = ""
    params: P

    def __init__(
        self,
        detection_range_m: float | None,
        safety_margin_m: float,
        heading_gain_per_s: float,
        avoid_world_edges: bool,
    ) -> None:
        self.detection_range_m: float | None = detection_range_m
        self._margin = float(safety_margin_m)
        self._heading_gain = float(heading_gain_per_s)
        self._avoid_edges = avoid_world_edges
        self._configure(RobotConfig(), DEFAULT_DT_S, None, Obstacles())

    def reset(self, context: PlannerContext, rng: np.random.Generator) -> None:
        """Take the robot's limits, the step and the static obstacles of the episode.

        The planner is deterministic: it draws nothing from ``rng``.
        """
        self._configure(context.robot, context.dt_s, context.world, context.obstacles)

    def _configure(
        self, robot: RobotConfig, dt_s: float, world: WorldBounds | None, obstacles: Obstacles
    ) -> None:
        self._robot = robot
        self._unicycle = robot.kinematics == "unicycle"
        self._segments, self._circles = static_geometry(obstacles)
        self._near = np.zeros(self._segments.shape[0])
        edges = False
        bounds = (0.0, 0.0, 0.0, 0.0)
        if self._avoid_edges and world is not None:
            edges = True
            bounds = (
                float(world.x_min),
                float(world.x_max),
                float(world.y_min),
                float(world.y_max),
            )
        self.common = CommonParams(
            radius_m=float(robot.radius_m),
            max_speed_mps=float(robot.max_speed_mps),
            max_angular_speed_radps=float(robot.max_angular_speed_radps),
            heading_gain_per_s=self._heading_gain,
            unicycle=self._unicycle,
            margin_m=self._margin,
            dt_s=float(dt_s),
            goal_radius_m=float(robot.goal_radius_m),
            avoid_edges=edges,
            x_min=bounds[0],
            x_max=bounds[1],
            y_min=bounds[2],
            y_max=bounds[3],
        )
        self.params = self._own_params(robot, dt_s)
        if any(math.isnan(value) for value in (*self.common, *self.params)):
            raise PlannerError(
                f"{self.name}: NaN in the planner parameters {self.common!r}, {self.params!r}"
            )
        # What the kernels are passed each step: the same fields as plain tuples, which
        # numba types far faster than NamedTuples (see srfm.planners._geometry).
        self._common_fields = tuple(self.common)
        self._params_fields = tuple(self.params)

    def _own_params(self, robot: RobotConfig, dt_s: float) -> P:
        """The planner's own kernel parameters (a NamedTuple) for this robot and step."""
        raise NotImplementedError
