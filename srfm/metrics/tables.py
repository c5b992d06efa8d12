"""Benchmark tables: the paper's Table 3 layout in Markdown and LaTeX, and a JSON summary.

Rows are (scenario, planner); each cell is mean ± sample std over seeds. The best mean
of a column within a scenario is bold. Significance is tested against one reference
planner (the paper's "ours"): on a row of another planner, ``*`` marks a significant
difference to the reference by Welch's t-test and ``†`` by the paired t-test over the
shared seeds (p < 0.05); on the reference's own row a mark means the reference differs
significantly from every other planner by that test.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any, Final

import attrs
import numpy as np

from srfm.errors import MetricError
from srfm.metrics.episode import EPISODE_METRICS, EpisodeMetrics, MetricInfo
from srfm.metrics.stats import ALPHA, Comparison, Summary, compare, summarize

__all__ = [
    "OUTCOME_COLUMNS",
    "TABLE_COLUMNS",
    "BenchmarkTable",
    "Cell",
    "benchmark_table",
    "summary_dict",
    "to_latex",
    "to_markdown",
]

_INFO: Final = {m.name: m for m in EPISODE_METRICS}

TABLE_COLUMNS: Final[tuple[tuple[str, str], ...]] = (
    ("frechet_m", "Fréchet dist. (m)"),
    ("min_robot_distance_m", "Min. robot dist. (m)"),
    ("path_length_m", "Traj. length (m)"),
    ("time_to_goal_s", "Time (s)"),
)
"""The paper's Table 3 columns: metric name and header."""

OUTCOME_COLUMNS: Final[tuple[tuple[str, str], ...]] = (
    ("robot_success", "Success"),
    ("robot_collision", "Collision"),
    ("robot_timeout", "Timeout"),
    ("robot_out_of_bounds", "Out of bounds"),
    ("robot_time_to_goal_s", "Robot time (s)"),
    ("robot_path_length_m", "Robot path (m)"),
)
"""The robot-side table: outcome rates and the robot's own efficiency."""

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
        cells: ``cells[(scenario, planner)][metric]``.
        comparisons: ``comparisons[(scenario, planner)][metric]`` against the reference.
    """

    columns: tuple[tuple[str, str], ...]
    scenarios: tuple[str, ...]
    planners: tuple[str, ...]
    reference: str | None
    cells: Mapping[tuple[str, str], Mapping[str, Cell]]
    comparisons: Mapping[tuple[str, str], Mapping[str, Comparison]]


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
            best = _best(summaries, _INFO[name])
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
    )


def _best(summaries: Mapping[str, Summary], info: MetricInfo) -> set[str]:
    means = {p: s.mean for p, s in summaries.items() if not math.isnan(s.mean)}
    if not means or info.better == "":
        return set()
    target = min(means.values()) if info.better == "lower" else max(means.values())
    return {p for p, m in means.items() if m == target}


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


def _cell_text(cell: Cell, *, latex: bool) -> str:
    s = cell.summary
    marks = (WELCH_MARK if cell.welch else "") + (PAIRED_MARK if cell.paired else "")
    if latex:
        body = f"{_number(s.mean)} \\pm {_number(s.std)}".replace("–", "\\text{--}")
        if cell.best:
            body = f"\\mathbf{{{body}}}"
        mark = marks.replace(PAIRED_MARK, "\\dagger").replace(WELCH_MARK, "\\ast")
        return f"${'^{' + mark + '}' if mark else ''}{body}$"
    body = f"{_number(s.mean)} ± {_number(s.std)}"
    if cell.best:
        body = f"**{body}**"
    marks = marks.replace("*", "\\*")  # a literal asterisk, not emphasis
    return f"{marks}{body}" if marks else body


def _arrow(name: str) -> str:
    return {"lower": " ↓", "higher": " ↑", "": ""}[_INFO[name].better]


def _legend(table: BenchmarkTable) -> str:
    text = "Mean ± sample std over seeds; bold: best mean of the column within the scenario."
    if table.reference is not None:
        text += (
            f" Significance against {table.reference} (p < {ALPHA}): \\{WELCH_MARK} Welch's "
            f"t-test, {PAIRED_MARK} paired t-test over the shared seeds; on "
            f"{table.reference}'s own row, significant against every other planner."
        )
    return text


def to_markdown(table: BenchmarkTable) -> str:
    """The table as GitHub Markdown, with a legend line underneath."""
    headers = ["Scenario", "Planner"] + [f"{h}{_arrow(n)}" for n, h in table.columns]
    lines = [
        "| " + " | ".join(headers) + " |",
        "|" + "|".join(["---"] * 2 + ["--:"] * len(table.columns)) + "|",
    ]
    for scenario in table.scenarios:
        for planner in table.planners:
            row = table.cells[(scenario, planner)]
            texts = [_cell_text(row[n], latex=False) for n, _ in table.columns]
            lines.append("| " + " | ".join([scenario, planner, *texts]) + " |")
    return "\n".join(lines) + "\n\n" + _legend(table) + "\n"


def _tex_escape(text: str) -> str:
    return text.replace("\\", "\\textbackslash{}").replace("_", "\\_").replace("&", "\\&")


def to_latex(table: BenchmarkTable) -> str:
    """The table as a LaTeX ``tabular`` (needs ``\\usepackage{multirow}``)."""
    arrows = {"lower": "$\\downarrow$", "higher": "$\\uparrow$", "": ""}
    heads = [
        f"\\textbf{{{_tex_escape(h)}}} {arrows[_INFO[n].better]}".rstrip() for n, h in table.columns
    ]
    lines = [
        "% " + _legend(table),
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
            texts = [_cell_text(row[n], latex=True) for n, _ in table.columns]
            lines.append(" & ".join([first, _tex_escape(planner), *texts]) + " \\\\")
        lines.append("\\hline")
    lines.append("\\end{tabular}")
    return "\n".join(lines) + "\n"


def _json_number(x: float) -> float | None:
    return None if math.isnan(x) else x


def summary_dict(table: BenchmarkTable) -> dict[str, Any]:
    """Every cell's n, mean, std and the tests against the reference, as plain data
    (NaN as None) for a JSON summary."""
    out: dict[str, Any] = {"reference": table.reference, "alpha": ALPHA, "scenarios": {}}
    for scenario in table.scenarios:
        per_planner: dict[str, Any] = {}
        for planner in table.planners:
            metrics: dict[str, Any] = {}
            for name, _ in table.columns:
                cell = table.cells[(scenario, planner)][name]
                entry: dict[str, Any] = {
                    "n": cell.summary.n,
                    "mean": _json_number(cell.summary.mean),
                    "std": _json_number(cell.summary.std),
                    "best": cell.best,
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
