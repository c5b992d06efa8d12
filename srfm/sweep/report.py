"""``srfm sweep report DIR``: what a sweep says about the planners.

Two parts, written into ``DIR/report/``:

- **Against each factor** (``<factor>.png``, ``<factor>_by_scenario.png``): each
  planner's mean Fréchet deviation and success rate at every value of the factor, the
  other factors and the scenarios pooled, with 95 % confidence bands (Student's t
  interval of the mean; Wilson's interval of a proportion); and the deviation per
  scenario.
- **Ranking stability** (``report.md``, ``rankings.csv``): in every cell and scenario
  the planners are ranked by their mean of the metric (default ``frechet_m``, lower is
  better); Kendall's τ (``scipy.stats.kendalltau``, τ-b: ties allowed) compares each
  cell's ranking with the reference cell's (the cell whose values are the sweep's base
  parameters, else the first), per scenario and for the scenario-averaged ranking; and
  each pair of planners whose order in a cell is the reverse of the reference order is
  listed as a flip, with the paired t-test of the two planners in that cell (the same
  seeds), so a flip inside the noise can be told from a real one.

Rows with a null metric (undefined for that episode) are left out of its mean, as in
the benchmark's tables. The report reads whatever partitions exist: on a sweep still
running it says how many episodes it found.
"""

from __future__ import annotations

import csv
import io
import itertools
import json
import math
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, Final

import attrs
import numpy as np
from numpy.typing import NDArray

from srfm._io import MAX_DOCUMENT_BYTES, read_input_bytes, write_file_set
from srfm._text import count
from srfm.errors import SweepError
from srfm.metrics.episode import EPISODE_METRICS
from srfm.metrics.stats import ALPHA, compare, wilson
from srfm.sweep._run import DATA_DIR, SWEEP_MANIFEST

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = [
    "REPORT_DIR",
    "SweepData",
    "kendall_tau",
    "load_sweep",
    "report_figures",
    "report_text",
    "write_sweep_report",
]

REPORT_DIR: Final = "report"
_DPI: Final = 110
FloatArray = NDArray[np.float64]


@attrs.frozen(kw_only=True, eq=False)
class SweepData:
    """A sweep's manifest and its episodes as columns.

    Attributes:
        folder: the sweep folder.
        factors: the design's factors.
        cells: cell id -> factor values.
        scenarios, planners: in the spec's order.
        base: the base SRFM parameters.
        columns: column name -> (E,) array, one entry per episode found, sorted by
            (cell, scenario, planner, seed) in the spec's order.
        expected: episodes in the whole sweep.
    """

    folder: Path
    factors: tuple[str, ...]
    cells: dict[str, dict[str, float]]
    scenarios: tuple[str, ...]
    planners: tuple[str, ...]
    base: dict[str, float]
    columns: dict[str, NDArray[Any]]
    expected: int

    @classmethod
    def from_columns(
        cls,
        *,
        folder: Path,
        factors: tuple[str, ...],
        cells: dict[str, dict[str, float]],
        scenarios: tuple[str, ...],
        planners: tuple[str, ...],
        base: dict[str, float],
        columns: dict[str, NDArray[Any]],
        expected: int,
    ) -> SweepData:
        """A sweep's data from episodes as columns in any order (``cell``,
        ``scenario``, ``planner``, ``seed``, the factors and the metrics the report
        reads), sorted by (cell, scenario, planner, seed) in the spec's order: how
        :func:`load_sweep` reads a sweep folder, and how a sweep's episodes kept
        elsewhere are read back."""
        cell_rank = {c: i for i, c in enumerate(cells)}
        scen_rank = {s: i for i, s in enumerate(scenarios)}
        plan_rank = {p: i for i, p in enumerate(planners)}
        order = sorted(
            range(len(columns["seed"])),
            key=lambda i: (
                cell_rank.get(str(columns["cell"][i]), len(cell_rank)),
                scen_rank.get(str(columns["scenario"][i]), len(scen_rank)),
                plan_rank.get(str(columns["planner"][i]), len(plan_rank)),
                int(columns["seed"][i]),
            ),
        )
        index = np.array(order, dtype=np.int64)
        return cls(
            folder=folder,
            factors=factors,
            cells=cells,
            scenarios=scenarios,
            planners=planners,
            base=base,
            columns={k: v[index] for k, v in columns.items()},
            expected=expected,
        )

    @property
    def episodes(self) -> int:
        """Episodes found."""
        return len(self.columns["seed"])

    def reference_cell(self) -> str:
        """The cell nearest the base parameters: each factor's distance to the base
        value over the factor's range, summed (the first of equals; factors that are
        not model parameters do not count)."""

        def distance(values: dict[str, float]) -> float:
            total = 0.0
            for f, v in values.items():
                if f not in self.base:
                    continue
                levels = [c[f] for c in self.cells.values()]
                span = (max(levels) - min(levels)) or 1.0
                total += abs(v - self.base[f]) / span
            return total

        return min(self.cells, key=lambda c: distance(self.cells[c]))


