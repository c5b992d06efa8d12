"""Every generated block of the docs, from the committed results sets (``make docs-tables``).

    .venv/bin/python tools/results/generate.py           # rewrite every block in docs/
    .venv/bin/python tools/results/generate.py --check   # exit 1 naming each stale block

A block is the text between ``<!-- generated: NAME -->`` and ``<!-- end: NAME -->`` in
any page under docs/ or the README; ``BLOCKS`` maps NAME to the function that writes it
from the sets of ``docs/results/`` (``tools/results/sets.py``) and other committed data. Nothing is
simulated: the whole run reads Parquet and JSON files (the test
``tests/docs/test_generated.py`` runs ``--check`` in ``make test``, so a hand-edited
number fails). A block whose set is not committed says so, with the command that makes
it. Every table carries its provenance: the set, when and on which commit it was
measured, its wall time, its command, planners, parameters and policies.

Whole files that a run tool writes in full (``FILES``: path -> text, e.g.
docs/real_encounters/tables.md) are rewritten and checked the same way, by the
function the tool writes them with (the figures: ``tools/results/figures.py``).
"""

from __future__ import annotations

import argparse
import math
import re
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

import numpy as np

from srfm.benchmark._models import robustness_markdown, robustness_of_values
from srfm.metrics.headroom import seeds_needed, sigma_d
from srfm.metrics.stats import summarize
from srfm.metrics.tables import (
    TABLE_COLUMNS,
    benchmark_table,
    summary_dict,
    to_markdown,
)
from srfm.models.params import PRESETS, SRFMParams, response_model_name
from srfm.scenarios.suites import SUITES
from tools.analysis import compare_presets, discrimination, paper_table3, suite_summary
from tools.results import (
    audit_a_pages,
    audit_b_pages,
    encounters_text,
    fitting_pages,
    fitting_text,
    io_pages,
    performance_pages,
    planner_pages,
    readme_pages,
    response_pages,
    rl_study,
    sensitivity,
    sets,
    whole_files,
)
from tools.results import pages as data_pages

DOCS = sets.ROOT / "docs"
BEGIN = re.compile(r"<!-- generated: ([a-z0-9-]+) -->\n")
END = "<!-- end: {name} -->"
SEVEN = ("dwa", "orca", "social-force", "straight", "td3-base", "td3-srfm", "vo")


class MissingError(Exception):
    """A results set a block needs is not committed."""


def _need(*names: str) -> None:
    missing = [n for n in names if not sets.exists(n)]
    if missing:
        raise MissingError(
            " and ".join(f"`{n}` (`python tools/results/run.py {n}`)" for n in missing)
        )


def _preset(params: dict[str, Any]) -> str:
    for name, preset in PRESETS.items():
        if preset.as_dict() == params:
            return f"`{name}`"
    return "custom parameters"


def _minutes(seconds: float) -> str:
    return f"{seconds / 60:.0f} min" if seconds >= 90 else f"{seconds:.0f} s"


def provenance(name: str) -> str:
    """One line: what a set is, when and how it was measured."""
    m = sets.manifest(name)
    rs = m["results_set"]
    req = m["request"]
    seeds = req["seeds"]
    p = m["params"]
    pol = rs["policies_weights_sha256"]
    policies = ", ".join(f"`{k}` weights {v[:12]}" for k, v in pol.items())
    return (
        f"*Results set [`{name}`]({_link(name)}): {rs['episodes']:,} episodes, measured "
        f"{rs['started'][:16].replace('T', ' ')}–{rs['finished'][11:16]} UTC on commit "
        f"`{rs['commit']}` ({_minutes(rs['wall_s'])} of wall time with {rs['jobs']} "
        f"workers; {rs['machine']}); "
        f"`{rs['command']}`; planners {', '.join(req['planners'])}; seeds "
        f"{seeds[0]}–{seeds[-1]}; parameters {_preset(p)} (A_r = {p['a_robot']:g} m/s², "
        f"B_r = {p['b_robot']:g} m); policies: {policies}.*"
    )


_PAGE: Path = DOCS / "index.md"


def _link(name: str) -> str:
    """A relative link from the page being written to a set's manifest."""
    target = sets.SETS[name].folder / sets.MANIFEST
    rel = Path(*([".."] * len(_PAGE.parent.relative_to(DOCS).parts))) / target.relative_to(DOCS)
    return rel.as_posix()


def _table(name: str, *, reference: str | None, columns: Any = TABLE_COLUMNS) -> Any:
    m = sets.manifest(name)
    req = m["request"]
    return benchmark_table(
        sets.episodes(name),
        scenarios=req["scenarios"],
        planners=req["planners"],
        seeds=req["seeds"],
        reference=reference,
        columns=columns,
        correction="holm",
    )


# -- the blocks -----------------------------------------------------------------------


def sets_index() -> str:
    """Every results set: episodes, size, command, when, wall time."""
    lines = [
        "| set | episodes | size (MB) | measured (UTC) | commit | wall time (workers) | command |",
        "|---|--:|--:|---|---|--:|---|",
    ]
    total = 0
    for name, rset in sets.SETS.items():
        if not sets.exists(name):
            lines.append(f"| `{name}` | – | – | not committed | – | – | `{rset.command()}` |")
            continue
        rs = sets.manifest(name)["results_set"]
        size = sets.folder_bytes(name)
        total += size
        lines.append(
            f"| [`{name}`]({_link(name)}) | {rs['episodes']:,} | {size / 1e6:.2f} | "
            f"{rs['started'][:16].replace('T', ' ')} | `{rs['commit']}` | "
            f"{_minutes(rs['wall_s'])} ({rs['jobs']}) | `{rs['command']}` |"
        )
    lines += [
        "",
        f"All sets together: {total / 1e6:.2f} MB of the budget of "
        f"{sets.BUDGET_BYTES / 1e6:.1f} MB.",
    ]
    return "\n".join(lines)


