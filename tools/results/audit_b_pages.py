"""Figures of docs/reliability.md, docs/results/robustness.md, ... that were typed outside
generated blocks, now written from what they come from: the run-size model of
``srfm/sim/budget.py`` and ``srfm/sim/episode.py`` (its shipped coefficients, and its
estimate of a large crowd) and the presets fitted from real data
(``srfm/models/presets/*.toml``). ``tools/results/generate.py`` registers :data:`BLOCKS`.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from typing import Any

from srfm.models.params import SRFMParams, preset_meta
from srfm.planners.velocity_obstacles import VOConfig
from srfm.scenarios import Scenario
from srfm.scenarios._schema import parse_scenario
from srfm.sim import budget
from srfm.sim.budget import estimate_episode_time, format_duration
from srfm.sim.episode import estimate_episode_memory, format_bytes
from tools.results import rl_study, sets
from tools.results.fitting_pages import prose
from tools.results.pages import _run_provenance, _set_provenance, outcome_run, set_results

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


SHIPPING_NOTE = re.compile(
    r"among the runs finished on (\d{4}-\d\d-\d\d) at (\d\d:\d\d) "
    r"\(training seeds (\d+)-(\d+)\)"
)


def rl_shipped_runs() -> str:
    """docs/rl.md: which study run and checkpoint each shipped policy is, from the policy
    files (their weights' SHA-256 and training record) and the study's validation."""
    runs = rl_study.shipped_runs()
    parts, when, episodes = [], set(), set()
    for planner, stem in rl_study.SHIPPED.items():
        training = sets.read_json(sets.ROOT / "srfm" / "policies" / f"{stem}.json")["training"]
        best = sets.read_json(rl_study.STUDY / "validation" / f"{runs[planner]}.json")["best"]
        if int(best["steps"]) != int(training["steps"]):
            raise SystemExit(
                f"srfm/policies/{stem}.json: step {training['steps']} is not the chosen "
                f"checkpoint of {runs[planner]} (step {best['steps']})"
            )
        match = SHIPPING_NOTE.search(training["note"])
        if match is None:
            raise SystemExit(f"srfm/policies/{stem}.json: its note does not say when it shipped")
        when.add(match.groups())
        episodes.add(int(best["episodes"]))
        verb = "run" if parts else "is run"
        study = "" if parts else " of `tools/rl/study.py`"
        parts.append(
            f"`{planner}` {verb} `{runs[planner]}`{study} at {int(best['steps']):,} actions"
        )
    if len(when) != 1 or len(episodes) != 1:
        raise SystemExit(f"the shipped policies disagree on their shipping: {when}, {episodes}")
    day, time, first, last = when.pop()
    return prose(
        f"**Which runs.** Since {day} {time} {' and '.join(parts)}, chosen by the rule "
        "below among the study's runs finished then (training "
        f"seeds {first}–{last} of both arms). Each run's own checkpoint is the one after "
        "the k2 curriculum with the highest success, then the fewest collisions, on the "
        f"validation set with 10 seeds per scenario from 20000 on ({episodes.pop()} episodes; "
        "`tools/rl/validate_checkpoints.py`, tables in `tools/rl/study/validation/`)."
    )


def _goals(results: list[Any], planner: str) -> tuple[int, int]:
    """Episodes of ``planner`` that reached the goal, and all of its episodes."""
    mine = [r for r in results if r.planner == planner]
    return sum(r.outcome == "goal_reached" for r in mine), len(mine)


def planner_vo_range() -> str:
    """docs/planners.md: VO at its default detection range and at the paper's 1.4 m."""
    default = VOConfig().detection_range_m
    shipped = set_results("paper")
    variant, manifest = outcome_run("variants")
    if "vo.detection_range_m=1.4" not in manifest["overrides"]:
        raise SystemExit("docs/planner_outcomes/variants no longer runs vo.detection_range_m=1.4")
    at_default, n_default = _goals(shipped, "vo")
    at_paper, n_paper = _goals(variant, "vo")
    return (
        prose(
            "This implementation always has a command (the latest-collision fallback). On "
            f"the evaluation scenarios it reaches the goal in {at_default} of {n_default} "
            f"episodes at the default {default:g} m, and in {at_paper} of {n_paper} at "
            "1.4 m (`VOConfig(detection_range_m=1.4)`; table below), so the default stays "
            f"{default:g} m."
        )
        + "\n\n"
        + _set_provenance("paper").replace(", the rows of the planners above.*", ".*")
        + " "
        + _run_provenance("variants", manifest)
    )


def _and(names: list[str]) -> str:
    return names[0] if len(names) == 1 else ", ".join(names[:-1]) + " and " + names[-1]


def planner_francis_goals() -> str:
    """docs/planners.md: the routed classical planners' outcomes in the Francis suite."""
    results = set_results("francis")
    req = sets.manifest("francis")["request"]
    classical = [
        p for p in ("dwa", "orca", "social-force", "straight", "vo") if p in req["planners"]
    ]
    always, missed = [], []
    for planner in classical:
        goals, n = _goals(results, planner)
        if goals == n:
            always.append(f"`{planner}`")
        else:
            missed.append(f"`{planner}` in {goals:,} of {n:,}")
    n = len(req["scenarios"]) * len(req["seeds"])
    parts = []
    if always:
        parts.append(f"{_and(always)} reach the goal in all {n:,} episodes each")
    if missed:
        parts.append("; ".join(missed))
    return prose(
        f"With these routes, in the Francis suite ({len(req['scenarios'])} scenarios, seeds "
        f"{req['seeds'][0]}–{req['seeds'][-1]}): {'; '.join(parts)} "
        "([results/suites.md](results/suites.md#the-francis-suite)); the planners themselves "
        "are unchanged and still plan locally."
    )


BLOCKS: dict[str, Callable[[], str]] = {
    "planner-vo-range": planner_vo_range,
    "planner-francis-goals": planner_francis_goals,
    "rl-shipped-runs": rl_shipped_runs,
    "run-size-formula": run_size_formula,
    "run-size-crowd": run_size_crowd,
    "robustness-fitted-preset": robustness_fitted_preset,
}
