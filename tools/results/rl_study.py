"""The generated blocks of docs/rl.md on issue 30's walls-aware study and the shipped
policies, from committed data only (``tools/results/generate.py``):

- the shipped policies against the targets: the results sets of docs/results/ (the
  paper, Francis, NavWareSet and flows suites run the shipped policies on seeds 0-99);
- every study run against the targets and the claim over training seeds: the
  committed episodes ``tools/rl/study/report/seed<s>.csv.gz`` (and ``report_ttc/``,
  under the real-data preset), written by ``tools/rl/study_evaluate.py``, read with
  ``tools/rl/study_report.py``'s rules;
- the runs' checkpoint validation: ``tools/rl/study/validation/<run>.json``
  (``tools/rl/validate_checkpoints.py``), their wall times ``tools/rl/study/runs.json``
  (``tools/rl/study.py``);
- which run each shipped policy is: the SHA-256 of its weights in
  ``srfm/policies/td3_*.json`` against the study's exported policies.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from tools.results import sets
from tools.rl.study_report import (
    MARGIN_M,
    POLICY,
    REPORT_SCENARIOS,
    Shares,
    claim_rows,
    committed,
    misses_target,
    planners_of,
    shares,
)

STUDY = sets.ROOT / "tools" / "rl" / "study"
SHIPPED = {"td3-base": "td3_base", "td3-srfm": "td3_srfm"}
"""The shipped TD3 planners and their policy files' stems in srfm/policies/."""
SETS_OF_REPORT = ("paper", "francis", "navwareset", "flows")
"""The results sets that hold the report's scenarios for the shipped policies."""
PAPER_RANGE_M = (0.04, 0.09)
"""The deviation differences the paper reports between its two policies (m)."""


Cell = Shares
"""A policy's shares in one scenario over seeds 0-99 and whether they miss."""


@dataclass(frozen=True)
class Claim:
    """One scenario's row of the study's claim table, as the report prints it (p-values
    to 2 significant digits, intervals to the millimetre)."""

    scenario: str
    n: int
    mean: float
    ci95: str
    p: float
    p_holm: float
    ci90: str
    answer: str


def run_name(planner: str) -> str:
    """``tools.rl.study_planners:k2_seed4`` (a benchmark planner) -> ``k2-seed4`` (a run)."""
    match = POLICY.fullmatch(planner)
    if match is None:
        raise SystemExit(f"{STUDY}: unexpected planner {planner!r}")
    return f"k{match[1]}-seed{match[2]}"


def report_targets(part: str = "report") -> dict[tuple[str, str], Cell]:
    """(scenario, run) -> the run's shares in the study's committed episodes (a run
    with no episodes of a scenario has none)."""
    table = committed(part)
    out = {}
    for planner in planners_of(table):
        for scenario in REPORT_SCENARIOS:
            cell = shares(table, scenario, planner)
            if cell is not None:
                out[scenario, run_name(planner)] = cell
    return out


def runs_of(cells: dict[tuple[str, str], Cell]) -> list[str]:
    """The runs, k2 = 0 first, by training seed."""
    return sorted({r for _, r in cells}, key=lambda r: (r.split("-")[0], _seed(r)))


def _seed(run: str) -> int:
    return int(run.rsplit("seed", 1)[1])


def _p(p: float) -> float:
    """A p-value as the report prints it, 2 significant digits."""
    return float(f"{p:.2g}")


def report_claim(part: str = "report") -> list[Claim]:
    """The claim over training seeds on the study's committed episodes, one row per
    scenario of the part (a scenario without episodes is left out)."""
    table = committed(part)
    scenarios = {s for s, _ in table}
    return [
        Claim(
            r.scenario,
            r.n,
            r.mean,
            f"{r.lo:+.3f} to {r.hi:+.3f}",
            _p(r.p),
            _p(r.p_holm),
            f"{r.lo90:+.3f} to {r.hi90:+.3f}",
            r.answer,
        )
        for r in claim_rows(table, planners_of(table))
        if r.scenario in scenarios
    ]


def validation(run: str) -> tuple[float, float]:
    """Success and collision rates of a run's chosen checkpoint on the validation set."""
    best = sets.read_json(STUDY / "validation" / f"{run}.json")["best"]
    return float(best["success_rate"]), float(best["collision_rate"])


def shipped_runs() -> dict[str, str]:
    """Shipped planner -> the study run whose exported weights it ships."""
    by_sha = {
        sets.read_json(p)["weights_sha256"]: p.stem
        for p in sorted((STUDY / "policies").glob("*.json"))
    }
    out = {}
    for planner, stem in SHIPPED.items():
        sha = sets.read_json(sets.ROOT / "srfm" / "policies" / f"{stem}.json")["weights_sha256"]
        if sha not in by_sha:
            raise SystemExit(f"srfm/policies/{stem}.npz is none of the study's policies")
        out[planner] = by_sha[sha]
    return out


