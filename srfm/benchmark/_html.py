"""The results page: ``report.html``, one self-contained page over a results folder.

The page is plain HTML with its CSS inline and no script: it opens offline from the
folder (``file://``), and every image and link is a path relative to it (the figures,
the tables' source files, every episode's ``.mcap`` and ``.rrd``). It is rendered from
the folder's own files (``manifest.json``, ``summary.json``, ``episodes.csv``, the
figures and the logs), so ``srfm report DIR`` rebuilds it from a results folder alone;
the benchmark renders it from the reports it is about to write, in the same set.
"""

from __future__ import annotations

import csv
import html
import io
import json
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any, Final

from srfm._io import (
    MAX_DOCUMENT_BYTES,
    atomic_write_bytes,
    check_columns,
    folder_lock,
    read_input_bytes,
)
from srfm._text import count
from srfm.benchmark._request import check_manifest_schema
from srfm.benchmark._results import episode_path, read_episode
from srfm.errors import BenchmarkError, SrfmError
from srfm.metrics.episode import EPISODE_METRICS, METRIC_GROUPS
from srfm.metrics.floor_files import load_floors
from srfm.metrics.report import MANIFEST, SUMMARY_SCHEMA, render_tables
from srfm.metrics.tables import GIVEN_SUCCESS, base_metric, outcome_shares, share_text
from srfm.models.params import SRFMParams
from srfm.sim.record import ROBOT_OUTCOMES

__all__ = ["REPORT", "render_report", "write_report"]

REPORT: Final = "report.html"
"""The results page of a results folder."""

_INFO: Final = {m.name: m for m in EPISODE_METRICS}
_ARROWS: Final = {"lower": "↓", "higher": "↑", "": ""}
_OUTCOME_TITLES: Final = {
    "goal_reached": "goal reached",
    "collision": "collision",
    "timeout": "timeout",
    "out_of_bounds": "out of bounds",
    "planner_failed": "planner failed",
}
_DATA_FILES: Final = (
    ("table.md", "the paper's Table 3 layout (Markdown)"),
    ("table.tex", "the same in LaTeX"),
    ("outcomes.md", "robot outcomes (Markdown)"),
    ("table_extended.md", "every metric (Markdown)"),
    ("table_extended.tex", "every metric (LaTeX)"),
    ("suite.md", "suite statistics: IQMs, probabilities of improvement (Markdown)"),
    ("episodes.csv", "one row per episode"),
    ("episodes.parquet", "the same as Parquet"),
    ("pedestrians.csv", "one row per episode and pedestrian"),
    ("pedestrians.parquet", "the same as Parquet"),
    ("summary.json", "every cell: n, undefined, mean, std, p-values"),
    ("rankings.md", "rank probabilities under the parameter draws (Markdown)"),
    ("rankings.json", "the same with every draw's means"),
    ("param_draws.json", "the parameter draws"),
    ("robustness.md", "orderings of planners under every response model (Markdown)"),
    ("robustness.json", "the same with every test"),
    ("models.json", "the response models of the run"),
    (MANIFEST, "versions, parameters, request and command"),
)

_CSS: Final = """
body { font-family: system-ui, -apple-system, "Segoe UI", sans-serif; margin: 0;
  color: #1d1d1f; background: #fff; line-height: 1.45; }
header { background: #1f3a5f; color: #fff; padding: 1.2em 2em; }
header h1 { margin: 0 0 .2em 0; font-size: 1.6em; }
header p { margin: 0; opacity: .9; }
nav { background: #eef2f7; padding: .6em 2em; position: sticky; top: 0; z-index: 2;
  border-bottom: 1px solid #d0d7e2; }
nav a { margin-right: 1.2em; color: #1f3a5f; text-decoration: none; font-weight: 600; }
main { padding: 0 2em 3em 2em; max-width: 1400px; }
h2 { border-bottom: 2px solid #1f3a5f; padding-bottom: .2em; margin-top: 1.8em;
  scroll-margin-top: 3em; }
td.ok { background: #e8f3e8; }
td.some { background: #fdf3dc; }
td.bad { background: #f9e0e0; }
h3 { margin-bottom: .4em; }
.scroll { overflow-x: auto; }
table { border-collapse: collapse; margin: .4em 0 .6em 0; font-size: .9em; }
th, td { border: 1px solid #d0d7e2; padding: .25em .6em; text-align: right;
  white-space: nowrap; }
th { background: #f3f6fa; }
td.name, th.name { text-align: left; }
tr.group td { background: #f9fafc; font-style: italic; text-align: left; }
td.best { font-weight: 700; background: #e8f3e8; }
th.cond, td.cond { border-left: 2px solid #9db3cf; }
td.shares { color: #444; font-size: .88em; }
.n { color: #8a5a00; font-size: .85em; }
.mark { color: #a00; font-weight: 700; }
.legend { font-size: .88em; color: #444; max-width: 70em; }
figure { margin: 1em 0; }
figure img { max-width: 100%; border: 1px solid #d0d7e2; }
figcaption { font-size: .88em; color: #444; }
details { margin: .3em 0; }
summary { cursor: pointer; font-weight: 600; }
.seeds a { margin-right: .35em; }
code { background: #f3f6fa; padding: 0 .25em; }
dl.kv { display: grid; grid-template-columns: max-content auto; gap: .1em 1em; }
dl.kv dt { font-weight: 600; }
dl.kv dd { margin: 0; }
.missing { color: #a00; }
td.prob { color: #000; min-width: 2.6em; }
"""