def paper_table3_block() -> str:
    _need("paper")
    table = _table("paper", reference="td3-srfm")
    lines = paper_table3.lines(summary_dict(table))
    return provenance("paper") + "\n\n" + "\n".join(lines)


def paper_full() -> str:
    _need("paper")
    table = _table("paper", reference="td3-srfm")
    return provenance("paper") + "\n\n" + to_markdown(table).strip()


def _outcome_sentence(name: str, planners: tuple[str, ...] | None = None) -> str:
    """Which planners reached the goal in every episode, and the others' outcomes."""
    t = sets.table(name)
    rows = list(zip(*(t[c].to_pylist() for c in ("scenario", "planner", "outcome")), strict=True))
    req = sets.manifest(name)["request"]
    chosen = planners or tuple(req["planners"])
    always, parts = [], []
    for p in chosen:
        mine = [(s, o) for s, q, o in rows if q == p]
        misses: dict[str, dict[str, int]] = {}
        for s, o in mine:
            if o != "goal_reached":
                misses.setdefault(s, {}).setdefault(o, 0)
                misses[s][o] += 1
        if not misses:
            always.append(f"`{p}`")
            continue
        text = "; ".join(
            f"{s}: " + ", ".join(f"{k} {v.replace('_', ' ')}" for v, k in sorted(c.items()))
            for s, c in misses.items()
        )
        parts.append(f"`{p}` ({text})")
    n = len(req["seeds"])
    head = (
        f"Reached the goal in all {n} seeds of every scenario: {', '.join(always)}."
        if always
        else ""
    )
    tail = (" Episodes that did not: " + "; ".join(parts) + ".") if parts else ""
    return (head + tail).strip()


def paper_outcomes() -> str:
    _need("paper")
    return _outcome_sentence("paper")


def _rows(name: str) -> list[dict[str, Any]]:
    """Discrimination rows (reference points per scenario) of a set with straight and
    oracle."""
    req = sets.manifest(name)["request"]
    return _disc_rows([name], req["scenarios"])


def _disc_rows(names: list[str], scenarios: list[str]) -> list[dict[str, Any]]:
    cells: dict[tuple[str, str], dict[int, dict[str, float]]] = {}
    planners: list[str] = []
    for name in names:
        for (s, p), by_seed in sets.frechet(name).items():
            cells[s, p] = {
                k: {"frechet_m": v, "success": float(o == "goal_reached")}
                for k, (v, o) in by_seed.items()
            }
        planners += [p for p in sets.manifest(name)["request"]["planners"] if p not in planners]
    ordered = [p for p in discrimination.PLANNERS if p in planners]
    return discrimination.measure(cells, list(scenarios), ordered)


def paper_references() -> str:
    _need("paper")
    rows = _rows("paper")
    return (
        discrimination.table(rows, selection=False)
        + "\n\nNormalised scores (0: `straight`, 1: the oracle) with their 95 % paired-"
        "bootstrap intervals, over all episodes (failures included):\n\n"
        + discrimination.scores_table(rows)
    )


def _suite_means(name: str, without: list[str]) -> str:
    t = sets.table(name)
    cols = {c: t[c].to_pylist() for c in ("scenario", "planner", "frechet_m", "outcome")}
    rows = [
        {
            "scenario": s,
            "planner": p,
            "frechet_m": "" if v is None else repr(v),
            "robot_success": str(float(o == "goal_reached")),
            "robot_collision": str(float(o == "collision")),
        }
        for s, p, v, o in zip(
            cols["scenario"], cols["planner"], cols["frechet_m"], cols["outcome"], strict=True
        )
    ]
    return "\n".join(suite_summary.summary(rows, without=without, success=True)[2:])


def francis_references() -> str:
    _need("francis")
    return provenance("francis") + "\n\n" + discrimination.table(_rows("francis"), selection=False)


def francis_means() -> str:
    _need("francis")
    return _suite_means("francis", ["narrow_hallway"])


def francis_scores() -> str:
    _need("francis")
    return discrimination.scores_table(_rows("francis"))


def francis_outcomes() -> str:
    _need("francis")
    return _outcome_sentence("francis")


def francis_full() -> str:
    _need("francis")
    table = _table("francis", reference="straight")
    return to_markdown(table).strip()


def navwareset_references() -> str:
    _need("navwareset")
    rows = _rows("navwareset")
    return (
        provenance("navwareset")
        + "\n\n"
        + discrimination.table(rows, selection=False)
        + "\n\n"
        + discrimination.means_table(rows)
    )


def flows_table() -> str:
    _need("flows")
    table = _table("flows", reference="td3-srfm")
    return (
        provenance("flows")
        + "\n\n"
        + to_markdown(table).strip()
        + "\n\n"
        + _outcome_sentence("flows")
    )


