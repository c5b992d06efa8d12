"""docs/sensitivity.md's sweep as committed data, and the page's tables from it.

    .venv/bin/python tools/results/sensitivity.py pack results/sensitivity \\
        --commit C --started ISO --finished ISO --wall-s S --machine TEXT

``pack`` keeps of a finished ``srfm sweep docs/sweeps/sensitivity.toml`` folder only
what the page's tables need, one row per episode (``docs/sensitivity/episodes.csv.gz``:
A_r, B_r, scenario, planner, seed, Fréchet deviation, robot success; about 0.2 MB),
and the run's record (``docs/sensitivity/run.json``: command, commit, times, machine).
The blocks below render from those two files; ``tools/results/generate.py`` registers
them (``BLOCKS``). The ranking blocks of the same page read the sweep report's
``docs/sensitivity/rankings.csv`` of the same run (``tools/results/fitting_pages.py``).
"""

from __future__ import annotations

import argparse
import csv
import gzip
import io
import json
import math
import shlex
import sys
from collections.abc import Callable
from functools import cache
from pathlib import Path
from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from srfm.fitting import holm
from srfm.metrics.stats import ALPHA, compare, wilson
from srfm.sweep.report import SweepData, load_sweep, mean_ci, report_figures, report_text
from tools.results import fitting_pages as fp
from tools.results.fitting_pages import DOCS, MissingDataError, prose

EPISODES: Final = DOCS / "sensitivity" / "episodes.csv.gz"
RUN: Final = DOCS / "sensitivity" / "run.json"
COMMAND: Final = "nice -n 10 srfm sweep docs/sweeps/sensitivity.toml --out results/sensitivity -j 2"
REPORT_COMMAND: Final = "srfm sweep report results/sensitivity"
FACTORS: Final = ("a_robot", "b_robot")
TEXT_COLUMNS: Final = ("scenario", "planner")
COLUMNS: Final = (*FACTORS, *TEXT_COLUMNS, "seed", "frechet_m", "robot_success")
REFERENCE: Final = {"a_robot": 7.93, "b_robot": 0.99}
"""The paper's A_r and B_r: the sweep's reference cell."""
LABELS: Final = {"a_robot": "A_r", "b_robot": "B_r"}
SPEC_KEYS: Final = ("name", "planners", "scenarios", "seeds", "cells", "factors", "params")
"""What :data:`RUN` keeps of the sweep's manifest: enough to read the episodes back as
the sweep (:func:`sweep_data`), whose report ``srfm sweep report`` wrote."""


# -- pack -------------------------------------------------------------------------------


def _value(x: Any) -> str:
    """A cell of the CSV: floats as ``repr`` (exact), NaN as empty."""
    if isinstance(x, float | np.floating):
        return "" if math.isnan(x) else repr(float(x))
    if isinstance(x, np.integer):
        return str(int(x))
    return str(x)


def episodes_csv(folder: Path) -> bytes:
    """The sweep's episodes, only :data:`COLUMNS`, as gzip'd CSV (mtime 0: the same
    episodes give the same bytes)."""
    data = load_sweep(folder)
    if data.episodes != data.expected:
        raise SystemExit(f"{folder}: {data.episodes} of {data.expected} episodes: not finished")
    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="\n")
    writer.writerow(COLUMNS)
    cols = data.columns
    for i in range(data.episodes):
        writer.writerow([_value(cols[c][i]) for c in COLUMNS])
    out = io.BytesIO()
    with gzip.GzipFile(fileobj=out, mode="wb", mtime=0) as f:
        f.write(buf.getvalue().encode("utf-8"))
    return out.getvalue()


def run_payload(folder: Path, record: dict[str, Any], episodes: int) -> dict[str, Any]:
    """:data:`RUN` of a finished sweep folder: the run's ``record`` (commit, times,
    machine), its episodes, versions and what :func:`sweep_of` needs of its manifest."""
    manifest = json.loads((folder / "sweep.json").read_text(encoding="utf-8"))
    return {
        "command": COMMAND,
        "report_command": REPORT_COMMAND,
        **record,
        "episodes": episodes,
        "versions": manifest["versions"],
        "spec": {k: manifest[k] for k in SPEC_KEYS},
    }