def _esc(text: object) -> str:
    return html.escape(str(text), quote=True)


def _read_bytes(out: Path, name: str, files: Mapping[str, bytes]) -> bytes | None:
    """A report file: from ``files`` (about to be written) or else from the folder."""
    if name in files:
        return files[name]
    path = out / name
    if not path.is_file():
        return None
    return read_input_bytes(
        path, max_bytes=MAX_DOCUMENT_BYTES * 4, error=BenchmarkError, what="results file"
    )


def _has(out: Path, name: str, files: Mapping[str, bytes]) -> bool:
    return name in files or (out / name).is_file()


def _json_file(out: Path, name: str, files: Mapping[str, bytes]) -> Any:
    data = _read_bytes(out, name, files)
    if data is None:
        raise BenchmarkError(
            f"{out / name} is missing: not a complete benchmark results folder (run "
            "`srfm benchmark --out` on it to finish it)"
        )
    try:
        return json.loads(data.decode("utf-8"))
    except (UnicodeDecodeError, ValueError, RecursionError) as exc:
        raise BenchmarkError(f"{out / name}: damaged ({exc})") from None


def _summary(out: Path, files: Mapping[str, bytes]) -> Any:
    """``summary.json`` of this srfm's schema (another is an error saying what to do)."""
    summary = _json_file(out, "summary.json", files)
    if not isinstance(summary, dict) or summary.get("schema") != SUMMARY_SCHEMA:
        got = summary.get("schema") if isinstance(summary, dict) else None
        raise BenchmarkError(
            f"{out / 'summary.json'}: summary schema {got!r}, this srfm writes "
            f"{SUMMARY_SCHEMA!r}; run the benchmark again into a new --out folder"
        )
    return summary


def _seed_ranges(seeds: Sequence[int]) -> str:
    """``[0, 1, 2, 5]`` as ``0–2, 5``."""
    parts: list[str] = []
    start = prev = None
    for s in seeds:
        if start is None:
            start = prev = s
        elif prev is not None and s == prev + 1:
            prev = s
        else:
            parts.append(f"{start}" if start == prev else f"{start}–{prev}")
            start = prev = s
    if start is not None:
        parts.append(f"{start}" if start == prev else f"{start}–{prev}")
    return ", ".join(parts)


def _number(x: float | None) -> str:
    return "–" if x is None else f"{x:.2f}"


def _cell(entry: Mapping[str, Any], n_seeds: int, *, conditioned: bool = False) -> str:
    """One cell; a column conditioned on success (``conditioned``) always shows its n
    and is shaded as such."""
    marks = str(entry.get("marks", ""))
    body = f"{_number(entry.get('mean'))} ± {_number(entry.get('std'))}"
    mark = f'<span class="mark">{_esc(marks)}</span>' if marks else ""
    n = int(entry.get("n", 0))
    note = f' <span class="n">(n={n})</span>' if n < n_seeds or conditioned else ""
    classes = [c for c, on in (("best", entry.get("best")), ("cond", conditioned)) if on]
    cls = f' class="{" ".join(classes)}"' if classes else ""
    return f"<td{cls}>{mark}{_esc(body)}{note}</td>"


def _info(column: str) -> Any:
    return _INFO.get(base_metric(column))


def _arrow(column: str) -> str:
    info = _info(column)
    return _ARROWS[info.better] if info is not None else ""


def _shares(summary: Mapping[str, Any], scenario: str, planner: str) -> str:
    counts = (summary.get("outcomes") or {}).get(scenario, {}).get(planner)
    return f'<td class="name shares">{_esc(outcome_shares(counts))}</td>' if counts else "<td></td>"


def _interval(entry: Mapping[str, Any], digits: int) -> str:
    est, low, high = (entry.get(k) for k in ("estimate", "low", "high"))
    if est is None:
        return "–"
    if low is None or high is None:
        return f"{est:.{digits}f}"
    return f"{est:.{digits}f} [{low:.{digits}f}, {high:.{digits}f}]"


def _score(ref: Mapping[str, Any], planner: str) -> str:
    """A normalised score as the tables print it (:func:`srfm.metrics.tables.score_text`)."""
    score = ref["scores"][planner]
    k = f"(k={score['n']}/{ref.get('n_seeds', score['n'])})"
    if score.get("estimate") is None:
        return f"undefined {k}"
    return f"{_interval(score, 2)} {k}"


def _headroom(ref: Mapping[str, Any]) -> str:
    text = _interval(ref["headroom"], 3)
    beats = ref.get("beats_oracle") or []
    if beats:
        text += f" ≥ (lower bound: {', '.join(beats)} beat the oracle)"
    return text