def shipped_cells() -> dict[tuple[str, str], tuple[Cell, dict[str, int], str]]:
    """(scenario, planner) -> the shipped policy's cell, its outcome counts and the
    results set, for every scenario of the report, from the committed results sets."""
    out = {}
    for name in SETS_OF_REPORT:
        if not sets.exists(name):
            continue
        t = sets.table(name)
        counts: dict[tuple[str, str], dict[str, int]] = {}
        for s, p, o in zip(
            *(t[c].to_pylist() for c in ("scenario", "planner", "outcome")), strict=True
        ):
            if p in SHIPPED and s in REPORT_SCENARIOS and (s, p) not in out:
                counts.setdefault((s, p), {}).setdefault(o, 0)
                counts[s, p][o] += 1
        for (s, p), c in counts.items():
            n = sum(c.values())
            goal, col = c.get("goal_reached", 0) / n, c.get("collision", 0) / n
            cell = Cell(goal, col, c.get("out_of_bounds", 0) / n, misses_target(s, goal, col))
            out[s, p] = (cell, c, name)
    return out


def _list(names: list[str]) -> str:
    quoted = [f"`{n}`" for n in names]
    if len(quoted) <= 1:
        return "".join(quoted)
    return ", ".join(quoted[:-1]) + " and " + quoted[-1]


def _kind(scenario: str) -> str:
    from srfm.scenarios import EVALUATION_SCENARIOS
    from srfm.scenarios.training import LIBRARY_HELDOUT

    if scenario in EVALUATION_SCENARIOS:
        return "paper"
    return "held out" if scenario in LIBRARY_HELDOUT else "training"


def _misses(planner: str, cells: dict[tuple[str, str], tuple[Cell, dict[str, int], str]]) -> str:
    """What a shipped policy misses, in words ("" when nothing)."""
    collides, waits, other = [], [], []
    for s in REPORT_SCENARIOS:
        cell, counts, _ = cells[s, planner]
        if not cell.miss:
            continue
        n = sum(counts.values())
        if cell.collision > 0 and cell.out_of_bounds == 0:
            collides.append(f"{100 * cell.collision:.0f} % of `{s}`")
        elif counts.get("timeout", 0) == n - counts.get("goal_reached", 0):
            waits.append(f"`{s}` in {counts.get('timeout', 0)} of {n} episodes (no collision)")
        else:
            other.append(f"`{s}` ({cell.text()})")
    said = []
    if collides:
        said.append("collides in " + " and ".join(collides))
    if waits:
        said.append("waits until the horizon in " + " and ".join(waits))
    if other:
        said.append("misses " + " and ".join(other))
    return f"`{planner}` " + "; ".join(said) if said else ""


def _verdict(cells: dict[tuple[str, str], tuple[Cell, dict[str, int], str]]) -> str:
    parts = [m for p in SHIPPED if (m := _misses(p, cells))]
    if not parts:
        return "**The targets are met** by both."
    return "**The targets are not met.** " + "; ".join(parts) + "."


def shipped_targets() -> str:
    """The shipped pair against the targets, and what they miss."""
    runs = shipped_runs()
    cells = shipped_cells()
    missing = [s for s in REPORT_SCENARIOS for p in SHIPPED if (s, p) not in cells]
    if missing:
        return f"*Not measured yet: no committed results set with {', '.join(missing)}.*"
    used = sorted({cells[s, p][2] for s in REPORT_SCENARIOS for p in SHIPPED})
    lines = [
        f"*From the results sets {', '.join(f'`{n}`' for n in used)} "
        "([results](results/index.md)), which ran the shipped files on seeds 0–99.*",
        "",
        "| scenario | set | " + " | ".join(f"`{p}` (`{runs[p]}`)" for p in SHIPPED) + " |",
        "|---|---|" + "---|" * len(SHIPPED),
    ]
    for s in REPORT_SCENARIOS:
        texts = [cells[s, p][0].text() for p in SHIPPED]
        lines.append(f"| {s} | {_kind(s)} | " + " | ".join(texts) + " |")
    verdict = _verdict(cells)
    study = report_targets()
    siblings = []
    for p, run in runs.items():
        arm, seed = run.split("-")
        sibling = f"{'k2' if arm == 'k0' else 'k0'}-{seed}"
        theirs = [s for s in REPORT_SCENARIOS if (s, sibling) in study and study[s, sibling].miss]
        siblings.append(
            f"`{sibling}` (the sibling of `{runs[p]}`) "
            + (f"misses {_list(theirs)}" if theirs else "meets every target")
        )
    chosen = [validation(r)[0] for r in runs_of(study)]
    lines += [
        "",
        verdict
        + " Their siblings of the same training seed, in the study's report: "
        + "; ".join(siblings)
        + f". The validation set does not predict these cells: every run's chosen "
        f"checkpoint succeeds in {100 * min(chosen):.0f}–{100 * max(chosen):.0f} % of it.",
    ]
    consistent = [
        s
        for s in REPORT_SCENARIOS
        for p in SHIPPED
        if (s, runs[p]) in study and study[s, runs[p]].text() != cells[s, p][0].text()
    ]
    if consistent:
        lines += ["", f"*The study's report disagrees with the sets in {', '.join(consistent)}.*"]
    return "\n".join(lines)


