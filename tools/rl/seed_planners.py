"""The policy of every training seed of the shipped recipe, as planners for
``srfm benchmark`` (docs/rl.md, "The claim over training seeds"):

    srfm benchmark -p td3-srfm,td3-base,dwa,vo,orca,social-force,straight \\
        -p tools.rl.seed_planners:srfm_seed11,tools.rl.seed_planners:base_seed11,... --out DIR

Run from the repository root with it on the import path (PYTHONPATH=.): the module is
imported by name in every worker. Each factory loads the NumPy policy file
``tools/rl/policies/td3_<variant>_seed<k>`` exported from that stage-2 run's best
checkpoint (tools/rl/train_policies.sh); ``stage1_seed<k>`` the pre-training runs' RL_base
policies (``tools/rl/policies/stage1/``).
"""

from __future__ import annotations

from pathlib import Path

from srfm.planners.td3 import TD3Planner

POLICIES = Path(__file__).resolve().parent / "policies"


def _planner(variant: str, seed: int) -> TD3Planner:
    return TD3Planner(POLICIES / f"td3_{variant}_seed{seed}.json", f"td3-{variant}-seed{seed}")


def _stage1(seed: int) -> TD3Planner:
    return TD3Planner(POLICIES / "stage1" / f"td3_base_seed{seed}.json", f"stage1-seed{seed}")


def stage1_seed1() -> TD3Planner:
    """Stage 1 (pre-training, RL_base), training seed 1."""
    return _stage1(1)


def stage1_seed2() -> TD3Planner:
    """Stage 1 (pre-training, RL_base), training seed 2."""
    return _stage1(2)


def stage1_seed3() -> TD3Planner:
    """Stage 1 (pre-training, RL_base), training seed 3."""
    return _stage1(3)


def srfm_seed11() -> TD3Planner:
    """SRFM-aware, stage 2, training seed 11."""
    return _planner("srfm", 11)


def srfm_seed12() -> TD3Planner:
    """SRFM-aware, stage 2, training seed 12."""
    return _planner("srfm", 12)


def srfm_seed13() -> TD3Planner:
    """SRFM-aware, stage 2, training seed 13."""
    return _planner("srfm", 13)


def base_seed11() -> TD3Planner:
    """RL_base, stage 2, training seed 11."""
    return _planner("base", 11)


def base_seed12() -> TD3Planner:
    """RL_base, stage 2, training seed 12."""
    return _planner("base", 12)


def base_seed13() -> TD3Planner:
    """RL_base, stage 2, training seed 13."""
    return _planner("base", 13)
