"""Verdicts that survive the response model: one benchmark under several models of how
people answer a robot.

Every deviation srfm reports rests on its model of the pedestrians' response to the
robot, and the ordering of planners can change with it (docs/real_encounters.md).
``srfm benchmark --params agrawal2024,navwareset2026_ttc,FILE.toml`` therefore runs the
same scenarios × planners × seeds under each model: the first is the run's own (the
results folder's tables, figures and logs), every other one a results folder of its own,
``OUT/models/<name>/`` (no logs, no figures; resumed like any run). The models are
written to ``OUT/models.json``, and a folder refuses a run with other models.

Once every model is finished, :func:`render_robustness` writes, per scenario
(``robustness.md``, ``robustness.json``, a section of ``report.html`` and the
``robustness`` entry of ``summary.json``):

- for every pair of planners (A, B) and every model, the mean paired difference of the
  episode's Fréchet deviation over the seeds where both are defined, A − B, and the
  two-sided paired t-test of it; the p-values of the whole run (every scenario, pair and
  model) are adjusted together by Holm's method (:data:`ALPHA` = 0.05);
- the pair's verdict: **holds** when the difference is significant, in the same
  direction, under every model; **flips** when it is significant in opposite directions
  under two models; **unresolved** otherwise (not significant under some model, and no
  two significant models disagree);
- Kendall's τ-b between the planners' mean deviations under every two models, with a
  95 % percentile bootstrap interval over the seeds (:data:`BOOTSTRAP_RESAMPLES`
  resamples of the seeds, the same seeds for every model and planner, from
  ``numpy.random.default_rng(BOOTSTRAP_SEED)``), and over the suite the mean of the
  scenarios' τ with the interval of the same resamples (each scenario's seeds resampled
  on their own: a stratified bootstrap).

A statement of the form "A deviates people less than B in scenario S" is one that
**holds** here; docs/benchmark.md, "Results that survive the model".
"""

from __future__ import annotations

import contextlib
import itertools
import json
import math
import warnings
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any, Final

import attrs
import numpy as np
from numpy.typing import NDArray

from srfm._io import MAX_DOCUMENT_BYTES, atomic_write_text, read_input_bytes
from srfm._validate import path_name
from srfm.errors import BenchmarkError
from srfm.metrics.episode import EpisodeMetrics
from srfm.metrics.stats import ALPHA, adjust_p_values, compare
from srfm.models.params import SRFMParams

__all__ = [
    "BOOTSTRAP_RESAMPLES",
    "BOOTSTRAP_SEED",
    "MODELS_DIR",
    "MODELS_JSON",
    "ROBUSTNESS_JSON",
    "ROBUSTNESS_MD",
    "ResponseModels",
    "Robustness",
    "check_models",
    "kendall_tau_b",
    "model_folder",
    "robustness",
    "robustness_document",
    "robustness_markdown",
    "robustness_of_values",
]

MODELS_DIR: Final = "models"
MODELS_JSON: Final = "models.json"
ROBUSTNESS_MD: Final = "robustness.md"
ROBUSTNESS_JSON: Final = "robustness.json"
ROBUST_METRIC: Final = "frechet_m"
"""The metric the orderings are tested on: the episode's mean Fréchet deviation."""
BOOTSTRAP_RESAMPLES: Final = 2000
BOOTSTRAP_SEED: Final = 0
INTERVAL: Final = (2.5, 97.5)
_SCHEMA: Final = "srfm.models/1"
_ROBUSTNESS_SCHEMA: Final = "srfm.robustness/1"
VERDICTS: Final = ("holds", "flips", "unresolved")


@attrs.frozen
class ResponseModels:
    """The response models of a run, the run's own first.

    Attributes:
        names: each model's name (a preset's name, or a parameter file's stem): the
            folder ``OUT/models/<name>/`` of every model but the first.
        params: each model's parameters.
    """

    names: tuple[str, ...]
    params: tuple[SRFMParams, ...]

    def __attrs_post_init__(self) -> None:
        if len(self.names) != len(self.params):
            raise BenchmarkError("need one parameter set per response model name")
        if len(self.names) < 2:
            raise BenchmarkError("several response models need at least two")
        for name in self.names:
            path_name(name, "response model name", BenchmarkError)
        seen: set[str] = set()
        for name in self.names:
            if name in seen:
                raise BenchmarkError(f"response model {name!r} is given twice")
            seen.add(name)

    def document(self) -> dict[str, Any]:
        return {
            "schema": _SCHEMA,
            "models": [
                {"name": n, "params": p.as_dict()}
                for n, p in zip(self.names, self.params, strict=True)
            ],
        }


