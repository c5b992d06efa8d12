"""Scenarios: the built-in TOML files shipped in this folder, and user files.

``load_scenario("footpath")`` loads a built-in scenario by name;
``load_scenario("my/file.toml")`` loads a user file. The schema is documented in
:mod:`srfm.scenarios._schema` and in ``docs/scenarios.md``.
"""

from __future__ import annotations

from functools import cache
from importlib import resources
from pathlib import Path
from typing import Final

from srfm._text import plain
from srfm.errors import ScenarioError
from srfm.scenarios._schema import (
    MAX_HORIZON_STEPS,
    SCHEMA_VERSION,
    RandomSpec,
    Scenario,
    parse_scenario,
    read_scenario_file,
)
from srfm.scenarios._setup import (
    EpisodeSetup,
    entry_steps,
    entry_times,
    episode_setup,
    next_goal,
    source_goals,
    validate_seed,
)
from srfm.scenarios._v2 import EntrySource, RobotRecording
from srfm.world import WorldBounds  # the type of Scenario.world, exported with it

__all__ = [
    "BUILTIN_SCENARIOS",
    "EVALUATION_SCENARIOS",
    "FLOW_SCENARIOS",
    "FRANCIS_SCENARIOS",
    "LARGE_SCENARIOS",
    "MAX_HORIZON_STEPS",
    "NAVWARESET_SCENARIOS",
    "SCHEMA_VERSION",
    "EntrySource",
    "EpisodeSetup",
    "RandomSpec",
    "RobotRecording",
    "Scenario",
    "WorldBounds",
    "builtin_scenarios",
    "entry_steps",
    "entry_times",
    "episode_setup",
    "load_scenario",
    "next_goal",
    "parse_scenario",
    "scenario_names",
    "source_goals",
    "validate_seed",
]

# The paper's five evaluation scenarios, in its order, then the training scenario.
EVALUATION_SCENARIOS: Final = ("footpath", "crosswalk", "cross_footpath", "circle", "concert")
"""The paper's five evaluation scenarios, in its order (15 m × 15 m worlds, 10
pedestrians, 750 steps of 1/15 s = 50 s); the benchmark's default suite."""
# Scenarios after Francis et al. 2023 ("Principles and guidelines for evaluating social
# robot navigation algorithms"), with walls, doors, corners and rooms (issue 17).
FRANCIS_SCENARIOS: Final = (
    "frontal_approach",
    "pedestrian_obstruction",
    "pedestrian_overtaking",
    "robot_overtaking",
    "down_path",
    "intersection",
    "intersection_open",
    "blind_corner",
    "narrow_hallway",
    "narrow_doorway",
    "entering_room",
    "exiting_room",
    "parallel_traffic",
    "perpendicular_traffic",
    "circular_crossing",
    "robot_crowding",
    "crowd_navigation",
)
# The NavWareSet room (scene 13's map) with the dataset's five layouts (issue 17;
# written by tools/scenarios/make_navwareset_scenarios.py).
NAVWARESET_SCENARIOS: Final = (
    "navwareset_frontal_approach",
    "navwareset_obstruction",
    "navwareset_blind_corner",
    "navwareset_perpendicular_crossing",
    "navwareset_circular_crossing",
)
# Pedestrians entering during the run (sources and entry times; issue 17).
FLOW_SCENARIOS: Final = ("corridor_flow",)
BUILTIN_SCENARIOS: Final = (
    *EVALUATION_SCENARIOS,
    "random",
    *FRANCIS_SCENARIOS,
    *NAVWARESET_SCENARIOS,
    *FLOW_SCENARIOS,
)
"""The names of every built-in scenario: the paper's five, its random training scenario,
then the scenarios after Francis et al. 2023, the NavWareSet room and the flows
(``srfm scenarios`` describes each; docs/scenarios.md)."""
# Large crowds (issue 19; 300-400 pedestrians, stepped with the cell list and the
# interaction cut-off): built in and loadable by name, run by `srfm benchmark --suite
# large`, but kept out of BUILTIN_SCENARIOS, whose scenarios every test, the RL
# environment (exact kernel, small crowds) and the paper's tables iterate over.
LARGE_SCENARIOS: Final = ("concert_crowd", "station_concourse")


@cache
def _builtin(name: str) -> Scenario:
    ref = resources.files(__name__).joinpath(f"{name}.toml")
    with resources.as_file(ref) as path:
        scenario = read_scenario_file(Path(path))
    if scenario.name != name:
        raise ScenarioError(f"{name}.toml: name is {scenario.name!r}, expected {name!r}")
    return scenario


def load_scenario(name_or_path: str | Path) -> Scenario:
    """Load a built-in scenario by name, a generated walled layout by
    ``generated:SEED`` or ``generated:KIND:SEED``
    (:mod:`srfm.scenarios.generated`), or a scenario TOML file by path.

    Raises:
        ScenarioError: unknown name, missing file, or a file that breaks the schema
            (the message names the file and the key).
    """
    text = str(name_or_path)
    if isinstance(name_or_path, str):
        from srfm.scenarios.generated import generated_scenario, parse_generated_name

        named = parse_generated_name(text)
        if named is not None:
            return generated_scenario(named[1], named[0])
    if isinstance(name_or_path, str) and text in scenario_names():
        return _builtin(text)
    path = Path(name_or_path)
    if path.suffix == ".toml" or path.exists():
        return read_scenario_file(path)
    known = ", ".join(scenario_names())
    raise ScenarioError(
        f"unknown scenario {plain(text)}; built-in: {known}; or generated:SEED, "
        "generated:KIND:SEED, or a .toml path"
    )


def scenario_names() -> tuple[str, ...]:
    """Every built-in name :func:`load_scenario` (and ``--scenario``) accepts: the
    built-in scenarios, then the large crowds (``srfm scenarios`` lists them all, and the
    generated layouts ``generated:SEED``)."""
    return (*BUILTIN_SCENARIOS, *LARGE_SCENARIOS)


def builtin_scenarios() -> list[Scenario]:
    """Every built-in scenario: the paper's in its order, the training one, then Francis's."""
    return [_builtin(name) for name in BUILTIN_SCENARIOS]
