"""Benchmark tables: the paper's Table 3 layout, the robot outcomes and the extended
table of every metric, in Markdown and LaTeX, and a JSON summary.

Rows are (scenario, planner) (the extended table: one block per scenario, a row per
metric, a column per planner); each cell is mean ± sample std over the seeds that have
a value. Rules, stated under every table:

- **n.** A value can be undefined (NaN: a time to goal that never happened, a time to
  collision when nobody was on a collision course). Undefined values are not part of
  the mean; they are counted (``undefined`` in ``summary.json``), and a cell whose n
  is below the number of seeds S shows its n.
- **Bold.** The best mean of a column within a scenario, among the cells with
  n ≥ :func:`min_n_for_best` (S) = max(2, ⌈0.8 S⌉) whose planner reached the goal in at
  least the scenario's best goal rate minus ``GOAL_MARGIN`` (10 percentage points): a
  planner that reached its goal in one seed of a hundred is never bold for its time to
  goal, nor one that waited out the horizon for its gentle deviation. Nothing is bold in a
  column where every planner's mean ties (every planner reached its goal every time).
- **Conditioned on success.** A column ``METRIC|success`` (:func:`given_success`) holds
  the metric over the episodes in which the robot reached its goal only, and always
  shows its n (the number of such seeds): a planner that stops early or collides is not
  gentle on the people it never met. Every table also carries each planner's outcome
  shares (goal reached, collision, out of bounds, timeout) beside its numbers.
- **Significance** is tested against one reference planner (the paper's "ours"): on a
  row of another planner, ``*`` marks a significant difference to the reference by
  Welch's t-test and ``†`` by the paired t-test over the shared seeds; on the
  reference's own row a mark means the reference differs significantly from every
  other planner by that test. The p-values are adjusted for multiple comparisons over
  the table's family of tests (each kind of test on its own: every defined Welch
  p-value of the table is one family, every paired one another) and a mark means an
  adjusted p < 0.05: Holm's correction by default (the Table 3 layout and the
  outcomes), Benjamini–Hochberg's for the extended table of every metric
  (:func:`srfm.metrics.stats.adjust_p_values`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any, Final

import attrs
import numpy as np

from srfm._text import plain
from srfm.errors import MetricError
from srfm.metrics.episode import EPISODE_METRICS, METRIC_GROUPS, EpisodeMetrics, MetricInfo
from srfm.metrics.headroom import (
    DETECT_M,
    MIN_HEADROOM_M,
    MIN_SCORE_SHARE,
    MIN_STANDARD_ERRORS,
    POWER,
    Interval,
    ScenarioReferences,
    scenario_references,
)
from srfm.metrics.stats import (
    ALPHA,
    CORRECTIONS,
    Comparison,
    Summary,
    adjust_p_values,
    compare,
    summarize,
)
from srfm.sim.record import ROBOT_OUTCOMES

__all__ = [
    "EXTENDED_COLUMNS",
    "GIVEN_SUCCESS",
    "GOAL_MARGIN",
    "OUTCOME_COLUMNS",
    "TABLE_COLUMNS",
    "BenchmarkTable",
    "Cell",
    "ExtraBlock",
    "base_metric",
    "benchmark_table",
    "discrimination_text",
    "given_success",
    "headroom_text",
    "legend",
    "min_n_for_best",
    "outcome_shares",
    "references_markdown",
    "score_text",
    "share_text",
    "summary_dict",
    "to_latex",
    "to_latex_extended",
    "to_markdown",
    "to_markdown_extended",
]

_INFO: Final = {m.name: m for m in EPISODE_METRICS}

GIVEN_SUCCESS: Final = "|success"
"""The suffix of a column conditioned on success: ``frechet_m|success`` is the Fréchet
deviation over the episodes in which the robot reached its goal."""
SUCCESS_OUTCOME: Final = "goal_reached"


def given_success(metric: str) -> str:
    """The column name of ``metric`` conditioned on success (``frechet_m|success``)."""
    return metric + GIVEN_SUCCESS


def base_metric(column: str) -> str:
    """The metric a column holds (``frechet_m`` for ``frechet_m|success``)."""
    return column.removesuffix(GIVEN_SUCCESS)


def _conditioned(column: str) -> bool:
    return column.endswith(GIVEN_SUCCESS)


TABLE_COLUMNS: Final[tuple[tuple[str, str], ...]] = (
    ("frechet_m", "Fréchet dist. (m)"),
    (given_success("frechet_m"), "Fréchet dist. | success (m)"),
    ("min_robot_distance_m", "Min. robot dist. (m)"),
    (given_success("min_robot_distance_m"), "Min. robot dist. | success (m)"),
    ("path_length_m", "Traj. length (m)"),
    (given_success("path_length_m"), "Traj. length | success (m)"),
    ("robot_duration_s", "Time: robot run (s)"),
)
"""The paper's Table 3 columns, each pedestrian and social one also conditioned on
success (:func:`given_success`): column name and header. The paper's "Time" column is
the duration of the robot's run (its reference code recorded the pedestrians only until
the robot arrived), so that is what this column holds; the pedestrians' own time to
goal is ``time_to_goal_s`` in the extended table."""

OUTCOME_COLUMNS: Final[tuple[tuple[str, str], ...]] = (
    ("robot_success", "Success"),
    ("robot_collision", "Collision"),
    ("robot_timeout", "Timeout"),
    ("robot_out_of_bounds", "Out of bounds"),
    ("robot_time_to_goal_s", "Robot time (s)"),
    ("robot_path_length_m", "Robot path (m)"),
)
"""The robot-side table: outcome rates and the robot's own efficiency."""

