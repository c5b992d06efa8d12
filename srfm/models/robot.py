"""The robot: configuration with kinematic limits, state, and the motion update.

Two kinematic models:

- ``unicycle``: command (v, ω), v in [−v_max, v_max] m/s, ω in [−ω_max, ω_max] rad/s;
  the heading turns by ω dt and the robot moves v dt along the mid-step heading.
- ``holonomic``: command (vx, vy) in the world frame, |v| ≤ v_max; the heading follows
  the direction of motion.

Both respect acceleration limits: the applied velocity changes by at most
``max_accel_mps2 · dt`` per step (and ω by ``max_angular_accel_radps2 · dt``).

The update itself is the numba kernel :func:`srfm.models._robot_kernels.move_robot`,
the one implementation that the simulator and the RL environment call as well;
:func:`apply_command` validates a command and calls it.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Callable, Mapping
from typing import Any, Literal

import attrs
import numpy as np
from numpy.typing import NDArray

from srfm._text import plain
from srfm._validate import physical
from srfm.errors import ParameterError, PlannerError
from srfm.models._robot_kernels import RobotLimits, move_robot

__all__ = [
    "KINEMATICS",
    "Kinematics",
    "RobotConfig",
    "RobotState",
    "apply_command",
    "command_pair",
    "stopped",
]

Kinematics = Literal["unicycle", "holonomic"]
KINEMATICS: tuple[Kinematics, ...] = ("unicycle", "holonomic")


def _bounded(kind: str) -> Any:
    """A validator: a number > 0 within the physical range of ``kind`` (one table of
    bounds for every input: :data:`srfm._validate.BOUNDS`)."""

    def check(inst: Any, attribute: attrs.Attribute[float], value: Any) -> None:
        physical(value, f"robot.{attribute.name}", kind, ParameterError, strict=True)

    return check


def _kinematics(inst: Any, attribute: attrs.Attribute[str], value: Any) -> None:
    if not isinstance(value, str) or value not in KINEMATICS:
        raise ParameterError(f"robot.kinematics must be one of {KINEMATICS}, got {plain(value)}")


@attrs.frozen(kw_only=True)
class RobotConfig:
    """Robot body and limits (docs/model.md, "The robot"; the paper's v ∈ [−0.5, 0.5] m/s,
    ω ∈ [−π, π] rad/s).

    Attributes:
        kinematics: ``"unicycle"`` (v, ω) or ``"holonomic"`` (vx, vy).
        radius_m: body radius (m); collision when the centre distance to a pedestrian
            is below the sum of radii.
        max_speed_mps: v_max (m/s).
        max_angular_speed_radps: ω_max (rad/s), unicycle only.
        max_accel_mps2: largest change of linear velocity per second (m/s²).
        max_angular_accel_radps2: largest change of ω per second (rad/s²).
        goal_radius_m: the goal counts as reached within this distance (m).
    """

    kinematics: Kinematics = attrs.field(default="unicycle", validator=_kinematics)
    radius_m: float = attrs.field(default=0.2, validator=_bounded("radius"))
    max_speed_mps: float = attrs.field(default=0.5, validator=_bounded("speed"))
    max_angular_speed_radps: float = attrs.field(
        default=math.pi, validator=_bounded("angular_speed")
    )
    max_accel_mps2: float = attrs.field(default=1.0, validator=_bounded("acceleration"))
    max_angular_accel_radps2: float = attrs.field(
        default=2.0 * math.pi, validator=_bounded("acceleration")
    )
    goal_radius_m: float = attrs.field(default=0.5, validator=_bounded("radius"))

    def for_kernels(self) -> RobotLimits:
        """The body and limits as the robot kernels take them (a NamedTuple)."""
        return RobotLimits(
            holonomic=self.kinematics == "holonomic",
            radius_m=float(self.radius_m),
            max_speed_mps=float(self.max_speed_mps),
            max_angular_speed_radps=float(self.max_angular_speed_radps),
            max_accel_mps2=float(self.max_accel_mps2),
            max_angular_accel_radps2=float(self.max_angular_accel_radps2),
            goal_radius_m=float(self.goal_radius_m),
        )


@attrs.frozen(kw_only=True)
class RobotState:
    """Robot pose and applied velocity.

    Attributes:
        x, y: position (m).
        theta: heading (rad) in (−π, π].
        vx, vy: world-frame velocity applied during the last step (m/s).
        v, omega: unicycle speed along the heading (m/s) and turn rate (rad/s); for a
            holonomic robot v is the speed and omega the heading change per second.
    """

    x: float
    y: float
    theta: float
    vx: float = 0.0
    vy: float = 0.0
    v: float = 0.0
    omega: float = 0.0

    @property
    def position(self) -> NDArray[np.float64]:
        """(2,) position (m)."""
        return np.array([self.x, self.y])

    @property
    def pose(self) -> NDArray[np.float64]:
        """(3,) = (x, y, theta)."""
        return np.array([self.x, self.y, self.theta])

    def as_array(self) -> NDArray[np.float64]:
        """(7,) = (x, y, theta, vx, vy, v, omega), the robot kernels' layout."""
        return np.array([self.x, self.y, self.theta, self.vx, self.vy, self.v, self.omega])

    @classmethod
    def from_array(cls, robot: NDArray[np.float64]) -> RobotState:
        """The state held in a (7,) array of the robot kernels' layout."""
        x, y, theta, vx, vy, v, omega = robot.tolist()
        return cls(x=x, y=y, theta=theta, vx=vx, vy=vy, v=v, omega=omega)


