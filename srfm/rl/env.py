"""The gymnasium environment ``srfm/SocialNav-v0`` (needs the ``rl`` extra).

Importing this module registers the environment with gymnasium (its only side
effect), with ``max_episode_steps`` = :data:`MAX_EPISODE_STEPS` (750, the horizon of
every built-in scenario)::

    import gymnasium as gym
    import srfm.rl.env

    env = gym.make("srfm/SocialNav-v0", scenario="random")
    # or, without importing srfm first:
    env = gym.make("srfm.rl.env:srfm/SocialNav-v0")

:class:`SocialNavEnv`'s docstring describes the action, the observation, the reward
and the episode end; ``docs/rl.md`` more.
"""

from srfm._deps import require

require("gymnasium")

import gymnasium  # noqa: E402

from srfm.rl._env import MAX_EPISODE_STEPS, SocialNavEnv  # noqa: E402
from srfm.rl._ids import ENV_ID  # noqa: E402

__all__ = ["ENV_ID", "MAX_EPISODE_STEPS", "SocialNavEnv"]

if ENV_ID not in gymnasium.registry:
    gymnasium.register(
        id=ENV_ID, entry_point="srfm.rl.env:SocialNavEnv", max_episode_steps=MAX_EPISODE_STEPS
    )