def _validation_text(run: str) -> str:
    success, collisions = validation(run)
    return f"{success:.3f} / " + (f"{collisions:.3f}" if collisions else "0")


def validation_table() -> str:
    """Each run's chosen checkpoint on the validation set, and the shipping rule over
    every finished run."""
    runs = runs_of(report_targets())
    shipped = shipped_runs()
    seeds = sorted({_seed(r) for r in runs})
    lines = [
        "| training seed | " + " | ".join(str(s) for s in seeds) + " |",
        "|---|" + "---|" * len(seeds),
    ]
    for arm in ("k0", "k2"):
        cells = []
        for s in seeds:
            text = _validation_text(f"{arm}-seed{s}")
            cells.append(f"**{text}**" if f"{arm}-seed{s}" in shipped.values() else text)
        lines.append(f"| k2 = {arm[1]} | " + " | ".join(cells) + " |")
    picks = []
    for arm in ("k0", "k2"):
        mine = [r for r in runs if r.startswith(arm + "-")]
        best = max(mine, key=lambda r: (validation(r)[0], -validation(r)[1], -_seed(r)))
        ties = [r for r in mine if validation(r) == validation(best) and r != best]
        picks.append(
            f"`{best}` ({_validation_text(best)}"
            + (f"; tied with {_list(ties)}, lower training seed" if ties else "")
            + ")"
        )
    same = set(shipped.values()) == {p.split(" ")[0].strip("`") for p in picks}
    return (
        "\n".join(lines)
        + "\n\nBold: the shipped runs. Applied to all "
        + f"{len(seeds)} training seeds, the rule picks "
        + " and ".join(picks)
        + (": the runs shipped." if same else ": not the runs shipped.")
    )


def study_misses() -> str:
    """Cells missed by each run, and the runs that meet every target."""
    cells = report_targets()
    runs = runs_of(cells)
    seeds = sorted({_seed(r) for r in runs})
    missed = {r: sum(c.miss for (_, q), c in cells.items() if q == r) for r in runs}
    lines = [
        "| training seed | " + " | ".join(str(s) for s in seeds) + " |",
        "|---|" + "---|" * len(seeds),
    ]
    for arm in ("k0", "k2"):
        lines.append(
            f"| k2 = {arm[1]} | " + " | ".join(str(missed[f"{arm}-seed{s}"]) for s in seeds) + " |"
        )
    clean = [r for r in runs if missed[r] == 0]
    shipped = shipped_runs()
    notes = []
    for run in shipped.values():
        ties = [
            r for r in runs if r != run and r[:2] == run[:2] and validation(r) == validation(run)
        ]
        if ties:
            notes.append(
                f"the shipped `{run}` ties {_list(ties)} at {_validation_text(run)} on "
                f"validation and misses {missed[run]} cell{'' if missed[run] == 1 else 's'}"
            )
        else:
            notes.append(
                f"the shipped `{run}` misses {missed[run]} cell{'' if missed[run] == 1 else 's'}"
            )
    return (
        "\n".join(lines)
        + f"\n\n{len(clean)} of the {len(runs)} runs meet every target ({_list(clean)}); "
        "the recipe does not make a policy that generalises from every training seed, and "
        "the validation set does not tell which seeds do (" + "; ".join(notes) + ")."
    )


def _fmt_answer(c: Claim) -> str:
    answer = c.answer
    match = re.search(r"about (\d+) seeds", answer)
    if match:
        answer = answer.replace(match[0], f"about {int(match[1]):,} seeds")
    return f"**{answer}**" if answer.startswith("equivalent") else answer


def _minus(text: str) -> str:
    """Negative numbers with the minus sign (the report writes a hyphen)."""
    return re.sub(r"(?<!\w)-(?=\d)", "−", text)