def model_folder(out: Path, name: str) -> Path:
    """The results folder of response model ``name`` (not the run's own) in ``out``."""
    return out / MODELS_DIR / name


def check_models(out: Path, models: ResponseModels) -> None:
    """Write ``OUT/models.json``, or check that the folder's is the same set of models
    (a run of other models into the same folder is refused before anything is written)."""
    path = out / MODELS_JSON
    doc = models.document()
    if path.is_file():
        old = _read_json(path)
        if old != json.loads(json.dumps(doc)):
            raise BenchmarkError(
                f"{out} holds a run under other response models ({path}); use a new --out"
            )
        return
    atomic_write_text(path, json.dumps(doc, indent=1) + "\n")


def _read_json(path: Path) -> Any:
    try:
        return json.loads(
            read_input_bytes(
                path, max_bytes=MAX_DOCUMENT_BYTES, what="models file", error=BenchmarkError
            )
        )
    except ValueError:
        raise BenchmarkError(f"{path}: damaged response models file; use a new --out") from None


def folder_models(out: Path) -> list[str] | None:
    """The names of the models of the run in ``out`` (the run's own first), or None for
    a folder of one model."""
    path = out / MODELS_JSON
    if not path.is_file():
        return None
    doc = _read_json(path)
    try:
        if doc["schema"] != _SCHEMA:
            raise KeyError("schema")
        return [str(m["name"]) for m in doc["models"]]
    except (KeyError, TypeError):
        raise BenchmarkError(f"{path}: damaged response models file; use a new --out") from None