EXTENDED_COLUMNS: Final[tuple[tuple[str, str], ...]] = tuple(
    column
    for group in METRIC_GROUPS
    for m in EPISODE_METRICS
    if m.group == group
    for column in (
        ((m.name, m.name), (given_success(m.name), given_success(m.name)))
        if group in ("pedestrian", "social")
        else ((m.name, m.name),)
    )
)
"""Every episode metric, grouped (pedestrian side, social, robot), for the extended
table; each pedestrian and social metric followed by the same conditioned on success."""

REFERENCE_PAIR: Final = ("straight", "oracle")
"""The planners whose presence adds the reference points (headroom, normalised scores)
to a table with a Fréchet column."""

DEFAULT_CORRECTION: Final = "holm"
"""The correction of a table's family of tests unless it names another."""


GOAL_MARGIN: Final = 0.1
"""A cell is bold only when its planner reached the goal in at least the scenario's
best goal rate minus this (10 percentage points): a planner that stays put is never
the gentlest."""


def min_n_for_best(n_seeds: int) -> int:
    """The least n for a cell to be bold: max(2, ⌈0.8 · n_seeds⌉)."""
    return max(2, math.ceil(0.8 * n_seeds - 1e-9))


WELCH_MARK: Final = "*"
PAIRED_MARK: Final = "†"


@attrs.frozen
class Cell:
    """One table cell: the summary over seeds, whether it is the column's best within
    its scenario, and the significance marks."""

    summary: Summary
    best: bool
    welch: bool
    paired: bool


@attrs.frozen
class BenchmarkTable:
    """Rows of (scenario, planner) with one :class:`Cell` per column.

    Attributes:
        columns: (metric name, header) pairs.
        scenarios: scenario names in row order.
        planners: planner names in row order within each scenario.
        reference: the planner significance is tested against (None: no tests).
        n_seeds: S, the number of seeds of every cell.
        cells: ``cells[(scenario, planner)][column]``.
        comparisons: ``comparisons[(scenario, planner)][column]`` against the reference,
            with the p-values adjusted over the table's family.
        correction: the multiple-comparison correction of the marks
            (:data:`srfm.metrics.stats.CORRECTIONS`).
        family: the number of defined tests of each kind (``"welch"``, ``"paired"``)
            the correction was taken over.
        outcomes: ``outcomes[(scenario, planner)][outcome]``: how many of the seeds
            ended in each of :data:`srfm.sim.record.ROBOT_OUTCOMES`.
        references: per scenario, the Fréchet deviation's reference points (headroom,
            normalised scores, standard error, seeds needed, whether it
            discriminates; :mod:`srfm.metrics.headroom`) when the table has a
            ``frechet_m`` column and both the ``straight`` and ``oracle`` planners;
            empty otherwise.
    """

    columns: tuple[tuple[str, str], ...]
    scenarios: tuple[str, ...]
    planners: tuple[str, ...]
    reference: str | None
    cells: Mapping[tuple[str, str], Mapping[str, Cell]]
    comparisons: Mapping[tuple[str, str], Mapping[str, Comparison]]
    n_seeds: int = 0
    correction: str = DEFAULT_CORRECTION
    family: Mapping[str, int] = attrs.field(factory=dict)
    outcomes: Mapping[tuple[str, str], Mapping[str, int]] = attrs.field(factory=dict)
    references: Mapping[str, ScenarioReferences] = attrs.field(factory=dict)

    @property
    def min_n(self) -> int:
        """The least n of a bold cell (:func:`min_n_for_best`)."""
        return min_n_for_best(self.n_seeds)


