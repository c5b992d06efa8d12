"""srfm: the Social Robot Force Model, twin counterfactual crowd simulation and a benchmark.

Quick use::

    import srfm
    record = srfm.run_episode("crosswalk", seed=0, planner="straight")
    print(record.outcome, record.twin_separation_m().max())
"""

from typing import TYPE_CHECKING

from srfm._lazy import lazy_names
from srfm._version import __version__
from srfm.errors import (
    BenchmarkError,
    DatasetError,
    DatasetWarning,
    FolderInUseError,
    LogError,
    MetricError,
    MissingDependencyError,
    OutputError,
    ParameterError,
    PlannerError,
    PlannerFailedError,
    PlannerFailureWarning,
    ResourceError,
    ScenarioError,
    SimulationError,
    SrfmError,
    SrfmWarning,
    SweepError,
    UserCodeError,
    WriteError,
)

# The API below is imported on first use (srfm/_lazy.py).
if TYPE_CHECKING:
    from srfm.models import (
        PRESETS,
        ForceComponents,
        RobotBody,
        SRFMParams,
        force_components,
        load_params,
        save_params,
        step_crowd,
    )
    from srfm.models.robot import RobotConfig, RobotState, apply_command
    from srfm.models.state import CrowdState, Obstacles
    from srfm.scenarios import (
        BUILTIN_SCENARIOS,
        EVALUATION_SCENARIOS,
        Scenario,
        builtin_scenarios,
        episode_setup,
        load_scenario,
    )
    from srfm.sim.episode import run_episode
    from srfm.sim.record import EpisodeRecord, Event
    from srfm.sim.simulator import TwinSimulator

_LAZY: dict[str, str] = {
    "PRESETS": "srfm.models",
    "ForceComponents": "srfm.models",
    "RobotBody": "srfm.models",
    "SRFMParams": "srfm.models",
    "force_components": "srfm.models",
    "load_params": "srfm.models",
    "save_params": "srfm.models",
    "step_crowd": "srfm.models",
    "RobotConfig": "srfm.models.robot",
    "RobotState": "srfm.models.robot",
    "apply_command": "srfm.models.robot",
    "CrowdState": "srfm.models.state",
    "Obstacles": "srfm.models.state",
    "BUILTIN_SCENARIOS": "srfm.scenarios",
    "EVALUATION_SCENARIOS": "srfm.scenarios",
    "Scenario": "srfm.scenarios",
    "builtin_scenarios": "srfm.scenarios",
    "episode_setup": "srfm.scenarios",
    "load_scenario": "srfm.scenarios",
    "run_episode": "srfm.sim.episode",
    "EpisodeRecord": "srfm.sim.record",
    "Event": "srfm.sim.record",
    "TwinSimulator": "srfm.sim.simulator",
}


__all__ = [
    "BUILTIN_SCENARIOS",
    "EVALUATION_SCENARIOS",
    "PRESETS",
    "BenchmarkError",
    "CrowdState",
    "DatasetError",
    "DatasetWarning",
    "EpisodeRecord",
    "Event",
    "FolderInUseError",
    "ForceComponents",
    "LogError",
    "MetricError",
    "MissingDependencyError",
    "Obstacles",
    "OutputError",
    "ParameterError",
    "PlannerError",
    "PlannerFailedError",
    "PlannerFailureWarning",
    "ResourceError",
    "RobotBody",
    "RobotConfig",
    "RobotState",
    "SRFMParams",
    "Scenario",
    "ScenarioError",
    "SimulationError",
    "SrfmError",
    "SrfmWarning",
    "SweepError",
    "TwinSimulator",
    "UserCodeError",
    "WriteError",
    "__version__",
    "apply_command",
    "builtin_scenarios",
    "episode_setup",
    "force_components",
    "load_params",
    "load_scenario",
    "run_episode",
    "save_params",
    "step_crowd",
]


__getattr__, __dir__ = lazy_names(__name__, _LAZY, globals())
