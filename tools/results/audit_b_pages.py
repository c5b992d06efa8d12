"""Figures of docs/reliability.md, docs/results/robustness.md, ... that were typed outside
generated blocks, now written from what they come from: the run-size model of
``srfm/sim/budget.py`` and ``srfm/sim/episode.py`` (its shipped coefficients, and its
estimate of a large crowd) and the presets fitted from real data
(``srfm/models/presets/*.toml``). ``tools/results/generate.py`` registers :data:`BLOCKS`.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from srfm.models.params import SRFMParams, preset_meta
from srfm.scenarios import Scenario
from srfm.scenarios._schema import parse_scenario
from srfm.sim import budget
from srfm.sim.budget import estimate_episode_time, format_duration
from srfm.sim.episode import estimate_episode_memory, format_bytes
from tools.results.fitting_pages import prose

CROWD_PEDESTRIANS = 100_000
"""The large crowd of docs/reliability.md (and of ``tests/reliability/test_run_size_limits.py``)."""
CROWD_SPACING_M = 1.5


def _micro(seconds: float) -> str:
    """A coefficient in µs or ns, as the formula writes it: ``15 µs``, ``5.2 ns``."""
    if seconds >= 1e-7:
        return f"{seconds * 1e6:.2g} µs"
    return f"{seconds * 1e9:.2g} ns"


def run_size_formula() -> str:
    """The run-size model's CPU time of one twin episode, with its shipped coefficients."""
    b: Any = budget  # the coefficients are module constants, private by name
    sample, ped, pair, obstacle = (
        b._SAMPLE_S,
        b._PED_SAMPLE_S,
        b._PAIR_SAMPLE_S,
        b._OBSTACLE_PED_SAMPLE_S,
    )
    metric, metric_sq = b._METRIC_PED_SAMPLE_S, b._METRIC_PED_SAMPLE_SQ_S
    return (
        "```text\n"
        f"S · ({_micro(sample)} + N · ({_micro(ped)} + {_micro(pair)} · K + "
        f"{_micro(obstacle)} · M)) + N · S · ({_micro(metric)} + {_micro(metric_sq)} · S)\n"
        "```"
    )


def crowd_scenario(n: int = CROWD_PEDESTRIANS) -> Scenario:
    """A version-1 scenario of ``n`` pedestrians on a 1.5 m grid, each crossing the world
    (the crowd of ``tests/reliability/test_run_size_limits.py``)."""
    side = int(n**0.5 + 0.999999)
    points = [
        (1.0 + CROWD_SPACING_M * i, 1.0 + CROWD_SPACING_M * j)
        for j in range(side)
        for i in range(side)
    ][:n]
    width = side * CROWD_SPACING_M + 2.0
    data = {
        "schema_version": 1,
        "name": "crowd",
        "description": f"{n} pedestrians",
        "world": {"x_min": -5.0, "x_max": width + 5, "y_min": -5.0, "y_max": width + 5},
        "robot": {"start": [-4.0, -4.0], "goal": [width + 4, width + 4]},
        "pedestrians": {
            "starts": [[x, y] for x, y in points],
            "goals": [[width - x, y] for x, y in points],
        },
    }
    return parse_scenario(data, "crowd")


def run_size_crowd() -> str:
    """What the model estimates for one episode of a crowd of 100,000 pedestrians."""
    crowd = crowd_scenario()
    return prose(
        f"A scenario of {crowd.n_pedestrians:,} pedestrians ({crowd.horizon_steps} steps) is "
        f"estimated by the model at about {format_duration(estimate_episode_time(crowd))} "
        f"of CPU time and {format_bytes(estimate_episode_memory(crowd))} per episode "
        "(`srfm.sim.budget.estimate_episode_time`, "
        "`srfm.sim.episode.estimate_episode_memory`)."
    )


def robustness_fitted_preset() -> str:
    """docs/results/robustness.md: the robot force of ``navwareset2025`` as fitted."""
    p = SRFMParams.preset("navwareset2025")
    meta = preset_meta("navwareset2025")
    return prose(
        f"`navwareset2025`'s robot force as fitted ({meta['robot_form']}, "
        f"`srfm/models/presets/navwareset2025.toml`): A_r = {p.a_robot:.2f} m/s², "
        f"B_r = {p.b_robot:.2f} m."
    )


BLOCKS: dict[str, Callable[[], str]] = {
    "run-size-formula": run_size_formula,
    "run-size-crowd": run_size_crowd,
    "robustness-fitted-preset": robustness_fitted_preset,
}