def claim_table() -> str:
    """The paper's claim over training seeds (the study's report), and what it says."""
    from srfm.scenarios import EVALUATION_SCENARIOS

    rows = report_claim()
    lines = [
        "| scenario | n seeds | Δ Fréchet (m) | 95 % CI | p (Holm) | 90 % CI | answer |",
        "|---|---:|---:|---|---:|---|---|",
    ]
    for c in rows:
        cells = [f"{c.mean:+.3f}", c.ci95, f"{c.p_holm:g}", c.ci90]
        lines.append(
            f"| {c.scenario} | {c.n} | "
            + " | ".join(_minus(x) for x in cells)
            + f" | {_fmt_answer(c)} |"
        )
    full = max(c.n for c in rows)
    short = [c for c in rows if c.n < full]
    equivalent = [c.scenario for c in rows if c.answer.startswith("equivalent")]
    lowers = [c for c in rows if "lowers" in c.answer]
    raw = min(rows, key=lambda c: c.p)
    near = [
        c
        for c in rows
        if c.scenario in EVALUATION_SCENARIOS
        and c.answer.startswith("inconclusive")
        and round(c.mean, 3) <= -MARGIN_M
    ]
    need = [int(m[1]) for c in near if (m := re.search(r"about (\d+) seeds", c.answer))]
    text = "\n".join(lines) + "\n\n"
    if short:
        text += (
            f"n < {full}: a training seed whose policy never reached the goal in a scenario "
            "has no mean there ("
            + ", ".join(
                f"`{c.scenario}`: {full - c.n} such pair{'s' if full - c.n > 1 else ''}"
                for c in short
            )
            + "). In words:\n\n"
        )
    if lowers:
        text += (
            f"- **The penalty lowers deviation in {_list([c.scenario for c in lowers])}** "
            "(Holm-adjusted p below 0.05).\n"
        )
    else:
        text += (
            "- **No scenario shows that the penalty lowers deviation** (no Holm-adjusted p "
            f"below 0.05; the smallest raw p is {raw.p:g}, `{raw.scenario}`).\n"
        )
    if equivalent:
        text += (
            f"- **In {_list(equivalent)} the two arms are equivalent within ±{MARGIN_M} m**: "
            "there the penalty makes no difference of the size the paper reports "
            f"({PAPER_RANGE_M[0]}–{PAPER_RANGE_M[1]} m).\n"
        )
    text += '- **Elsewhere the answer is "inconclusive".**'
    if near and need:
        low, high = min(c.mean for c in near), max(c.mean for c in near)
        text += _minus(
            f" In {_list([c.scenario for c in near])} the point estimates ({low:.3f} to "
            f"{high:.3f} m) are at least the equivalence margin in size, but their 95 % "
            f"intervals include 0 and the paper's gaps alike; {min(need)}–{max(need)} "
            "training seeds per arm would settle them."
        )
    text += (
        " In the walled held-out scenarios the seed-to-seed spread (a seed that swerves "
        "into a corner or not) is far larger than any effect of the penalty."
    )
    return text


def claim_ttc() -> str:
    """The claim under navwareset2026_ttc (the committed ``report_ttc`` episodes), in one
    paragraph."""
    rows = report_claim("report_ttc")
    parts = []
    for c in rows:
        if c.answer.startswith("equivalent"):
            parts.append(f"`{c.scenario}` **equivalent** ({c.mean:+.3f} m, 90 % CI {c.ci90})")
        else:
            need = re.search(r"about (\d+) seeds", c.answer)
            n = f"n = {c.n}, " if c.n < max(r.n for r in rows) else ""
            parts.append(
                f"`{c.scenario}` {c.mean:+.3f} m ({n}95 % CI {c.ci95}, inconclusive"
                + (f": about {int(need[1]):,} seeds" if need else "")
                + ")"
            )
    return _minus("; ".join(parts)) + (
        f"; Holm-adjusted p ≥ {min(c.p_holm for c in rows):g} everywhere."
    )


def wall_times() -> str:
    """Each run's training wall time (runs.json) and the load noted beside it."""
    runs: dict[str, Any] = sets.read_json(STUDY / "runs.json")
    notes: dict[str, str] = sets.read_json(STUDY / "load_notes.json")["load_average"]
    seeds = sorted({_seed(r) for r in runs})
    lines = [
        "| training seed | " + " | ".join(str(s) for s in seeds) + " |",
        "|---|" + "---|" * len(seeds),
    ]
    for arm in ("k0", "k2"):
        lines.append(
            f"| k2 = {arm[1]} (s) | "
            + " | ".join(f"{runs[f'{arm}-seed{s}']['wall_time_s']:,.0f}" for s in seeds)
            + " |"
        )
    lines.append("| load average | " + " | ".join(notes[str(s)] for s in seeds) + " |")
    unfinished = [r for r, v in runs.items() if not v["finished"]]
    if unfinished:
        lines += ["", f"Unfinished: {', '.join(unfinished)}."]
    return "\n".join(lines)


