"""The gymnasium environment ``srfm/SocialNav-v0`` (needs the ``rl`` extra).

Importing this module registers the environment with gymnasium (its only side
effect)::

    import gymnasium as gym
    import srfm.rl

    env = gym.make("srfm/SocialNav-v0", scenario="random")
    # or, without importing srfm.rl first:
    env = gym.make("srfm.rl:srfm/SocialNav-v0")

See ``docs/rl.md`` for the observation, the action and the reward.
"""

from srfm.rl._deps import INSTALL_HINT, MissingDependencyError, require

require("gymnasium")

from srfm.rl._config import DEFAULT_K_DIV, EnvConfig  # noqa: E402
from srfm.rl._core import ObservationBuilder  # noqa: E402
from srfm.rl._env import SocialNavEnv  # noqa: E402

__all__ = [
    "DEFAULT_K_DIV",
    "ENV_ID",
    "INSTALL_HINT",
    "EnvConfig",
    "MissingDependencyError",
    "ObservationBuilder",
    "SocialNavEnv",
]

ENV_ID = "srfm/SocialNav-v0"


def _register() -> None:
    import gymnasium

    if ENV_ID not in gymnasium.registry:
        gymnasium.register(id=ENV_ID, entry_point="srfm.rl:SocialNavEnv")


_register()
