"""Dataset adapters (JRDB, ETH/UCY, NavWareSet) to canonical trajectories and MCAP.

Empty until the datasets issue lands; raw layouts are documented in the repository's
top-level ``datasets/`` folder.
"""

__all__: list[str] = []