def summary() -> str:
    """The two bullets of the page's summary: the shipped pair against the targets and
    the answer to the paper's claim."""
    cells = shipped_cells()
    if any((s, p) not in cells for s in REPORT_SCENARIOS for p in SHIPPED):
        return "*Not measured yet: the results sets lack scenarios of the report.*"
    parts = [m for p in SHIPPED if (m := _misses(p, cells))]
    study = report_targets()
    runs = runs_of(study)
    clean = [r for r in runs if not any(study[s, r].miss for s in REPORT_SCENARIOS)]
    claims = report_claim()
    equivalent = [c.scenario for c in claims if c.answer.startswith("equivalent")]
    lowers = [c.scenario for c in claims if "lowers" in c.answer]
    n_seeds = max(c.n for c in claims)
    from srfm.scenarios import EVALUATION_SCENARIOS

    near = [
        c
        for c in claims
        if c.scenario in EVALUATION_SCENARIOS
        and c.answer.startswith("inconclusive")
        and round(c.mean, 3) <= -MARGIN_M
    ]
    result = (
        f"- **The result** (seeds 0–99, {len(REPORT_SCENARIOS)} scenarios: the paper's five, "
        "the library's eight held-out ones and `corridor_flow`): the targets (≥ 95 % goal, "
        "≤ 2 % collisions; ≤ 5 % collisions in `corridor_flow`) are "
        + (
            "**not met** by the shipped pair: " + "; ".join(parts)
            if parts
            else "**met** by the shipped pair"
        )
        + f". {len(clean)} of the study's {len(runs)} runs meet every target; the "
        "validation set used for choosing cannot tell which "
        "([The shipped policies](#the-shipped-policies))."
    )
    claim = (
        "- **The paper's claim** (does the deviation penalty lower deviation at equal "
        f"success?), with {n_seeds} training seeds per arm: "
        + (f"**equivalent within ±{MARGIN_M} m in {_list(equivalent)}**, " if equivalent else "")
        + f"inconclusive in the other {len(claims) - len(equivalent) - len(lowers)} scenarios"
        + (
            _minus(
                f" (in {_list([c.scenario for c in near])} the estimates, "
                f"{min(c.mean for c in near):.3f} to {max(c.mean for c in near):.3f} m, "
                "are as large as the margin but their intervals include 0)"
            )
            if near
            else ""
        )
        + (
            f", lowered significantly in {_list(lowers)}"
            if lowers
            else ", lowered significantly nowhere"
        )
        + " ([State of the walls-aware study](#state-of-the-walls-aware-study)). The earlier "
        "answer from 3 + 3 seeds is in "
        "[history/rl.md](history/rl.md#the-answer-to-the-papers-question)."
    )
    return result + "\n" + claim


REWARD_STATS = sets.ROOT / "docs" / "rl" / "reward_stats.json"


def reward_stats() -> str:
    """The size of the deviation term under random actions (tools/rl/reward_stats.py)."""
    from srfm.rl import DEFAULT_K_DIV

    if not REWARD_STATS.is_file():
        return (
            "*Not measured yet: `python tools/rl/reward_stats.py --json "
            "docs/rl/reward_stats.json`.*"
        )
    doc = sets.read_json(REWARD_STATS)
    return (
        f"- **The size of r_div**: with random actions in the `random` scenario it is "
        f"non-zero in {100 * doc['nonzero_share']:.0f} % of the steps, {doc['mean_m']:.4f} m "
        f"on average, {doc['p99_m']:.3f} m at the 99th percentile ({doc['steps']:,} steps; "
        f"`{doc['command']}`, commit `{doc['commit']}`, {doc['started'][:10]}), so "
        f"k2 = {DEFAULT_K_DIV:g} makes a close pass cost up to about "
        f"{DEFAULT_K_DIV * doc['p99_m']:.2f} per step, against k1 · r_dist ≤ 0.1."
    )


def _study_misses(scenario: str) -> tuple[int, int, int]:
    """(runs, runs that miss the scenario's target, of those the runs with a collision)
    in the study's committed episodes."""
    cells = report_targets()
    mine = [c for (s, _), c in cells.items() if s == scenario]
    missed = [c for c in mine if c.miss]
    return len(mine), len(missed), sum(c.collision > 0 for c in missed)