def load_sweep(folder: str | Path) -> SweepData:
    """Read a sweep folder's manifest and Parquet dataset.

    Raises:
        SweepError: no sweep manifest, or a dataset that cannot be read.
    """
    import pyarrow.dataset as ds

    folder = Path(folder)
    path = folder / SWEEP_MANIFEST
    if not path.is_file():
        raise SweepError(f"{folder}: no {SWEEP_MANIFEST}: not a sweep folder (srfm sweep --out)")
    raw = read_input_bytes(
        path, max_bytes=MAX_DOCUMENT_BYTES * 16, error=SweepError, what="sweep manifest"
    )
    try:
        doc = json.loads(raw.decode("utf-8"))
        factors = tuple(str(f) for f in doc["factors"])
        cells = {
            str(c): {str(k): float(v) for k, v in vals.items()} for c, vals in doc["cells"].items()
        }
        scenarios = tuple(str(s) for s in doc["scenarios"])
        planners = tuple(str(p) for p in doc["planners"])
        base = {str(k): float(v) for k, v in doc["params"].items()}
        expected = len(cells) * len(scenarios) * len(planners) * len(doc["seeds"])
    except (UnicodeDecodeError, ValueError, KeyError, TypeError, AttributeError) as exc:
        raise SweepError(f"{path}: damaged sweep manifest ({exc!r})") from None
    data = folder / DATA_DIR
    if not data.is_dir():
        raise SweepError(f"{folder}: no {DATA_DIR}/ folder: the sweep has not written any episode")
    try:
        table = ds.dataset(data, format="parquet", partitioning="hive").to_table()
    except (OSError, ValueError) as exc:
        raise SweepError(f"{data}: cannot read the Parquet dataset: {exc}") from None
    if table.num_rows == 0:
        raise SweepError(f"{data}: no episodes yet")
    cols: dict[str, NDArray[Any]] = {}
    for name in ("cell", "scenario", "planner", "outcome"):
        cols[name] = np.array(table.column(name).to_pylist(), dtype=object)
    cols["seed"] = np.array(table.column("seed").to_pylist(), dtype=np.int64)
    for name in (*factors, *(m.name for m in EPISODE_METRICS)):
        values = table.column(name).to_pylist()
        cols[name] = np.array([math.nan if v is None else v for v in values], dtype=np.float64)
    return SweepData.from_columns(
        folder=folder,
        factors=factors,
        cells=cells,
        scenarios=scenarios,
        planners=planners,
        base=base,
        columns=cols,
        expected=expected,
    )


def mean_ci(values: FloatArray) -> tuple[float, float, int]:
    """Mean and the half-width of its 95 % Student's t interval of the finite values
    (NaN half-width below two values), and their count."""
    from scipy import stats

    x = values[np.isfinite(values)]
    n = int(x.size)
    if n == 0:
        return math.nan, math.nan, 0
    mean = float(x.mean())
    if n < 2:
        return mean, math.nan, n
    half = float(stats.t.ppf(1 - ALPHA / 2, n - 1) * x.std(ddof=1) / math.sqrt(n))
    return mean, half, n


def kendall_tau(a: Sequence[float], b: Sequence[float]) -> float:
    """Kendall's τ-b between two score vectors over the same planners (NaN when either
    has no spread or holds NaN)."""
    from scipy import stats

    x, y = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(y))):
        return math.nan
    if np.ptp(x) == 0 or np.ptp(y) == 0:
        return math.nan
    return float(stats.kendalltau(x, y).statistic)