def _by_seed(
    results: Sequence[EpisodeMetrics], scenario: str, planner: str, seeds: Sequence[int]
) -> list[EpisodeMetrics]:
    found = {r.seed: r for r in results if r.scenario == scenario and r.planner == planner}
    missing = [s for s in seeds if s not in found]
    if missing:
        raise MetricError(
            f"no result for scenario {scenario!r}, planner {planner!r}, seeds {missing[:5]}"
        )
    return [found[s] for s in seeds]


def _column_value(result: EpisodeMetrics, column: str) -> float:
    """The value of one column for one episode: NaN for a column conditioned on success
    when the robot did not reach its goal."""
    if _conditioned(column) and result.outcome != SUCCESS_OUTCOME:
        return math.nan
    return float(result.values[base_metric(column)])


def benchmark_table(
    results: Sequence[EpisodeMetrics],
    *,
    scenarios: Sequence[str],
    planners: Sequence[str],
    seeds: Sequence[int],
    reference: str | None,
    columns: Sequence[tuple[str, str]] = TABLE_COLUMNS,
    correction: str = DEFAULT_CORRECTION,
    with_references: bool = True,
) -> BenchmarkTable:
    """Summaries, best marks and significance for every (scenario, planner, column).

    Args:
        results: one entry per (scenario, planner, seed); others are ignored.
        scenarios: row order of the scenarios.
        planners: row order of the planners.
        seeds: the seeds to use (every one must be present for every row).
        reference: planner to test the others against (must be in ``planners``), or
            None for no tests.
        columns: (column, header) pairs; a column is a metric of
            :data:`EPISODE_METRICS` or one conditioned on success (:func:`given_success`).
        correction: the multiple-comparison correction over the table's family of tests
            (each kind of test its own family), one of
            :data:`srfm.metrics.stats.CORRECTIONS`.
        with_references: add the reference points (``references``) when the run has
            ``straight`` and ``oracle`` and the table a ``frechet_m`` column.
    """
    if reference is not None and reference not in planners:
        raise MetricError(f"reference planner {reference!r} is not among {list(planners)}")
    if correction not in CORRECTIONS:
        raise MetricError(
            f"unknown correction {plain(correction)}; known: {', '.join(CORRECTIONS)}"
        )
    for name, _ in columns:
        if base_metric(name) not in _INFO:
            raise MetricError(f"unknown metric {plain(name)}; known: {sorted(_INFO)}")
    summaries: dict[tuple[str, str], dict[str, Summary]] = {}
    raw: dict[tuple[str, str], dict[str, Comparison]] = {}
    outcomes: dict[tuple[str, str], dict[str, int]] = {}
    seeds = list(seeds)
    min_n = min_n_for_best(len(seeds))
    for scenario in scenarios:
        episodes = {p: _by_seed(results, scenario, p, seeds) for p in planners}
        for p in planners:
            counts = dict.fromkeys(ROBOT_OUTCOMES, 0)
            for r in episodes[p]:
                counts[r.outcome] += 1
            outcomes[(scenario, p)] = counts
        for name, _ in columns:
            values = {p: np.array([_column_value(r, name) for r in episodes[p]]) for p in planners}
            for p in planners:
                summaries.setdefault((scenario, p), {})[name] = summarize(values[p])
                if reference is not None and p != reference:
                    raw.setdefault((scenario, p), {})[name] = compare(values[reference], values[p])
    comps, family = _adjusted(raw, correction)
    references: dict[str, ScenarioReferences] = {}
    if (
        with_references
        and all(p in planners for p in REFERENCE_PAIR)
        and any(n == "frechet_m" for n, _ in columns)
    ):
        for scenario in scenarios:
            episodes = {p: _by_seed(results, scenario, p, seeds) for p in planners}
            references[scenario] = scenario_references(
                {
                    p: np.array([_column_value(r, "frechet_m") for r in episodes[p]])
                    for p in planners
                },
                success={
                    p: np.array([r.outcome == SUCCESS_OUTCOME for r in episodes[p]])
                    for p in planners
                },
            )
    cells: dict[tuple[str, str], dict[str, Cell]] = {}
    for scenario in scenarios:
        rates = {p: outcomes[(scenario, p)][SUCCESS_OUTCOME] / max(1, len(seeds)) for p in planners}
        top = max(rates.values(), default=0.0)
        eligible = {p for p in planners if rates[p] >= top - GOAL_MARGIN - 1e-12}
        for name, _ in columns:
            column = {p: summaries[(scenario, p)][name] for p in planners}
            best = _best(column, _INFO[base_metric(name)], min_n, eligible)
            row_comps = {p: comps[(scenario, p)][name] for p in planners if (scenario, p) in comps}
            for p in planners:
                welch, paired = _marks(p, reference, row_comps)
                cells.setdefault((scenario, p), {})[name] = Cell(
                    column[p], p in best, welch, paired
                )
    return BenchmarkTable(
        columns=tuple(columns),
        scenarios=tuple(scenarios),
        planners=tuple(planners),
        reference=reference,
        cells=cells,
        comparisons=comps,
        n_seeds=len(seeds),
        correction=correction,
        family=family,
        outcomes=outcomes,
        references=references,
    )


