"""The ``stay`` reference: a robot that never moves (a standing obstacle)."""

from __future__ import annotations

import numpy as np

from srfm.planners._base import FloatArray, Observation, PlannerContext

__all__ = ["StayPlanner"]


class StayPlanner:
    """Command zero at every step: the robot stands at its start for the whole episode.

    A reference point of the benchmark, not a navigation policy: it never reaches its
    goal (its episodes end in a timeout), and the deviation it causes is what a robot
    standing in the scene does to the crowd. Zero is (v, ω) = (0, 0) for a unicycle and
    (vx, vy) = (0, 0) for a holonomic robot. Observes no pedestrians, draws nothing.
    """

    name = "stay"
    detection_range_m: float | None = 0.0

    def reset(self, context: PlannerContext, rng: np.random.Generator) -> None:
        """Nothing to remember."""

    def act(self, observation: Observation) -> FloatArray:
        """(0, 0)."""
        return np.zeros(2)
