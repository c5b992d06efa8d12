"""Shipped TD3 policies, loaded by ``srfm.planners.td3``.

``td3_srfm`` (SRFM-aware, k2 > 0) and ``td3_base`` (RL_base, k2 = 0), each as

- ``<name>.npz`` + ``<name>.json``: the NumPy policy file the registered planners
  ``td3-srfm`` and ``td3-base`` run (weights and metadata; loads with NumPy only, no
  pickle);
The stable-baselines3 checkpoints they were exported from (``srfm export-policy``)
are not part of the package: they are kept in the repository's ``tools/rl/policies/``
(SB3's loader unpickles: load only trusted files). ``tools/rl/train_policies.sh`` trains
and exports them; ``docs/rl.md`` gives the exact commands, the steps trained and the wall
time.
"""
