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


class MissingDataError(Exception):
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
        raise MissingDataError(
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
        f"{manifest['jobs']} workers" + (f" (load average {load[0]:.1f})" if load else "") + ".*"
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
    holo, _ = outcome_run("holonomic")
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
        "**Verdict.** The planners' **mean deviations "
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
                else f"{v['systematic']} of them exceed twice their standard error over the seeds"
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


# -- the scenario library's checks -----------------------------------------------------

SCENARIO_CHECKS = DOCS / "scenarios" / "checks.json"


def scenario_checks() -> str:
    """The issue-17 checks of every library scenario (tools/scenarios/check_scenarios.py)."""
    if not SCENARIO_CHECKS.is_file():
        raise MissingDataError(
            "`docs/scenarios/checks.json` (`python tools/scenarios/check_scenarios.py "
            "--json docs/scenarios/checks.json`)"
        )
    doc = sets.read_json(SCENARIO_CHECKS)
    lines = [
        f"*`{doc['command']}`: commit `{doc['commit']}`, "
        f"{doc['started'][:16].replace('T', ' ')} UTC, {doc['wall_s']:.0f} s on "
        f"{doc['cpus']} CPUs (1-min load {doc['load_average']:.1f} at the end).*",
        "",
        "| scenario | pedestrians arrived | in a wall | overlaps | robot goal (planner) |",
        "|---|---|---|---|---|",
    ]
    for name, r in doc["scenarios"].items():
        lines.append(
            f"| {name} | {r['ped_arrived']}/{r['ped_total']} | {r['in_wall_samples']} | "
            f"{r['overlapping_starts']} | {r['robot_goals']}/{r['seeds']} ({r['planner']})"
            + ("" if r["ok"] else " **FAIL**")
            + " |"
        )
    failed = [n for n, r in doc["scenarios"].items() if not r["ok"]]
    lines += [
        "",
        f"{len(doc['scenarios'])} scenarios × {next(iter(doc['scenarios'].values()))['seeds']} "
        "seeds: " + (f"{', '.join(failed)} fail a check." if failed else "every check passes."),
    ]
    return "\n".join(lines)


def _iv(x: dict[str, Any], digits: int) -> str:
    return f"{x['estimate']:.{digits}f} [{x['low']:.{digits}f}, {x['high']:.{digits}f}]"


def attribution_findings() -> str:
    """What the attribution tables say, each number from docs/attribution/paper.json."""
    doc = sets.read_json(ATTRIBUTION)
    planners: list[str] = doc["planners"]
    refs = ("oracle", "stay")
    default = [p for p in planners if p not in refs]
    scen: dict[str, Any] = doc["scenarios"]
    n_pairs = len(planners) * (len(planners) - 1) // 2
    verdicts = {s: e["floor"]["verdict"] for s, e in scen.items()}
    top = max(scen, key=lambda s: scen[s]["floor"]["share"])
    rest = [s for s in scen if s != top]
    f_top = scen[top]["floor"]
    shares = [100 * scen[s]["floor"]["share"] for s in rest]
    top_means = [scen[top]["frechet_m"][p] for p in default]
    measures = (
        "**Every paper scenario measures the robot**"
        if all(v == "robot" for v in verdicts.values())
        else "**Not every paper scenario measures the robot** ("
        + ", ".join(f"`{s}`: {v}" for s, v in verdicts.items() if v != "robot")
        + ")"
    )
    b1 = (
        f"- {measures}, by the floor's share of the deviation: a 1 mm nudge moves the crowd "
        f"by {min(shares):.1f}–{max(shares):.1f} % of what the planners do in "
        + ", ".join(f"`{s}`" for s in rest)
        + f", and by {100 * f_top['share']:.1f} % in `{top}` (mean {f_top['mean']:.3f} m; "
        f"{max(f_top['values']):.2f} m in the worst seed). `{top}` is the chaotic one, but "
        f"its {min(top_means):.2f}–{max(top_means):.2f} m of the {len(default)} default "
        "planners are not chaos: the crowd does not move that far without the robot's push."
    )
    below = scen[top]["not_attributable"]
    below_pairs = {frozenset((a, b)) for a, b, _ in below}
    default_pairs = {frozenset((a, b)) for i, a in enumerate(default) for b in default[i + 1 :]}
    exactly = below_pairs == default_pairs
    spread_means = max(top_means) - min(top_means)
    others = {s: scen[s]["not_attributable"] for s in rest}
    counts = [len(v) for v in others.values()]
    largest = max((abs(d) for v in others.values() for _, _, d in v), default=0.0)
    b2 = (
        f"- **The differences between planners in `{top}` are the crowd's chaos**: its "
        f"floor's spread ({f_top['std']:.3f} m over the seeds) is larger than "
        f"{len(below)} of the {n_pairs} differences of mean deviation between the "
        f"{len(planners)} planners there"
        + (
            f": exactly the {len(default_pairs)} pairs of the {len(default)} default "
            f"planners, whose means lie within {spread_means:.3f} m of each other. Only the "
            "differences to " + " and ".join(f"`{r}`" for r in refs) + " are attributable there."
            if exactly
            else "."
        )
        + f" In the other scenarios {min(counts)}–{max(counts)} of the {n_pairs} pairs are "
        f"below the spread, pairs whose means differ by at most {largest:.4f} m."
    )
    goers = [(s, p) for s in scen for p in planners if scen[s]["goal"][p] > 0 and p != "stay"]
    knock = max(scen[s]["split"][p]["frechet_knock_on_m"]["mean"] for s, p in goers)
    felt = [scen[s]["split"][p]["pedestrians_felt"]["mean"] for s, p in goers]
    stay_out = [
        (s, scen[s]["split"]["stay"])
        for s in scen
        if scen[s]["split"]["stay"]["frechet_knock_on_m"]["mean"] > 0
    ]
    b3 = (
        f"- **There is no knock-on deviation to speak of at {doc['felt_force_mps2']:g} m/s²**: "
        f"for every planner that drives to its goal at most {knock:.3f} m of the deviation "
        f"is knock-on, and {min(felt):.1f}–{max(felt):.1f} pedestrians a scene felt the robot"
        + (
            "; only `stay`, which never moves, leaves pedestrians of "
            + " and ".join(
                f"`{s}` out of its reach ({x['pedestrians_felt']['mean']:.1f} felt it; "
                f"{x['frechet_knock_on_m']['mean']:.3f} m knock-on)"
                for s, x in stay_out
            )
            if stay_out
            else ""
        )
        + "."
    )
    suite = doc["suite"]
    dev = suite["deviation_iqm"]
    deployable = [p for p in default if p != "straight"] + ["straight"]
    best = min(deployable, key=lambda p: dev[p]["estimate"])
    rivals = [p for p in deployable if p != best]
    imp = suite["improvement"][best]
    p_vs = [imp[p]["estimate"] for p in rivals]
    score = suite["score_iqm"]
    best_score = score.get(best) or {}
    named = doc["score_scenarios"].get(best, [])
    missing = [s for s in scen if s not in named]
    other_scores = [
        score[p]["estimate"] for p in rivals if score.get(p) and score[p]["estimate"] is not None
    ]
    above = [s for s in scen if scen[s]["beats_oracle"]]
    n_eps = dev[best]["n"]
    rival_iqm = [dev[p]["estimate"] for p in rivals]
    b4 = (
        f"- **Suite aggregates**: over the {n_eps} (scenario, seed) episodes `{best}` has the "
        f"lowest IQM deviation of the deployable planners, {_iv(dev[best], 3)} m, against "
        f"{min(rival_iqm):.3f}–{max(rival_iqm):.3f} m "
        f"for the others (`oracle` {dev['oracle']['estimate']:.3f}, `stay` "
        f"{dev['stay']['estimate']:.3f}), and it deviates a person less than each of them with "
        f"probability {min(p_vs):.2f}–{max(p_vs):.2f}."
        + (
            f" Its IQM normalised score, {_iv(best_score, 2)}, is over {len(named)} scenarios"
            + (
                "; in "
                + ", ".join(
                    f"`{s}` it reached the goal in {scen[s]['goal'][best]} of "
                    f"{scen[s]['floor']['n']} seeds, so its score there is undefined"
                    for s in missing
                )
                if missing
                else ""
            )
            + "."
            if best_score.get("estimate") is not None
            else ""
        )
        + (
            f" Every other deployable planner's IQM score is {min(other_scores):.2f}–"
            f"{max(other_scores):.2f}."
            if other_scores
            else ""
        )
        + (
            " No planner scored above 1, so every headroom is the oracle's (none is a lower "
            "bound in this run)."
            if not above
            else f" In {', '.join(above)} a planner beat the oracle: the headroom is a lower bound."
        )
    )
    return "\n".join([b1, b2, b3, b4])
