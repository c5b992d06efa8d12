"""The planner protocol: what a planner is told at reset and what it sees each step."""

from __future__ import annotations

from typing import Final, Protocol, runtime_checkable

import attrs
import numpy as np
from numpy.typing import NDArray

from srfm._text import plain
from srfm.errors import PlannerError
from srfm.models.robot import RobotConfig, RobotState
from srfm.models.state import Obstacles
from srfm.scenarios import RobotRecording
from srfm.world import WorldBounds

__all__ = ["PRIVILEGED_HOOK", "Observation", "Planner", "PlannerContext", "check_planner"]

FloatArray = NDArray[np.float64]

PRIVILEGED_HOOK: Final = "attach_episode"
"""A planner with a method of this name is a *privileged reference*, not a navigation
policy: :func:`srfm.run_episode` calls it after ``reset`` with the running episode's
engine (:class:`srfm.sim.engine.EpisodeEngine`), which it may read and copy but must not
change. The ``oracle`` reference planner is one (:mod:`srfm.planners.oracle`)."""


@attrs.frozen(kw_only=True, eq=False)
class PlannerContext:
    """Episode information given to :meth:`Planner.reset`.

    Attributes:
        scenario: scenario name.
        seed: episode seed.
        dt_s: simulation step (s).
        horizon_steps: number of steps in the episode.
        robot: body and kinematic limits; commands must be in ``robot.kinematics``.
        robot_goal: (2,) goal (m).
        world: world bounds (m).
        obstacles: static walls and pillars.
        robot_recording: the scenario's recorded robot trajectory (``[robot.recording]``,
            replayed by the ``recorded`` planner), or None.
    """

    scenario: str
    seed: int
    dt_s: float
    horizon_steps: int
    robot: RobotConfig
    robot_goal: FloatArray
    world: WorldBounds
    obstacles: Obstacles
    robot_recording: RobotRecording | None = None


@attrs.frozen(kw_only=True, eq=False)
class Observation:
    """What a planner sees at one step (factual crowd only).

    Pedestrian arrays hold the pedestrians whose centre is closer than the planner's
    ``detection_range_m`` to the robot centre (all of them when it is None), in index
    order; ``ped_ids`` are their indices in the crowd.

    Attributes:
        step: step index (0 at the start).
        time_s: simulated time (s).
        robot: the robot's pose and current velocity.
        robot_goal: (2,) goal (m).
        ped_ids: (k,) int indices.
        ped_pos: (k, 2) positions (m).
        ped_vel: (k, 2) velocities (m/s).
        ped_radius: (k,) radii (m).
        obstacles: static walls and pillars.
    """

    step: int
    time_s: float
    robot: RobotState
    robot_goal: FloatArray
    ped_ids: NDArray[np.intp]
    ped_pos: FloatArray
    ped_vel: FloatArray
    ped_radius: FloatArray
    obstacles: Obstacles


@runtime_checkable
class Planner(Protocol):
    """A robot navigation policy.

    A planner is reset once per episode with the episode's context and its own
    ``numpy.random.Generator`` (derived from the episode seed; a planner must draw no
    other randomness), then asked for a command at every step while the robot is
    active. The command is a length-2 array in the robot's kinematics: (v, ω) for a
    unicycle, world-frame (vx, vy) for a holonomic robot; the simulator clips it to
    the robot's limits.

    Attributes:
        name: the registry name.
        detection_range_m: only pedestrians closer than this (m, finite, >= 0) to
            the robot are observed; 0 observes none, None every pedestrian.
    """

    name: str
    detection_range_m: float | None

    def reset(self, context: PlannerContext, rng: np.random.Generator) -> None:
        """Prepare for a new episode; forget everything about earlier ones."""
        ...

    def act(self, observation: Observation) -> FloatArray:
        """The command for this step."""
        ...


def check_planner(planner: object) -> None:
    """Check that ``planner`` follows the :class:`Planner` protocol before it is used.

    A planner needs a ``name`` (a non-empty string) and callable ``reset`` and ``act``;
    ``detection_range_m`` may be left out, which observes every pedestrian (its value is
    checked by :func:`srfm.run_episode`).

    Raises:
        PlannerError: naming every member that is missing or unusable.
    """
    problems = protocol_problems(planner)
    if problems:
        name = getattr(planner, "name", None)
        label = repr(name) if isinstance(name, str) and name else type(planner).__qualname__
        raise protocol_error(label, problems)


def protocol_problems(planner: object, *, check_name: bool = True) -> list[str]:
    """What ``planner`` lacks of the protocol, one phrase each (empty when nothing)."""
    problems = []
    if check_name:
        if not hasattr(planner, "name"):
            problems.append("no 'name' attribute")
        elif not isinstance(planner.name, str) or not planner.name:
            problems.append(f"'name' must be a non-empty string, got {plain(planner.name)}")
    for method in ("reset", "act"):
        if not hasattr(planner, method):
            problems.append(f"no {method}() method")
        elif not callable(getattr(planner, method)):
            problems.append(f"{method!r} is not callable")
    return problems


def protocol_error(label: str, problems: list[str]) -> PlannerError:
    """The error for a planner (``label``: its name or type) lacking ``problems``."""
    return PlannerError(
        f"planner {label} lacks the Planner protocol (name, detection_range_m, reset, act): "
        + "; ".join(problems)
    )