def command_pair(command: Any, what: str = "a command") -> tuple[float, float]:
    """The two numbers of a planner's command (or an agent's action), checked.

    Args:
        command: (2,) (v, ω) for a unicycle, (vx, vy) world frame for a holonomic robot:
            a sequence or array of exactly two real numbers (not strings, booleans or
            complex numbers).
        what: how the message names the value (``"a command"``, ``"an action"``).

    Returns:
        (c0, c1) as floats.

    Raises:
        PlannerError: the command is not two finite real numbers; the message names it.
    """

    def bad() -> PlannerError:
        # Built only on failure: the repr of an array costs about 0.1 ms, which at one
        # command per step was 12 % of a warm quick benchmark (cProfile, 2026-11-27).
        return PlannerError(f"{what} must be two real numbers, got {plain(command)}")

    if type(command) is np.ndarray and command.shape == (2,) and command.dtype.kind in "fiu":
        # The common case (a planner's or an agent's array), checked without the
        # per-element type tests below (they cost about 1 µs a step): real, not bool.
        c0, c1 = (float(x) for x in command.tolist())
    else:
        c0, c1 = _command_numbers(command, bad)
    if not (math.isfinite(c0) and math.isfinite(c1)):
        raise PlannerError(f"{what} must be finite, got {plain(command)}")
    return c0, c1


def _command_numbers(command: Any, bad: Callable[[], PlannerError]) -> tuple[float, float]:
    """The two numbers of a command that is not a numeric array of shape (2,)."""
    if isinstance(command, str | bytes | Mapping) or not hasattr(command, "__len__"):
        raise bad()
    try:
        if len(command) != 2:
            raise bad()
        first, second = command[0], command[1]
    except (TypeError, KeyError, IndexError, ValueError):
        raise bad() from None
    for value in (first, second):
        if not isinstance(value, numbers.Real) or isinstance(value, bool | np.bool_):
            raise bad()
    return float(first), float(second)


def apply_command(state: RobotState, command: Any, config: RobotConfig, dt: float) -> RobotState:
    """Move the robot one step of ``dt`` seconds under ``command`` within its limits.

    A checked call of the robot kernel :func:`srfm.models._robot_kernels.move_robot`
    (the module docstring describes the two kinematic models).

    Args:
        state: the robot before the step.
        command: (2,) (v m/s, ω rad/s) for a unicycle, (vx, vy) m/s in the world frame
            for a holonomic robot.
        config: body and limits.
        dt: step (s).

    Returns:
        The robot after the step, with the velocity actually applied.

    Raises:
        PlannerError: the command is not two finite numbers.
    """
    c0, c1 = command_pair(command)
    robot = state.as_array()
    move_robot(robot, c0, c1, config.for_kernels(), float(dt))
    return RobotState.from_array(robot)


def stopped(state: RobotState) -> RobotState:
    """The same pose at rest."""
    return RobotState(x=state.x, y=state.y, theta=state.theta)