def nws2025_issue15_table() -> str:
    """The paper's benchmark with navwareset2025 as issue 15 fitted it (docs/fitting.md):
    success / collision rate / mean Fréchet deviation per planner and scenario."""
    name = "paper_nws2025_issue15"
    _need(name)
    req = sets.manifest(name)["request"]
    t = sets.table(name)
    cols = {c: t[c].to_pylist() for c in ("scenario", "planner", "outcome", "frechet_m")}
    cells: dict[tuple[str, str], list[tuple[str, float | None]]] = {}
    for s, p, o, v in zip(*cols.values(), strict=True):
        cells.setdefault((s, p), []).append((o, v))
    lines = [
        provenance(name),
        "",
        f"Success / robot collision rate / mean Fréchet deviation (m) over seeds "
        f"{req['seeds'][0]}–{req['seeds'][-1]} (n = {len(req['seeds'])} per cell):",
        "",
        "| planner | " + " | ".join(req["scenarios"]) + " |",
        "|---|" + "---|" * len(req["scenarios"]),
    ]
    for p in sorted(req["planners"]):
        row = []
        for s in req["scenarios"]:
            eps = cells[s, p]
            goal = sum(o == "goal_reached" for o, _ in eps) / len(eps)
            hit = sum(o == "collision" for o, _ in eps) / len(eps)
            dev = summarize(np.array([np.nan if v is None else v for _, v in eps])).mean
            row.append(f"{goal:.2f} / {hit:.2f} / {dev:.3f}")
        lines.append(f"| {p} | " + " | ".join(row) + " |")
    hits = {
        sc: sum(o == "collision" for o, _ in cells[sc, "straight"]) / len(req["seeds"])
        for sc in req["scenarios"]
    }
    often = [h for h in hits.values() if h >= 0.5]
    means = {
        k: summarize(np.array([np.nan if v is None else v for _, v in eps])).mean
        for k, eps in cells.items()
    }
    circle = max(m for (sc, _), m in means.items() if sc == "circle")
    rest = max(m for (sc, _), m in means.items() if sc != "circle")
    lines += [
        "",
        f"`straight` collides in {100 * min(often):.0f}–{100 * max(often):.0f} % of the "
        f"episodes of {len(often)} scenarios; the mean deviation of any planner is at most "
        f"{circle:.2f} m in `circle` and {rest:.2f} m elsewhere.",
    ]
    return "\n".join(lines)


def _preset_block(a: str, b: str) -> str:
    _need(a, b)
    ma, scen, planners, _ = compare_presets.means_of_rows(_csv_rows(a), frozenset(SEVEN), a)
    mb, scen_b, planners_b, _ = compare_presets.means_of_rows(_csv_rows(b), frozenset(SEVEN), b)
    if (scen, planners) != (scen_b, planners_b):
        raise SystemExit(f"{a} and {b} hold different scenarios or planners")
    lines = compare_presets.comparison(
        ma, mb, scen, planners, ("agrawal2024", "navwareset2026_ttc")
    )
    return provenance(a) + "\n\n" + provenance(b) + "\n\n" + "\n".join(lines)


def _csv_rows(name: str) -> list[dict[str, str]]:
    t = sets.table(name)
    return [
        {"scenario": s, "planner": p, "frechet_m": "" if v is None else repr(v)}
        for s, p, v in zip(
            *(t[c].to_pylist() for c in ("scenario", "planner", "frechet_m")), strict=True
        )
    ]


def presets_paper() -> str:
    return _preset_block("paper", "paper_ttc")


def presets_francis() -> str:
    return _preset_block("francis", "francis_ttc")


def _robustness_block(names: tuple[str, ...]) -> str:
    """Which orderings of the seven default planners hold under every response model:
    the same episodes of a suite under each model, one committed set per model
    (srfm.benchmark.robustness_of_values, as `srfm benchmark --params A,B,C` computes
    them in one run)."""
    _need(*names)
    request = sets.manifest(names[0])["request"]
    scenarios, seeds = list(request["scenarios"]), list(request["seeds"])
    models = []
    for name in names:
        other = sets.manifest(name)
        if other["request"]["scenarios"] != scenarios or other["request"]["seeds"] != seeds:
            raise SystemExit(f"{names[0]} and {name} hold different scenarios or seeds")
        models.append(response_model_name(SRFMParams(**other["params"])))
    cells = [sets.frechet(name) for name in names]
    values = np.array(
        [[[sets.frechet_array(c, s, p, seeds) for p in SEVEN] for s in scenarios] for c in cells]
    )
    table = robustness_of_values(
        values, models=models, scenarios=scenarios, planners=SEVEN, n_seeds=len(seeds)
    )
    provenances = "\n\n".join(provenance(name) for name in names)
    return provenances + "\n\n" + robustness_markdown(table, level=3)


def robustness_paper() -> str:
    return _robustness_block(("paper", "paper_ttc", "paper_nws2025"))


def robustness_francis() -> str:
    return _robustness_block(("francis", "francis_ttc", "francis_nws2025"))


def _rank_table() -> Any:
    _need("draws")
    return sets.rank_table_of("draws")


def rankings_summary() -> str:
    table = _rank_table()
    base = sets.frechet("draws")
    seeds = sets.manifest("draws")["request"]["seeds"]
    lines = [
        provenance("draws"),
        "",
        f"P(ranked first) [95 % Monte-Carlo interval over the {table.n_draws} draws] / "
        f"expected rank (1–{len(table.planners)}), by mean Fréchet deviation over seeds "
        f"{seeds[0]}–{seeds[-1]}; last column: the order at the run's own parameters:",
        "",
        "| scenario | " + " | ".join(table.planners) + " | order at the base parameters |",
        "|---|" + "--:|" * len(table.planners) + "---|",
    ]
    for s in table.scenarios:
        cells = []
        for p in table.planners:
            probs = table.probabilities[s][p]
            low, high = table.probability_interval(s, p, 1)
            expected = sum((r + 1) * v for r, v in enumerate(probs))
            cells.append(f"{probs[0]:.2f} [{low:.2f}, {high:.2f}] / {expected:.1f}")
        base_means = {
            p: summarize(sets.frechet_array(base, s, p, seeds)).mean for p in table.planners
        }
        order = sorted(table.planners, key=lambda p: base_means[p])
        lines.append(f"| {s} | " + " | ".join(cells) + " | " + ", ".join(order) + " |")
    return "\n".join(lines)


