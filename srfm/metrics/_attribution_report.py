"""The report parts of issue 41: the noise floor and the direct / knock-on split per
scenario (rows of the extended table, ``summary.json``), and the suite statistics
(``suite.md``, ``summary.json``). One writer for the benchmark and ``srfm score``
(:mod:`srfm.metrics.report`)."""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping, Sequence
from typing import Any, Final

import numpy as np

from srfm.metrics.attribution import (
    CHAOS_SHARE,
    FELT_FORCE_MPS2,
    ROBOT_SHARE,
    SPLIT_COLUMNS,
    FloorSummary,
    attributable,
    deviation_split,
    floor_summary,
)
from srfm.metrics.episode import EpisodeMetrics
from srfm.metrics.headroom import Interval, min_score_seeds
from srfm.metrics.stats import summarize
from srfm.metrics.suite import LEVEL, N_RESAMPLES, SuiteStats
from srfm.metrics.tables import ExtraBlock
from srfm.sim.floor import NUDGE_M

__all__ = [
    "ATTRIBUTION_LEGEND",
    "attribution",
    "suite_dict",
    "suite_markdown",
]

ATTRIBUTION_LEGEND: Final = (
    f"Direct: the Fréchet deviation of the pedestrians on whom the robot's force reached "
    f"{FELT_FORCE_MPS2:g} m/s² (1 % of a pedestrian's goal force) at some step, knock-on: "
    "of those on whom it never did (it reached them through other people); each a sum "
    "over its pedestrians divided by all the episode's pedestrians, so direct + knock-on "
    "= frechet_m. Noise floor: the deviation of the crowd without a robot against a copy "
    f"with one pedestrian's start moved {NUDGE_M * 1e3:g} mm (mean ± SD over the seeds; "
    "the same for every planner). A difference between two planners' mean deviations "
    "below the floor's spread (its SD over the seeds) is not attributable to the "
    f"planners. The floor's share of the planners' mean deviation: below {ROBOT_SHARE:g} "
    f"the scenario measures the robot, from {CHAOS_SHARE:g} on mostly the crowd's chaos, "
    "in between both. Descriptive: no tests, no bold."
)


def _number(x: float, digits: int = 2) -> str:
    return "–" if math.isnan(x) else f"{x:.{digits}f}"


def _mean_std(values: Sequence[float], digits: int = 2) -> str:
    s = summarize(np.asarray(values, dtype=np.float64))
    return f"{_number(s.mean, digits)} ± {_number(s.std, digits)}"


def _json(x: float) -> float | None:
    return None if math.isnan(x) else float(x)


def _floor_dict(f: FloorSummary) -> dict[str, Any]:
    return {
        "n": f.n,
        "mean": f.mean,
        "std": _json(f.std),
        "values": list(f.values),
        "deviation": _json(f.deviation),
        "share": _json(f.share),
        "verdict": f.verdict,
    }


def _floor_note(f: FloorSummary, pairs: Sequence[tuple[str, str, float, bool]]) -> str:
    verdict = {
        "robot": "the scenario measures the robot",
        "chaos": "the scenario measures mostly the crowd's chaos",
        "both": "the scenario measures both the robot and the crowd's chaos",
        "–": "no verdict",
    }[f.verdict]
    spread = f.std if not math.isnan(f.std) else f.mean
    text = (
        f"Noise floor (no robot, one start moved {NUDGE_M * 1e3:g} mm): "
        f"{f.mean:.4f} ± {_number(f.std, 4)} m over {f.n} seeds, "
        f"{_number(100.0 * f.share, 1)} % of the planners' mean deviation "
        f"({_number(f.deviation, 3)} m): {verdict}."
    )
    weak = [f"{a}–{b} ({abs(d):.3f} m)" for a, b, d, ok in pairs if not ok]
    if weak:
        text += (
            f" Differences of mean deviation below the floor's spread ({spread:.4f} m), "
            "not attributable to the planners: " + ", ".join(weak) + "."
        )
    else:
        text += (
            f" Every difference of mean deviation is at least the floor's spread ({spread:.4f} m)."
        )
    return text