def _attribution(doc: Mapping[str, Any] | None, planners: Sequence[str]) -> str:
    """The noise floor and the direct / knock-on deviation of every scenario."""
    if not doc:
        return "<p>No attribution in this summary.</p>"
    floor_rows, split_rows = [], []
    for scenario, entry in doc["scenarios"].items():
        floor = entry.get("floor")
        if floor is not None:
            weak = [
                f"{d['a']}–{d['b']}" for d in entry.get("differences", []) if not d["attributable"]
            ]
            share = floor.get("share")
            std = floor.get("std")
            floor_rows.append(
                f'<tr><td class="name">{_esc(scenario)}</td><td>{floor["mean"]:.4f}</td>'
                f"<td>{'–' if std is None else f'{std:.4f}'}</td>"
                f"<td>{'–' if share is None else f'{100 * share:.1f} %'}</td>"
                f'<td class="name verdict">{_esc(floor["verdict"])}</td>'
                f'<td class="name weak">{_esc(", ".join(weak) or "none")}</td></tr>'
            )
        tds = []
        for p in planners:
            cells = entry["split"][p]
            direct = cells["frechet_direct_m"]["mean"]
            knock = cells["frechet_knock_on_m"]["mean"]
            felt = cells["pedestrians_felt"]["mean"]
            text = "–" if direct is None else f"{direct:.3f} / {knock:.3f} ({felt:.1f} felt)"
            tds.append(f'<td class="split">{_esc(text)}</td>')
        split_rows.append(f'<tr><td class="name">{_esc(scenario)}</td>{"".join(tds)}</tr>')
    parts = []
    if floor_rows:
        parts.append(
            '<h3 id="floor">Noise floor</h3><div class="scroll"><table class="floor"><thead>'
            '<tr><th class="name">Scenario</th><th>Floor (m)</th><th>SD over seeds (m)</th>'
            '<th>Share of the deviation</th><th class="name">Measures</th>'
            '<th class="name">Differences not attributable to the planners</th></tr></thead>'
            "<tbody>" + "".join(floor_rows) + "</tbody></table></div>"
        )
    else:
        parts.append("<p>This folder has no noise floor files.</p>")
    head = "".join(f"<th>{_esc(p)}</th>" for p in planners)
    parts.append(
        '<h3 id="split">Direct and knock-on deviation</h3><div class="scroll">'
        '<table class="split"><thead><tr><th class="name">Scenario</th>'
        f"{head}</tr></thead><tbody>"
        + "".join(split_rows)
        + "</tbody></table></div>"
        + '<p class="legend">Each cell: mean direct / knock-on deviation (m) and the mean '
        "number of pedestrians who felt the robot. " + _esc(doc["legend"]) + "</p>"
    )
    return "".join(parts)


def _suite(doc: Mapping[str, Any] | None, profiles: bool) -> str:
    """The suite statistics: IQMs, probabilities of improvement, profiles."""
    if not doc:
        return "<p>No suite statistics in this summary.</p>"
    planners = list(doc["deviation_iqm"])
    scored = bool(doc.get("score_iqm"))
    rows = []
    for p in planners:
        d = doc["deviation_iqm"][p]
        row = (
            f'<tr><td class="name">{_esc(p)}</td><td>{_esc(_interval(d, 3))}</td><td>{d["n"]}</td>'
        )
        if scored:
            x = doc["score_iqm"][p]
            row += f"<td>{_esc(_interval(x, 2))}</td><td>{x['n']}</td>"
        rows.append(row + "</tr>")
    score_head = "<th>IQM norm. score [95 % CI]</th><th>episodes</th>" if scored else ""
    poi = []
    for a in planners:
        tds = "".join(
            "<td>–</td>" if a == b else f"<td>{_esc(_interval(doc['improvement'][a][b], 2))}</td>"
            for b in planners
        )
        poi.append(f'<tr><td class="name">{_esc(a)}</td>{tds}</tr>')
    figure = (
        '<figure><img src="figures/profiles.png" alt="Performance profiles">'
        "<figcaption>Performance profiles: the share of each planner's episodes whose "
        "deviation is at most τ.</figcaption></figure>"
        if profiles
        else "<p>No profiles figure (<code>--no-figures</code>).</p>"
    )
    return (
        '<h3 id="iqm">Interquartile means</h3><div class="scroll"><table class="iqm"><thead>'
        '<tr><th class="name">Planner</th><th>IQM deviation (m) [95 % CI]</th><th>n</th>'
        f"{score_head}</tr></thead><tbody>" + "".join(rows) + "</tbody></table></div>"
        '<h3 id="improvement">Probability of improvement P(row &lt; column)</h3>'
        '<div class="scroll"><table class="poi"><thead><tr><th class="name"></th>'
        + "".join(f"<th>{_esc(p)}</th>" for p in planners)
        + "</tr></thead><tbody>"
        + "".join(poi)
        + '</tbody></table></div><h3 id="profiles">Performance profiles</h3>'
        + figure
        + f'<p class="legend">{_esc(doc["legend"])}</p>'
    )


def _references(summary: Mapping[str, Any]) -> str:
    """The reference points of every scenario (headroom, SE, seeds needed, whether it
    discriminates), when the run has ``straight`` and ``oracle``."""
    refs = summary.get("references")
    if not refs:
        return ""
    rows = []
    for scenario, ref in refs.items():
        flag = (
            '<td class="name ok">yes</td>'
            if ref["discriminates"]
            else '<td class="name bad nodisc">does not discriminate</td>'
        )
        se = ref.get("standard_error")
        rows.append(
            f'<tr><td class="name">{_esc(scenario)}</td>'
            f"<td>{_esc(_headroom(ref))}</td>"
            f"<td>{'–' if se is None else f'{se:.3f}'}</td>"
            f"<td>{_esc(ref.get('seeds_needed') or '–')}</td>{flag}</tr>"
        )
    return (
        '<h3 id="references">Reference points: headroom and power</h3>'
        '<div class="scroll"><table class="references"><thead><tr><th class="name">Scenario'
        "</th><th>Headroom (m) [95 % CI]</th><th>SE (m)</th><th>Seeds for 0.05 m</th>"
        '<th class="name">Discriminates</th></tr></thead><tbody>'
        + "".join(rows)
        + '</tbody></table></div><p class="legend">'
        + _esc(summary.get("references_legend", ""))
        + "</p>"
    )