def rankings_intervals() -> str:
    table = _rank_table()
    lines = [
        "| scenario | planner | P(1st) [95 %] | P(last) [95 %] | Fréchet over the draws (m): "
        "2.5 % · median · 97.5 % |",
        "|---|---|--:|--:|--:|",
    ]
    last = len(table.planners)
    for s in table.scenarios:
        for p in table.planners:
            probs = table.probabilities[s][p]
            f_low, f_high = table.probability_interval(s, p, 1)
            l_low, l_high = table.probability_interval(s, p, last)
            low, mid, high = table.interval(s, p)
            lines.append(
                f"| {s} | {p} | {probs[0]:.2f} [{f_low:.2f}, {f_high:.2f}] | "
                f"{probs[-1]:.2f} [{l_low:.2f}, {l_high:.2f}] | "
                f"{low:.3f} · {mid:.3f} · {high:.3f} |"
            )
    return table.description + ".\n\n" + "\n".join(lines)


def _suite_change(suite: list[str]) -> str:
    shipped = list(SUITES["discriminative"])
    entered = [s for s in suite if s not in shipped]
    left = [s for s in shipped if s not in suite]
    if not entered and not left:
        return "the suite shipped as `discriminative`"
    return (
        f"against the suite shipped as `discriminative`, entered: "
        f"{', '.join(f'`{s}`' for s in entered) or 'none'}; left: "
        f"{', '.join(f'`{s}`' for s in left) or 'none'}"
    )


def selection_table() -> str:
    if not sets.exists("selection"):
        doc = sets.read_json(DOCS / "discrimination" / "selection.json")
        rows = doc["scenarios"]
        suite = list(doc["suite"])
        head = (
            "*Not measured again with the shipped entries yet (results set `selection`: "
            "`python tools/results/run.py selection`). The selection that chose the "
            "shipped suite, measured on 2026-11-27 with the entries of then (the TD3 "
            "planners were the paper-observation policies), from "
            "`docs/discrimination/selection.json`"
            + (f"; not complete then: {', '.join(doc['incomplete'])}" if doc["incomplete"] else "")
            + ":*"
        )
    else:
        rows = _rows("selection")
        suite = discrimination.select(rows)
        head = provenance("selection")
    qualified = sum(not r["fails"] for r in rows)
    text = (
        head
        + "\n\n"
        + discrimination.table(rows, selection=True)
        + f"\n\n{qualified} of the {len(rows)} candidates qualify; the rule chooses "
        + ", ".join(f"`{s}`" for s in suite)
        + f" ({_suite_change(suite)})."
    )
    if sets.exists("selection") and sets.exists("selection_flow"):
        text += "\n\n" + _flow_condition_d()
    return text


def _flow_condition_d() -> str:
    """corridor_flow against condition (d), which does not involve the oracle."""
    req = sets.manifest("selection_flow")["request"]
    cells = sets.frechet("selection_flow")
    values = {
        p: sets.frechet_array(cells, "corridor_flow", p, req["seeds"]) for p in req["planners"]
    }
    sd = sigma_d(values)
    needed = seeds_needed(sd)
    verdict = (
        "fails (d) whatever the oracle would do, so it cannot enter the suite"
        if needed > discrimination.MAX_SEEDS
        else "meets (d); whether it qualifies would need the oracle's episodes"
    )
    return (
        provenance("selection_flow")
        + f"\n\n`corridor_flow`, the one candidate not above (its oracle costs tens of "
        f"seconds an episode), measured without the oracle on the same seeds: σ_d = "
        f"{sd:.3f} m over the pairs of its {len(req['planners']) - 2} non-reference "
        f"planners, {needed:,} seeds to detect 0.05 m: it {verdict}."
    )


def discriminative_tables() -> str:
    _need("francis", "navwareset")
    suite = list(SUITES["discriminative"])
    names = [n for n in ("francis", "navwareset", "paper") if sets.exists(n)]
    available = {s for n in names for s in sets.manifest(n)["request"]["scenarios"]}
    missing = [s for s in suite if s not in available]
    if missing:
        raise MissingError(f"with the scenarios {', '.join(missing)}")
    rows = _disc_rows(names, suite)
    failing = [r for r in rows if discrimination._qualifies(r)]
    verdict = (
        "Every one of them meets the rule's conditions (a)–(d) on these seeds too."
        if not failing
        else "On these seeds "
        + "; ".join(
            f"`{r['scenario']}` fails ({', '.join(discrimination._qualifies(r))})"
            + (f": {r['seeds_needed']:,} seeds for 0.05 m" if r["seeds_needed"] else "")
            for r in failing
        )
        + f"; the other {len(rows) - len(failing)} meet (a)–(d)."
    )
    return (
        f"The suite `discriminative` ({', '.join(f'`{s}`' for s in suite)}) on seeds 0–99, "
        f"from the sets {', '.join(f'`{n}`' for n in names)}. {verdict}\n\n"
        + discrimination.table(rows, selection=False)
        + "\n\nFréchet deviation per planner (m, mean ± SD over seeds, all episodes; in "
        "brackets the share of episodes that reached the goal):\n\n"
        + discrimination.means_table(rows)
        + "\n\nNormalised score (0 = `straight`, 1 = the oracle; [95 % paired-bootstrap "
        "interval]):\n\n" + discrimination.scores_table(rows)
    )