def _select(data: SweepData, **where: Any) -> NDArray[np.bool_]:
    mask = np.ones(data.episodes, dtype=bool)
    for key, value in where.items():
        mask &= data.columns[key] == value
    return mask


def _png(fig: Figure) -> bytes:
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    FigureCanvasAgg(fig)
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=_DPI, metadata={"Software": None})
    return buf.getvalue()


def _label(factor: str) -> str:
    names = {"a_robot": "A_r (m/s²)", "b_robot": "B_r (m)", "lambda_robot": "λ_r"}
    return names.get(factor, factor)


def _factor_figure(data: SweepData, factor: str, metric: str) -> bytes:
    """The metric and the success rate of each planner against one factor."""
    from matplotlib.figure import Figure

    levels = sorted(set(data.columns[factor][np.isfinite(data.columns[factor])].tolist()))
    fig = Figure(figsize=(10.0, 4.0), layout="constrained")
    ax_m, ax_s = fig.subplots(1, 2)
    for planner in data.planners:
        means, halves, rates, lows, highs = [], [], [], [], []
        for level in levels:
            mask = _select(data, planner=planner) & (data.columns[factor] == level)
            mean, half, _ = mean_ci(data.columns[metric][mask])
            means.append(mean)
            halves.append(0.0 if math.isnan(half) else half)
            ok = data.columns["robot_success"][mask]
            ok = ok[np.isfinite(ok)]
            p, lo, hi = wilson(int(ok.sum()), int(ok.size))
            rates.append(p)
            lows.append(lo)
            highs.append(hi)
        m, h = np.array(means), np.array(halves)
        (line,) = ax_m.plot(levels, m, marker="o", label=planner)
        ax_m.fill_between(levels, m - h, m + h, color=line.get_color(), alpha=0.2)
        ax_s.plot(levels, rates, marker="o", color=line.get_color(), label=planner)
        ax_s.fill_between(levels, lows, highs, color=line.get_color(), alpha=0.2)
    ax_m.set_xlabel(_label(factor))
    ax_m.set_ylabel(f"mean {metric}")
    ax_m.set_title(f"{metric} (95 % CI), scenarios and other factors pooled", fontsize=9)
    ax_s.set_xlabel(_label(factor))
    ax_s.set_ylabel("robot success rate")
    ax_s.set_ylim(-0.02, 1.02)
    ax_s.set_title("success (95 % Wilson interval)", fontsize=9)
    ax_m.legend(fontsize=8)
    if factor in data.base:
        for ax in (ax_m, ax_s):
            ax.axvline(data.base[factor], color="0.5", linestyle=":", linewidth=1)
    return _png(fig)


def _by_scenario_figure(data: SweepData, factor: str, metric: str) -> bytes:
    """The metric of each planner against one factor, one panel per scenario."""
    from matplotlib.figure import Figure

    levels = sorted(set(data.columns[factor][np.isfinite(data.columns[factor])].tolist()))
    n = len(data.scenarios)
    fig = Figure(figsize=(3.0 * n + 0.5, 3.4), layout="constrained")
    axes = np.atleast_1d(fig.subplots(1, n, squeeze=False)[0])
    for ax, scenario in zip(axes, data.scenarios, strict=True):
        for planner in data.planners:
            stats_ = [
                mean_ci(
                    data.columns[metric][
                        _select(data, planner=planner, scenario=scenario)
                        & (data.columns[factor] == level)
                    ]
                )
                for level in levels
            ]
            m = np.array([s[0] for s in stats_])
            h = np.array([0.0 if math.isnan(s[1]) else s[1] for s in stats_])
            (line,) = ax.plot(levels, m, marker="o", markersize=3, label=planner)
            ax.fill_between(levels, m - h, m + h, color=line.get_color(), alpha=0.2)
        ax.set_title(scenario, fontsize=9)
        ax.set_xlabel(_label(factor), fontsize=8)
        if factor in data.base:
            ax.axvline(data.base[factor], color="0.5", linestyle=":", linewidth=1)
    axes[0].set_ylabel(f"mean {metric}")
    axes[0].legend(fontsize=7)
    return _png(fig)