def _adjusted(
    raw: Mapping[tuple[str, str], Mapping[str, Comparison]], correction: str
) -> tuple[dict[tuple[str, str], dict[str, Comparison]], dict[str, int]]:
    """Every comparison with its p-values adjusted over the family of its kind of test
    (all Welch p-values of the table, all paired ones), and the size of each family."""
    keys = [(row, name) for row, by_name in raw.items() for name in by_name]
    welch = np.array([raw[row][name].welch_p for row, name in keys], dtype=np.float64)
    paired = np.array([raw[row][name].paired_p for row, name in keys], dtype=np.float64)
    welch_adj = adjust_p_values(welch, correction)
    paired_adj = adjust_p_values(paired, correction)
    out: dict[tuple[str, str], dict[str, Comparison]] = {}
    for k, (row, name) in enumerate(keys):
        out.setdefault(row, {})[name] = attrs.evolve(
            raw[row][name],
            welch_p_adjusted=float(welch_adj[k]),
            paired_p_adjusted=float(paired_adj[k]),
        )
    family = {
        "welch": int(np.count_nonzero(np.isfinite(welch))),
        "paired": int(np.count_nonzero(np.isfinite(paired))),
    }
    return out, family


def _best(
    summaries: Mapping[str, Summary], info: MetricInfo, min_n: int, eligible: set[str]
) -> set[str]:
    means = {
        p: s.mean
        for p, s in summaries.items()
        if s.n >= min_n and not math.isnan(s.mean) and p in eligible
    }
    if not means or info.better == "":
        return set()
    target = min(means.values()) if info.better == "lower" else max(means.values())
    best = {p for p, m in means.items() if m == target}
    # A column where every planner ties (all 1.00 success) singles nobody out.
    return set() if best == set(summaries) else best


def _marks(
    planner: str, reference: str | None, comps: Mapping[str, Comparison]
) -> tuple[bool, bool]:
    if reference is None:
        return False, False
    if planner != reference:
        c = comps[planner]
        return c.welch_p_adjusted < ALPHA, c.paired_p_adjusted < ALPHA
    if not comps:
        return False, False
    return (
        all(c.welch_p_adjusted < ALPHA for c in comps.values()),
        all(c.paired_p_adjusted < ALPHA for c in comps.values()),
    )


def _number(x: float) -> str:
    return "–" if math.isnan(x) else f"{x:.2f}"


_OUTCOME_SHORT: Final = {
    "goal_reached": "goal",
    "collision": "coll.",
    "out_of_bounds": "out",
    "timeout": "timeout",
    "planner_failed": "failed",
}


def share_text(k: int, n: int) -> str:
    """k of n as a percentage that never reads 0 % or 100 % unless it is exactly that:
    499 of 500 is 99.8 %, not 100 %."""
    if n == 0:
        return "–"
    share = 100.0 * k / n
    for digits in (0, 1):
        text = f"{share:.{digits}f}"
        if 0 < k < n and float(text) in (0.0, 100.0):
            continue
        return f"{text} %"
    return "< 0.1 %" if share < 50 else "> 99.9 %"


def outcome_shares(counts: Mapping[str, int]) -> str:
    """How a cell's episodes ended, as shares: the goal always, then every other
    outcome that happened (``"72 % goal, 28 % coll."``)."""
    n = sum(counts.values())
    parts = [f"{share_text(counts.get('goal_reached', 0), n)} goal"]
    parts += [
        f"{share_text(counts[o], n)} {_OUTCOME_SHORT[o]}"
        for o in ROBOT_OUTCOMES
        if o != "goal_reached" and counts.get(o)
    ]
    return ", ".join(parts)


def _cell_text(cell: Cell, n_seeds: int, *, latex: bool, always_n: bool = False) -> str:
    s = cell.summary
    marks = (WELCH_MARK if cell.welch else "") + (PAIRED_MARK if cell.paired else "")
    n_note = f" (n={s.n})" if s.n < n_seeds or always_n else ""
    if latex:
        body = f"{_number(s.mean)} \\pm {_number(s.std)}".replace("–", "\\text{--}")
        if cell.best:
            body = f"\\mathbf{{{body}}}"
        mark = marks.replace(PAIRED_MARK, "\\dagger").replace(WELCH_MARK, "\\ast")
        return f"${'^{' + mark + '}' if mark else ''}{body}${n_note}"
    body = f"{_number(s.mean)} ± {_number(s.std)}"
    if cell.best:
        body = f"**{body}**"
    marks = marks.replace("*", "\\*")  # a literal asterisk, not emphasis
    return (f"{marks}{body}" if marks else body) + n_note