def _wide_table(summary: Mapping[str, Any]) -> str:
    """A (scenario, planner) × column table of a ``summary.json`` table entry, with
    each planner's normalised score (when the run has the reference planners) and
    each row's outcome shares last."""
    columns = [(str(n), str(h)) for n, h in summary["columns"]]
    n_seeds = int(summary["n_seeds"])
    refs = summary.get("references") or {}
    head = "".join(
        ('<th class="cond">' if n.endswith(GIVEN_SUCCESS) else "<th>")
        + f"{_esc(h)} {_arrow(n)}</th>"
        for n, h in columns
    )
    rows = []
    for scenario, planners in summary["scenarios"].items():
        for k, (planner, cells) in enumerate(planners.items()):
            first = (
                f'<td class="name" rowspan="{len(planners)}">{_esc(scenario)}</td>'
                if k == 0
                else ""
            )
            tds = "".join(
                _cell(cells[n], n_seeds, conditioned=n.endswith(GIVEN_SUCCESS)) for n, _ in columns
            )
            if refs:
                tds += f'<td class="score">{_esc(_score(refs[scenario], planner))}</td>'
            tds += _shares(summary, scenario, planner)
            rows.append(f'<tr>{first}<td class="name">{_esc(planner)}</td>{tds}</tr>')
    score_head = "<th>Norm. score ↑</th>" if refs else ""
    return (
        '<div class="scroll"><table><thead><tr><th class="name">Scenario</th>'
        f'<th class="name">Planner</th>{head}{score_head}<th class="name">Outcomes</th></tr>'
        "</thead><tbody>"
        + "".join(rows)
        + f'</tbody></table></div><p class="legend">{_esc(summary["legend"])}</p>'
        + _references(summary)
    )


def _extended_tables(summary: Mapping[str, Any]) -> str:
    """One metric × planner table per scenario, grouped, each in a ``<details>``."""
    names = [str(n) for n, _ in summary["columns"]]
    n_seeds = int(summary["n_seeds"])
    out = [f'<p class="legend">{_esc(summary["legend"])}</p>']
    for k, (scenario, planners) in enumerate(summary["scenarios"].items()):
        head = "".join(f"<th>{_esc(p)}</th>" for p in planners)
        shares = "".join(_shares(summary, scenario, p) for p in planners)
        rows = [f'<tr class="outcomes"><td class="name">Outcomes</td><td></td>{shares}</tr>']
        for group, title in METRIC_GROUPS.items():
            in_group = [n for n in names if _info(n) is not None and _info(n).group == group]
            if not in_group:
                continue
            rows.append(
                f'<tr class="group"><td colspan="{len(planners) + 2}">{_esc(title)}</td></tr>'
            )
            for name in in_group:
                info = _info(name)
                conditioned = name.endswith(GIVEN_SUCCESS)
                tds = "".join(
                    _cell(cells[name], n_seeds, conditioned=conditioned)
                    for cells in planners.values()
                )
                label = f"<code>{_esc(info.name)}</code>" + (" | success" if conditioned else "")
                title_text = info.definition + (
                    " Over the seeds in which the robot reached its goal." if conditioned else ""
                )
                rows.append(
                    f'<tr><td class="name" title="{_esc(title_text)}">{label} '
                    f"{_ARROWS[info.better]}</td><td>{_esc(info.unit)}</td>{tds}</tr>"
                )
        opened = " open" if k == 0 else ""
        out.append(
            f"<details{opened}><summary>{_esc(scenario)}</summary>"
            '<div class="scroll"><table><thead><tr><th class="name">Metric</th><th>Unit</th>'
            f"{head}</tr></thead><tbody>" + "".join(rows) + "</tbody></table></div></details>"
        )
    return "".join(out)


def _rankings(doc: Mapping[str, Any]) -> str:
    """The rank probabilities under the parameter draws: a planner × rank table per
    scenario (the cell shaded by its probability) with the interval of the planner's
    mean deviation over the draws."""
    planners = [str(p) for p in doc["planners"]]
    ranks = "".join(f"<th>{r + 1}</th>" for r in range(len(planners)))
    parts = [f'<p class="legend">{_esc(doc["legend"])}</p>']
    for scenario, rows in doc["scenarios"].items():
        trs = []
        for planner in planners:
            entry = rows[planner]
            tds = "".join(
                f'<td class="prob" style="background: rgba(31, 58, 95, {0.6 * float(v):.3f})">'
                f"{float(v):.2f}</td>"
                for v in entry["rank_probabilities"]
            )
            low, mid, high = (float(v) for v in entry["interval"])
            trs.append(
                f'<tr><td class="name">{_esc(planner)}</td>{tds}'
                f"<td>{low:.3f} · {mid:.3f} · {high:.3f}</td></tr>"
            )
        parts.append(
            f'<h3>{_esc(scenario)}</h3><div class="scroll"><table class="ranks"><thead><tr>'
            f'<th class="name" rowspan="2">Planner</th><th colspan="{len(planners)}">P(rank)'
            '</th><th rowspan="2">Fréchet dev. (m): 2.5 % · median · 97.5 %</th></tr>'
            f"<tr>{ranks}</tr></thead><tbody>" + "".join(trs) + "</tbody></table></div>"
        )
    return "".join(parts)


