"""Generated blocks of docs/planners.md and docs/metrics.md, from committed data only
(``tools/results/generate.py``):

- the planners' robot outcomes: the unicycle table from the results set ``paper``, the
  holonomic robot, pedestrians who ignore the robot and two planner variants from
  ``docs/planner_outcomes/<run>/`` (``tools/analysis/planner_outcomes.py --out``);
- the convergence in the time step: ``docs/convergence/frechet.csv``
  (``tools/analysis/convergence.py``);
- the noise floor, the direct / knock-on split and the suite statistics of the paper
  suite: ``docs/attribution/paper.json`` (``tools/analysis/attribution.py``).
"""

from __future__ import annotations

import collections
import math
import statistics
from pathlib import Path
from typing import Any

from tools.analysis import attribution, convergence, planner_outcomes
from tools.analysis.planner_outcomes import DEFAULT_PLANNERS, Result
from tools.results import sets

DOCS = sets.ROOT / "docs"
OUTCOMES = DOCS / "planner_outcomes"
CONVERGENCE = DOCS / "convergence" / "frechet.csv"
ATTRIBUTION = DOCS / "attribution" / "paper.json"


class Missing(Exception):
    """Data a block needs is not committed."""


# -- robot outcomes of the planners -----------------------------------------------------


def set_results(name: str) -> list[Result]:
    """A results set's episodes as planner_outcomes' :class:`Result` (the same
    quantities: the benchmark's robot_mean_speed_mps is path length / active time,
    robot_time_to_goal_s is undefined unless the goal was reached)."""
    t = sets.table(name)
    cols = {
        c: t[c].to_pylist()
        for c in (
            "scenario",
            "planner",
            "seed",
            "outcome",
            "end_step",
            "robot_mean_speed_mps",
            "robot_time_to_goal_s",
            "min_robot_distance_m",
        )
    }
    return [
        Result(
            scenario=cols["scenario"][i],
            planner=cols["planner"][i],
            seed=int(cols["seed"][i]),
            outcome=cols["outcome"][i],
            end_step=int(cols["end_step"][i]),
            speed_mps=float(cols["robot_mean_speed_mps"][i]),
            time_to_goal_s=_float(cols["robot_time_to_goal_s"][i]),
            min_distance_m=float(cols["min_robot_distance_m"][i]),
        )
        for i in range(t.num_rows)
    ]


def _float(x: float | None) -> float:
    return math.nan if x is None else float(x)


def outcome_run(run: str) -> tuple[list[Result], dict[str, Any]]:
    """A committed planner_outcomes run."""
    folder = OUTCOMES / run
    if not (folder / "episodes.parquet").is_file():
        raise Missing(
            f"`docs/planner_outcomes/{run}` (`python tools/analysis/planner_outcomes.py "
            f"... --out docs/planner_outcomes/{run}`)"
        )
    return planner_outcomes.read(folder)


def _run_provenance(run: str, manifest: dict[str, Any]) -> str:
    load = manifest.get("load_average")
    return (
        f"*Data `docs/planner_outcomes/{run}/` ({len(manifest['scenarios'])} scenarios × "
        f"{len(manifest['planners'])} planners × seeds {manifest['seeds'][0]}–"
        f"{manifest['seeds'][1]}): `{manifest['command']}`, commit `{manifest['commit']}`, "
        f"{manifest['started'][:16].replace('T', ' ')} UTC, {manifest['wall_s']:.0f} s with "
        f"{manifest['jobs']} workers"
        + (f" (load average {load[0]:.1f})" if load else "")
        + ".*"
    )


def _set_provenance(name: str) -> str:
    rs = sets.manifest(name)["results_set"]
    return (
        f"*From the results set [`{name}`](results/index.md) (measured "
        f"{rs['started'][:16].replace('T', ' ')} UTC on commit `{rs['commit']}`: "
        f"`{rs['command']}`), the rows of the planners above.*"
    )


def _scenarios(results: list[Result]) -> list[str]:
    return list(dict.fromkeys(r.scenario for r in results))


def outcomes_unicycle() -> str:
    results = [r for r in set_results("paper") if r.planner in DEFAULT_PLANNERS]
    lines = planner_outcomes.markdown_table(results, _scenarios(results), list(DEFAULT_PLANNERS))
    return _set_provenance("paper") + "\n\n" + "\n".join(lines)


def outcomes_holonomic() -> str:
    results, manifest = outcome_run("holonomic")
    lines = planner_outcomes.markdown_table(
        results, manifest["scenarios"], list(manifest["planners"])
    )
    return _run_provenance("holonomic", manifest) + "\n\n" + "\n".join(lines)


def outcomes_summary() -> str:
    """Which planners reached the goal every time, under either kinematics."""
    uni = [r for r in set_results("paper") if r.planner in DEFAULT_PLANNERS]
    holo, manifest = outcome_run("holonomic")
    both = uni + holo
    failed = [r for r in both if r.outcome != "goal_reached"]
    per = len(uni) // len(DEFAULT_PLANNERS)
    cells: dict[tuple[str, str, int], list[Result]] = collections.defaultdict(list)
    for k, group in enumerate((uni, holo)):
        for r in group:
            cells[r.scenario, r.planner, k].append(r)
    ttg = [
        statistics.fmean(r.time_to_goal_s for r in rs if r.outcome == "goal_reached")
        for rs in cells.values()
        if any(r.outcome == "goal_reached" for r in rs)
    ]
    speeds = [statistics.fmean(r.speed_mps for r in rs) for rs in cells.values()]
    closest = [statistics.fmean(r.min_distance_m for r in rs) for rs in cells.values()]
    horizon_s = 750 / 15
    head = (
        f"Every planner reaches the goal in all {per} episodes of either kinematics"
        if not failed
        else f"{len(failed)} of the {len(both)} episodes did not reach the goal ("
        + ", ".join(f"{r.planner} {r.scenario} seed {r.seed}: {r.outcome}" for r in failed[:10])
        + (", …" if len(failed) > 10 else "")
        + ")"
    )
    return (
        f"{head}; the slowest mean time to the goal is {max(ttg):.1f} s of the "
        f"{horizon_s:.0f} s horizon, at mean speeds of {min(speeds):.3f}–{max(speeds):.3f} m/s; "
        f"the mean closest approach is {min(closest):.2f}–{max(closest):.2f} m."
    )


