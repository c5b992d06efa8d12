"""The twin simulation: the simulator, the episode loop and the episode record.

Data flow: :mod:`srfm.models` (physics) and :mod:`srfm.scenarios` (episode set-ups)
feed :class:`TwinSimulator`; :func:`run_episode` drives it with a planner from
:mod:`srfm.planners` and returns an :class:`EpisodeRecord`.
"""

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