def _robustness(doc: Mapping[str, Any]) -> str:
    """Which orderings of planners hold under every response model: the verdict counts
    and Kendall's τ per scenario, then every pair's differences under each model."""
    models = [str(m) for m in doc["models"]]
    legend = (
        f"Response models: {', '.join(models)} (the first is this run's own). For each "
        f"pair of planners A, B: the mean paired difference A − B of the Fréchet "
        f"deviation over {doc['n_seeds']} seeds, under each model; * = significant "
        f"({doc['test']}, adjusted p < {doc['alpha']}). holds: significant in the same "
        "direction under every model; flips: significant in opposite directions under two "
        "models; unresolved: otherwise. τ: Kendall's τ-b between two models' orderings "
        f"of the planners, 95 % bootstrap interval over the seeds "
        f"({doc['bootstrap_resamples']} resamples)."
    )
    rows = []
    for scenario, counts in doc["counts"].items():
        rows.append(
            f'<tr><td class="name">{_esc(scenario)}</td><td>{counts["holds"]}</td>'
            f"<td>{counts['flips']}</td><td>{counts['unresolved']}</td></tr>"
        )
    parts = [
        f'<p class="legend">{_esc(legend)}</p>',
        '<div class="scroll"><table class="robustness"><thead><tr><th class="name">Scenario'
        "</th><th>holds</th><th>flips</th><th>unresolved</th></tr></thead><tbody>"
        + "".join(rows)
        + "</tbody></table></div>",
    ]
    taus = "".join(
        f'<tr><td class="name">{_esc(t["scenario"])}</td><td>{_esc(" vs ".join(t["models"]))}'
        f"</td><td>{_tau(t['tau'])}</td><td>[{_tau(t['interval'][0])}, "
        f"{_tau(t['interval'][1])}]</td></tr>"
        for t in doc["kendall_tau"]
    )
    parts.append(
        '<div class="scroll"><table class="taus"><thead><tr><th class="name">Scenario</th>'
        "<th>Models</th><th>Kendall τ</th><th>95 % interval</th></tr></thead><tbody>"
        + taus
        + "</tbody></table></div>"
    )
    heads = "".join(f"<th>A − B (m), {_esc(m)}</th>" for m in models)
    for scenario, pairs in doc["pairs"].items():
        trs = []
        for pair in pairs:
            cells = "".join(
                f"<td>{_tau(d, 3)}{' *' if p is not None and p < doc['alpha'] else ''}</td>"
                for d, p in zip(pair["difference_m"], pair["p_holm"], strict=True)
            )
            trs.append(
                f'<tr><td class="name">{_esc(pair["a"])}</td><td>{_esc(pair["b"])}</td>'
                f'{cells}<td class="verdict">{_esc(pair["verdict"])}</td></tr>'
            )
        parts.append(
            f"<details><summary>{_esc(scenario)}</summary>"
            '<div class="scroll"><table><thead><tr><th class="name">A</th><th>B</th>'
            f"{heads}<th>verdict</th></tr></thead><tbody>"
            + "".join(trs)
            + "</tbody></table></div></details>"
        )
    return "".join(parts)


def _model_name(request: Mapping[str, Any]) -> str:
    """The response model a summary's request ran under (a preset's name, or custom)."""
    from srfm.models.params import SRFMParams, response_model_name

    try:
        return response_model_name(SRFMParams(**request["params"]))
    except (KeyError, TypeError, SrfmError):
        return "unknown (the summary names no valid parameter set)"


def _tau(value: float | None, digits: int = 2) -> str:
    return "–" if value is None else f"{float(value):+.{digits}f}"


def _episodes(out: Path, files: Mapping[str, bytes]) -> list[dict[str, str]]:
    data = _read_bytes(out, "episodes.csv", files)
    if data is None:
        raise BenchmarkError(f"{out / 'episodes.csv'} is missing: not a complete results folder")
    rows = csv.DictReader(io.StringIO(data.decode("utf-8")))
    check_columns(rows.fieldnames or [], str(out / "episodes.csv"), BenchmarkError)
    return list(rows)