def _text(table: BenchmarkTable, scenario: str, planner: str, column: str, *, latex: bool) -> str:
    return _cell_text(
        table.cells[(scenario, planner)][column],
        table.n_seeds,
        latex=latex,
        always_n=_conditioned(column),
    )


def _arrow(name: str) -> str:
    return {"lower": " ↓", "higher": " ↑", "": ""}[_INFO[base_metric(name)].better]


def legend(table: BenchmarkTable, *, markdown: bool = True, model: str | None = None) -> str:
    """The rules of ``table`` in one paragraph: what a cell is, n, undefined values,
    conditioning on success, bolding and the significance marks with their correction
    (printed under every table); with ``model``, the response model of the pedestrians
    the table was computed under (:func:`srfm.models.params.response_model_name`)."""
    s = table.n_seeds
    undefined = "`undefined`" if markdown else "'undefined'"
    text = (
        f"Mean ± sample std over the seeds with a defined value; (n=k): only k of the {s} "
        "seeds have one (the others are undefined, e.g. a time to goal that never "
        f"happened; counted as {undefined} in summary.json, never silently dropped). Bold: "
        f"best mean of the column within the scenario among the cells with n ≥ {table.min_n} "
        f"(the rule: n ≥ max(2, ⌈0.8 × {s} seeds⌉)) whose planner reached the goal in at "
        f"least the scenario's best goal rate minus {GOAL_MARGIN * 100:g} percentage points, "
        "none where every planner ties; ↓ lower is better, ↑ higher is better."
    )
    if any(_conditioned(n) for n, _ in table.columns):
        text += (
            " '| success': the same metric over the seeds in which the robot reached its "
            "goal only, with their number n in every cell; outcomes: the shares of the "
            "seeds that ended with the goal reached, a collision (coll.), out of bounds "
            "(out) or a timeout."
        )
        if any(counts.get("planner_failed") for counts in table.outcomes.values()):
            text += (
                " failed: an external planner failed and its episode ended there "
                "(docs/planners-any-language.md)."
            )
    if table.reference is not None:
        star = f"\\{WELCH_MARK}" if markdown else WELCH_MARK
        how = CORRECTIONS[table.correction]
        family = (
            f"adjusted p < {ALPHA} after {how} over this table's "
            f"{table.family.get('welch', 0)} Welch and, separately, "
            f"{table.family.get('paired', 0)} paired tests"
            if table.correction != "none"
            else f"p < {ALPHA}, {how}"
        )
        text += (
            f" Significance against {table.reference} ({family}): {star} Welch's "
            f"t-test, {PAIRED_MARK} paired t-test over the shared seeds; on "
            f"{table.reference}'s own row, significant against every other planner."
        )
    if model is not None:
        text += f" Response model of the pedestrians: {model}."
    return text


def to_markdown(table: BenchmarkTable, *, model: str | None = None) -> str:
    """The table as GitHub Markdown, with each row's outcome shares and its rules
    (:func:`legend`, naming the response model ``model`` when given) underneath."""
    headers = ["Scenario", "Planner"]
    headers += [f"{h}{_arrow(n)}".replace("|", "\\|") for n, h in table.columns]
    scored = bool(table.references)
    if scored:
        headers.append("Norm. score ↑")
    headers.append("Outcomes")
    lines = [
        "| " + " | ".join(headers) + " |",
        "|" + "|".join(["---"] * 2 + ["--:"] * (len(table.columns) + scored) + ["---"]) + "|",
    ]
    for scenario in table.scenarios:
        for planner in table.planners:
            texts = [_text(table, scenario, planner, n, latex=False) for n, _ in table.columns]
            if scored:
                texts.append(score_text(table.references[scenario], planner))
            shares = outcome_shares(table.outcomes[(scenario, planner)])
            lines.append("| " + " | ".join([scenario, planner, *texts, shares]) + " |")
    text = "\n".join(lines) + "\n\n" + legend(table, model=model) + "\n"
    if scored:
        text += "\n" + references_markdown(table)
    return text


def _interval_text(x: Interval, spec: str) -> str:
    if math.isnan(x.estimate):
        return "–"
    if math.isnan(x.low):
        return format(x.estimate, spec)
    return f"{x.estimate:{spec}} [{x.low:{spec}}, {x.high:{spec}}]"