@attrs.frozen
class _Ranking:
    scenario: str  # "all": the mean over scenarios of each planner's mean
    cell: str
    means: tuple[float, ...]  # per planner, in data.planners order

    def order(self, planners: Sequence[str]) -> list[str]:
        ranked = sorted(
            range(len(planners)),
            key=lambda i: (math.inf if math.isnan(self.means[i]) else self.means[i], i),
        )
        return [planners[i] for i in ranked]

    def text(self, planners: Sequence[str]) -> str:
        """Best first; ``=`` between planners with the same mean."""
        if all(math.isnan(m) for m in self.means):
            return "(no episodes yet)"
        order = self.order(planners)
        out = order[0]
        for prev, name in itertools.pairwise(order):
            a, b = self.means[planners.index(prev)], self.means[planners.index(name)]
            out += " = " if a == b or (math.isnan(a) and math.isnan(b)) else " < "
            out += name
        return out


def _rankings(data: SweepData, metric: str) -> dict[tuple[str, str], _Ranking]:
    out: dict[tuple[str, str], _Ranking] = {}
    for cell in data.cells:
        per_scenario = []
        for scenario in data.scenarios:
            means = tuple(
                mean_ci(
                    data.columns[metric][_select(data, cell=cell, scenario=scenario, planner=p)]
                )[0]
                for p in data.planners
            )
            out[(scenario, cell)] = _Ranking(scenario, cell, means)
            per_scenario.append(means)
        overall = tuple(float(np.mean(col)) for col in zip(*per_scenario, strict=True))
        out[("all", cell)] = _Ranking("all", cell, overall)
    return out


def _fmt(x: float, digits: int = 2) -> str:
    return "–" if math.isnan(x) else f"{x:.{digits}f}"


def _cell_text(data: SweepData, cell: str) -> str:
    return ", ".join(f"{f} = {data.cells[cell][f]:g}" for f in data.factors)


def _paired_p(data: SweepData, cell: str, scenario: str, p: str, q: str, metric: str) -> float:
    """Paired t-test p of planners p and q in one cell and scenario (shared seeds)."""
    a_mask = _select(data, cell=cell, scenario=scenario, planner=p)
    b_mask = _select(data, cell=cell, scenario=scenario, planner=q)
    a = dict(zip(data.columns["seed"][a_mask].tolist(), data.columns[metric][a_mask], strict=True))
    b = dict(zip(data.columns["seed"][b_mask].tolist(), data.columns[metric][b_mask], strict=True))
    seeds = sorted(set(a) & set(b))
    if len(seeds) < 2:
        return math.nan
    return compare([a[s] for s in seeds], [b[s] for s in seeds]).paired_p


