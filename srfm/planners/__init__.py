"""Robot planners: the protocol, the registry, and the built-in planners.

Every built-in planner is registered here, and only here (the ones that need more than
NumPy, or code above this package, are imported when first made), so that
``srfm planners``, ``srfm benchmark -p`` and :func:`make_planner` see the same names
whatever else was imported.
"""

from srfm.planners._base import Observation, Planner, PlannerContext, check_planner
from srfm.planners._registry import (
    PlannerInfo,
    available_planners,
    make_planner,
    register_planner,
)
from srfm.planners.dwa import DWAConfig, DWAPlanner
from srfm.planners.orca import ORCAConfig, ORCAPlanner
from srfm.planners.social_force import SocialForceConfig, SocialForcePlanner
from srfm.planners.stay import StayPlanner
from srfm.planners.straight import StraightPlanner
from srfm.planners.velocity_obstacles import VelocityObstaclePlanner, VOConfig

__all__ = [
    "DWAConfig",
    "DWAPlanner",
    "ORCAConfig",
    "ORCAPlanner",
    "Observation",
    "Planner",
    "PlannerContext",
    "PlannerInfo",
    "SocialForceConfig",
    "SocialForcePlanner",
    "StayPlanner",
    "StraightPlanner",
    "VOConfig",
    "VelocityObstaclePlanner",
    "available_planners",
    "check_planner",
    "make_planner",
    "register_planner",
]

register_planner(
    "straight", StraightPlanner, "drive straight to the goal at top speed, ignoring people"
)
register_planner(
    "dwa", DWAPlanner, "Dynamic Window Approach (Fox et al. 1997): best arc of the dynamic window"
)
register_planner(
    "vo", VelocityObstaclePlanner, "Velocity Obstacles: admissible velocity closest to the goal"
)
register_planner("orca", ORCAPlanner, "ORCA (van den Berg et al. 2011): reciprocal half-planes")
register_planner(
    "social-force", SocialForcePlanner, "the robot moved toward its goal by a social force model"
)


def _td3_srfm() -> Planner:
    from srfm.planners.td3 import td3_srfm  # lazy: the policy file is read when used

    return td3_srfm()


def _td3_base() -> Planner:
    from srfm.planners.td3 import td3_base

    return td3_base()


def _recorded() -> Planner:
    from srfm.planners.recorded import RecordedRobotPlanner

    return RecordedRobotPlanner()


register_planner(
    "recorded",
    _recorded,
    "replay the scenario's recorded robot ([robot.recording]; `srfm data scenario` writes "
    "such scenarios); runs only on such scenarios",
    default=False,
)
register_planner("td3-srfm", _td3_srfm, "TD3 policy trained with the SRFM deviation penalty")
register_planner(
    "td3-base", _td3_base, "TD3 policy trained without the deviation penalty (RL_base)"
)


register_planner(
    "stay",
    StayPlanner,
    "reference: a robot that never moves (a standing obstacle)",
    default=False,
)
# The oracle reads the episode's engine, so its code lives in srfm.sim, above the
# planners: it is named here by module:attribute and imported when first made.
register_planner(
    "oracle",
    "srfm.sim.oracle:OraclePlanner",
    "privileged reference: plans over the twin simulator itself (knows the crowd model, "
    "every goal and the counterfactual) for the least deviation that still reaches the "
    "goal; not deployable",
    default=False,
)