def oracle_cost() -> str:
    """The oracle's CPU time per episode (docs/discrimination/oracle_cost*.json, written
    by ``tools/analysis/discrimination.py cost``) and its goal rate in the sets."""
    rows = [
        "| suite | scenario | CPU s / episode, mean (max), seeds 0–19 | oracle reached the "
        "goal, seeds 0–99 |",
        "|---|---|--:|--:|",
    ]
    notes = []
    for suite, file, name in (
        ("paper", "oracle_cost.json", "paper"),
        ("francis", "oracle_cost_francis.json", "francis"),
    ):
        doc = sets.read_json(DOCS / "discrimination" / file)
        if "scenarios" not in doc:  # written before the file kept its provenance
            doc = {"scenarios": doc}
            notes.append(
                f"`docs/discrimination/{file}`: no provenance recorded (measured "
                "2026-11-27 while two RL trainings held both cores)"
            )
        else:
            loads = doc["load_average"] or [math.nan]
            notes.append(
                f"`{doc['command']}`: commit `{doc['commit']}`, started "
                f"{doc['started'][:16].replace('T', ' ')} UTC, {doc['cpus']} CPUs, 1-min load "
                f"{min(loads):.1f}–{max(loads):.1f}"
            )
        cells = sets.frechet(name) if sets.exists(name) else {}
        for scenario, entry in doc["scenarios"].items():
            by_seed = cells.get((scenario, "oracle"), {})
            reached = sum(o == "goal_reached" for _, o in by_seed.values())
            goal = f"{100 * reached / len(by_seed):.0f} %" if by_seed else "–"
            rows.append(
                f"| {suite} | {scenario} | {entry['mean_s']:.2f} ({entry['max_s']:.2f}) | {goal} |"
            )
    return "*Measured by " + "; ".join(notes) + ".*\n\n" + "\n".join(rows)


PERFORMANCE_GOALS = DOCS / "results" / "performance" / "goals.json"
# Issue 39's speed goals: (row of the measurement, label, the figure, the goal, at least?)
SPEED_GOALS: tuple[tuple[str, str, str, float, bool], ...] = (
    (
        "full",
        "`srfm benchmark` (seeds 0-99, 7 planners, 3,500 episodes, default logs), wall s",
        "wall_s",
        60.0,
        False,
    ),
    (
        "simulate",
        "`srfm simulate --scenario crosswalk --seed 0 --planner dwa` (warm cache), wall s",
        "wall_s",
        1.0,
        False,
    ),
    (
        "shared-crowd",
        "crowd step at N = 1,000, srfm / JuPedSim agent-steps per s",
        "1000",
        3.0,
        True,
    ),
    (
        "shared-crowd",
        "crowd step at N = 10,000, srfm / JuPedSim agent-steps per s",
        "10000",
        3.5,
        True,
    ),
)


def _figures(row: dict[str, Any], figure: str) -> list[float]:
    runs = row["runs"]["A"]
    if figure.isdigit():
        return [r[f"srfm_{figure}"] / r[f"jupedsim_{figure}"] for r in runs]
    return [float(r[figure]) for r in runs]


def performance_goals() -> str:
    """Issue 39's speed goals beside the figures of the committed measurement."""
    return performance_goals_table(sets.read_json(PERFORMANCE_GOALS))


def _met(median: float, goal: float, at_least: bool) -> bool:
    """Whether a speed goal is met by the median of its runs."""
    return median >= goal if at_least else median <= goal


def performance_goals_table(doc: dict[str, Any]) -> str:
    """The goal table of one ``bench_commands.py --json`` record (tree A's runs)."""
    lines = [
        f"Measured {doc['date']} on commit `{doc['commits']['A']}`, {doc['cores']} cores "
        f"({doc['cpu']}): `{doc['command']}`; median (min–max) of the runs, the load "
        "average (1/5/15 min) before and after each row.",
        "",
        "| what | runs | median (min–max) | goal | verdict | load |",
        "|---|--:|---|---|---|---|",
    ]
    for row_name, label, figure, goal, at_least in SPEED_GOALS:
        row = doc["rows"].get(row_name)
        if row is None:
            lines.append(
                f"| {label} | 0 | not measured | {'≥' if at_least else '≤'} {goal:g} | – | – |"
            )
            continue
        values = _figures(row, figure)
        median = float(np.median(values))
        met = _met(median, goal, at_least)
        unit = "×" if at_least else " s"
        lines.append(
            f"| {label} | {len(values)} | {median:.2f}{unit} ({min(values):.2f}–{max(values):.2f}) "
            f"| {'≥' if at_least else '≤'} {goal:g}{unit} | {'**met**' if met else 'not met'} "
            f"| {row['load_before']} → {row['load_after']} |"
        )
    return "\n".join(lines)


def readme_speed() -> str:
    """The README's line on speed: each goal's verdict on the committed measurement."""
    doc = sets.read_json(PERFORMANCE_GOALS)
    verdicts = []
    for row_name, _, figure, goal, at_least in SPEED_GOALS:
        row = doc["rows"].get(row_name)
        median = float(np.median(_figures(row, figure))) if row else math.nan
        verdicts.append(_met(median, goal, at_least))
    full, simulate, crowd_1k, crowd_10k = verdicts
    goals = {name: goal for name, _, _, goal, _ in SPEED_GOALS}

    def within(ok: bool) -> str:
        return "within" if ok else "not within"

    crowd = (
        "beats JuPedSim's social force model on the same crowd by more than the goals"
        if crowd_1k and crowd_10k
        else "does not beat JuPedSim's social force model on the same crowd by both goals"
    )
    n_1k, n_10k = (SPEED_GOALS[k][3] for k in (2, 3))
    return fitting_pages.prose(
        "- A one-off command pays for importing numba and loading its compiled kernels, and "
        "the very first run compiles them. On two idle cores of the developers' machine "
        f"({doc['date'][:10]}, [Speed goals](docs/performance.md#speed-goals)) `srfm simulate` "
        f"is {within(simulate)} its goal of {goals['simulate']:g} s, the full 3,500-episode "
        f"benchmark {within(full)} its goal of {goals['full']:g} s, and the crowd step "
        f"{crowd} of {n_1k:g}× at 1,000 pedestrians and {n_10k:g}× at 10,000. Crowds of "
        "hundreds or thousands step in O(N) with an interaction cut-off."
    )


