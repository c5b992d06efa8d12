"""Velocity Obstacles, planner name ``vo``.

The velocity obstacle of a pedestrian B (Fiorini and Shiller 1998; the paper cites
the non-linear generalisation of Large, Sekhavat, Shiller and Laugier 2002, which
reduces to it for obstacles moving at constant velocity) is the set of robot
velocities u that bring the two discs into contact within the time horizon T:

    VO_B^T = { u | ∃ t ∈ [0, T]: |(x_B + v_B t) − (x_R + u t)| < r_R + r_B + margin }.

Membership is tested exactly through the time to collision of the relative motion
(:func:`srfm.planners._geometry.time_to_collision`): u ∈ VO_B^T iff that time is <= T.
With ``time_horizon_s = None`` the cones are untruncated. Pillars are obstacles with
zero velocity, walls are capsules around their segments, and the world's edges are
walls too (unless ``avoid_world_edges`` is off).

Each step the planner considers a fixed candidate set: the preferred velocity (top
speed toward the goal), ``speed_samples`` rings of speeds v_max i / speed_samples with
``heading_samples`` directions each (starting at the goal direction), and zero. It
takes the candidate outside every velocity obstacle that is closest to the preferred
velocity; when every candidate is inside some obstacle, the one whose collision comes
latest (then: the closest to the preferred velocity). The candidates are expressed in
the goal's frame, so their order by distance to the preferred velocity is computed
once per episode (:func:`candidate_velocities`) and the kernel stops at the first
admissible one. A holonomic robot is commanded
that velocity; a unicycle turns toward it with ω = clip(k_θ e, ±ω_max) and drives at
|u| max(cos e, 0), e the heading error.
"""

from __future__ import annotations

import math

import attrs
import numpy as np

from srfm.models.robot import RobotConfig
from srfm.planners._base import FloatArray, Observation
from srfm.planners._common import (
    KernelPlanner,
    check_bool,
    check_detection_range,
    check_non_negative,
    check_optional_positive,
    check_positive,
    check_positive_int,
)
from srfm.planners._geometry import time_to_collision
from srfm.planners._vo_kernels import VOParams, vo_command

__all__ = [
    "VOConfig",
    "VelocityObstaclePlanner",
    "candidate_velocities",
    "in_velocity_obstacle",
]


@attrs.frozen(kw_only=True)
class VOConfig:
    """Parameters of :class:`VelocityObstaclePlanner`.

    Attributes:
        detection_range_m: pedestrians closer than this to the robot are observed (m);
            None observes everyone. The paper's VO needed 1.4 m to finish every
            scenario; see docs/planners.md for this implementation.
        time_horizon_s: T, only collisions within T seconds count (s); None for
            untruncated cones.
        speed_samples: rings of candidate speeds in (0, v_max].
        heading_samples: candidate directions per ring.
        safety_margin_m: added to the sum of radii (m).
        heading_gain_per_s: k_θ of the unicycle heading control (1/s).
        avoid_world_edges: treat the edges of the world as walls.
    """

    detection_range_m: float | None = attrs.field(default=2.0, validator=check_detection_range)
    time_horizon_s: float | None = attrs.field(default=3.0, validator=check_optional_positive)
    speed_samples: int = attrs.field(default=5, validator=check_positive_int)
    heading_samples: int = attrs.field(default=32, validator=check_positive_int)
    safety_margin_m: float = attrs.field(default=0.1, validator=check_non_negative)
    heading_gain_per_s: float = attrs.field(default=4.0, validator=check_positive)
    avoid_world_edges: bool = attrs.field(default=True, validator=check_bool)


def in_velocity_obstacle(
    rel_pos: tuple[float, float],
    obstacle_vel: tuple[float, float],
    velocity: tuple[float, float],
    radius: float,
    time_horizon_s: float | None = None,
) -> bool:
    """Whether ``velocity`` lies in the velocity obstacle of a moving disc.

    Args:
        rel_pos: the obstacle's centre relative to the robot (m).
        obstacle_vel: the obstacle's velocity (m/s).
        velocity: the robot velocity tested (m/s).
        radius: combined radius (m).
        time_horizon_s: T (s); None for the untruncated cone.

    Returns:
        True when moving at ``velocity`` brings the centres closer than ``radius``
        within T (touching exactly at the boundary counts as inside).
    """
    t = time_to_collision(
        float(rel_pos[0]),
        float(rel_pos[1]),
        float(velocity[0]) - float(obstacle_vel[0]),
        float(velocity[1]) - float(obstacle_vel[1]),
        float(radius),
    )
    horizon = math.inf if time_horizon_s is None else float(time_horizon_s)
    return t < math.inf and t <= horizon


def candidate_velocities(max_speed_mps: float, speeds: int, headings: int) -> FloatArray:
    """(n, 2) candidate velocities in the goal frame (x toward the goal), nearest to the
    preferred velocity (max_speed_mps, 0) first (ties in generation order).

    The preferred velocity itself, ``speeds`` rings of speeds v_max i / speeds with
    ``headings`` directions each, starting at the goal direction, and zero. Their
    distance to the preferred velocity does not depend on where the goal lies, so the
    order is fixed once per episode.
    """
    ring = np.arange(1, speeds + 1) * max_speed_mps / speeds
    angle = 2.0 * math.pi * np.arange(headings) / headings
    grid = np.stack(
        [np.outer(ring, np.cos(angle)).ravel(), np.outer(ring, np.sin(angle)).ravel()], axis=1
    )
    cands = np.concatenate([[[max_speed_mps, 0.0]], grid, [[0.0, 0.0]]])
    cost = np.hypot(cands[:, 0] - max_speed_mps, cands[:, 1])
    return np.ascontiguousarray(cands[np.argsort(cost, kind="stable")])


class VelocityObstaclePlanner(KernelPlanner[VOParams]):
    """Velocity Obstacles: the admissible velocity closest to the preferred one.

    Args:
        config: parameters; the defaults of :class:`VOConfig` when omitted.
    """

    name = "vo"

    def __init__(self, config: VOConfig | None = None) -> None:
        self.config = config if config is not None else VOConfig()
        c = self.config
        super().__init__(
            c.detection_range_m, c.safety_margin_m, c.heading_gain_per_s, c.avoid_world_edges
        )

    def _own_params(self, robot: RobotConfig, dt_s: float) -> VOParams:
        c = self.config
        self._candidates = candidate_velocities(
            robot.max_speed_mps, c.speed_samples, c.heading_samples
        )
        return VOParams(horizon_s=math.inf if c.time_horizon_s is None else float(c.time_horizon_s))

    def act(self, observation: Observation) -> FloatArray:
        """(v, ω) for a unicycle, (vx, vy) for a holonomic robot."""
        r = observation.robot
        command = vo_command(
            r.x, r.y, r.theta, observation.robot_goal,
            observation.ped_pos, observation.ped_vel, observation.ped_radius,
            self._segments, self._circles, self._common_fields, self._params_fields,
            self._candidates, self._near,
        )  # fmt: skip
        return np.array(command)