def outcome_variants() -> str:
    results, manifest = outcome_run("variants")
    planners = list(manifest["planners"])
    scenarios = manifest["scenarios"]
    per = {p: [r for r in results if r.planner == p] for p in planners}
    parts = []
    for p in planners:
        mine = per[p]
        goal = sum(r.outcome == "goal_reached" for r in mine)
        means = [
            statistics.fmean(
                r.time_to_goal_s for r in mine if r.scenario == s and r.outcome == "goal_reached"
            )
            for s in scenarios
        ]
        parts.append(
            f"`{p}` reached the goal in {goal} of its {len(mine)} episodes, mean time to the "
            "goal " + ", ".join(f"{m:.2f}" for m in means) + " s"
        )
    return (
        _run_provenance("variants", manifest)
        + "\n\nWith "
        + ", ".join(f"`{o}`" for o in manifest["overrides"])
        + ": "
        + "; ".join(parts)
        + f" (scenarios in the order {', '.join(scenarios)})."
    )


def outcome_stress() -> str:
    results, manifest = outcome_run("a_robot_0")
    planners = list(manifest["planners"])
    counts: dict[tuple[str, str], collections.Counter[str]] = collections.defaultdict(
        collections.Counter
    )
    for r in results:
        counts[r.scenario, r.planner][r.outcome] += 1
    lines = [
        "| scenario | " + " | ".join(planners) + " |",
        "|---|" + "---|" * len(planners),
    ]
    oob = 0
    for s in manifest["scenarios"]:
        cells = []
        for p in planners:
            c = counts[s, p]
            n = sum(c.values())
            oob += c["out_of_bounds"]
            cells.append(
                " / ".join(
                    f"{100 * c[o] / n:.0f}" for o in ("goal_reached", "collision", "timeout")
                )
            )
        lines.append(f"| {s} | " + " | ".join(cells) + " |")
    n = len(results) // (len(planners) * len(manifest["scenarios"]))
    note = "no episode left the world" if oob == 0 else f"{oob} episodes left the world"
    return (
        _run_provenance("a_robot_0", manifest)
        + "\n\n"
        + "\n".join(lines)
        + f"\n\n(success / collision / timeout %, {n} seeds; {note}.)"
    )


# -- convergence in the time step --------------------------------------------------------


def convergence_tables() -> str:
    return "\n".join(convergence.table_lines(CONVERGENCE))


def convergence_verdict() -> str:
    """The verdict's numbers, from the same file."""
    v = convergence.summary(CONVERGENCE)
    worst = v["worst_mean"]
    by_scenario = v["worst_mean_by_scenario"]
    top = max(by_scenario, key=lambda s: by_scenario[s])
    others = {s: x for s, x in by_scenario.items() if s != top}
    second = max(others, key=lambda s: others[s])
    lows = v["mean_changes"][top]
    flips_top = v["flips"][top]
    return (
        f"**Verdict.** The planners' **mean deviations "
        + ("have converged" if worst <= convergence.THRESHOLD else "have not converged")
        + f"** at the default step: every one of the {v['n_means']} changes by at most "
        f"{100 * worst:.1f} % from dt to dt/4 ({100 * min(lows):.1f}–{100 * max(lows):.1f} % "
        f"in `{top}`, the largest; at most {100 * others[second]:.1f} % elsewhere, "
        f"`{second}`'s `{v['worst_mean_planner'][second]}`, "
        f"{v['worst_mean_value'][second]:.3f} m at dt, included). "
        + (
            "**The differences between planners have not, by the 5 % rule**: in "
            + (
                "every scenario"
                if len(v["over"]) == len(by_scenario)
                else ", ".join(f"`{s}`" for s in v["over"])
            )
            + f" some pair with a difference of at least {convergence.SMALL_M} m changes by "
            f"more than 5 % (up to {100 * v['worst_rel']:.0f} % in `{v['worst_rel_scenario']}`)"
            + (
                f", and in `{top}` {len(flips_top)} of the {v['pairs']} pairs change sign"
                if flips_top
                else ""
            )
            + f". These changes are small in metres (at most {v['worst_abs']:.3f} m) and "
            + (
                "none of them is larger than twice its standard error over the seeds"
                if v["systematic"] == 0
                else f"{v['systematic']} of them exceed twice their standard error over "
                "the seeds"
            )
            if v["over"]
            else "The differences between planners have converged too, by the 5 % rule"
        )
        + "."
    )


# -- noise floor, split, suite statistics ---------------------------------------------


def attribution_tables() -> str:
    doc = sets.read_json(ATTRIBUTION)
    return (
        f"*Data `docs/attribution/paper.json`: `{doc['source']}`.*\n\n"
        + "\n".join(attribution.table_lines(ATTRIBUTION)).strip()
    )


def _path(p: Path) -> str:
    return p.relative_to(sets.ROOT).as_posix()
