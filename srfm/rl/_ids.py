"""Names of the environment, importable without gymnasium."""

from typing import Final

__all__ = ["ENV_ID"]

ENV_ID: Final = "srfm/SocialNav-v0"
"""The gymnasium id of :class:`srfm.rl.SocialNavEnv`."""