def score_text(ref: ScenarioReferences, planner: str) -> str:
    """A planner's normalised score with its interval and k/n, the seeds on which it,
    ``straight`` and the oracle all reached the goal: ``0.19 [0.16, 0.23] (k=97/100)``;
    ``undefined (k=1/3)`` below :func:`srfm.metrics.headroom.min_score_seeds`."""
    score = ref.scores[planner]
    k = f"(k={score.n}/{ref.n_seeds})"
    if math.isnan(score.estimate):
        return f"undefined {k}"
    return f"{_interval_text(score, '.2f')} {k}"


def headroom_text(ref: ScenarioReferences) -> str:
    """The headroom with its interval, labelled a lower bound where a planner beat the
    oracle (the oracle is then not a bound)."""
    text = _interval_text(ref.headroom, ".3f")
    if not ref.oracle_is_bound:
        text += f" ≥ (lower bound: {', '.join(ref.beats_oracle)} beat the oracle)"
    return text


def discrimination_text(ref: ScenarioReferences) -> str:
    """``yes`` or ``does not discriminate`` with the reason."""
    if ref.discriminates:
        return "yes"
    room = ref.headroom.estimate
    why = []
    if not room >= MIN_HEADROOM_M:
        why.append(f"headroom < {MIN_HEADROOM_M:g} m")
    if not room >= MIN_STANDARD_ERRORS * ref.standard_error:
        why.append(f"headroom < {MIN_STANDARD_ERRORS:g} SE")
    return "**does not discriminate**" + (f" ({', '.join(why)})" if why else "")


def references_legend() -> str:
    """What the reference points are, in one paragraph."""
    return (
        "Reference points of the Fréchet deviation (docs/benchmark.md): headroom = "
        "straight − oracle, mean over the seeds with its paired 95 % t-interval; SE: the "
        "seed-to-seed standard error of straight's mean; seeds needed to detect a "
        f"{DETECT_M:g} m difference between two planners (paired t-test, α = {ALPHA}, "
        f"power {POWER:g}); a scenario whose headroom is below {MIN_HEADROOM_M:g} m or "
        f"below {MIN_STANDARD_ERRORS:g} SE does not discriminate. Norm. score = "
        "(straight − planner) / (straight − oracle) of the means (0: straight, 1: the "
        "oracle) over the k of the n seeds on which the planner, straight and the oracle "
        "all reached the goal (paired; the headroom over the seeds on which straight and "
        "the oracle did), with the 95 % percentile interval of a paired bootstrap over "
        f"those seeds; undefined below k = max(2, ⌈{MIN_SCORE_SHARE:g} n⌉). Where a planner "
        "scores above 1 the oracle is not a bound and the headroom is a lower bound."
    )


def references_markdown(table: BenchmarkTable) -> str:
    """The reference points of every scenario as a Markdown table with its legend."""
    lines = [
        "| Scenario | Headroom (m) [95 % CI] | SE (m) | Seeds for "
        f"{DETECT_M:g} m | Discriminates |",
        "|---|--:|--:|--:|---|",
    ]
    for scenario in table.scenarios:
        ref = table.references[scenario]
        needed = "–" if ref.seeds_needed is None else str(ref.seeds_needed)
        se = "–" if math.isnan(ref.standard_error) else f"{ref.standard_error:.3f}"
        lines.append(
            f"| {scenario} | {headroom_text(ref)} | {se} | {needed} | {discrimination_text(ref)} |"
        )
    return "\n".join(lines) + "\n\n" + references_legend() + "\n"


def _row_label(name: str) -> str:
    """A metric's row in the extended table: ``frechet_m`` or ``frechet_m`` | success."""
    base = base_metric(name)
    return f"`{base}` \\| success" if _conditioned(name) else f"`{base}`"


@attrs.frozen
class ExtraBlock:
    """Rows added under a scenario's block of the extended table (no bold, no tests).

    Attributes:
        title: the group's title row.
        rows: (name, unit, one text per planner) per row.
        note: a paragraph under the scenario's table.
    """

    title: str
    rows: tuple[tuple[str, str, tuple[str, ...]], ...]
    note: str = ""


