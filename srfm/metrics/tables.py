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
  n ≥ :func:`min_n_for_best` (S) = max(2, ⌈0.8 S⌉): a planner that reached its goal in
  one seed of a hundred is never bold for its time to goal. Nothing is bold in a
  column where every planner's mean ties (every planner reached its goal every time).
- **Significance** is tested against one reference planner (the paper's "ours"): on a
  row of another planner, ``*`` marks a significant difference to the reference by
  Welch's t-test and ``†`` by the paired t-test over the shared seeds (p < 0.05); on the
  reference's own row a mark means the reference differs significantly from every
  other planner by that test.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any, Final

import attrs
import numpy as np

from srfm.errors import MetricError
from srfm.metrics.episode import EPISODE_METRICS, METRIC_GROUPS, EpisodeMetrics, MetricInfo
from srfm.metrics.stats import ALPHA, Comparison, Summary, compare, summarize

__all__ = [
    "EXTENDED_COLUMNS",
    "OUTCOME_COLUMNS",
    "TABLE_COLUMNS",
    "BenchmarkTable",
    "Cell",
    "benchmark_table",
    "legend",
    "min_n_for_best",
    "summary_dict",
    "to_latex",
    "to_latex_extended",
    "to_markdown",
    "to_markdown_extended",
]

_INFO: Final = {m.name: m for m in EPISODE_METRICS}

TABLE_COLUMNS: Final[tuple[tuple[str, str], ...]] = (
    ("frechet_m", "Fréchet dist. (m)"),
    ("min_robot_distance_m", "Min. robot dist. (m)"),
    ("path_length_m", "Traj. length (m)"),
    ("robot_duration_s", "Time: robot run (s)"),
)
"""The paper's Table 3 columns: metric name and header. The paper's "Time" column is
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
    (m.name, m.name) for group in METRIC_GROUPS for m in EPISODE_METRICS if m.group == group
)
"""Every episode metric, grouped (pedestrian side, social, robot), for the extended table."""


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
        cells: ``cells[(scenario, planner)][metric]``.
        comparisons: ``comparisons[(scenario, planner)][metric]`` against the reference.
    """

    columns: tuple[tuple[str, str], ...]
    scenarios: tuple[str, ...]
    planners: tuple[str, ...]
    reference: str | None
    cells: Mapping[tuple[str, str], Mapping[str, Cell]]
    comparisons: Mapping[tuple[str, str], Mapping[str, Comparison]]
    n_seeds: int = 0

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


def benchmark_table(
    results: Sequence[EpisodeMetrics],
    *,
    scenarios: Sequence[str],
    planners: Sequence[str],
    seeds: Sequence[int],
    reference: str | None,
    columns: Sequence[tuple[str, str]] = TABLE_COLUMNS,
) -> BenchmarkTable:
    """Summaries, best marks and significance for every (scenario, planner, column).

    Args:
        results: one entry per (scenario, planner, seed); others are ignored.
        scenarios: row order of the scenarios.
        planners: row order of the planners.
        seeds: the seeds to use (every one must be present for every row).
        reference: planner to test the others against (must be in ``planners``), or
            None for no tests.
        columns: (metric, header) pairs; metrics from :data:`EPISODE_METRICS`.
    """
    if reference is not None and reference not in planners:
        raise MetricError(f"reference planner {reference!r} is not among {list(planners)}")
    for name, _ in columns:
        if name not in _INFO:
            raise MetricError(f"unknown metric {name!r}; known: {sorted(_INFO)}")
    cells: dict[tuple[str, str], dict[str, Cell]] = {}
    comps: dict[tuple[str, str], dict[str, Comparison]] = {}
    seeds = list(seeds)
    min_n = min_n_for_best(len(seeds))
    for scenario in scenarios:
        values = {
            planner: {
                name: np.array(
                    [r.values[name] for r in _by_seed(results, scenario, planner, seeds)]
                )
                for name, _ in columns
            }
            for planner in planners
        }
        for name, _ in columns:
            summaries = {p: summarize(values[p][name]) for p in planners}
            best = _best(summaries, _INFO[name], min_n)
            row_comps: dict[str, Comparison] = {}
            if reference is not None:
                for p in planners:
                    if p != reference:
                        row_comps[p] = compare(values[reference][name], values[p][name])
            for p in planners:
                welch, paired = _marks(p, reference, row_comps)
                cells.setdefault((scenario, p), {})[name] = Cell(
                    summaries[p], p in best, welch, paired
                )
                if p in row_comps:
                    comps.setdefault((scenario, p), {})[name] = row_comps[p]
    return BenchmarkTable(
        columns=tuple(columns),
        scenarios=tuple(scenarios),
        planners=tuple(planners),
        reference=reference,
        cells=cells,
        comparisons=comps,
        n_seeds=len(seeds),
    )


def _best(summaries: Mapping[str, Summary], info: MetricInfo, min_n: int) -> set[str]:
    means = {p: s.mean for p, s in summaries.items() if s.n >= min_n and not math.isnan(s.mean)}
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
        return c.welch_significant, c.paired_significant
    if not comps:
        return False, False
    return (
        all(c.welch_significant for c in comps.values()),
        all(c.paired_significant for c in comps.values()),
    )


def _number(x: float) -> str:
    return "–" if math.isnan(x) else f"{x:.2f}"


def _cell_text(cell: Cell, n_seeds: int, *, latex: bool) -> str:
    s = cell.summary
    marks = (WELCH_MARK if cell.welch else "") + (PAIRED_MARK if cell.paired else "")
    n_note = f" (n={s.n})" if s.n < n_seeds else ""
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


def _arrow(name: str) -> str:
    return {"lower": " ↓", "higher": " ↑", "": ""}[_INFO[name].better]


def legend(table: BenchmarkTable, *, markdown: bool = True) -> str:
    """The rules of ``table`` in one paragraph: what a cell is, n, undefined values,
    bolding and the significance marks (printed under every table)."""
    s = table.n_seeds
    undefined = "`undefined`" if markdown else "'undefined'"
    text = (
        f"Mean ± sample std over the seeds with a defined value; (n=k): only k of the {s} "
        "seeds have one (the others are undefined, e.g. a time to goal that never "
        f"happened; counted as {undefined} in summary.json, never silently dropped). Bold: "
        f"best mean of the column within the scenario among the cells with n ≥ {table.min_n} "
        f"(the rule: n ≥ max(2, ⌈0.8 × {s} seeds⌉)), none where every planner ties; "
        "↓ lower is better, ↑ higher is better."
    )
    if table.reference is not None:
        star = f"\\{WELCH_MARK}" if markdown else WELCH_MARK
        text += (
            f" Significance against {table.reference} (p < {ALPHA}): {star} Welch's "
            f"t-test, {PAIRED_MARK} paired t-test over the shared seeds; on "
            f"{table.reference}'s own row, significant against every other planner."
        )
    return text


def to_markdown(table: BenchmarkTable) -> str:
    """The table as GitHub Markdown, with its rules (:func:`legend`) underneath."""
    headers = ["Scenario", "Planner"] + [f"{h}{_arrow(n)}" for n, h in table.columns]
    lines = [
        "| " + " | ".join(headers) + " |",
        "|" + "|".join(["---"] * 2 + ["--:"] * len(table.columns)) + "|",
    ]
    for scenario in table.scenarios:
        for planner in table.planners:
            row = table.cells[(scenario, planner)]
            texts = [_cell_text(row[n], table.n_seeds, latex=False) for n, _ in table.columns]
            lines.append("| " + " | ".join([scenario, planner, *texts]) + " |")
    return "\n".join(lines) + "\n\n" + legend(table) + "\n"


def to_markdown_extended(table: BenchmarkTable) -> str:
    """Every column of ``table`` as rows, a column per planner, one block per scenario,
    grouped as :data:`~srfm.metrics.episode.METRIC_GROUPS` (the extended table)."""
    names = [n for n, _ in table.columns]
    lines = [
        "# Every metric, per scenario",
        "",
        "Definitions, units and sources: docs/metrics.md. " + legend(table),
        "",
    ]
    for scenario in table.scenarios:
        lines += [
            f"## {scenario}",
            "",
            "| Metric | Unit | " + " | ".join(table.planners) + " |",
            "|---|---|" + "|".join(["--:"] * len(table.planners)) + "|",
        ]
        for group, title in METRIC_GROUPS.items():
            in_group = [n for n in names if _INFO[n].group == group]
            if not in_group:
                continue
            lines.append(f"| *{title}* | |" + " |" * len(table.planners))
            for name in in_group:
                texts = [
                    _cell_text(table.cells[(scenario, p)][name], table.n_seeds, latex=False)
                    for p in table.planners
                ]
                lines.append(
                    f"| `{name}`{_arrow(name)} | {_INFO[name].unit} | " + " | ".join(texts) + " |"
                )
        lines.append("")
    return "\n".join(lines)


def _tex_escape(text: str) -> str:
    return text.replace("\\", "\\textbackslash{}").replace("_", "\\_").replace("&", "\\&")


_TEX_ARROWS: Final = {"lower": "$\\downarrow$", "higher": "$\\uparrow$", "": ""}


def _tex_comment(text: str) -> str:
    return "% " + text.replace("\\*", "*")


def to_latex(table: BenchmarkTable) -> str:
    """The table as a LaTeX ``tabular`` (needs ``\\usepackage{multirow}``)."""
    heads = [
        f"\\textbf{{{_tex_escape(h)}}} {_TEX_ARROWS[_INFO[n].better]}".rstrip()
        for n, h in table.columns
    ]
    lines = [
        _tex_comment(legend(table, markdown=False)),
        "\\begin{tabular}{ll" + "c" * len(table.columns) + "}",
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
            row = table.cells[(scenario, planner)]
            texts = [_cell_text(row[n], table.n_seeds, latex=True) for n, _ in table.columns]
            lines.append(" & ".join([first, _tex_escape(planner), *texts]) + " \\\\")
        lines.append("\\hline")
    lines.append("\\end{tabular}")
    return "\n".join(lines) + "\n"


def to_latex_extended(table: BenchmarkTable) -> str:
    """The extended table as LaTeX: one ``tabular`` per scenario, a row per metric."""
    names = [n for n, _ in table.columns]
    cols = len(table.planners)
    lines = [_tex_comment(legend(table, markdown=False))]
    for scenario in table.scenarios:
        lines += [
            f"% {scenario}",
            "\\begin{tabular}{ll" + "c" * cols + "}",
            "\\hline",
            f"\\multicolumn{{{cols + 2}}}{{l}}{{\\textbf{{{_tex_escape(scenario)}}}}} \\\\",
            "\\textbf{Metric} & \\textbf{Unit} & "
            + " & ".join(f"\\textbf{{{_tex_escape(p)}}}" for p in table.planners)
            + " \\\\",
            "\\hline",
        ]
        for group, title in METRIC_GROUPS.items():
            in_group = [n for n in names if _INFO[n].group == group]
            if not in_group:
                continue
            lines.append(
                f"\\multicolumn{{{cols + 2}}}{{l}}{{\\textit{{{_tex_escape(title)}}}}} \\\\"
            )
            for name in in_group:
                texts = [
                    _cell_text(table.cells[(scenario, p)][name], table.n_seeds, latex=True)
                    for p in table.planners
                ]
                head = f"\\texttt{{{_tex_escape(name)}}} {_TEX_ARROWS[_INFO[name].better]}".rstrip()
                unit = _tex_escape(_INFO[name].unit)
                lines.append(" & ".join([head, unit, *texts]) + " \\\\")
        lines += ["\\hline", "\\end{tabular}", ""]
    return "\n".join(lines)


def _json_number(x: float) -> float | None:
    return None if math.isnan(x) else x


def summary_dict(table: BenchmarkTable) -> dict[str, Any]:
    """Every cell's n, undefined count, mean, std, bold flag and the tests against the
    reference, with the columns and the rules, as plain data (NaN as None) for a JSON
    summary."""
    out: dict[str, Any] = {
        "reference": table.reference,
        "alpha": ALPHA,
        "n_seeds": table.n_seeds,
        "min_n_for_best": table.min_n,
        "columns": [[name, header] for name, header in table.columns],
        "legend": legend(table, markdown=False),
        "scenarios": {},
    }
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
                    entry["paired_n"] = comp.n_pairs
                metrics[name] = entry
            per_planner[planner] = metrics
        out["scenarios"][scenario] = per_planner
    return out
