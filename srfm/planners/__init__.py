"""Robot planners: the protocol, the registry, and the built-in planners."""

from srfm.planners._base import Observation, Planner, PlannerContext
from srfm.planners._registry import (
    PlannerInfo,
    available_planners,
    make_planner,
    register_planner,
)
from srfm.planners.straight import StraightPlanner

__all__ = [
    "Observation",
    "Planner",
    "PlannerContext",
    "PlannerInfo",
    "StraightPlanner",
    "available_planners",
    "make_planner",
    "register_planner",
]

register_planner(
    "straight", StraightPlanner, "drive straight to the goal at top speed, ignoring people"
)