def to_markdown_extended(
    table: BenchmarkTable,
    extra: Mapping[str, ExtraBlock] | None = None,
    *,
    model: str | None = None,
) -> str:
    """Every column of ``table`` as rows, a column per planner, one block per scenario,
    grouped as :data:`~srfm.metrics.episode.METRIC_GROUPS`, under a row of the
    planners' outcome shares (the extended table); ``extra[scenario]`` adds its rows
    and note under the scenario's block."""
    names = [n for n, _ in table.columns]
    lines = [
        "# Every metric, per scenario",
        "",
        "Definitions, units and sources: docs/metrics.md. " + legend(table, model=model),
        "",
    ]
    for scenario in table.scenarios:
        shares = [outcome_shares(table.outcomes[(scenario, p)]) for p in table.planners]
        lines += [
            f"## {scenario}",
            "",
            "| Metric | Unit | " + " | ".join(table.planners) + " |",
            "|---|---|" + "|".join(["--:"] * len(table.planners)) + "|",
            "| Outcomes | | " + " | ".join(shares) + " |",
        ]
        for group, title in METRIC_GROUPS.items():
            in_group = [n for n in names if _INFO[base_metric(n)].group == group]
            if not in_group:
                continue
            lines.append(f"| *{title}* | |" + " |" * len(table.planners))
            for name in in_group:
                texts = [_text(table, scenario, p, name, latex=False) for p in table.planners]
                unit = _INFO[base_metric(name)].unit
                lines.append(
                    f"| {_row_label(name)}{_arrow(name)} | {unit} | " + " | ".join(texts) + " |"
                )
        block = (extra or {}).get(scenario)
        if block is not None:
            lines.append(f"| *{block.title}* | |" + " |" * len(table.planners))
            for name, unit, row in block.rows:
                lines.append(f"| {name} | {unit} | " + " | ".join(row) + " |")
            if block.note:
                lines += ["", block.note]
        lines.append("")
    return "\n".join(lines)


def _tex_escape(text: str) -> str:
    return (
        text.replace("\\", "\\textbackslash{}")
        .replace("_", "\\_")
        .replace("&", "\\&")
        .replace("%", "\\%")
        .replace("|", "$\\mid$")
    )


_TEX_ARROWS: Final = {"lower": "$\\downarrow$", "higher": "$\\uparrow$", "": ""}


def _tex_comment(text: str) -> str:
    return "% " + text.replace("\\*", "*")


def to_latex(table: BenchmarkTable, *, model: str | None = None) -> str:
    """The table as a LaTeX ``tabular`` (needs ``\\usepackage{multirow}``), its legend
    (naming the response model ``model`` when given) as a comment."""
    heads = [
        f"\\textbf{{{_tex_escape(h)}}} {_TEX_ARROWS[_INFO[base_metric(n)].better]}".rstrip()
        for n, h in table.columns
    ]
    scored = bool(table.references)
    if scored:
        heads.append("\\textbf{Norm. score} $\\uparrow$")
    heads.append("\\textbf{Outcomes}")
    lines = [
        _tex_comment(legend(table, markdown=False, model=model)),
        "\\begin{tabular}{ll" + "c" * (len(table.columns) + scored) + "l}",
        "\\hline",
        " & \\textbf{Planner} & " + " & ".join(heads) + " \\\\",
        "\\hline",
    ]
    for scenario in table.scenarios:
        for k, planner in enumerate(table.planners):
            first = (
                f"\\multirow{{{len(table.planners)}}}{{*}}{{{_tex_escape(scenario)}}}"
                if k == 0
                else ""
            )
            texts = [_text(table, scenario, planner, n, latex=True) for n, _ in table.columns]
            if scored:
                texts.append(
                    _tex_escape(score_text(table.references[scenario], planner)).replace("–", "--")
                )
            shares = _tex_escape(outcome_shares(table.outcomes[(scenario, planner)]))
            lines.append(" & ".join([first, _tex_escape(planner), *texts, shares]) + " \\\\")
        lines.append("\\hline")
    lines.append("\\end{tabular}")
    return "\n".join(lines) + "\n"