def usual_misses() -> str:
    """The cells the study's runs miss most, from its committed episodes."""
    n, concert, concert_coll = _study_misses("concert")
    _, flow, flow_coll = _study_misses("corridor_flow")
    _, down, _ = _study_misses("down_path")
    _, corner, _ = _study_misses("blind_corner")
    return (
        f"The usual misses (of the {n} runs): `concert`, a standing crowd across the path, "
        f"missed by {concert} runs ({concert - concert_coll} of them without a collision: "
        f"they wait until the horizon); `corridor_flow`, collisions with the entering "
        f"stream, by {flow} ({flow_coll} with collisions); `down_path` by {down} and "
        f"`blind_corner` by {corner} (`tools/rl/study/report/`)."
    )


EXPORT_MATCH = sets.ROOT / "docs" / "rl" / "export_match.json"


def export_match() -> str:
    """The shipped NumPy actors against their checkpoints' own (tools/rl/export_match.py)."""
    if not EXPORT_MATCH.is_file():
        return (
            "*Not measured yet: `python tools/rl/export_match.py --json "
            "docs/rl/export_match.json`.*"
        )
    doc = sets.read_json(EXPORT_MATCH)
    found = doc["policies"]
    backends = sorted({p["backend"].upper() for p in found.values()})
    counts = {p["observations"] for p in found.values()}
    if len(counts) != 1:
        raise SystemExit(f"{EXPORT_MATCH}: the policies ran on different observation counts")
    largest = max(p["max_abs_diff"] for p in found.values())
    within = f"{largest:.1e}".replace("e-0", "e-")
    scenarios = _list(doc["scenarios"])
    run = doc["run"]
    return (
        "The exported actor is the checkpoint's: for both shipped policies its action "
        f"equals the {' and '.join(backends)} checkpoint's deterministic `model.predict` "
        f"within {within} on {counts.pop():,} observations ({doc['uniform']:,} uniform "
        f"in [−1, 1], {doc['sparse']:,} sparse ones, and {doc['per_scenario']:,} from "
        f"episodes of each of {scenarios} under the policy; `{run['command']}`, commit "
        f"`{run['commit']}`, {run['started'][:10]}). Tested on untrained networks: within "
        "2e-6 of SB3's (`tests/planners/test_td3.py`) and 1e-5 of SBX's "
        "(`tests/rl/test_train.py`)."
    )


RANGE_BEAMS = sets.ROOT / "docs" / "rl" / "range_beams.json"


def range_beams() -> str:
    """What range beams cost the training step (tools/bench/bench_range_beams.py)."""
    if not RANGE_BEAMS.is_file():
        return (
            "*Not measured yet: `python tools/bench/bench_range_beams.py --json "
            "docs/rl/range_beams.json`.*"
        )
    doc = sets.read_json(RANGE_BEAMS)
    best: dict[str, dict[int, float]] = {}
    for row in doc["rows"]:
        best.setdefault(row["scenario"], {})[row["beams"]] = min(row["us_per_step"])
    beams = max(b for by in best.values() for b in by)
    run = doc["run"]
    cells = [
        _minus(
            f"`{scenario}`: {by[0]:.1f} → {by[beams]:.1f} µs "
            f"({100 * (by[beams] / by[0] - 1):+.0f} %)"
        )
        for scenario, by in best.items()
    ]
    return (
        f"**Cost.** {beams} beams take the training set-up's step (no full twin; the best of "
        f"{doc['repeats']} blocks of {doc['steps']:,} steps with random actions, other jobs "
        f"paused) in {', '.join(cells[:-1])} and {cells[-1]} (`{run['command']}`, "
        f"commit `{run['commit']}`, {run['started'][:10]}; {run['machine']})."
    )


def evaluation_runs() -> str:
    """How long the committed evaluation of the study's policies took, with the load."""
    lines = []
    for part, what in (("report", "14 scenarios"), ("report_ttc", "five paper scenarios")):
        runs: dict[str, Any] = sets.read_json(STUDY / part / "runs.json")
        walls = [r["wall_s"] / 60 for r in runs.values()]
        first = min(r["started"] for r in runs.values())
        last = max(r["finished"] for r in runs.values())
        commits = sorted({r["commit"] for r in runs.values()})
        size = sum(f.stat().st_size for f in (STUDY / part).glob("seed*.csv.gz")) / 1e6
        lines.append(
            f"`{part}/` ({what}, {len(runs)} training seeds × 2 policies × seeds 0–99; "
            f"{size:.2f} MB): "
            f"{sum(walls):.0f} min of wall time in all, {min(walls):.0f}–{max(walls):.0f} min "
            f"a training seed, {first[:10]} {first[11:16]} to {last[11:16]} UTC, commit "
            + ", ".join(f"`{c}`" for c in commits)
        )
    return (
        "The committed evaluation (`python tools/rl/study_evaluate.py --seeds 1-10 --jobs 2`, "
        "at nice 10 beside other work, so these are not speed figures): "
        + "; ".join(lines)
        + " (each seed's run record, with the machine's load: `runs.json` beside the "
        "episodes)."
    )


