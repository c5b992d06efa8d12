"""The Dynamic Window Approach (Fox, Burgard, Thrun 1997), planner name ``dwa``.

At every step the planner searches the *dynamic window*: the velocities the robot can
reach within the window time t_w at its acceleration limits, intersected with its
speed limits,

    V_r = [v − a t_w, v + a t_w] ∩ [v_min, v_max]  ×  [ω − α t_w, ω + α t_w] ∩ [−ω_max, ω_max],

with a and α the robot's ``max_accel_mps2`` and ``max_angular_accel_radps2``. Fox et
al. take t_w = one control step (``window_time_s = None``); the default is 0.25 s, so
that the planner also considers turns it cannot start within one 1/15 s step (with
one step, the robot kept circling around goals it passed at 0.5–1 m in the ``circle``
scenario, see docs/planners.md).

A grid of ``v_samples`` × ``omega_samples`` (v, ω) pairs spanning the window is
forward-simulated for ``horizon_s`` seconds in steps of ``rollout_step_s``: the
robot's velocity approaches the sample at the acceleration limits (at once when the
sample lies within one step) and then holds it, so each rollout is an arc after a
short ramp. Rollouts are checked against the observed pedestrians (moved at constant
velocity when ``predict_pedestrians``), the walls, the pillars and the world's edges,
all inflated by ``safety_margin_m``. A rollout that touches anything within the
horizon is inadmissible (Fox et al. only demand that the robot can brake before the
contact; with people walking into the robot's path, a colliding arc is never safe).
Among the admissible ones the planner maximises

    G(v, ω) = α · heading + β · clearance + γ · velocity,

    heading   = 1 − |θ_goal| / π, θ_goal the angle of the goal seen from the robot's
                predicted pose: as in Fox et al., moving toward the sample for the
                window time, then braking to rest at the acceleration limits
                (1 when the rollout reaches the goal radius)
    clearance = min(smallest gap along the rollout, clearance_cap_m) / clearance_cap_m
    velocity  = v / v_max

with α, β, γ the ``heading_weight``, ``clearance_weight`` and ``velocity_weight``.
Each term lies in [0, 1]; Fox et al. also smooth the terms over the window, which is
left out here. When no rollout is admissible, the one whose first contact comes latest
(then: the one with the larger clearance) is taken.

A holonomic robot searches the disc of (vx, vy) within a t_w of acceleration of its
velocity (the points of a ``holonomic_samples`` × ``holonomic_samples`` grid inside
it), rolls out straight lines after the same ramp, and takes the direction of the
sample velocity as its heading (heading term 0.5 for the zero velocity).

Each step is one numba kernel call (:func:`srfm.planners._dwa_kernels.dwa_unicycle`,
:func:`srfm.planners._dwa_kernels.dwa_holonomic`); with no pedestrian, obstacle or edge
within reach of the rollouts, they are skipped and only the heading and velocity
terms are computed.
"""

from __future__ import annotations

import attrs
import numpy as np

from srfm._text import plain
from srfm.errors import PlannerError
from srfm.models.robot import RobotConfig
from srfm.planners._base import FloatArray, Observation
from srfm.planners._common import (
    KernelPlanner,
    check_bool,
    check_detection_range,
    check_finite,
    check_non_negative,
    check_optional_positive,
    check_positive,
    check_positive_int,
)
from srfm.planners._dwa_kernels import DWAParams, dwa_holonomic, dwa_unicycle, dynamic_window

__all__ = ["DWAConfig", "DWAPlanner"]


