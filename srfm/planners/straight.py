"""The ``straight`` baseline: drive to the goal at top speed, ignoring people."""

from __future__ import annotations

import math

import numpy as np

from srfm.models.robot import RobotConfig
from srfm.planners._base import FloatArray, Observation, PlannerContext

__all__ = ["StraightPlanner"]


class StraightPlanner:
    """Head for the goal at full speed; turn toward it first if it lies behind.

    Unicycle: ω = clip(2 · heading error / s, ±ω_max) and v = v_max · max(cos(error), 0).
    Holonomic: v = v_max toward the goal. Observes no pedestrians.
    """

    name = "straight"
    detection_range_m: float | None = 0.0

    def __init__(self) -> None:
        self._robot = RobotConfig()

    def reset(self, context: PlannerContext, rng: np.random.Generator) -> None:
        """Remember the robot's limits; the planner draws no randomness."""
        self._robot = context.robot

    def act(self, observation: Observation) -> FloatArray:
        """The command toward ``observation.robot_goal``."""
        robot = observation.robot
        dx = float(observation.robot_goal[0]) - robot.x
        dy = float(observation.robot_goal[1]) - robot.y
        vmax = self._robot.max_speed_mps
        if self._robot.kinematics == "holonomic":
            dist = math.hypot(dx, dy)
            if dist < 1e-12:
                return np.zeros(2)
            return np.array([vmax * dx / dist, vmax * dy / dist])
        error = math.remainder(math.atan2(dy, dx) - robot.theta, 2.0 * math.pi)
        wmax = self._robot.max_angular_speed_radps
        omega = max(-wmax, min(wmax, 2.0 * error))
        return np.array([vmax * max(math.cos(error), 0.0), omega])