def study43_train_wall() -> str:
    """The issue-43 runs' training wall times (tools/rl/study43/runs.json)."""
    runs: dict[str, Any] = sets.read_json(sets.ROOT / "tools" / "rl" / "study43" / "runs.json")
    minutes = [r["wall_time_s"] / 60 for r in runs.values() if r["finished"]]
    steps = sorted({r["steps"] for r in runs.values() if r["finished"]})
    return (
        f"Training took {min(minutes):.0f}–{max(minutes):.0f} minutes a run "
        f"({len(minutes)} runs of {' or '.join(f'{n:,}' for n in steps)} actions, two side "
        "by side on the shared "
        "machine; `tools/rl/study43/runs.json`)."
    )


SCENES_SHIPPED = sets.ROOT / "tools" / "rl" / "study43" / "validation_scenes_shipped.csv.gz"
SCENES = (
    "val_standing_band",
    "val_standing_patch",
    "val_standing_corridor",
    "val_corner_right",
    "val_junction_blind",
    "val_corner_group",
)
"""The issue-43 validation scenes, standing crowds first."""


def scenes_shipped() -> str:
    """The shipped policies on the issue-43 validation scenes (committed episodes of
    tools/rl/study43/shipped_scenes.py)."""
    from tools.rl.study_report import load

    table = load(SCENES_SHIPPED)
    run = sets.read_json(SCENES_SHIPPED.with_suffix("").with_suffix(".json"))
    counts = {}
    for (scene, planner), rows in table.items():
        n = len(rows)
        goal = sum(float(r["robot_success"]) for r in rows)
        col = sum(float(r["robot_collision"]) for r in rows)
        oob = sum(float(r["robot_out_of_bounds"]) for r in rows)
        counts[scene, planner] = (round(goal), round(col), round(n - goal - col - oob), n)
    missing = [(s, p) for s in SCENES for p in SHIPPED if (s, p) not in counts]
    if missing or len(counts) != len(SCENES) * len(SHIPPED):
        raise SystemExit(f"{SCENES_SHIPPED}: not the six scenes by the two policies {missing}")

    def cell(goal: int, col: int, timeouts: int, n: int) -> str:
        text = f"{goal / n:.1f} / {col / n:.1f}"
        return text + (f" ({timeouts} timeouts)" if timeouts == n else "")

    lines = [
        f"*Run `{run['command']}`, commit `{run['commit']}`, {run['started'][:10]}; "
        "goal / collision shares of "
        f"{counts[SCENES[0], 'td3-srfm'][3]} episodes.*",
        "",
        "| scene | `td3-srfm` | `td3-base` |",
        "|---|---|---|",
    ]
    for scene in SCENES:
        lines.append(
            f"| {scene} | {cell(*counts[scene, 'td3-srfm'])} | {cell(*counts[scene, 'td3-base'])} |"
        )
    standing = ("val_standing_band", "val_standing_patch")
    waits = sum(counts[s, "td3-srfm"][2] for s in standing)
    total = sum(counts[s, "td3-srfm"][3] for s in standing)
    corners = ("val_corner_right", "val_junction_blind", "val_corner_group")
    worst = max(corners, key=lambda s: counts[s, "td3-base"][1])
    base_col = sum(counts[s, "td3-base"][1] for s in corners)
    runs = shipped_runs()
    chosen = [validation(runs[p])[0] for p in SHIPPED]
    return (
        "\n".join(lines)
        + f"\n\n`td3-srfm` times out in {waits} of the {total} episodes with a standing "
        "crowd across the path (`val_standing_band`, `val_standing_patch`), as it waits in "
        f"`concert`; `td3-base` collides in {base_col} of the "
        f"{sum(counts[s, 'td3-base'][3] for s in corners)} episodes at the corners "
        f"({counts[worst, 'td3-base'][1]} of {counts[worst, 'td3-base'][3]} in `{worst}`), "
        "as in `blind_corner`. On the issue-30 validation set their chosen checkpoints "
        f"succeeded in {min(chosen):.3f}–{max(chosen):.3f} of the episodes."
    )


VAL30 = sets.ROOT / "tools" / "rl" / "study43" / "val30"
_ORDINAL = ("first", "second", "third", "fourth", "fifth", "sixth", "seventh", "eighth")