PERFORMANCE_VS = DOCS / "results" / "performance" / "vs-fe28b0b.json"


def performance_vs() -> str:
    """Two checkouts timed in turn on one machine (``bench_commands.py --vs``)."""
    doc = sets.read_json(PERFORMANCE_VS)
    lines = [
        f"Measured {doc['date']}, {doc['cores']} cores ({doc['cpu']}): "
        f"A = `{doc['commits']['A']}`, B = `{doc['commits']['B']}`, run in turn: "
        f"`{doc['command']}`; median (min–max).",
        "",
        "| what | runs each | A | B | A / B (medians) | load |",
        "|---|--:|---|---|--:|---|",
    ]
    for row_name, label, figure, _, at_least in SPEED_GOALS:
        row = doc["rows"].get(row_name)
        if row is None:
            continue
        a = _figures(row, figure)
        b = _figures({"runs": {"A": row["runs"]["B"]}}, figure)
        unit = "×" if at_least else " s"

        def spread(v: list[float], unit: str = unit) -> str:
            return f"{float(np.median(v)):.2f}{unit} ({min(v):.2f}–{max(v):.2f})"

        lines.append(
            f"| {label} | {len(a)} | {spread(a)} | {spread(b)} "
            f"| {float(np.median(a)) / float(np.median(b)):.3f} "
            f"| {row['load_before']} → {row['load_after']} |"
        )
    return "\n".join(lines)


def _vs_medians(row: dict[str, Any], figure: str) -> tuple[float, float]:
    """The medians of checkout A and of checkout B in one row of a ``--vs`` record."""
    a = _figures(row, figure)
    b = _figures({"runs": {"A": row["runs"]["B"]}}, figure)
    return float(np.median(a)), float(np.median(b))


def performance_vs_reading() -> str:
    """What the before-and-after record says of the commands' wall times."""
    doc = sets.read_json(PERFORMANCE_VS)
    gaps = [
        abs(1.0 - a / b) * 100
        for a, b in (_vs_medians(doc["rows"][name], "wall_s") for name in ("full", "simulate"))
    ]
    return fitting_pages.prose(
        f"The code of `{doc['commits']['B']}` (the last figures on an idle machine before "
        f"this page's, 2026-11-27), timed in turn with `{doc['commits']['A']}` on one machine "
        f"({doc['date'][:10]}), takes within {min(gaps):.0f}–{max(gaps):.0f} % of its wall "
        "time for `srfm benchmark` and `srfm simulate` (block below): most of the difference "
        "from the figures of 2026-11-27 is the machine, not the code, and a slower machine "
        "can miss the command goals that this one meets (the old figures: "
        "[history](history/performance.md#speed-goals-as-read-on-2026-12-05))."
    )


def performance_crowd_change() -> str:
    """The crowd step against JuPedSim before (``--vs`` record) and after (goals)."""
    before = sets.read_json(PERFORMANCE_VS)["rows"]["shared-crowd"]
    after = sets.read_json(PERFORMANCE_GOALS)["rows"]["shared-crowd"]
    parts = []
    for _, _, figure, goal, _ in (g for g in SPEED_GOALS if g[2].isdigit()):
        n = int(figure)
        was = _figures(before, figure) + _figures({"runs": {"A": before["runs"]["B"]}}, figure)
        now = _figures(after, figure)
        parts.append(
            f"{min(was):.1f}–{max(was):.1f}× before, {min(now):.1f}–{max(now):.1f}× after, "
            f"at N = {n:,} (goal {goal:g}×)"
        )
    return fitting_pages.prose(
        "The crowd step against JuPedSim's social force model, every run of the two records "
        f"above: {'; '.join(parts)}."
    )


STUDY43 = sets.ROOT / "tools" / "rl" / "study43"


def _study43_runs() -> dict[str, Any]:
    runs: dict[str, Any] = sets.read_json(STUDY43 / "runs.json")
    return runs


