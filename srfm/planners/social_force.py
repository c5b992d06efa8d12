"""A social-force robot, planner name ``social-force``: the robot is moved toward its
goal by a social force model (Helbing and Molnár 1995), like the pedestrians of the
SRFM, within its own limits.

Each step the robot feels (unit mass, so forces are accelerations)

    F = (v_des − v) / τ
        + Σ_j A exp((r_R + r_j − d_j) / B) ψ(φ_j; λ) n_j      (observed pedestrians)
        + Σ_o A_o exp((r_R − d_o) / B_o) n_o                   (walls, pillars, edges)

with v_des = (g − x) capped at the desired speed (the robot slows down within one
second of its goal, as SRFM pedestrians do), n the unit vector from the pedestrian
(the obstacle's closest point) to the robot, d the centre distance (the distance to
the obstacle's surface) and ψ = λ + (1 − λ)(1 + cos φ)/2 with φ the angle between the
robot's heading and the direction to the pedestrian. The new velocity is
v + F dt capped at v_max (semi-implicit Euler with the simulation step), where v is
the robot's current velocity. A holonomic robot is commanded that velocity; a
unicycle turns toward it with ω = clip(k_θ e, ±ω_max) and drives at
|v| max(cos e, 0), e the heading error.

Defaults: A = 2.0 m/s² and λ = 0.4 as the SRFM pedestrians of the ``agrawal2024``
preset, but a shorter range B = 0.4 m (instead of 0.89 m) and a quicker relaxation
τ = 0.4 s (instead of 0.6 s). With the pedestrian values the robot, which has 0.5 m/s
where people have 1.25 m/s, was held back far more than the other planners (mean
speed 0.34–0.45 m/s against 0.49 m/s); with these it averages 0.47–0.49 m/s on the
evaluation scenarios (docs/planners.md). The obstacle terms are the model's
(A_o = 25 m/s², B_o = 0.08 m). Like two social-force pedestrians walking straight at
each other, the robot cannot avoid a person who walks straight at it and does not
react; SRFM pedestrians do react.
"""

from __future__ import annotations

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
    check_unit_interval,
)
from srfm.planners._social_force_kernels import SocialForceParams, social_force_command

__all__ = ["SocialForceConfig", "SocialForcePlanner"]


@attrs.frozen(kw_only=True)
class SocialForceConfig:
    """Parameters of :class:`SocialForcePlanner`.

    Attributes:
        detection_range_m: pedestrians closer than this to the robot are observed (m);
            None observes everyone. Default 2 m (the paper).
        desired_speed_mps: speed toward the goal (m/s); None for the robot's top speed.
        tau_s: τ, relaxation time of the goal term (s).
        ped_strength_mps2: A, strength of the pedestrian repulsion (m/s²).
        ped_range_m: B, range of the pedestrian repulsion (m).
        anisotropy: λ in [0, 1], the weight of pedestrians behind the robot.
        obstacle_strength_mps2: A_o, strength of the wall and pillar repulsion (m/s²).
        obstacle_range_m: B_o, range of the wall and pillar repulsion (m).
        heading_gain_per_s: k_θ of the unicycle heading control (1/s).
        avoid_world_edges: the edges of the world repel the robot like walls.
    """

    detection_range_m: float | None = attrs.field(default=2.0, validator=check_detection_range)
    desired_speed_mps: float | None = attrs.field(default=None, validator=check_optional_positive)
    tau_s: float = attrs.field(default=0.4, validator=check_positive)
    ped_strength_mps2: float = attrs.field(default=2.0, validator=check_non_negative)
    ped_range_m: float = attrs.field(default=0.4, validator=check_positive)
    anisotropy: float = attrs.field(default=0.4, validator=check_unit_interval)
    obstacle_strength_mps2: float = attrs.field(default=25.0, validator=check_non_negative)
    obstacle_range_m: float = attrs.field(default=0.08, validator=check_positive)
    heading_gain_per_s: float = attrs.field(default=4.0, validator=check_positive)
    avoid_world_edges: bool = attrs.field(default=True, validator=check_bool)


class SocialForcePlanner(KernelPlanner[SocialForceParams]):
    """A robot driven by a social force model toward its goal.

    Args:
        config: parameters; the defaults of :class:`SocialForceConfig` when omitted.
    """

    name = "social-force"

    def __init__(self, config: SocialForceConfig | None = None) -> None:
        self.config = config if config is not None else SocialForceConfig()
        c = self.config
        super().__init__(c.detection_range_m, 0.0, c.heading_gain_per_s, c.avoid_world_edges)

    def _own_params(self, robot: RobotConfig, dt_s: float) -> SocialForceParams:
        c = self.config
        vdes = robot.max_speed_mps if c.desired_speed_mps is None else c.desired_speed_mps
        return SocialForceParams(
            desired_speed_mps=float(vdes),
            tau_s=float(c.tau_s),
            ped_strength_mps2=float(c.ped_strength_mps2),
            ped_range_m=float(c.ped_range_m),
            anisotropy=float(c.anisotropy),
            obstacle_strength_mps2=float(c.obstacle_strength_mps2),
            obstacle_range_m=float(c.obstacle_range_m),
        )

    def act(self, observation: Observation) -> FloatArray:
        """(v, ω) for a unicycle, (vx, vy) for a holonomic robot."""
        r = observation.robot
        command = social_force_command(
            r.x, r.y, r.theta, r.vx, r.vy, observation.robot_goal,
            observation.ped_pos, observation.ped_vel, observation.ped_radius,
            self._segments, self._circles, self._common_fields, self._params_fields,
        )  # fmt: skip
        return np.array(command)
