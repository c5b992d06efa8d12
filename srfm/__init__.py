"""srfm: the Social Robot Force Model, twin counterfactual crowd simulation and a benchmark.

Quick use::

    import srfm
    record = srfm.run_episode("crosswalk", seed=0, planner="straight")
    print(record.outcome, record.twin_separation_m().max())
"""

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
    ResourceError,
    ScenarioError,
    SimulationError,
    SrfmError,
    SrfmWarning,
    SweepError,
    UserCodeError,
    WriteError,
)
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