def rl43_validation() -> str:
    """Every run's chosen checkpoint on the validation set (the study's selection data)."""
    runs = _study43_runs()
    seeds = sorted({int(name.split("seed")[1]) for name in runs})
    lines = [
        "| arm | " + " | ".join(f"seed {s}" for s in seeds) + " |",
        "|---|" + "---|" * len(seeds),
    ]
    for k2 in ("0", "2"):
        cells = []
        for seed in seeds:
            path = STUDY43 / "validation" / f"k{k2}-seed{seed}.json"
            if not path.is_file():
                cells.append("training" if f"k{k2}-seed{seed}" in runs else "–")
                continue
            best = sets.read_json(path)["best"]
            cells.append(
                f"{best['success_rate']:.3f} / {best['collision_rate']:.3f} "
                f"({best['steps'] // 1000}k)"
            )
        lines.append(f"| k2 = {k2} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def rl43_curves() -> str:
    """Validation success and timeouts of every run at each checkpoint (learning curves)."""
    paths = sorted(
        (STUDY43 / "validation").glob("k*-seed*.json"),
        key=lambda q: (q.name.split("-")[0], int(q.stem.split("seed")[1])),
    )
    docs = {q.stem: sets.read_json(q)["checkpoints"] for q in paths}
    steps = sorted({c["steps"] for cps in docs.values() for c in cps})
    lines = [
        "| run | " + " | ".join(f"{s // 1000}k" for s in steps) + " |",
        "|---|" + "--:|" * len(steps),
    ]
    for run, cps in docs.items():
        at = {c["steps"]: c for c in cps}
        cells = [
            f"{at[s]['success_rate']:.2f} ({at[s]['timeout_rate']:.2f})" if s in at else "–"
            for s in steps
        ]
        lines.append(f"| {run} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def _study43_report() -> tuple[Any, str]:
    """The study's evaluation table (tools/rl/study43/report/seed*.csv.gz) and a line
    saying which training seeds it holds."""
    from tools.rl.study43 import report as report43

    files = sorted((STUDY43 / "report").glob("seed*.csv.gz"), key=lambda p: int(p.name[4:-7]))
    if not files:
        raise MissingError(
            "`tools/rl/study43/report/` (`PYTHONPATH=. python tools/rl/study43/evaluate.py`)"
        )
    seeds = [int(p.name[4:-7]) for p in files]
    head = (
        f"*From `tools/rl/study43/report/seed*.csv.gz`: training seeds "
        f"{', '.join(map(str, seeds))} ({len(seeds)} of the 10 the study fixed), each "
        "seed's four policies on the 14 report scenarios, evaluation seeds 0–99 "
        "(`PYTHONPATH=. python tools/rl/study43/evaluate.py --seeds 1-10`).*"
    )
    return report43.load(*files), head


def rl43_summary() -> str:
    """The study's outcome in sentences, from the same data as its tables."""
    from tools.results import rl_study
    from tools.rl.study43 import report as report43

    table, _ = _study43_report()
    found = report43.arms(table)
    misses = {
        (k2, final): {s: report43.missed(table, name) for s, name in runs.items()}
        for (k2, final), runs in found.items()
    }
    picks = {k2: report43.validation_choice(STUDY43 / "validation", k2) for k2 in ("0", "2")}
    shipped = rl_study.shipped_cells()
    shipped_miss = {
        planner: sum(cell.miss for (_, p), (cell, _, _) in shipped.items() if p == planner)
        for planner in rl_study.SHIPPED
    }
    every = [m for runs in misses.values() for m in runs.values() if m is not None]
    perfect = sum(m == 0 for m in every)
    text = []
    for k2, planner in (("0", "td3-base"), ("2", "td3-srfm")):
        pick = picks[k2]
        if pick is None:
            continue
        own = misses.get((k2, False), {}).get(pick[0])
        text.append(
            f"k2 = {k2}: the rule picks `k{k2}-seed{pick[0]}`, which misses {own} of the 14 "
            f"cells; the shipped `{planner}` (issue 30) misses {shipped_miss[planner]}"
        )
    rows = [
        line.split(" | ")
        for line in report43.claim(table, final=False)
        if line.startswith("| ") and not line.startswith("| scenario")
    ]

    def count(column: int) -> str:
        answers = [row[column] for row in rows]
        kinds = {
            "lower with the penalty": sum(x.startswith("lower") for x in answers),
            "higher with the penalty": sum(x.startswith("higher") for x in answers),
            "equivalent": sum(x.startswith("equivalent") for x in answers),
            "untestable (no training seed with a goal in both arms)": sum(
                x.startswith("too few") for x in answers
            ),
        }
        rest = len(answers) - sum(kinds.values())
        return ", ".join(
            [f"{k} in {v}" for k, v in kinds.items() if v]
            + ([f"inconclusive in {rest}"] if rest else [])
        )

    return (
        "; ".join(text)
        + f". Of the {len(every)} policies (10 training seeds × 2 arms × chosen and final "
        f"checkpoints), {perfect} meet every target; the fewest cells missed is "
        f"{min(every)}. The claim on the chosen checkpoints, over the {len(rows)} "
        f"scenarios: deviation {count(7)}; success (co-primary) {count(13)}."
    )


def rl43_targets() -> str:
    from tools.rl.study43 import report as report43

    table, head = _study43_report()
    return "\n".join(
        [head, "", *report43.ship_table(table, STUDY43 / "validation"), "",
         "Cells missed (of 14) per run:", "", *report43.missed_table(table)]
    )  # fmt: skip


def rl43_claim() -> str:
    from tools.rl.study43 import report as report43

    table, head = _study43_report()
    return "\n".join(
        [head, "", "**Chosen checkpoints (primary):**", "", *report43.claim(table, final=False),
         "", "**Final checkpoints, 300,000 actions (sensitivity):**", "",
         *report43.claim(table, final=True)]
    )  # fmt: skip


BLOCKS: dict[str, Callable[[], str]] = {
    "results-sets": sets_index,
    "paper-table3": paper_table3_block,
    "paper-outcomes": paper_outcomes,
    "paper-references": paper_references,
    "paper-full": paper_full,
    "francis-references": francis_references,
    "francis-means": francis_means,
    "francis-scores": francis_scores,
    "francis-outcomes": francis_outcomes,
    "francis-full": francis_full,
    "navwareset-references": navwareset_references,
    "flows-table": flows_table,
    "nws2025-issue15": nws2025_issue15_table,
    "presets-paper": presets_paper,
    "presets-francis": presets_francis,
    "robustness-paper": robustness_paper,
    "robustness-francis": robustness_francis,
    "rankings-summary": rankings_summary,
    "rankings-intervals": rankings_intervals,
    "selection-table": selection_table,
    "discriminative-tables": discriminative_tables,
    **rl_study.BLOCKS,
    "planner-outcomes-unicycle": data_pages.outcomes_unicycle,
    "planner-outcomes-holonomic": data_pages.outcomes_holonomic,
    "planner-outcomes-summary": data_pages.outcomes_summary,
    "planner-outcomes-variants": data_pages.outcome_variants,
    "planner-outcomes-stress": data_pages.outcome_stress,
    "convergence-tables": data_pages.convergence_tables,
    "convergence-verdict": data_pages.convergence_verdict,
    "attribution-tables": data_pages.attribution_tables,
    "attribution-findings": data_pages.attribution_findings,
    "scenario-checks": data_pages.scenario_checks,
    "oracle-cost": oracle_cost,
    "performance-goals": performance_goals,
    "performance-vs-before": performance_vs,
    "performance-vs-reading": performance_vs_reading,
    "performance-crowd-change": performance_crowd_change,
    "readme-speed": readme_speed,
    "rl43-validation": rl43_validation,
    "rl43-curves": rl43_curves,
    "rl43-summary": rl43_summary,
    "rl43-targets": rl43_targets,
    "rl43-claim": rl43_claim,
    **fitting_pages.BLOCKS,
    **fitting_text.BLOCKS,
    **encounters_text.BLOCKS,
    **sensitivity.BLOCKS,
    **io_pages.BLOCKS,
    **response_pages.BLOCKS,
    **planner_pages.BLOCKS,
    **readme_pages.BLOCKS,
    **performance_pages.BLOCKS,
    **audit_a_pages.BLOCKS,
    **audit_b_pages.BLOCKS,
}


FILES: dict[str, Callable[[], str]] = {
    **whole_files.FILES,
}
"""Whole files (path from the repository's root) -> their text from committed data."""

_MISSING = (MissingError, data_pages.MissingDataError, fitting_pages.MissingDataError)


def file_text(path: str) -> str:
    """The text of the whole file ``path`` (from the repository's root) from its data."""
    if path not in FILES:
        raise SystemExit(f"unknown generated file {path!r}; known: {sorted(FILES)}")
    try:
        return FILES[path]()
    except _MISSING as exc:
        raise SystemExit(f"{path}: cannot be written: no committed {exc}") from None


def stale_files(root: Path = sets.ROOT) -> list[str]:
    """``path: whole file`` for every file of ``FILES`` under ``root`` whose bytes differ
    from what its data give (or that is missing)."""
    found = []
    for path in FILES:
        page = root / path
        if not page.is_file() or page.read_bytes() != file_text(path).encode("utf-8"):
            found.append(f"{path}: whole file")
    return found


def write_files(root: Path = sets.ROOT) -> list[str]:
    """Rewrite every file of ``FILES`` under ``root`` that differs; its paths."""
    changed = []
    for path in FILES:
        page, data = root / path, file_text(path).encode("utf-8")
        if not page.is_file() or page.read_bytes() != data:
            page.parent.mkdir(parents=True, exist_ok=True)
            page.write_bytes(data)
            changed.append(path)
    return changed


def render(name: str, page: Path) -> str:
    """The text of block ``name`` as written on ``page``."""
    global _PAGE
    _PAGE = page
    if name not in BLOCKS:
        raise SystemExit(f"{page}: unknown generated block {name!r}; known: {sorted(BLOCKS)}")
    try:
        return BLOCKS[name]().strip()
    except MissingError as exc:
        return f"*Not measured yet: no committed results set {exc}.*"
    except data_pages.MissingDataError as exc:
        return f"*Not measured yet: no committed data {exc}.*"
    except fitting_pages.MissingDataError as exc:
        return f"*Not measured yet: no committed {exc}.*"


def rewrite(text: str, page: Path) -> tuple[str, list[str]]:
    """The page with every block regenerated, and the names of the blocks that changed."""
    out, pos, changed = [], 0, []
    for match in BEGIN.finditer(text):
        name = match.group(1)
        end = text.find(END.format(name=name), match.end())
        if end < 0:
            raise SystemExit(f"{page}: block {name!r} has no {END.format(name=name)!r}")
        new = "\n" + render(name, page) + "\n\n"
        if text[match.end() : end] != new:
            changed.append(name)
        out += [text[pos : match.end()], new]
        pos = end
    out.append(text[pos:])
    return "".join(out), changed


def pages() -> list[Path]:
    """Every Markdown page under docs/, and the README, with a generated block."""
    candidates = [sets.ROOT / "README.md", *sorted(DOCS.rglob("*.md"))]
    return [p for p in candidates if BEGIN.search(p.read_text(encoding="utf-8"))]


def stale() -> list[str]:
    """``page: block`` for every block whose committed text differs from the data's,
    after ``path: whole file`` for every whole file that does."""
    found = stale_files()
    for page in pages():
        _, changed = rewrite(page.read_text(encoding="utf-8"), page)
        found += [f"{page.relative_to(sets.ROOT)}: {name}" for name in changed]
    return found


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--check", action="store_true", help="change nothing; exit 1 if stale")
    args = ap.parse_args(argv)
    if args.check:
        found = stale()
        for line in found:
            print(f"stale: {line}")
        if found:
            raise SystemExit("generated blocks or files differ from the data: make docs-tables")
        return
    for path in write_files():  # first: blocks read some of them (sensitivity/rankings.csv)
        print(f"{path}: whole file")
    for page in pages():
        text = page.read_text(encoding="utf-8")
        new, changed = rewrite(text, page)
        if changed:
            page.write_text(new, encoding="utf-8")
            print(f"{page.relative_to(sets.ROOT)}: {', '.join(changed)}")


if __name__ == "__main__":
    main()
