"""The twin simulation: the simulator, the episode loop and the episode record.

Data flow: :mod:`srfm.models` (physics) and :mod:`srfm.scenarios` (episode set-ups)
feed :class:`TwinSimulator`; :func:`run_episode` drives it with a planner from
:mod:`srfm.planners` and returns an :class:`EpisodeRecord`.
"""

from srfm.planners import register_planner
from srfm.sim.episode import PLANNER_STREAM, planner_rng, run_episode
from srfm.sim.oracle import OracleConfig, OraclePlanner
from srfm.sim.record import EpisodeRecord, Event
from srfm.sim.simulator import TwinSimulator

__all__ = [
    "PLANNER_STREAM",
    "EpisodeRecord",
    "Event",
    "OracleConfig",
    "OraclePlanner",
    "TwinSimulator",
    "planner_rng",
    "run_episode",
]

# The oracle reads the episode's engine, so it lives here and is registered here (srfm
# imports srfm.sim, so it is there whenever a planner is looked up by name).
register_planner(
    "oracle",
    OraclePlanner,
    "privileged reference: plans over the twin simulator itself (knows the crowd model, "
    "every goal and the counterfactual) for the least deviation that still reaches the "
    "goal; not deployable, not in the default benchmark",
    default=False,
)