def _stability(data: SweepData, metric: str) -> tuple[str, str]:
    """The ranking-stability section of report.md and rankings.csv."""
    ranks = _rankings(data, metric)
    ref = data.reference_cell()
    scopes = [*data.scenarios, "all"]
    lines = [
        f"## Ranking stability ({metric}, lower is better)",
        "",
        f"Reference cell: `{ref}` ({_cell_text(data, ref)}; the cell nearest the base "
        "parameters). Kendall's τ-b of each cell's "
        "ranking of the planners against the reference cell's ranking, per scenario "
        "and for the mean over scenarios (`all`); – where a ranking is undefined (every "
        "planner tied, e.g. no robot force at all, or a planner without episodes).",
        "",
        "| cell | " + " | ".join(data.factors) + " | " + " | ".join(scopes) + " |",
        "|---|" + "--:|" * len(data.factors) + "--:|" * len(scopes),
    ]
    taus: dict[str, list[float]] = {s: [] for s in scopes}
    for cell in data.cells:
        row = []
        for scope in scopes:
            tau = kendall_tau(ranks[(scope, ref)].means, ranks[(scope, cell)].means)
            taus[scope].append(tau)
            row.append(_fmt(tau))
        values = " | ".join(f"{data.cells[cell][f]:g}" for f in data.factors)
        lines.append(f"| `{cell}` | {values} | " + " | ".join(row) + " |")
    lines += [
        "",
        "| scope | cells with τ defined | mean τ | min τ | cells with τ = 1 |",
        "|---|--:|--:|--:|--:|",
    ]
    for scope in scopes:
        t = np.array(taus[scope])
        ok = t[np.isfinite(t)]
        lines.append(
            f"| {scope} | {ok.size} of {t.size} | {_fmt(float(ok.mean()) if ok.size else math.nan)}"
            f" | {_fmt(float(ok.min()) if ok.size else math.nan)} | {int(np.sum(ok == 1.0))} |"
        )
    lines += [
        "",
        "### Rankings (mean over scenarios)",
        "",
        "| cell | " + " | ".join(data.factors) + " | ranking (best first) |",
        "|---|" + "--:|" * len(data.factors) + "---|",
    ]
    for cell in data.cells:
        values = " | ".join(f"{data.cells[cell][f]:g}" for f in data.factors)
        order = ranks[("all", cell)].text(data.planners)
        lines.append(f"| `{cell}` | {values} | {order} |")
    lines += [
        "",
        "### Flips",
        "",
        "Pairs of planners whose order in a cell is the reverse of their order in the "
        f"reference cell; p: paired t-test of the two planners in that cell (significant "
        f"below {ALPHA}).",
        "",
        "| scenario | pair (reference order) | cell | "
        + " | ".join(data.factors)
        + " | means in the cell | p |",
        "|---|---|---|" + "--:|" * len(data.factors) + "---|--:|",
    ]
    flips = 0
    for scenario in data.scenarios:
        ref_means = ranks[(scenario, ref)].means
        for i, p in enumerate(data.planners):
            for j in range(i + 1, len(data.planners)):
                q = data.planners[j]
                before = np.sign(ref_means[i] - ref_means[j])
                if before == 0 or math.isnan(before):
                    continue
                first, second = (p, q) if before < 0 else (q, p)
                for cell in data.cells:
                    means = ranks[(scenario, cell)].means
                    after = np.sign(means[i] - means[j])
                    if math.isnan(after) or after != -before:
                        continue
                    flips += 1
                    pv = _paired_p(data, cell, scenario, p, q, metric)
                    values = " | ".join(f"{data.cells[cell][f]:g}" for f in data.factors)
                    a, b = (means[i], means[j]) if first == p else (means[j], means[i])
                    lines.append(
                        f"| {scenario} | {first} < {second} | `{cell}` | {values} | "
                        f"{_fmt(a, 3)} vs {_fmt(b, 3)} | {_fmt(pv, 3)}"
                        f"{' *' if pv < ALPHA else ''} |"
                    )
    lines += ["", f"{flips} flips in all.", "", *_pairwise(data, ranks, metric)]
    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="\n")
    writer.writerow(["scope", "cell", *data.factors, "planner", f"mean_{metric}", "rank"])
    for scope in scopes:
        for cell in data.cells:
            r = ranks[(scope, cell)]
            ranked = r.order(data.planners)
            for k, planner in enumerate(data.planners):
                writer.writerow(
                    [
                        scope,
                        cell,
                        *(repr(data.cells[cell][f]) for f in data.factors),
                        planner,
                        repr(r.means[k]),
                        ranked.index(planner) + 1,
                    ]
                )
    return "\n".join(lines) + "\n", buf.getvalue()


def _pairwise(data: SweepData, ranks: dict[tuple[str, str], _Ranking], metric: str) -> list[str]:
    """Across every (cell, scenario) where the planners are not all tied: how often each
    planner has the lowest mean, and for each pair how often the first is
    significantly lower, significantly higher (paired t-test), or neither."""
    pairs = [(p, q) for i, p in enumerate(data.planners) for q in data.planners[i + 1 :]]
    lowest = dict.fromkeys(data.planners, 0)
    counts = {pair: [0, 0, 0] for pair in pairs}
    total = 0
    for cell in data.cells:
        for scenario in data.scenarios:
            means = ranks[(scenario, cell)].means
            finite = [m for m in means if not math.isnan(m)]
            if len(finite) < len(means) or max(finite) == min(finite):
                continue
            total += 1
            lowest[data.planners[int(np.argmin(means))]] += 1
            for i, (p, q) in enumerate(pairs):
                pv = _paired_p(data, cell, scenario, p, q, metric)
                a, b = means[data.planners.index(p)], means[data.planners.index(q)]
                counts[pairs[i]][2 if not pv < ALPHA else (0 if a < b else 1)] += 1
    lines = [
        "### Head to head",
        "",
        f"Over the {total} (cell, scenario) pairs where the planners are not all tied: "
        "how often each planner has the lowest mean, and for each pair how often the "
        f"first is significantly lower or higher than the second (paired t-test, p < {ALPHA}).",
        "",
        "| planner | lowest mean in |",
        "|---|--:|",
        *[f"| {p} | {lowest[p]} |" for p in data.planners],
        "",
        "| pair | first lower | first higher | not significant |",
        "|---|--:|--:|--:|",
        *[f"| {p} vs {q} | {c[0]} | {c[1]} | {c[2]} |" for (p, q), c in counts.items()],
    ]
    return lines