def kendall_tau_b(x: NDArray[np.float64], y: NDArray[np.float64]) -> NDArray[np.float64]:
    """Kendall's τ-b of every row of ``x`` with the same row of ``y`` (shape (R, P): R
    rankings of P items), NaN where a row is constant or holds NaN.

    The definition of ``scipy.stats.kendalltau`` (variant "b"), vectorised over rows: the
    bootstrap needs 2,000 of them per scenario and pair of models, and scipy's costs
    0.76 ms a call (measured 2026-12-05 on this project's machine: 11 s for the paper
    suite's three models, against 0.1 s here); tests/benchmark/test_models.py checks
    that both agree on random rankings with ties."""
    dx = np.sign(x[:, :, None] - x[:, None, :])
    dy = np.sign(y[:, :, None] - y[:, None, :])
    upper = np.triu(np.ones(x.shape[1], dtype=bool), 1)
    concordance = (dx * dy)[:, upper].sum(axis=1)
    untied_x = (dx[:, upper] != 0).sum(axis=1)
    untied_y = (dy[:, upper] != 0).sum(axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        tau = concordance / np.sqrt(untied_x.astype(np.float64) * untied_y)
    bad = np.isnan(x).any(axis=1) | np.isnan(y).any(axis=1) | (untied_x == 0) | (untied_y == 0)
    return np.where(bad, np.nan, tau)


@attrs.frozen
class PairVerdict:
    """One pair of planners in one scenario under every model."""

    a: str
    b: str
    differences: tuple[float, ...]  # mean of A − B over the shared seeds, per model
    n: tuple[int, ...]  # those seeds, per model
    p: tuple[float, ...]  # paired t-test, per model
    p_holm: tuple[float, ...]
    verdict: str


@attrs.frozen
class TauRow:
    """Kendall's τ-b between two models' orderings of the planners, with its interval."""

    scenario: str  # or "suite" for the mean over scenarios
    first: str
    second: str
    tau: float
    low: float
    high: float


@attrs.frozen
class Robustness:
    """The robustness of a run's verdicts to the response model (module docstring)."""

    models: tuple[str, ...]
    scenarios: tuple[str, ...]
    planners: tuple[str, ...]
    n_seeds: int
    pairs: Mapping[str, tuple[PairVerdict, ...]]
    taus: tuple[TauRow, ...]

    def counts(self, scenario: str) -> dict[str, int]:
        return {v: sum(p.verdict == v for p in self.pairs[scenario]) for v in VERDICTS}


def _values(
    results: Sequence[EpisodeMetrics], scenarios: Sequence[str], planners: Sequence[str]
) -> NDArray[np.float64]:
    """(scenario, planner, seed) array of the metric, in the request's order."""
    flat = np.array([r.values[ROBUST_METRIC] for r in results], dtype=np.float64)
    return flat.reshape(len(scenarios), len(planners), -1)


def _verdict(differences: Sequence[float], p_holm: Sequence[float]) -> str:
    signs = {
        math.copysign(1.0, d)
        for d, p in zip(differences, p_holm, strict=True)
        if math.isfinite(p) and p < ALPHA and d != 0.0
    }
    significant = sum(math.isfinite(p) and p < ALPHA for p in p_holm)
    if len(signs) > 1:
        return "flips"
    if significant == len(p_holm) and len(signs) == 1:
        return "holds"
    return "unresolved"


def robustness(
    per_model: Sequence[Sequence[EpisodeMetrics]],
    *,
    models: Sequence[str],
    scenarios: Sequence[str],
    planners: Sequence[str],
    n_seeds: int,
) -> Robustness:
    """The verdicts of the module docstring from each model's episode metrics (every
    scenario × planner × seed of the request, in that order, one list per model)."""
    values = np.stack([_values(r, scenarios, planners) for r in per_model])
    return robustness_of_values(
        values, models=models, scenarios=scenarios, planners=planners, n_seeds=n_seeds
    )


def robustness_of_values(
    values: NDArray[np.float64],
    *,
    models: Sequence[str],
    scenarios: Sequence[str],
    planners: Sequence[str],
    n_seeds: int,
) -> Robustness:
    """:func:`robustness` of the metric's values, shape (model, scenario, planner,
    seed), NaN where undefined (e.g. read from committed results sets)."""
    expected = (len(models), len(scenarios), len(planners), n_seeds)
    if values.shape != expected:
        raise BenchmarkError(f"need values of shape {expected}, got {values.shape}")
    pairs = list(itertools.combinations(range(len(planners)), 2))
    tests = [
        [[compare(values[m, s, j], values[m, s, i]) for m in range(len(models))] for i, j in pairs]
        for s in range(len(scenarios))
    ]
    p = np.array([[[c.paired_p for c in row] for row in block] for block in tests])
    p_holm = adjust_p_values(p, "holm").reshape(p.shape) if p.size else p
    verdicts: dict[str, tuple[PairVerdict, ...]] = {}
    for s, name in enumerate(scenarios):
        rows = []
        for k, (i, j) in enumerate(pairs):
            diffs = []
            ns = []
            for m in range(len(models)):
                a, b = values[m, s, i], values[m, s, j]
                both = np.isfinite(a) & np.isfinite(b)
                ns.append(int(both.sum()))
                diffs.append(float(np.mean(a[both] - b[both])) if both.any() else math.nan)
            rows.append(
                PairVerdict(
                    a=planners[i],
                    b=planners[j],
                    differences=tuple(diffs),
                    n=tuple(ns),
                    p=tuple(float(x) for x in p[s, k]),
                    p_holm=tuple(float(x) for x in p_holm[s, k]),
                    verdict=_verdict(diffs, [float(x) for x in p_holm[s, k]]),
                )
            )
        verdicts[name] = tuple(rows)
    return Robustness(
        models=tuple(models),
        scenarios=tuple(scenarios),
        planners=tuple(planners),
        n_seeds=n_seeds,
        pairs=verdicts,
        taus=_taus(values, models, scenarios),
    )


def _taus(
    values: NDArray[np.float64], models: Sequence[str], scenarios: Sequence[str]
) -> tuple[TauRow, ...]:
    """τ-b per scenario and pair of models, and the suite's mean over scenarios, each
    with its stratified bootstrap interval over the seeds."""
    n_models, n_scen, _, n_seeds = values.shape
    rng = np.random.default_rng(BOOTSTRAP_SEED)
    # One set of resampled seeds per scenario, shared by every model and planner.
    picks = rng.integers(0, n_seeds, size=(n_scen, BOOTSTRAP_RESAMPLES, n_seeds))
    with np.errstate(invalid="ignore"), _quiet_nanmean():
        means = np.nanmean(values, axis=3)  # (M, S, P)
        boot = np.stack(
            [
                np.nanmean(np.take(values[:, s], picks[s], axis=2), axis=3)  # (M, P, B)
                for s in range(n_scen)
            ],
            axis=1,
        )  # (M, S, P, B)
    rows: list[TauRow] = []
    for m1, m2 in itertools.combinations(range(n_models), 2):
        point = kendall_tau_b(means[m1], means[m2])  # (S,)
        per_boot = np.stack(
            [
                kendall_tau_b(boot[m1, s].T, boot[m2, s].T)  # (B,)
                for s in range(n_scen)
            ]
        )  # (S, B)
        for s, name in enumerate(scenarios):
            low, high = _interval(per_boot[s])
            rows.append(TauRow(name, models[m1], models[m2], float(point[s]), low, high))
        with np.errstate(invalid="ignore"), _quiet_nanmean():
            suite_boot = np.nanmean(per_boot, axis=0)
            suite = float(np.nanmean(point)) if np.isfinite(point).any() else math.nan
        low, high = _interval(suite_boot)
        rows.append(TauRow("suite", models[m1], models[m2], suite, low, high))
    return tuple(rows)


@contextlib.contextmanager
def _quiet_nanmean() -> Iterator[None]:
    """nanmean of an all-NaN slice is NaN, as meant here, without its warning."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        yield


def _interval(samples: NDArray[np.float64]) -> tuple[float, float]:
    finite = samples[np.isfinite(samples)]
    if finite.size == 0:
        return math.nan, math.nan
    low, high = np.percentile(finite, INTERVAL)
    return float(low), float(high)


def _number(x: float, digits: int = 3) -> str:
    return "–" if not math.isfinite(x) else f"{x:+.{digits}f}"


def robustness_markdown(table: Robustness, *, level: int = 1) -> str:
    """``robustness.md``: the verdict counts, the pairs and the τ table; its headings
    at ``level`` (the title) and below (a page's section uses 3)."""
    models = ", ".join(f"`{m}`" for m in table.models)
    sub = "#" * (level + 1)
    lines = [
        "#" * level + " Orderings of planners under every response model",
        "",
        f"Response models: {models} (the first is this run's own). Metric: the episode's "
        f"mean Fréchet deviation, n = {table.n_seeds} seeds per cell. For each pair of "
        "planners, A − B is the mean paired difference over the seeds both define; p is "
        "the two-sided paired t-test, adjusted by Holm over every scenario, pair and model "
        f"of the run; significant: adjusted p < {ALPHA}. **holds**: significant in the "
        "same direction under every model; **flips**: significant in opposite directions "
        "under two models; **unresolved**: otherwise. τ: Kendall's τ-b between two "
        "models' orderings of the planners by mean deviation, with a 95 % percentile "
        f"bootstrap interval over the seeds ({BOOTSTRAP_RESAMPLES} resamples; the suite "
        "row is the mean over scenarios, its seeds resampled per scenario).",
        "",
        "| scenario | holds | flips | unresolved |",
        "|---|---|---|---|",
    ]
    for s in table.scenarios:
        c = table.counts(s)
        lines.append(f"| {s} | {c['holds']} | {c['flips']} | {c['unresolved']} |")
    lines += ["", f"{sub} Kendall's τ between the models' orderings", ""]
    lines += ["| scenario | models | τ | 95 % interval |", "|---|---|---|---|"]
    for row in table.taus:
        lines.append(
            f"| {row.scenario} | `{row.first}` vs `{row.second}` | {_number(row.tau, 2)} | "
            f"[{_number(row.low, 2)}, {_number(row.high, 2)}] |"
        )
    header = " | ".join(f"A − B (m), `{m}`" for m in table.models)
    for s in table.scenarios:
        lines += ["", f"{sub} {s}", "", f"| A | B | {header} | verdict |"]
        lines.append("|---|---|" + "---|" * len(table.models) + "---|")
        for pair in table.pairs[s]:
            cells = " | ".join(
                _number(d) + (" *" if math.isfinite(p) and p < ALPHA else "")
                for d, p in zip(pair.differences, pair.p_holm, strict=True)
            )
            lines.append(f"| {pair.a} | {pair.b} | {cells} | {pair.verdict} |")
    lines += ["", "\\* Holm-adjusted p < 0.05.", ""]
    return "\n".join(lines)


def _none(x: float) -> float | None:
    return x if math.isfinite(x) else None


def robustness_document(table: Robustness) -> dict[str, Any]:
    """``robustness.json`` (and the ``robustness`` entry of ``summary.json``)."""
    return {
        "schema": _ROBUSTNESS_SCHEMA,
        "models": list(table.models),
        "metric": ROBUST_METRIC,
        "n_seeds": table.n_seeds,
        "test": "paired t-test, two-sided, Holm over the run",
        "alpha": ALPHA,
        "bootstrap_resamples": BOOTSTRAP_RESAMPLES,
        "counts": {s: table.counts(s) for s in table.scenarios},
        "pairs": {
            s: [
                {
                    "a": p.a,
                    "b": p.b,
                    "difference_m": [_none(x) for x in p.differences],
                    "n": list(p.n),
                    "p": [_none(x) for x in p.p],
                    "p_holm": [_none(x) for x in p.p_holm],
                    "verdict": p.verdict,
                }
                for p in table.pairs[s]
            ]
            for s in table.scenarios
        },
        "kendall_tau": [
            {
                "scenario": r.scenario,
                "models": [r.first, r.second],
                "tau": _none(r.tau),
                "interval": [_none(r.low), _none(r.high)],
            }
            for r in table.taus
        ],
    }
