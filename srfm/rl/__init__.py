"""Reinforcement learning: the gymnasium environment ``srfm/SocialNav-v0`` and TD3
training (both need the ``rl`` extra).

``import srfm.rl`` itself is light: it loads no gymnasium, torch or stable-baselines3,
so the command line and the training configuration work without them. The environment
lives in :mod:`srfm.rl.env`; importing that module (or using :class:`SocialNavEnv` or
:data:`MAX_EPISODE_STEPS` from here) registers ``srfm/SocialNav-v0`` with gymnasium and
raises :class:`srfm.MissingDependencyError` without the extra::

    import gymnasium as gym
    import srfm.rl.env

    env = gym.make("srfm/SocialNav-v0", scenario="random")
    # or, without importing srfm first:
    env = gym.make("srfm.rl.env:srfm/SocialNav-v0")

When gymnasium is already imported, ``import srfm.rl`` registers the environment too,
so that ``gym.make("srfm.rl:srfm/SocialNav-v0")`` keeps working.

:class:`EnvConfig` and :class:`ObservationBuilder` are defined in
:mod:`srfm.planners._observation` (the policy planners read them without gymnasium).
"""

from __future__ import annotations

import sys
from typing import TYPE_CHECKING, Any

from srfm._deps import INSTALL_HINT
from srfm.errors import MissingDependencyError
from srfm.planners._observation import DEFAULT_K_DIV, EnvConfig, ObservationBuilder
from srfm.rl._ids import ENV_ID

if TYPE_CHECKING:
    from srfm.rl.env import MAX_EPISODE_STEPS, SocialNavEnv

__all__ = [
    "DEFAULT_K_DIV",
    "ENV_ID",
    "INSTALL_HINT",
    "MAX_EPISODE_STEPS",
    "EnvConfig",
    "MissingDependencyError",
    "ObservationBuilder",
    "SocialNavEnv",
]

_FROM_ENV = frozenset({"MAX_EPISODE_STEPS", "SocialNavEnv"})


def __getattr__(name: str) -> Any:
    # PEP 562: the environment (and gymnasium) load on first use.
    if name in _FROM_ENV:
        from srfm.rl import env

        return getattr(env, name)
    raise AttributeError(f"module 'srfm.rl' has no attribute {name!r}")


if "gymnasium" in sys.modules:
    import srfm.rl.env  # noqa: F401  (registers srfm/SocialNav-v0)