def _factor_table(data: SweepData, factor: str, metric: str) -> list[str]:
    levels = sorted(set(data.columns[factor][np.isfinite(data.columns[factor])].tolist()))
    lines = [
        "| planner | " + " | ".join(f"{factor} = {v:g}" for v in levels) + " |",
        "|---|" + "--:|" * len(levels),
    ]
    for planner in data.planners:
        cells = []
        for level in levels:
            mask = _select(data, planner=planner) & (data.columns[factor] == level)
            mean, half, _ = mean_ci(data.columns[metric][mask])
            ok = data.columns["robot_success"][mask]
            ok = ok[np.isfinite(ok)]
            rate = wilson(int(ok.sum()), int(ok.size))[0]
            cells.append(f"{_fmt(mean, 3)} ± {_fmt(half, 3)} ({_fmt(100 * rate, 0)} %)")
        lines.append(f"| {planner} | " + " | ".join(cells) + " |")
    return lines


def _check_metric(metric: str) -> None:
    known = [m.name for m in EPISODE_METRICS]
    if metric not in known:
        raise SweepError(f"unknown metric {metric!r}; known: {', '.join(known)}")


def report_text(data: SweepData, *, metric: str = "frechet_m") -> tuple[str, str]:
    """The text of ``report.md`` and of ``rankings.csv`` of a sweep's data (the figures
    are :func:`report_figures`). One definition for ``srfm sweep report`` and for
    whatever rebuilds a report from a sweep's episodes kept elsewhere (the docs'
    ``tools/results/sensitivity.py``).

    Raises:
        SweepError: an unknown metric.
    """
    _check_metric(metric)
    lines = [
        f"# Sweep report: {data.folder.name}",
        "",
        f"{data.episodes} of {data.expected} episodes "
        + ("(complete)." if data.episodes == data.expected else "(the sweep is not finished).")
        + f" {count(len(data.cells), 'cell')} × {count(len(data.scenarios), 'scenario')} × "
        f"{count(len(data.planners), 'planner')}; factors: {', '.join(data.factors)}.",
        "",
    ]
    for factor in data.factors:
        lines += [
            f"## {factor}",
            "",
            f"![{factor}]({factor}.png)",
            "",
            f"![{factor} by scenario]({factor}_by_scenario.png)",
            "",
            f"Mean {metric} ± 95 % CI half-width (robot success rate), scenarios and "
            "other factors pooled:",
            "",
            *_factor_table(data, factor, metric),
            "",
        ]
    stability, rankings = _stability(data, metric)
    return "\n".join(lines) + "\n" + stability, rankings


def report_figures(data: SweepData, *, metric: str = "frechet_m") -> dict[str, bytes]:
    """The report's figures as PNG bytes, by file name (two per factor, in the order of
    the factors): the ones ``report.md`` shows.

    Raises:
        SweepError: an unknown metric.
    """
    _check_metric(metric)
    files: dict[str, bytes] = {}
    for factor in data.factors:
        files[f"{factor}.png"] = _factor_figure(data, factor, metric)
        files[f"{factor}_by_scenario.png"] = _by_scenario_figure(data, factor, metric)
    return files


def write_sweep_report(folder: str | Path, *, metric: str = "frechet_m") -> list[Path]:
    """Write ``report.md``, ``rankings.csv`` and the figures into ``folder/report/``;
    return their paths.

    Raises:
        SweepError: not a sweep folder, no episodes, or an unknown metric.
    """
    _check_metric(metric)
    data = load_sweep(folder)
    files = {f"{REPORT_DIR}/{k}": v for k, v in report_figures(data, metric=metric).items()}
    report, rankings = report_text(data, metric=metric)
    files[f"{REPORT_DIR}/report.md"] = report.encode("utf-8")
    files[f"{REPORT_DIR}/rankings.csv"] = rankings.encode("utf-8")
    write_file_set(data.folder, files)
    return [data.folder / name for name in files]
