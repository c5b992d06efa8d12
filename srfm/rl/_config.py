"""Configuration of the gymnasium environment (reward weights, social zone, observation)."""

from __future__ import annotations

import operator
from typing import Any, Final

import attrs

from srfm._validate import non_negative, positive
from srfm.errors import ParameterError
from srfm.models.robot import KINEMATICS, Kinematics

__all__ = ["DEFAULT_K_DIV", "EnvConfig"]

# Default weight of the one-step deviation penalty (per metre of summed deviation).
DEFAULT_K_DIV: Final = 2.0


def _non_negative(inst: Any, attribute: attrs.Attribute[float], value: Any) -> None:
    non_negative(value, f"env.{attribute.name}", ParameterError)


def _positive(inst: Any, attribute: attrs.Attribute[float], value: Any) -> None:
    positive(value, f"env.{attribute.name}", ParameterError)


def _max_peds(inst: Any, attribute: attrs.Attribute[int], value: Any) -> None:
    try:
        count = operator.index(value)
    except TypeError:
        count = -1
    if isinstance(value, bool) or not 0 <= count <= 1000:
        raise ParameterError(f"env.max_pedestrians must be an integer in [0, 1000], got {value!r}")


def _kinematics(inst: Any, attribute: attrs.Attribute[str | None], value: Any) -> None:
    if value is not None and value not in KINEMATICS:
        raise ParameterError(f"env.kinematics must be None or one of {KINEMATICS}, got {value!r}")


def _flag(inst: Any, attribute: attrs.Attribute[bool], value: Any) -> None:
    if not isinstance(value, bool):
        raise ParameterError(f"env.{attribute.name} must be True or False, got {value!r}")


@attrs.frozen(kw_only=True)
class EnvConfig:
    """Reward, observation and simulation options of ``srfm/SocialNav-v0``.

    Reward per step (paper Eq. 7): r = r_term − k1 · r_dist − k2 · r_div.

    Attributes:
        k1: weight of r_dist, the goal distance divided by the goal distance at reset,
            capped at 1 (dimensionless, 1 at the start, 0 at the goal).
        k2: weight of r_div (1/m), the summed one-step counterfactual deviation (m) of
            the pedestrians inside the social zone. 0 gives the paper's RL_base
            reward, > 0 the SRFM-aware one.
        social_zone_m: social zone radius (m): the pedestrians observed and the
            pedestrians whose deviation counts in r_div are those whose centre is
            closer than this to the robot centre (paper: 3 m).
        max_pedestrians: K, the number of observed pedestrian slots (paper: 10).
        success_reward: r_term when the robot reaches its goal.
        timeout_penalty: −r_term when the horizon is reached (a truncation). The
            defaults (25, and 50 for a collision) exceed the largest discounted sum of
            per-step penalties over TD3's horizon (about (k1 + k2 · 0.05 m) / (1 − γ)
            ≈ 35), so that ending an episode by a collision or by leaving the world
            never pays.
        velocity_scale_mps: relative pedestrian velocities in the observation are
            divided by this (m/s) and clipped to [−1, 1].
        kinematics: ``"unicycle"`` (v, ω), ``"holonomic"`` (robot-frame vx, vy), or
            None for the scenario's robot.
        counterfactual_twin: step the full counterfactual crowd as well (so an
            episode can be scored for deviation). The reward does not need it (it
            uses the one-step counterfactual); False skips it for faster training.
    """

    k1: float = attrs.field(default=0.1, validator=_non_negative)
    k2: float = attrs.field(default=DEFAULT_K_DIV, validator=_non_negative)
    social_zone_m: float = attrs.field(default=3.0, validator=_positive)
    max_pedestrians: int = attrs.field(default=10, validator=_max_peds)
    success_reward: float = attrs.field(default=25.0, validator=_non_negative)
    timeout_penalty: float = attrs.field(default=25.0, validator=_non_negative)
    velocity_scale_mps: float = attrs.field(default=2.0, validator=_positive)
    kinematics: Kinematics | None = attrs.field(default=None, validator=_kinematics)
    counterfactual_twin: bool = attrs.field(default=True, validator=_flag)

    @property
    def collision_penalty(self) -> float:
        """−r_term on a collision (pedestrian, wall or pillar) or on leaving the world:
        twice the timeout penalty (paper §IV-B)."""
        return 2.0 * self.timeout_penalty

    def replace(self, **changes: Any) -> EnvConfig:
        """A copy with some fields changed (validated)."""
        return attrs.evolve(self, **changes)