def pack(folder: Path, record: dict[str, Any]) -> None:
    """Write :data:`EPISODES` and :data:`RUN` from a finished sweep folder."""
    EPISODES.write_bytes(episodes_csv(folder))
    payload = run_payload(folder, record, len(read_episodes(EPISODES)["seed"]))
    RUN.write_text(json.dumps(payload, indent=1) + "\n", encoding="utf-8")


# -- read -------------------------------------------------------------------------------


def read_episodes(path: Path) -> dict[str, NDArray[Any]]:
    """Episodes written by :func:`episodes_csv`, as columns (floats NaN where undefined)."""
    if not path.is_file():
        raise MissingDataError(f"data file `{path.name}`")
    with gzip.open(path, "rt", encoding="utf-8", newline="") as f:
        rows = list(csv.DictReader(f))
    out: dict[str, NDArray[Any]] = {}
    for c in COLUMNS:
        values = [r[c] for r in rows]
        if c in TEXT_COLUMNS:
            out[c] = np.array(values, dtype=object)
        elif c == "seed":
            out[c] = np.array([int(v) for v in values], dtype=np.int64)
        else:
            out[c] = np.array([float(v) if v else math.nan for v in values], dtype=np.float64)
    return out


@cache
def episodes() -> dict[str, NDArray[Any]]:
    """The committed episodes as columns (floats NaN where undefined)."""
    if not EPISODES.is_file():
        raise MissingDataError(f"data file `docs/{EPISODES.relative_to(DOCS)}`")
    return read_episodes(EPISODES)


@cache
def run() -> dict[str, Any]:
    """The run's record."""
    if not RUN.is_file():
        raise MissingDataError(f"data file `docs/{RUN.relative_to(DOCS)}`")
    payload: dict[str, Any] = json.loads(RUN.read_text(encoding="utf-8"))
    return payload


def sweep_of(record: dict[str, Any], columns: dict[str, NDArray[Any]]) -> SweepData:
    """The sweep as ``srfm sweep report`` read it from its folder, read back from a run
    record (:func:`run_payload`) and its episodes (:func:`read_episodes`): the same
    columns the report reads, in the same order, the same cells, factors and base
    parameters (the reference cell), the folder named as ``--out`` named it."""
    spec = record["spec"]
    lacking = [k for k in SPEC_KEYS if k not in spec]
    if lacking:
        raise MissingDataError(f"{', '.join(lacking)} in the sweep's run record (pack it again)")
    factors = tuple(str(f) for f in spec["factors"])
    if set(factors) != set(FACTORS):
        raise SystemExit(f"the sweep's factors are {list(factors)}; its episodes hold {FACTORS}")
    cells = {
        str(c): {str(k): float(v) for k, v in values.items()} for c, values in spec["cells"].items()
    }
    cell_of = {tuple(values[f] for f in factors): c for c, values in cells.items()}
    keys = zip(*(columns[f].tolist() for f in factors), strict=True)
    cell = np.array([cell_of[key] for key in keys], dtype=object)
    command = shlex.split(str(record["command"]))
    return SweepData.from_columns(
        folder=Path(command[command.index("--out") + 1]),
        factors=factors,
        cells=cells,
        scenarios=tuple(str(s) for s in spec["scenarios"]),
        planners=tuple(str(p) for p in spec["planners"]),
        base={str(k): float(v) for k, v in spec["params"].items()},
        columns={"cell": cell, **columns},
        expected=len(cells) * len(spec["scenarios"]) * len(spec["planners"]) * len(spec["seeds"]),
    )


def sweep_data() -> SweepData:
    """The committed sweep (:data:`RUN`, :data:`EPISODES`) as ``srfm sweep report`` read it."""
    return sweep_of(run(), episodes())


@cache
def report() -> tuple[str, str]:
    """``docs/sensitivity/report.md`` and ``rankings.csv``: the sweep report's text, by
    ``srfm sweep report``'s own function, from the committed episodes."""
    return report_text(sweep_data())


def report_md() -> str:
    return report()[0]


def rankings_csv() -> str:
    return report()[1]


