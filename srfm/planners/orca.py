"""Optimal Reciprocal Collision Avoidance (van den Berg, Guy, Lin, Manocha 2011),
planner name ``orca``; written for srfm in numba (no bindings to RVO2).

Each step, every observed pedestrian B contributes one half-plane of robot velocities.
With p = x_B − x_R, v_rel = v_R − v_B and the truncated velocity obstacle
VO^τ = {v | ∃ t ∈ [0, τ]: |v t − p| < r_R + r_B + margin}, let u be the vector from
v_rel to the closest point of the boundary of VO^τ and n the outward normal there.
The robot takes its share ``responsibility`` of the avoidance:

    ORCA_B = { v | (v − (v_R + responsibility · u)) · n >= 0 }

(``responsibility`` 0.5 is the reciprocal ORCA of the paper, for agents that avoid
the robot as it avoids them, as SRFM pedestrians do; 1 assumes they do not react).
When the discs already overlap, the cut-off disc of one simulation step replaces the
τ one. Each wall, pillar and world edge closer than v_max τ_obs adds a hard
half-plane n · v >= −(d − r_R − margin) / τ_obs (d the distance to its closest point,
n the unit vector from there to the robot): the robot cannot reach it within τ_obs.

The new velocity is the one closest to the preferred velocity (top speed toward the
goal) inside |v| <= v_max and every half-plane, found by an incremental 2-D linear
program (the paper's §5.2). When the half-planes have no common point, the velocity
that minimises the largest violation of the pedestrian half-planes while meeting the
hard ones is taken (a 3-D linear program solved as a series of 2-D ones). A
holonomic robot is commanded that velocity; a unicycle turns toward it with
ω = clip(k_θ e, ±ω_max) and drives at |v| max(cos e, 0), e the heading error.
"""

from __future__ import annotations

import attrs
import numpy as np

from srfm.models.robot import RobotConfig
from srfm.planners import _orca_kernels
from srfm.planners._base import FloatArray, Observation
from srfm.planners._common import (
    KernelPlanner,
    check_bool,
    check_detection_range,
    check_non_negative,
    check_positive,
    check_unit_open,
)
from srfm.planners._orca_kernels import ORCAParams, orca_command

__all__ = ["ORCAConfig", "ORCAPlanner", "orca_halfplane"]


@attrs.frozen(kw_only=True)
class ORCAConfig:
    """Parameters of :class:`ORCAPlanner`.

    Attributes:
        detection_range_m: pedestrians closer than this to the robot are observed (m);
            None observes everyone. Default 2 m (the paper).
        time_horizon_s: τ, the time horizon of the pedestrian velocity obstacles (s).
        obstacle_time_horizon_s: τ_obs, the same for walls, pillars and edges (s).
        responsibility: the robot's share of each avoidance, in (0, 1].
        safety_margin_m: added to the sum of radii (m).
        heading_gain_per_s: k_θ of the unicycle heading control (1/s).
        avoid_world_edges: treat the edges of the world as walls.
    """

    detection_range_m: float | None = attrs.field(default=2.0, validator=check_detection_range)
    time_horizon_s: float = attrs.field(default=2.0, validator=check_positive)
    obstacle_time_horizon_s: float = attrs.field(default=1.0, validator=check_positive)
    responsibility: float = attrs.field(default=0.5, validator=check_unit_open)
    safety_margin_m: float = attrs.field(default=0.1, validator=check_non_negative)
    heading_gain_per_s: float = attrs.field(default=4.0, validator=check_positive)
    avoid_world_edges: bool = attrs.field(default=True, validator=check_bool)


def orca_halfplane(
    rel_pos: tuple[float, float],
    velocity: tuple[float, float],
    other_vel: tuple[float, float],
    radius: float,
    time_horizon_s: float,
    dt_s: float,
    responsibility: float = 0.5,
) -> tuple[tuple[float, float], tuple[float, float]]:
    """The ORCA half-plane of an agent from another one.

    Args:
        rel_pos: the other agent's centre relative to this one (m).
        velocity: this agent's current velocity (m/s).
        other_vel: the other agent's velocity (m/s).
        radius: combined radius (m).
        time_horizon_s: τ (s).
        dt_s: simulation step (s), used when the agents overlap.
        responsibility: this agent's share of the avoidance.

    Returns:
        (point, normal): the allowed velocities v satisfy (v − point) · normal >= 0;
        normal is a unit vector.
    """
    px, py, nx, ny = _orca_kernels.orca_halfplane(
        float(rel_pos[0]),
        float(rel_pos[1]),
        float(velocity[0]),
        float(velocity[1]),
        float(other_vel[0]),
        float(other_vel[1]),
        float(radius),
        float(time_horizon_s),
        float(dt_s),
        float(responsibility),
    )
    return (px, py), (nx, ny)


class ORCAPlanner(KernelPlanner[ORCAParams]):
    """ORCA: the velocity closest to the preferred one in every ORCA half-plane.

    Args:
        config: parameters; the defaults of :class:`ORCAConfig` when omitted.
    """

    name = "orca"

    def __init__(self, config: ORCAConfig | None = None) -> None:
        self.config = config if config is not None else ORCAConfig()
        c = self.config
        super().__init__(
            c.detection_range_m, c.safety_margin_m, c.heading_gain_per_s, c.avoid_world_edges
        )
        self._lines = np.zeros((16, 4))
        self._proj = np.zeros((16, 4))

    def _own_params(self, robot: RobotConfig, dt_s: float) -> ORCAParams:
        c = self.config
        return ORCAParams(
            tau_s=float(c.time_horizon_s),
            tau_obstacle_s=float(c.obstacle_time_horizon_s),
            responsibility=float(c.responsibility),
        )

    def act(self, observation: Observation) -> FloatArray:
        """(v, ω) for a unicycle, (vx, vy) for a holonomic robot."""
        r = observation.robot
        rows = observation.ped_pos.shape[0] + self._segments.shape[0] + self._circles.shape[0] + 4
        if rows > self._lines.shape[0]:
            self._lines = np.zeros((2 * rows, 4))
            self._proj = np.zeros((2 * rows, 4))
        command = orca_command(
            r.x, r.y, r.theta, r.vx, r.vy, observation.robot_goal,
            observation.ped_pos, observation.ped_vel, observation.ped_radius,
            self._segments, self._circles, self._common_fields, self._params_fields,
            self._lines, self._proj,
        )  # fmt: skip
        return np.array(command)