def _outcomes(
    rows: Sequence[Mapping[str, str]], scenarios: Sequence[str], planners: Sequence[str]
) -> str:
    """A sentence per planner, and one planner × scenario table of how the episodes
    ended: goals reached out of the episodes, then the failures by kind."""
    counts: dict[tuple[str, str], dict[str, int]] = {}
    for r in rows:
        cell = counts.setdefault((r["planner"], r["scenario"]), dict.fromkeys(ROBOT_OUTCOMES, 0))
        cell[r["outcome"]] = cell.get(r["outcome"], 0) + 1
    sentences = []
    trs = []
    for planner in planners:
        totals = dict.fromkeys(ROBOT_OUTCOMES, 0)
        tds = []
        for scenario in [*scenarios, ""]:
            if scenario:
                cell = counts.get((planner, scenario), dict.fromkeys(ROBOT_OUTCOMES, 0))
                for o in ROBOT_OUTCOMES:
                    totals[o] += cell[o]
            else:
                cell = totals
            n = sum(cell.values())
            reached = cell["goal_reached"]
            fails = ", ".join(
                f"{cell[o]} {_OUTCOME_TITLES[o]}" for o in ROBOT_OUTCOMES[1:] if cell[o]
            )
            kind = "ok" if n and reached == n else ("bad" if reached == 0 else "some")
            note = f'<br><span class="n">{_esc(fails)}</span>' if fails else ""
            tds.append(f'<td class="{kind}">{reached} / {n}{note}</td>')
        trs.append(f'<tr><td class="name">{_esc(planner)}</td>{"".join(tds)}</tr>')
        total = sum(totals.values())
        share = share_text(totals["goal_reached"], total)
        others = ", ".join(
            f"{totals[o]} {_OUTCOME_TITLES[o]}" for o in ROBOT_OUTCOMES[1:] if totals[o]
        )
        sentences.append(
            f"<li><b>{_esc(planner)}</b> reached its goal in {totals['goal_reached']} of "
            f"{total} episodes ({share})" + (f"; {_esc(others)}" if others else "") + ".</li>"
        )
    head = "".join(f"<th>{_esc(s)}</th>" for s in scenarios) + "<th>all</th>"
    return (
        "<ul>" + "".join(sentences) + "</ul>"
        '<p class="legend">Goals reached out of the episodes of each scenario; below, '
        "how the others ended.</p>"
        '<div class="scroll"><table><thead><tr><th class="name">Planner</th>'
        f"{head}</tr></thead><tbody>" + "".join(trs) + "</tbody></table></div>"
    )


def _log_links(
    out: Path, rows: Sequence[Mapping[str, str]], scenarios: Sequence[str], planners: Sequence[str]
) -> str:
    """Per scenario, per planner: a link to every episode's .mcap and .rrd that exists."""
    # Lazy and one-way (srfm.logs never imports the benchmark): the log writers are
    # loaded only for a page that links logs, which keeps `import srfm.benchmark` light.
    from srfm.logs import LOGS_DIR

    seeds: dict[tuple[str, str], list[int]] = {}
    for r in rows:
        seeds.setdefault((r["scenario"], r["planner"]), []).append(int(r["seed"]))
    parts = [
        "<p>MCAP files open in Foxglove and are re-scored by <code>srfm score</code>; "
        "Rerun recordings open with <code>rerun FILE.rrd</code> (docs/logging.md). A seed "
        "number is a link to that episode's file.</p>"
    ]
    any_logs = (out / LOGS_DIR).is_dir()
    for scenario in scenarios:
        trs = []
        n_mcap = n_rrd = 0
        for planner in planners:
            cells = []
            for suffix in (".mcap", ".rrd"):
                links = []
                for seed in sorted(seeds.get((scenario, planner), [])):
                    rel = f"{LOGS_DIR}/{scenario}/{planner}/seed-{seed:06d}{suffix}"
                    if (out / rel).is_file():
                        links.append(f'<a href="{_esc(rel)}">{seed}</a>')
                if suffix == ".mcap":
                    n_mcap += len(links)
                else:
                    n_rrd += len(links)
                cells.append(f'<td class="name seeds">{"".join(links) if links else "none"}</td>')
            trs.append(f'<tr><td class="name">{_esc(planner)}</td>{"".join(cells)}</tr>')
        parts.append(
            f"<details><summary>{_esc(scenario)}: {n_mcap} MCAP files, {n_rrd} Rerun "
            'recordings</summary><div class="scroll"><table><thead><tr><th class="name">'
            'Planner</th><th class="name">MCAP (seeds)</th><th class="name">Rerun .rrd '
            "(seeds)</th></tr></thead><tbody>" + "".join(trs) + "</tbody></table></div></details>"
        )
    if not any_logs:
        parts.append("<p>This run wrote no logs (<code>--no-logs</code>).</p>")
    return "".join(parts)


def _kv(items: Iterable[tuple[str, str]]) -> str:
    return (
        '<dl class="kv">' + "".join(f"<dt>{_esc(k)}</dt><dd>{v}</dd>" for k, v in items) + "</dl>"
    )