def figures() -> dict[str, bytes]:
    """The sweep report's figures (``docs/sensitivity/*.png``), by ``srfm sweep
    report``'s own function, from the committed episodes."""
    return report_figures(sweep_data())


def planners() -> list[str]:
    return [str(p) for p in run()["spec"]["planners"]]


def scenarios() -> list[str]:
    return [str(s) for s in run()["spec"]["scenarios"]]


def levels(factor: str) -> list[float]:
    return sorted(set(episodes()[factor].tolist()))


@cache
def pooled(factor: str, planner: str, level: float) -> tuple[float, float, float]:
    """Mean Fréchet deviation, the half-width of its 95 % t interval and the success
    rate of ``planner`` at ``factor = level``, the scenarios and the other factor
    pooled (as ``srfm sweep report``)."""
    e = episodes()
    mask = (e["planner"] == planner) & (e[factor] == level)
    mean, half, _ = mean_ci(e["frechet_m"][mask])
    ok = e["robot_success"][mask]
    ok = ok[np.isfinite(ok)]
    rate = wilson(int(ok.sum()), int(ok.size))[0]
    return mean, half, rate


def _pooled_table(factor: str) -> str:
    values = levels(factor)
    head = []
    for i, v in enumerate(values):
        text = f"**{v:g}**" if v == REFERENCE[factor] else f"{v:g}"
        head.append(f"{LABELS[factor]} = {text}" if i == 0 else text)
    lines = ["| planner | " + " | ".join(head) + " |", "|---|" + "--:|" * len(values)]
    for p in planners():
        cells = []
        for v in values:
            mean, half, rate = pooled(factor, p, v)
            ci = "" if not half > 0 else f" ± {half:.3f}"
            cells.append(f"{mean:.3f}{ci} ({100 * rate:.0f} %)")
        lines.append(f"| {p} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def sensitivity_by_a() -> str:
    """Per planner and A_r: mean deviation ± CI (success), B_r and scenarios pooled."""
    return _pooled_table("a_robot")


def sensitivity_by_b() -> str:
    """Per planner and B_r: mean deviation ± CI (success), A_r and scenarios pooled."""
    return _pooled_table("b_robot")


def sensitivity_success() -> str:
    """Each planner's success rate per scenario, over the cells with a robot force."""
    e = episodes()
    lines = [
        "| planner | " + " | ".join(scenarios()) + " |",
        "|---|" + "--:|" * len(scenarios()),
    ]
    for p in planners():
        cells = []
        for s in scenarios():
            ok = e["robot_success"][(e["planner"] == p) & (e["scenario"] == s) & (e["a_robot"] > 0)]
            ok = ok[np.isfinite(ok)]
            cells.append(f"{100 * wilson(int(ok.sum()), int(ok.size))[0]:.0f} %")
        lines.append(f"| {p} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def _seed_values(a: float, b: float, scenario: str, planner: str) -> dict[int, float]:
    e = episodes()
    mask = (
        (e["a_robot"] == a)
        & (e["b_robot"] == b)
        & (e["scenario"] == scenario)
        & (e["planner"] == planner)
    )
    return dict(zip(e["seed"][mask].tolist(), e["frechet_m"][mask].tolist(), strict=True))


def head_to_head() -> tuple[int, dict[tuple[str, str], list[int]]]:
    """Over the (cell, scenario) pairs with a robot force (A_r > 0) whose planners are
    not all tied: for each pair of planners how often the first's mean is
    significantly lower, significantly higher (paired t-test on the shared seeds,
    p < ALPHA) or neither, then how often lower and higher after Holm's correction
    over every test of the table; and the number of (cell, scenario) pairs."""
    names = planners()
    pairs = [(p, q) for i, p in enumerate(names) for q in names[i + 1 :]]
    tests: list[tuple[tuple[str, str], bool, float]] = []
    total = 0
    for a in (a for a in levels("a_robot") if a > 0):
        for b in levels("b_robot"):
            for s in scenarios():
                values = {p: _seed_values(a, b, s, p) for p in names}
                if not all(values.values()):
                    raise MissingDataError(f"episodes of A_r = {a:g}, B_r = {b:g}, {s}")
                means = [mean_ci(np.array(list(values[p].values())))[0] for p in names]
                if max(means) == min(means):
                    continue
                total += 1
                for p, q in pairs:
                    seeds = sorted(set(values[p]) & set(values[q]))
                    pv = compare([values[p][k] for k in seeds], [values[q][k] for k in seeds])
                    lower = means[names.index(p)] < means[names.index(q)]
                    tests.append(((p, q), lower, pv.paired_p))
    counts = {pair: [0, 0, 0, 0, 0] for pair in pairs}
    adjusted = holm([t[2] for t in tests])
    for (pair, lower, pv), p_holm in zip(tests, adjusted, strict=True):
        counts[pair][2 if not pv < ALPHA else 0 if lower else 1] += 1
        if p_holm < ALPHA:
            counts[pair][3 if lower else 4] += 1
    return total, counts


def sensitivity_pairs() -> str:
    """The head-to-head table of every pair of planners."""
    total, counts = head_to_head()
    lines = [
        prose(
            f"Head to head over the {total} (cell, scenario) pairs with A_r > 0 (paired "
            f"t-test of the two planners on the same seeds, p < {ALPHA}; the last two "
            f"columns after Holm's correction over the table's {total * len(counts)} tests):"
        ),
        "",
        "| pair | first significantly lower | first significantly higher | not significant "
        "| lower (Holm) | higher (Holm) |",
        "|---|--:|--:|--:|--:|--:|",
    ]
    lines += [
        f"| {p} vs {q} | {c[0]} | {c[1]} | {c[2]} | {c[3]} | {c[4]} |"
        for (p, q), c in counts.items()
    ]
    return "\n".join(lines)


def sensitivity_run() -> str:
    """The sentence saying when, where and how long the run was."""
    r = run()
    n = int(r["episodes"])
    return prose(
        f"Run on {r['started'][:10]} (commit {r['commit']}, the shipped policies of that "
        f"commit) with two workers under `nice -n 10`, while other work shared the "
        f"2-core machine ({r['machine']}): {n:,} episodes in {r['wall_s']:.0f} s "
        f"({n / r['wall_s']:.1f} episodes/s)."
    )


def _ranges(factor: str) -> dict[float, tuple[float, float]]:
    """Per level of ``factor``, the lowest and the highest planner's pooled mean."""
    out = {}
    for v in levels(factor):
        means = [pooled(factor, p, v)[0] for p in planners()]
        out[v] = (min(means), max(means))
    return out


def _range(lo: float, hi: float) -> str:
    return f"{lo:.2f}–{hi:.2f} m" if f"{lo:.2f}" != f"{hi:.2f}" else f"{lo:.2f} m"


def sensitivity_pooled_claims() -> str:
    """What the pooled tables say, in numbers read from them."""
    by_a, by_b = _ranges("a_robot"), _ranges("b_robot")
    gap = max(hi - lo for r in (by_a, by_b) for lo, hi in r.values())
    a_lo, a_hi = min(by_a), max(by_a)
    b_lo, b_hi = min(by_b), max(by_b)
    no_force = {p: pooled("a_robot", p, 0.0)[2] for p in planners()} if 0.0 in by_a else {}
    items = [
        f"- **The deviation is the model's parameter more than the planner's choice.** "
        f"Moving A_r from {a_lo:g} to {a_hi:g} m/s² moves the planners' pooled mean "
        f"deviation from {_range(*by_a[a_lo])} to {_range(*by_a[a_hi])}; moving B_r from "
        f"{b_lo:g} to {b_hi:g} m moves it from {_range(*by_b[b_lo])} to "
        f"{_range(*by_b[b_hi])}. The largest difference between two planners in any of "
        f"these pooled means is {gap:.3f} m. A Table 3 in metres is therefore only as "
        f"good as the fitted A_r and B_r: with the other fits of [fitting.md](fitting.md) "
        f"its numbers would change by more than the gaps between its rows.",
    ]
    if no_force:
        order = sorted(no_force, key=lambda p: no_force[p])
        rates = ", ".join(f"{100 * no_force[p]:.0f} % (`{p}`)" for p in order)
        items.append(
            "- **A_r = 0 is a degenerate benchmark.** Without a robot force the factual "
            "crowd is the counterfactual one, every deviation is exactly 0 (no ranking "
            f"at all), and the pedestrians walk into the robot: success falls to {rates}."
        )
    low = {p: min(pooled("a_robot", p, v)[2] for v in by_a if v > 0) for p in planners()}
    ranges = ", ".join(f"`{p}` {100 * low[p]:.0f} %" for p in planners())
    items.append(
        "- **Success with a robot force.** The lowest pooled success of each planner "
        f"over the columns with A_r > 0: {ranges}; the "
        "table below gives it per scenario (the success rates of the B_r table include "
        "the A_r = 0 cells)."
    )
    return prose("\n".join(items))


def sensitivity_policy_claims() -> str:
    """The head-to-head of the two policies and of the two classical planners."""
    total, counts = head_to_head()
    names = planners()
    lines = []
    if ("td3-srfm", "td3-base") in counts:
        lo, hi, ns, lo_holm, hi_holm = counts["td3-srfm", "td3-base"]
        lines.append(
            f"Across the robot forces of the grid, `td3-srfm` is significantly less "
            f"deviating than `td3-base` in {lo} of the {total} (cell, scenario) pairs, "
            f"significantly more in {hi}, and neither in {ns} (paired t-test, p < {ALPHA}, "
            f"uncorrected; {lo_holm} and {hi_holm} after Holm's correction)."
        )
    if ("dwa", "vo") in counts and {"dwa", "vo"} <= set(names):
        lo, hi, ns, _, _ = counts["dwa", "vo"]
        lines.append(
            f"DWA and VO are not significantly different in {ns} of the {total} pairs; "
            f"DWA is significantly lower in {lo} and higher in {hi}."
        )
    return prose(" ".join(lines))


def _cells_first() -> tuple[int, dict[str, int], int]:
    """Over the sweep report's cells with a robot force (rankings.csv, the mean over
    scenarios): the number of cells, how often each planner ranks first, and in how
    many cells both policies (``td3-*``) rank ahead of every other planner."""
    ranks = fp._rankings()
    cells = [(a, b) for (scope, a, b) in ranks if scope == "all" and a > 0]
    first = dict.fromkeys(planners(), 0)
    ahead = 0
    for a, b in cells:
        cell = ranks["all", a, b]
        order = sorted(cell, key=lambda p: cell[p][1])
        first[order[0]] += 1
        policies = [p for p in order if p.startswith("td3-")]
        ahead += order[: len(policies)] == policies
    return len(cells), first, ahead


def sensitivity_order_claims() -> str:
    """What the table of rankings says, counted from it."""
    n, first, ahead = _cells_first()
    leaders = sorted((p for p in first if first[p]), key=lambda p: -first[p])
    counts = ", ".join(f"`{p}` in {first[p]}" for p in leaders)
    return prose(
        f"Of the {n} cells with a robot force, the mean over scenarios ranks first {counts}; "
        f"both policies rank ahead of both classical planners in {ahead} of the {n}."
    )


BLOCKS: dict[str, Callable[[], str]] = {
    "sensitivity-run": sensitivity_run,
    "sensitivity-by-a": sensitivity_by_a,
    "sensitivity-by-b": sensitivity_by_b,
    "sensitivity-pooled-claims": sensitivity_pooled_claims,
    "sensitivity-success": sensitivity_success,
    "sensitivity-pairs": sensitivity_pairs,
    "sensitivity-policy-claims": sensitivity_policy_claims,
    "sensitivity-order-claims": sensitivity_order_claims,
}


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    sub = ap.add_subparsers(dest="cmd", required=True)
    p = sub.add_parser("pack", help="pack a finished sweep folder into docs/sensitivity/")
    p.add_argument("folder", type=Path)
    for name in ("commit", "started", "finished", "machine"):
        p.add_argument(f"--{name}", required=True)
    p.add_argument("--wall-s", type=float, required=True)
    args = ap.parse_args(argv)
    pack(
        args.folder,
        {
            "commit": args.commit,
            "started": args.started,
            "finished": args.finished,
            "wall_s": args.wall_s,
            "machine": args.machine,
        },
    )
    print(f"packed {args.folder} into {EPISODES.parent}")


if __name__ == "__main__":
    main()
