"""The generated sentences of docs/planners.md that say why a planner's default was
chosen: each compares the shipped default with the alternative it replaced, on the
same scenarios and seeds, from committed runs of ``tools/analysis/planner_outcomes.py``
(``docs/planner_outcomes/<run>/``) and the ``paper`` results set (the shipped
defaults). ``tools/results/generate.py`` registers :data:`BLOCKS`.
"""

from __future__ import annotations

import statistics
from collections.abc import Callable

from srfm.planners.dwa import DWAConfig
from srfm.planners.social_force import SocialForceConfig
from tools.analysis.planner_outcomes import Result
from tools.results.fitting_pages import prose
from tools.results.pages import _run_provenance, _set_provenance, outcome_run, set_results


def _cell(results: list[Result], planner: str, scenario: str) -> list[Result]:
    return [r for r in results if r.planner == planner and r.scenario == scenario]


def _misses(rs: list[Result]) -> str:
    """``all 100 reach the goal`` / ``2 of 100 time out`` (each outcome that is not the goal)."""
    bad = [r.outcome for r in rs if r.outcome != "goal_reached"]
    if not bad:
        return f"all {len(rs)} reach the goal"
    verbs = {"timeout": "time out", "collision": "collide", "out_of_bounds": "leave the world"}
    return ", ".join(
        f"{bad.count(k)} of {len(rs)} {verbs.get(k, k.replace('_', ' '))}" for k in sorted(set(bad))
    )


def _not_goal(rs: list[Result]) -> int:
    return sum(r.outcome != "goal_reached" for r in rs)


def _time_to_goal(rs: list[Result]) -> float:
    return statistics.fmean(r.time_to_goal_s for r in rs if r.outcome == "goal_reached")


def dwa_window() -> str:
    """DWA's window time: the shipped t_w against Fox et al.'s one control step."""
    shipped = set_results("paper")
    variant, manifest = outcome_run("variants")
    if "dwa.window_time_s=None" not in manifest["overrides"]:
        raise SystemExit("docs/planner_outcomes/variants no longer runs dwa.window_time_s=None")
    d = DWAConfig()
    lines = [
        f"| scenario | time to goal (s), shipped t_w = {d.window_time_s:g} s | not reached | "
        "time to goal (s), one step's window | not reached |",
        "|---|--:|--:|--:|--:|",
    ]
    for scenario in manifest["scenarios"]:
        a, b = _cell(shipped, "dwa", scenario), _cell(variant, "dwa", scenario)
        lines.append(
            f"| `{scenario}` | {_time_to_goal(a):.1f} | {_not_goal(a)} of {len(a)} | "
            f"{_time_to_goal(b):.1f} | {_not_goal(b)} of {len(b)} |"
        )
    return (
        prose(
            "Measured now: `dwa`'s mean time to the goal with the shipped window against one "
            "control step's window (`window_time_s=None`), both with rollout steps of "
            f"{d.rollout_step_s:g} s, seeds {manifest['seeds'][0]}–{manifest['seeds'][1]}:"
        )
        + "\n\n"
        + "\n".join(lines)
        + "\n\n"
        + _set_provenance("paper")
        + " "
        + _run_provenance("variants", manifest)
    )


def social_force_range() -> str:
    """The social-force planner's B and τ: the shipped values against agrawal2024's."""
    shipped = [r for r in set_results("paper") if r.planner == "social-force"]
    variant, manifest = outcome_run("social_force_agrawal")
    scenarios = list(manifest["scenarios"])
    c = SocialForceConfig()

    def speeds(rs: list[Result]) -> str:
        means = [
            statistics.fmean(r.speed_mps for r in _cell(rs, "social-force", s)) for s in scenarios
        ]
        return f"{min(means):.2f}–{max(means):.2f} m/s"

    def concert(rs: list[Result]) -> str:
        cell = _cell(rs, "social-force", "concert")
        return f"`concert` {_time_to_goal(cell):.1f} s to the goal and {_misses(cell)}"

    overrides = ", ".join(f"`{o}`" for o in manifest["overrides"])
    return (
        prose(
            f"With {overrides} (the pedestrians' values of `agrawal2024`) the robot's mean "
            f"speed per scenario is {speeds(variant)}, {concert(variant)}; with the shipped "
            f"B = {c.ped_range_m:g} m and τ = {c.tau_s:g} s it is {speeds(shipped)}, "
            f"{concert(shipped)}."
        )
        + "\n\n"
        + _set_provenance("paper")
        + " "
        + _run_provenance("social_force_agrawal", manifest)
    )


BLOCKS: dict[str, Callable[[], str]] = {
    "planner-dwa-window": dwa_window,
    "planner-social-force-range": social_force_range,
}