def _manifest_section(manifest: Mapping[str, Any], files: Sequence[str]) -> str:
    request = manifest.get("request") or {}
    command = manifest.get("command")
    versions = manifest.get("versions") or {}
    params = manifest.get("params") or {}
    metric_params = manifest.get("metric_params") or {}
    scenarios = manifest.get("scenarios") or {}
    run = [
        (
            "command",
            f"<code>{_esc(command)}</code>" if command else "(run from Python; no command line)",
        ),
        ("scenarios", _esc(", ".join(request.get("scenarios", [])))),
        ("planners", _esc(", ".join(request.get("planners", [])))),
        (
            "seeds",
            _esc(
                f"{_seed_ranges(request.get('seeds', []))} ({len(request.get('seeds', []))} seeds)"
            ),
        ),
        ("reference planner", _esc(request.get("reference") or "none (no significance tests)")),
        ("seed of the path figures", _esc(request.get("figure_seed"))),
    ]
    data_links = "".join(
        f'<li><a href="{_esc(name)}">{_esc(name)}</a>: {_esc(what)}</li>'
        for name, what in _DATA_FILES
        if name in files
    )
    return (
        "<h3>Run</h3>"
        + _kv(run)
        + "<h3>Versions</h3>"
        + _kv((k, _esc(v)) for k, v in versions.items())
        + "<h3>SRFM parameters (factual crowd)</h3>"
        + _kv((k, _esc(v)) for k, v in params.items())
        + "<h3>Metric thresholds</h3>"
        + _kv((k, _esc(v)) for k, v in metric_params.items())
        + "<h3>Scenario content (SHA-256)</h3>"
        + _kv((k, f"<code>{_esc(v)}</code>") for k, v in scenarios.items())
        + "<h3>Data files</h3><ul>"
        + data_links
        + "</ul>"
    )


def _figures(out: Path, files: Mapping[str, bytes], scenarios: Sequence[str], seed: Any) -> str:
    def exists(name: str) -> bool:
        return name in files or (out / name).is_file()

    parts = []
    charts = (
        (
            "figures/deviation.png",
            "Mean Fréchet deviation of the pedestrians per scenario and "
            "planner; error bars ± one sample std over the seeds.",
        ),
        (
            "figures/social_work.png",
            "Social work: the SRFM robot force integrated along each "
            "pedestrian's path, mean over pedestrians; error bars ± one sample std.",
        ),
    )
    for name, caption in charts:
        if exists(name):
            parts.append(
                f'<figure><img src="{_esc(name)}" alt="{_esc(caption)}">'
                f"<figcaption>{_esc(caption)}</figcaption></figure>"
            )
    paths = []
    for scenario in scenarios:
        name = f"figures/paths_{scenario}.png"
        if exists(name):
            caption = (
                f"{scenario}, seed {seed}: factual paths (solid), counterfactual twins (dashed, "
                "same colour), the robot (black; square: start, star: goal)."
            )
            paths.append(
                f'<figure><img src="{_esc(name)}" alt="{_esc(caption)}">'
                f"<figcaption>{_esc(caption)}</figcaption></figure>"
            )
    if not parts and not paths:
        return "<p>This run drew no figures (<code>--no-figures</code>).</p>"
    return (
        "".join(parts)
        + "<h3>Paths, one seed per scenario</h3>"
        + ("".join(paths) if paths else "<p>none</p>")
    )


def render_report(out: Path, files: Mapping[str, bytes] | None = None) -> bytes:
    """The bytes of ``report.html`` for the results folder ``out``.

    Args:
        out: the results folder (its manifest, logs and any file not in ``files``).
        files: report files about to be written, by path relative to ``out``; they take
            the place of the folder's copies.

    Raises:
        BenchmarkError: not a results folder of this srfm (no or another manifest or
            summary schema), or a file is missing or damaged.
    """
    files = dict(files or {})
    manifest = _json_file(out, MANIFEST, files)
    check_manifest_schema(out / MANIFEST, manifest)
    summary = _summary(out, files)
    request = summary["request"]
    scenarios = [str(s) for s in request["scenarios"]]
    planners = [str(p) for p in request["planners"]]
    seeds = [int(s) for s in request["seeds"]]
    rows = _episodes(out, files)
    present = sorted(set(files) | {n for n, _ in _DATA_FILES if (out / n).is_file()})
    figure_seed = (manifest.get("request") or {}).get("figure_seed", seeds[0] if seeds else "")
    reference = summary["table"].get("reference")
    title = "srfm benchmark results"
    intro = (
        f"{count(len(scenarios), 'scenario')} × {count(len(planners), 'planner')} × "
        f"{count(len(seeds), 'seed')} = {count(len(rows), 'twin episode')}. Reference planner "
        f"for the significance tests: {reference or 'none'}. Response model of the "
        f"pedestrians: {_model_name(request)}."
    )
    rankings = (
        _json_file(out, "rankings.json", files) if _has(out, "rankings.json", files) else None
    )
    robust = summary.get("robustness")
    nav = "".join(
        f'<a href="#{k}">{_esc(v)}</a>'
        for k, v in (
            ("table", "Table 3 layout"),
            ("outcomes", "Robot outcomes"),
            ("extended", "Every metric"),
            ("attribution", "Attribution"),
            ("suite", "Suite statistics"),
            *((("rankings", "Rankings under parameter draws"),) if rankings else ()),
            *((("robustness", "Under every response model"),) if robust else ()),
            ("figures", "Figures"),
            ("planners", "Per planner"),
            ("logs", "Episode logs"),
            ("manifest", "Manifest"),
        )
    )
    body = [
        f"<header><h1>{_esc(title)}</h1><p>{_esc(intro)}</p></header>",
        f"<nav>{nav}</nav><main>",
        '<h2 id="table">The paper\'s Table 3 layout</h2>',
        "<p>Fréchet deviation of the pedestrians, minimum robot distance, trajectory length "
        "of the pedestrians, and the duration of the robot's run (what the paper's Time "
        "column measured); beside each pedestrian and social column the same over the "
        "episodes in which the robot reached its goal ('| success', with their number n), "
        "and last how the episodes ended. Definitions: docs/metrics.md.</p>",
        _wide_table(summary["table"]),
        '<h2 id="outcomes">Robot outcomes</h2>',
        _wide_table(summary["outcomes"]),
        '<h2 id="extended">Every metric</h2>',
        "<p>One table per scenario; hover over a metric for its definition.</p>",
        _extended_tables(summary["extended"]),
        '<h2 id="attribution">What of the deviation is the robot\'s doing</h2>',
        _attribution(summary.get("attribution"), planners),
        '<h2 id="suite">Suite statistics</h2>',
        _suite(
            summary.get("suite"),
            "figures/profiles.png" in files or (out / "figures/profiles.png").is_file(),
        ),
        *(
            (
                '<h2 id="rankings">Rankings under the model\'s uncertainty</h2>',
                _rankings(rankings),
            )
            if rankings
            else ()
        ),
        *(
            (
                '<h2 id="robustness">Orderings under every response model</h2>',
                _robustness(robust),
            )
            if robust
            else ()
        ),
        '<h2 id="figures">Figures</h2>',
        _figures(out, files, scenarios, figure_seed),
        '<h2 id="planners">Per planner: how the robot\'s episodes ended</h2>',
        _outcomes(rows, scenarios, planners),
        '<h2 id="logs">Episode logs</h2>',
        _log_links(out, rows, scenarios, planners),
        '<h2 id="manifest">Manifest</h2>',
        _manifest_section(manifest, present),
        "</main>",
    ]
    page = (
        '<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
        '<meta name="viewport" content="width=device-width, initial-scale=1">'
        f"<title>{_esc(title)}</title><style>{_CSS}</style></head><body>"
        + "\n".join(body)
        + "</body></html>\n"
    )
    return page.encode("utf-8")