def attribution(
    results: Sequence[EpisodeMetrics],
    *,
    scenarios: Sequence[str],
    planners: Sequence[str],
    seeds: Sequence[int],
    floors: Mapping[str, Sequence[float]] | None,
) -> tuple[dict[str, ExtraBlock], dict[str, Any]]:
    """The extended table's rows (per scenario) and ``summary.json``'s
    ``attribution`` entry: the split per planner and, with ``floors`` (per scenario,
    one floor per seed in seed order), the noise floor and which differences between
    planners are attributable to them."""
    found = {(r.scenario, r.planner, r.seed): r for r in results}
    blocks: dict[str, ExtraBlock] = {}
    doc: dict[str, Any] = {
        "legend": ATTRIBUTION_LEGEND,
        "felt_force_mps2": FELT_FORCE_MPS2,
        "nudge_m": NUDGE_M,
        "robot_share": ROBOT_SHARE,
        "chaos_share": CHAOS_SHARE,
        "scenarios": {},
    }
    for scenario in scenarios:
        episodes = {p: [found[(scenario, p, s)] for s in seeds] for p in planners}
        splits = {p: [deviation_split(r) for r in episodes[p]] for p in planners}
        rows = []
        split_doc: dict[str, Any] = {}
        for name, unit, _ in SPLIT_COLUMNS:
            texts = []
            for p in planners:
                values = [x[name] for x in splits[p]]
                texts.append(_mean_std(values))
                s = summarize(np.asarray(values, dtype=np.float64))
                split_doc.setdefault(p, {})[name] = {
                    "n": s.n,
                    "mean": _json(s.mean),
                    "std": _json(s.std),
                }
            rows.append((f"`{name}`", unit, tuple(texts)))
        entry: dict[str, Any] = {"split": split_doc}
        note = ""
        if floors is not None and scenario in floors:
            deviations = [r["frechet_m"] for p in planners for r in episodes[p]]
            f = floor_summary(floors[scenario], deviations)
            means = {p: float(np.nanmean([r["frechet_m"] for r in episodes[p]])) for p in planners}
            pairs = []
            for a, b in itertools.combinations(planners, 2):
                d = means[a] - means[b]
                pairs.append((a, b, d, attributable(d, f)))
            entry["floor"] = _floor_dict(f)
            entry["differences"] = [
                {"a": a, "b": b, "difference_m": d, "attributable": ok} for a, b, d, ok in pairs
            ]
            note = _floor_note(f, pairs)
        else:
            entry["floor"] = None
        doc["scenarios"][scenario] = entry
        blocks[scenario] = ExtraBlock(
            title="Attribution: direct and knock-on deviation (descriptive)",
            rows=tuple(rows),
            note=note,
        )
    return blocks, doc


def _interval_dict(x: Interval) -> dict[str, Any]:
    return {
        "estimate": _json(x.estimate),
        "low": _json(x.low),
        "high": _json(x.high),
        "n": x.n,
        "level": x.level,
    }


def _interval_text(x: Interval, digits: int = 2) -> str:
    if math.isnan(x.estimate):
        return "–"
    if math.isnan(x.low):
        return f"{x.estimate:.{digits}f}"
    return f"{x.estimate:.{digits}f} [{x.low:.{digits}f}, {x.high:.{digits}f}]"


SUITE_LEGEND: Final = (
    "Over every (scenario, seed) of the run. IQM: interquartile mean (the mean of the "
    "middle 50 % of the episodes). Norm. score: per episode (straight − planner) / "
    "headroom on the seeds where the planner, straight and the oracle all reached the "
    "goal, in the scenarios where the planner's score is defined (k ≥ max(2, ⌈n/2⌉)). "
    "P(A < B): the probability that A deviates a person less than B does the same "
    "person (same scenario, seed and pedestrian; ties count one half), averaged over "
    "the seeds, then the scenarios. Intervals: "
    f"{LEVEL:.0%} percentile intervals of a stratified bootstrap ({N_RESAMPLES} "
    "resamples of the seeds within each scenario; scipy.stats.bootstrap), not "
    "corrected for the number of pairs (Agarwal et al., NeurIPS 2021)."
)


def suite_dict(stats: SuiteStats) -> dict[str, Any]:
    """``summary.json``'s ``suite`` entry."""
    return {
        "legend": SUITE_LEGEND,
        "n_resamples": N_RESAMPLES,
        "level": LEVEL,
        "deviation_iqm": {p: _interval_dict(x) for p, x in stats.deviation_iqm.items()},
        "score_iqm": {p: _interval_dict(x) for p, x in stats.score_iqm.items()},
        "score_scenarios": {p: list(v) for p, v in stats.score_scenarios.items()},
        "improvement": {
            a: {b: _interval_dict(stats.improvement[(a, b)]) for b in stats.planners if b != a}
            for a in stats.planners
        },
        "profile_taus_m": [float(t) for t in stats.taus],
        "profiles": {p: [float(v) for v in stats.profiles[p]] for p in stats.planners},
    }


def suite_markdown(stats: SuiteStats, n_seeds: int) -> str:
    """``suite.md``: the IQMs and the probabilities of improvement."""
    scored = bool(stats.score_iqm)
    head = "| Planner | IQM deviation (m) [95 % CI] | n |"
    rule = "|---|--:|--:|"
    if scored:
        head += " IQM norm. score [95 % CI] | episodes | scenarios |"
        rule += "--:|--:|---|"
    lines = ["# Suite statistics", "", head, rule]
    for p in stats.planners:
        d = stats.deviation_iqm[p]
        row = f"| {p} | {_interval_text(d, 3)} | {d.n} |"
        if scored:
            s = stats.score_iqm[p]
            named = ", ".join(stats.score_scenarios[p]) or "none"
            row += f" {_interval_text(s)} | {s.n} | {named} |"
        lines.append(row)
    lines += ["", "P(row < column): the row's planner deviates a person less.", ""]
    lines.append("| | " + " | ".join(stats.planners) + " |")
    lines.append("|---|" + "|".join(["--:"] * len(stats.planners)) + "|")
    for a in stats.planners:
        cells = [
            "–" if a == b else _interval_text(stats.improvement[(a, b)]) for b in stats.planners
        ]
        lines.append(f"| {a} | " + " | ".join(cells) + " |")
    lines += [
        "",
        SUITE_LEGEND + f" Scores need k ≥ {min_score_seeds(n_seeds)} of {n_seeds} seeds.",
        "",
    ]
    return "\n".join(lines)