@attrs.frozen(kw_only=True)
class DWAConfig:
    """Parameters of :class:`DWAPlanner`.

    Attributes:
        detection_range_m: pedestrians closer than this to the robot are observed (m);
            None observes everyone. Default 2 m (the paper).
        window_time_s: the window holds the velocities reachable within this time at
            the acceleration limits (s); None for one simulation step (Fox et al.).
        horizon_s: how far ahead each (v, ω) is simulated (s).
        rollout_step_s: integration step of the rollouts (s).
        v_samples: samples of v across the window (unicycle).
        omega_samples: samples of ω across the window (unicycle).
        holonomic_samples: samples per axis of (vx, vy) (holonomic robot).
        min_speed_mps: v_min, the lowest linear speed searched (m/s); 0 drives forward
            only. Must lie in [−v_max, v_max] of the robot.
        heading_weight: α, weight of the heading term.
        clearance_weight: β, weight of the clearance term.
        velocity_weight: γ, weight of the velocity term.
        clearance_cap_m: gaps beyond this count as free space (m).
        safety_margin_m: added to every radius in the rollouts (m).
        predict_pedestrians: move pedestrians at their observed velocity in the
            rollouts; False treats them as standing still (the original DWA).
        avoid_world_edges: treat the edges of the world as walls.
    """

    detection_range_m: float | None = attrs.field(default=2.0, validator=check_detection_range)
    window_time_s: float | None = attrs.field(default=0.25, validator=check_optional_positive)
    horizon_s: float = attrs.field(default=2.0, validator=check_positive)
    rollout_step_s: float = attrs.field(default=0.2, validator=check_positive)
    v_samples: int = attrs.field(default=5, validator=check_positive_int)
    omega_samples: int = attrs.field(default=11, validator=check_positive_int)
    holonomic_samples: int = attrs.field(default=9, validator=check_positive_int)
    min_speed_mps: float = attrs.field(default=0.0, validator=check_finite)
    heading_weight: float = attrs.field(default=1.0, validator=check_non_negative)
    clearance_weight: float = attrs.field(default=0.3, validator=check_non_negative)
    velocity_weight: float = attrs.field(default=0.3, validator=check_non_negative)
    clearance_cap_m: float = attrs.field(default=1.0, validator=check_positive)
    safety_margin_m: float = attrs.field(default=0.1, validator=check_non_negative)
    predict_pedestrians: bool = attrs.field(default=True, validator=check_bool)
    avoid_world_edges: bool = attrs.field(default=True, validator=check_bool)

    def __attrs_post_init__(self) -> None:
        if self.rollout_step_s > self.horizon_s:
            raise PlannerError(
                f"DWAConfig.rollout_step_s must be <= horizon_s ({self.horizon_s!r}), "
                f"got {plain(self.rollout_step_s)}"
            )
        if round(self.horizon_s / self.rollout_step_s) > 10_000:
            raise PlannerError(
                f"DWAConfig: horizon_s / rollout_step_s must be <= 10000 rollout steps, got "
                f"{plain(self.horizon_s)} / {plain(self.rollout_step_s)}"
            )


class DWAPlanner(KernelPlanner[DWAParams]):
    """The Dynamic Window Approach for a unicycle (and a holonomic) robot.

    Args:
        config: parameters; the defaults of :class:`DWAConfig` when omitted.

    Attributes:
        table: (samples, 5) what the last :meth:`act` computed, one row per sample of
            the window: the sample (v, ω) or (vx, vy), the smallest gap along its
            rollout (m), the time of its first contact (s, inf for none) and G (−inf
            when inadmissible). A holonomic window uses the first rows only (the
            grid points inside its disc). For inspection; the planner never reads it.
    """

    name = "dwa"

    def __init__(self, config: DWAConfig | None = None) -> None:
        self.config = config if config is not None else DWAConfig()
        c = self.config
        super().__init__(c.detection_range_m, c.safety_margin_m, 0.0, c.avoid_world_edges)

    def _own_params(self, robot: RobotConfig, dt_s: float) -> DWAParams:
        c = self.config
        if not -robot.max_speed_mps <= c.min_speed_mps <= robot.max_speed_mps:
            raise PlannerError(
                f"DWAConfig.min_speed_mps must lie in [-v_max, v_max] = "
                f"[{-robot.max_speed_mps!r}, {robot.max_speed_mps!r}], got {plain(c.min_speed_mps)}"
            )
        # A holonomic robot searches an n × n grid of (vx, vy).
        unicycle = robot.kinematics == "unicycle"
        params = DWAParams(
            min_speed_mps=float(c.min_speed_mps),
            accel_mps2=float(robot.max_accel_mps2),
            angular_accel_radps2=float(robot.max_angular_accel_radps2),
            steps=max(1, round(c.horizon_s / c.rollout_step_s)),
            rollout_step_s=float(c.rollout_step_s),
            v_samples=int(c.v_samples if unicycle else c.holonomic_samples),
            omega_samples=int(c.omega_samples if unicycle else c.holonomic_samples),
            heading_weight=float(c.heading_weight),
            clearance_weight=float(c.clearance_weight),
            velocity_weight=float(c.velocity_weight),
            clearance_cap_m=float(c.clearance_cap_m),
            predict_pedestrians=c.predict_pedestrians,
            window_time_s=float(dt_s if c.window_time_s is None else c.window_time_s),
        )
        self.table = np.full((params.v_samples * params.omega_samples, 5), np.nan)
        return params

    def window(self, v: float, omega: float) -> tuple[float, float, float, float]:
        """The dynamic window (v_lo, v_hi, ω_lo, ω_hi) at (v, ω) for the current robot."""
        return dynamic_window(float(v), float(omega), self._common_fields, self._params_fields)

    def act(self, observation: Observation) -> FloatArray:
        """(v, ω) for a unicycle, (vx, vy) for a holonomic robot."""
        r = observation.robot
        if self._unicycle:
            command = dwa_unicycle(
                r.x, r.y, r.theta, r.v, r.omega, observation.robot_goal,
                observation.ped_pos, observation.ped_vel, observation.ped_radius,
                self._segments, self._circles, self._common_fields, self._params_fields,
                self._near, self.table,
            )  # fmt: skip
        else:
            command = dwa_holonomic(
                r.x, r.y, r.vx, r.vy, observation.robot_goal,
                observation.ped_pos, observation.ped_vel, observation.ped_radius,
                self._segments, self._circles, self._common_fields, self._params_fields,
                self._near, self.table,
            )  # fmt: skip
        return np.array(command)