# The report files the page is drawn from; each is checked against the episode files.
_CHECKED_REPORTS: Final = ("summary.json", "episodes.csv")


def _manifest_request(path: Path, manifest: Any) -> tuple[list[str], list[str], list[int], Any]:
    """The scenarios, planners, seeds and reference of the run that wrote the folder's
    reports last, from its manifest (a damaged one is an error naming it)."""
    request = manifest.get("request") if isinstance(manifest, dict) else None
    if isinstance(request, dict):
        scenarios, planners, seeds = (request.get(k) for k in ("scenarios", "planners", "seeds"))
        reference = request.get("reference")
        if (
            isinstance(scenarios, list)
            and isinstance(planners, list)
            and isinstance(seeds, list)
            and scenarios
            and planners
            and seeds
            and all(isinstance(x, str) for x in (*scenarios, *planners))
            and all(type(x) is int for x in seeds)
            and (reference is None or isinstance(reference, str))
        ):
            return scenarios, planners, seeds, reference
    raise BenchmarkError(f"{path}: damaged manifest (its request); use a new --out")


def check_reports(out: Path) -> None:
    """Check what the results page is drawn from: the manifest, every episode file of
    its request (:func:`~srfm.benchmark._results.read_episode`: schema, checksum, the
    episode its path names), and ``summary.json`` and ``episodes.csv`` against the
    tables those episodes give (rendered again, compared byte for byte).

    Raises:
        BenchmarkError: naming the missing or damaged file, and what to do.
    """
    path = out / MANIFEST
    manifest = _json_file(out, MANIFEST, {})
    check_manifest_schema(path, manifest)
    scenarios, planners, seeds, reference = _manifest_request(path, manifest)
    _summary(out, {})  # an older or newer layout says so before the comparison below
    try:
        params = SRFMParams().replace(**manifest.get("params", {}))
    except (SrfmError, TypeError) as exc:
        raise BenchmarkError(f"{path}: damaged manifest (params: {exc}); use a new --out") from None
    results = []
    for scenario in scenarios:
        for planner in planners:
            for seed in seeds:
                episode = episode_path(out, scenario, planner, seed)
                if not episode.is_file():
                    raise BenchmarkError(
                        f"{episode} is missing: run the benchmark on {out} again to finish it"
                    )
                results.append(read_episode(episode, expect=(scenario, planner, seed)))
    files, _ = render_tables(
        results,
        scenarios=scenarios,
        planners=planners,
        seeds=seeds,
        params=params,
        reference=reference,
        floors=load_floors(out, scenarios, seeds),
    )
    for name in _CHECKED_REPORTS:
        if _read_bytes(out, name, {}) != files[name]:
            raise BenchmarkError(
                f"{out / name}: does not match the folder's episode files (damaged, edited, "
                f"or written by another srfm); run the benchmark on {out} again with the "
                "same options to rewrite its reports"
            )


def write_report(out: str | Path) -> Path:
    """Rebuild ``report.html`` of the results folder ``out`` from its files (holding the
    folder's lock), after checking them (:func:`check_reports`); return its path.

    Raises:
        BenchmarkError: see :func:`render_report` and :func:`check_reports`; also when
            ``out`` is not a folder.
    """
    out = Path(out)
    if not out.is_dir():
        raise BenchmarkError(f"{out} is not a folder")
    with folder_lock(out):
        check_reports(out)
        data = render_report(out)
        path = out / REPORT
        atomic_write_bytes(path, data)
    return path