def to_latex_extended(
    table: BenchmarkTable,
    extra: Mapping[str, ExtraBlock] | None = None,
    *,
    model: str | None = None,
) -> str:
    """The extended table as LaTeX: one ``tabular`` per scenario, a row per metric
    (``extra``: as :func:`to_markdown_extended`, its note as a comment)."""
    names = [n for n, _ in table.columns]
    cols = len(table.planners)
    lines = [_tex_comment(legend(table, markdown=False, model=model))]
    for scenario in table.scenarios:
        shares = [
            _tex_escape(outcome_shares(table.outcomes[(scenario, p)])) for p in table.planners
        ]
        lines += [
            f"% {scenario}",
            "\\begin{tabular}{ll" + "c" * cols + "}",
            "\\hline",
            f"\\multicolumn{{{cols + 2}}}{{l}}{{\\textbf{{{_tex_escape(scenario)}}}}} \\\\",
            "\\textbf{Metric} & \\textbf{Unit} & "
            + " & ".join(f"\\textbf{{{_tex_escape(p)}}}" for p in table.planners)
            + " \\\\",
            "\\hline",
            "Outcomes & & " + " & ".join(shares) + " \\\\",
        ]
        for group, title in METRIC_GROUPS.items():
            in_group = [n for n in names if _INFO[base_metric(n)].group == group]
            if not in_group:
                continue
            lines.append(
                f"\\multicolumn{{{cols + 2}}}{{l}}{{\\textit{{{_tex_escape(title)}}}}} \\\\"
            )
            for name in in_group:
                texts = [_text(table, scenario, p, name, latex=True) for p in table.planners]
                base = base_metric(name)
                label = f"\\texttt{{{_tex_escape(base)}}}" + (
                    " $\\mid$ success" if _conditioned(name) else ""
                )
                head = f"{label} {_TEX_ARROWS[_INFO[base].better]}".rstrip()
                unit = _tex_escape(_INFO[base].unit)
                lines.append(" & ".join([head, unit, *texts]) + " \\\\")
        block = (extra or {}).get(scenario)
        if block is not None:
            lines.append(
                f"\\multicolumn{{{cols + 2}}}{{l}}{{\\textit{{{_tex_escape(block.title)}}}}} \\\\"
            )
            for name, unit, row in block.rows:
                cells = [_tex_escape(name.replace("`", "")), _tex_escape(unit)]
                cells += [_tex_escape(t).replace("±", "$\\pm$").replace("–", "--") for t in row]
                lines.append(" & ".join(cells) + " \\\\")
        lines += ["\\hline", "\\end{tabular}", ""]
        if block is not None and block.note:
            lines += [_tex_comment(block.note), ""]
    return "\n".join(lines)


def _json_number(x: float) -> float | None:
    return None if math.isnan(x) else x


def summary_dict(table: BenchmarkTable) -> dict[str, Any]:
    """Every cell's n, undefined count, mean, std, bold flag and the tests against the
    reference (raw and adjusted p-values), each row's outcome counts, with the columns,
    the correction and the rules, as plain data (NaN as None) for a JSON summary."""
    out: dict[str, Any] = {
        "reference": table.reference,
        "alpha": ALPHA,
        "correction": table.correction,
        "family": dict(table.family),
        "n_seeds": table.n_seeds,
        "min_n_for_best": table.min_n,
        "columns": [[name, header] for name, header in table.columns],
        "legend": legend(table, markdown=False),
        "outcomes": {
            scenario: {p: dict(table.outcomes[(scenario, p)]) for p in table.planners}
            for scenario in table.scenarios
        },
        "scenarios": {},
    }
    if table.references:
        out["references"] = {
            scenario: _references_dict(table.references[scenario]) for scenario in table.scenarios
        }
        out["references_legend"] = references_legend()
    for scenario in table.scenarios:
        per_planner: dict[str, Any] = {}
        for planner in table.planners:
            metrics: dict[str, Any] = {}
            for name, _ in table.columns:
                cell = table.cells[(scenario, planner)][name]
                entry: dict[str, Any] = {
                    "n": cell.summary.n,
                    "undefined": cell.summary.undefined,
                    "mean": _json_number(cell.summary.mean),
                    "std": _json_number(cell.summary.std),
                    "best": cell.best,
                    "marks": (WELCH_MARK if cell.welch else "")
                    + (PAIRED_MARK if cell.paired else ""),
                }
                comp = table.comparisons.get((scenario, planner), {}).get(name)
                if comp is not None:
                    entry["welch_p"] = _json_number(comp.welch_p)
                    entry["paired_p"] = _json_number(comp.paired_p)
                    entry["welch_p_adjusted"] = _json_number(comp.welch_p_adjusted)
                    entry["paired_p_adjusted"] = _json_number(comp.paired_p_adjusted)
                    entry["paired_n"] = comp.n_pairs
                metrics[name] = entry
            per_planner[planner] = metrics
        out["scenarios"][scenario] = per_planner
    return out


def _interval_dict(x: Interval) -> dict[str, Any]:
    return {
        "estimate": _json_number(x.estimate),
        "low": _json_number(x.low),
        "high": _json_number(x.high),
        "n": x.n,
        "level": x.level,
    }


def _references_dict(ref: ScenarioReferences) -> dict[str, Any]:
    return {
        "n": ref.n,
        "headroom": _interval_dict(ref.headroom),
        "standard_error": _json_number(ref.standard_error),
        "sd_diff": _json_number(ref.sd_diff),
        "seeds_needed": ref.seeds_needed,
        "discriminates": ref.discriminates,
        "n_seeds": ref.n_seeds,
        "oracle_is_bound": ref.oracle_is_bound,
        "beats_oracle": list(ref.beats_oracle),
        "headroom_is_lower_bound": not ref.oracle_is_bound,
        "scores": {p: _interval_dict(x) for p, x in ref.scores.items()},
    }
