"""Shipped TD3 policy files (stable-baselines3 zips), loaded by ``srfm.planners.td3``.

``td3_srfm.zip`` (SRFM-aware, k2 > 0) and ``td3_base.zip`` (RL_base, k2 = 0) were
trained with ``tools/train_policies.sh``; ``docs/rl.md`` gives the exact commands,
the steps trained and the wall time. SB3's loader unpickles: load only trusted files.
"""