def _and(parts: list[str]) -> str:
    return parts[0] if len(parts) == 1 else ", ".join(parts[:-1]) + " and " + parts[-1]


def _ordinal(rank: int) -> str:
    return _ORDINAL[rank - 1] if rank <= len(_ORDINAL) else f"number {rank}"


def validation_check() -> str:
    """Would the issue-43 validation set have told issue 30's runs apart (the committed
    benchmark of the runs on the new scenes, tools/rl/study43/val30, and the study's
    committed episodes; tools/rl/study43/validation_check.py)."""
    from tools.rl.study43 import validation_check as vc

    rows = vc.rows_of(VAL30)
    labels = {
        "issue-30 set": f"issue-30 set ({rows[0][1][2]} episodes a run)",
        "new scenes": f"the six new scenes ({rows[0][2][2]})",
        "issue-43 set": f"issue-43 set (both, {rows[0][1][2] + rows[0][2][2]})",
    }
    lines = [
        "| validation set | Spearman ρ (validation success, cells missed), "
        f"{len(rows)} runs | p | the rule's k2 = 0 pick | k2 = 2 pick |",
        "|---|---:|---:|---|---|",
    ]
    found = {}
    for label in vc.SETS:
        rho, p, k0, k2 = found[label] = vc.ranking(rows, label)
        picks = [f"{rows[i][0]} (misses {rows[i][3]})" for i in (k0, k2)]
        lines.append(
            _minus(f"| {labels[label]} | {rho:+.2f} | {p:.2g} | {picks[0]} | {picks[1]} |")
        )
    old, new = found["issue-30 set"], found["issue-43 set"]
    closer = abs(new[0]) > abs(old[0])
    said = [
        f"The issue-43 set ranks the runs {'closer to' if closer else 'no closer to'} the "
        f"report (ρ {new[0]:+.2f} against {old[0]:+.2f}; the issue-30 figures are those of "
        "checkpoints chosen on that very set, which flatters it)."
    ]
    for arm, k in (("k2 = 0", 2), ("k2 = 2", 3)):
        a, b = rows[old[k]], rows[new[k]]
        said.append(
            f"For {arm} its rule picks `{b[0]}` (misses {b[3]}) where the issue-30 set "
            f"picked `{a[0]}` (misses {a[3]})."
        )
    both = [
        (-g / n, c / n, int(run.split("seed")[1]), run)
        for run, o, w, _ in rows
        if run.startswith("k2-")
        for g, c, n in [vc.on("issue-43 set", o, w)]
    ]
    ranked = [r[3] for r in sorted(both)]
    share = {r[3]: -r[0] for r in both}
    clean = sorted(
        (run for run, *_, m in rows if run.startswith("k2-") and m == 0), key=ranked.index
    )
    if clean:
        said.append(
            "Of the k2 = 2 runs that meet every target, "
            + _and(
                [
                    f"`{run}` ranks {_ordinal(ranked.index(run) + 1)} ({share[run]:.3f} success)"
                    for run in clean
                ]
            )
            + f" on the issue-43 set, where the pick has {share[ranked[0]]:.3f}."
        )
    said.append(
        f"One study's {len(rows)} runs: a {'better ' if closer else ''}predictor, not a guarantee."
    )
    return _minus("\n".join(lines)) + "\n\n" + _minus(" ".join(said))


def issue30_on_set() -> str:
    """Issue 30's runs' success on the issue-43 validation set (validation_check.py)."""
    from tools.rl.study43 import validation_check as vc

    rows = vc.rows_of(VAL30)
    shares = []
    for _, old, new, _ in rows:
        goal, _, n = vc.on("issue-43 set", old, new)
        shares.append(goal / n)
    return (
        f"Issue 30's {len(rows)} runs score {min(shares):.3f}–{max(shares):.3f} on the same "
        "set (their chosen checkpoints; above)."
    )


BLOCKS: dict[str, Callable[[], str]] = {
    "rl-usual-misses": usual_misses,
    "rl-summary": summary,
    "rl-validation": validation_table,
    "rl-shipped-targets": shipped_targets,
    "rl-study-misses": study_misses,
    "rl-claim": claim_table,
    "rl-claim-ttc": claim_ttc,
    "rl-wall-times": wall_times,
    "rl-reward-stats": reward_stats,
    "rl-export-match": export_match,
    "rl-range-beams": range_beams,
    "rl43-train-wall": study43_train_wall,
    "rl43-validation-check": validation_check,
    "rl43-scenes-shipped": scenes_shipped,
    "rl43-issue30-on-set": issue30_on_set,
    "rl-evaluation-runs": evaluation_runs,
}
"""docs/rl.md's blocks of the issue-30 study, registered in tools/results/generate.py."""
