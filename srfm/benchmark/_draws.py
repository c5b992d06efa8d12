"""Rankings under the model's uncertainty: the benchmark under K parameter draws.

The SRFM's robot force (A_r, B_r) is fitted, and its uncertainty moves every deviation
far more than the planner does (docs/sensitivity.md). ``srfm benchmark --param-draws K``
therefore runs every (scenario, planner, seed) cell again under K parameter sets drawn
from a documented distribution (:func:`draw_params`), each draw a benchmark results
folder of its own (``OUT/draws/draw-NNN/``, the same seeds, the same request), and
reports per scenario the probability that each planner ranks first … last by mean
Fréchet deviation, and the interval of each planner's mean deviation over the draws
(:func:`rank_table`; ``OUT/rankings.md``, ``OUT/rankings.json`` and a section of
``report.html``).

The distributions:

- ``"sensitivity"`` (the default, while no real-data fit with a bootstrap over scenes
  exists): A_r ~ U(3.965, 15.86) m/s² and B_r ~ U(0.5, 1.5) m, independent, every other
  parameter at the run's own: the ranges of the sensitivity sweep
  (docs/sensitivity.md: half to twice the paper's A_r = 7.93, and B_r around the
  paper's 0.99), without A_r = 0, where every deviation is 0 and nothing is ranked.
- ``"wide"``: A_r ~ log-U(0.25, 15.86) m/s² and B_r ~ log-U(0.1, 1.5) m, independent
  (uniform in the logarithm: every factor of two gets the same share of the draws),
  every other parameter at the run's own: from below the real-data fit of the robot
  force (A_r = 0.55 m/s², 0.26–0.75, B_r = 0.23 m, 0.14–0.29 over its bootstrap;
  docs/real_encounters.md) to the top of the sensitivity ranges.
- a CSV file of parameter sets, one a row, its header naming :class:`SRFMParams`
  fields (e.g. the bootstrap replicates of a fit over scenes: ``a_robot,b_robot,
  lambda_robot``); the fields it does not name stay at the run's own. K rows are
  chosen from the file without replacement (all of them, in a shuffled order, when K
  is the number of rows).

Both are deterministic from ``seed`` (``numpy.random.default_rng(seed)``); the draws
themselves are written to ``OUT/param_draws.json``, and a folder refuses a run with
other draws.
"""

from __future__ import annotations

import csv
import hashlib
import io
import json
import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any, Final

import attrs
import numpy as np
from numpy.typing import ArrayLike, NDArray

from srfm._io import MAX_DOCUMENT_BYTES, atomic_write_text, check_columns, read_input_bytes
from srfm._text import plain
from srfm.errors import BenchmarkError, ParameterError, SrfmError
from srfm.metrics.stats import wilson
from srfm.models.params import SRFMParams

__all__ = [
    "DRAWS_DIR",
    "PARAM_DRAWS",
    "RANKINGS_JSON",
    "RANKINGS_MD",
    "SENSITIVITY_RANGES",
    "WIDE_RANGES",
    "ParamDraws",
    "RankTable",
    "draw_folder",
    "draw_params",
    "rank_probabilities",
    "rank_table",
    "rankings_markdown",
    "render_rankings",
]

DRAWS_DIR: Final = "draws"
PARAM_DRAWS: Final = "param_draws.json"
RANKINGS_MD: Final = "rankings.md"
RANKINGS_JSON: Final = "rankings.json"
_SCHEMA: Final = "srfm.param_draws/1"
_RANKINGS_SCHEMA: Final = "srfm.rankings/2"
"""2: each rank probability's Monte-Carlo interval (``rank_probability_intervals``)."""
RANK_METRIC: Final = "frechet_m"
"""The metric planners are ranked by: the mean Fréchet deviation over the seeds."""
INTERVAL: Final = (2.5, 97.5)
"""The percentiles of the interval of each planner's mean deviation over the draws."""

SENSITIVITY_RANGES: Final[dict[str, tuple[float, float]]] = {
    "a_robot": (3.965, 15.86),
    "b_robot": (0.5, 1.5),
}
"""The ``"sensitivity"`` distribution: independent uniform ranges (low, high) of the
robot force's strength A_r (m/s²) and range B_r (m), those of docs/sensitivity.md
without A_r = 0."""
WIDE_RANGES: Final[dict[str, tuple[float, float]]] = {
    "a_robot": (0.25, 15.86),
    "b_robot": (0.1, 1.5),
}
"""The ``"wide"`` distribution: independent log-uniform ranges (low, high) of A_r (m/s²)
and B_r (m), from below the real-data fit (A_r = 0.55, B_r = 0.23) to the top of
:data:`SENSITIVITY_RANGES`."""
DISTRIBUTIONS: Final = ("sensitivity", "wide")
"""The named distributions of :func:`draw_params` (any other source is a CSV file)."""
MAX_DRAWS: Final = 1000
PROBABILITY_LEVEL: Final = 0.95
"""The level of each rank probability's Monte-Carlo interval (Wilson's, over the K
draws)."""


@attrs.frozen(kw_only=True)
class ParamDraws:
    """K parameter sets and where they came from.

    Attributes:
        source: ``"sensitivity"``, ``"wide"`` or the path of a CSV file of parameter
            sets.
        seed: the seed of the draw.
        params: the K parameter sets, in draw order.
        description: the distribution in words (shown in the reports).
        file_sha256: SHA-256 of the CSV file (None for a named distribution).
    """

    source: str
    seed: int
    params: tuple[SRFMParams, ...]
    description: str
    file_sha256: str | None = None

    def document(self) -> dict[str, Any]:
        """The draws as plain data (``param_draws.json``)."""
        return {
            "schema": _SCHEMA,
            "source": self.source,
            "file_sha256": self.file_sha256,
            "seed": self.seed,
            "k": len(self.params),
            "description": self.description,
            "draws": [p.as_dict() for p in self.params],
        }


def _check_k(k: int) -> int:
    if isinstance(k, bool) or not isinstance(k, int) or not 1 <= k <= MAX_DRAWS:
        raise ParameterError(
            f"the number of parameter draws must be in [1, {MAX_DRAWS}], got {plain(k)}"
        )
    return k


def _check_seed(seed: int) -> int:
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise ParameterError(
            f"the seed of the parameter draws must be an integer >= 0, got {plain(seed)}"
        )
    return seed


def draw_params(
    base: SRFMParams, k: int, *, seed: int = 0, source: str | Path = "sensitivity"
) -> ParamDraws:
    """K parameter sets from ``source``, deterministic from ``seed``.

    Args:
        base: the run's parameters; every field the distribution does not draw keeps
            its value.
        k: the number of draws, in [1, 1000].
        seed: the seed of ``numpy.random.default_rng``.
        source: ``"sensitivity"`` (:data:`SENSITIVITY_RANGES`), ``"wide"``
            (:data:`WIDE_RANGES`) or a CSV file (header: :class:`SRFMParams` field names;
            one parameter set a row).

    Raises:
        ParameterError: a bad k or seed, a file that cannot be read, an unknown field,
            a value the parameters refuse (naming the row), or fewer rows than k.
    """
    k = _check_k(k)
    seed = _check_seed(seed)
    rng = np.random.default_rng(seed)
    if str(source) == "sensitivity":
        names = list(SENSITIVITY_RANGES)
        low = np.array([SENSITIVITY_RANGES[n][0] for n in names])
        high = np.array([SENSITIVITY_RANGES[n][1] for n in names])
        values = rng.uniform(low, high, size=(k, len(names)))
        ranges = ", ".join(
            f"{n} ~ U({SENSITIVITY_RANGES[n][0]:g}, {SENSITIVITY_RANGES[n][1]:g})" for n in names
        )
        text = (
            f"{k} draws, seed {seed}: {ranges}, independent (the ranges of docs/sensitivity.md "
            "without A_r = 0); every other parameter at the run's own"
        )
        return _named_draws("sensitivity", seed, base, names, values, text)
    if str(source) == "wide":
        names = list(WIDE_RANGES)
        low = np.log([WIDE_RANGES[n][0] for n in names])
        high = np.log([WIDE_RANGES[n][1] for n in names])
        values = np.exp(rng.uniform(low, high, size=(k, len(names))))
        ranges = ", ".join(
            f"{n} ~ log-U({WIDE_RANGES[n][0]:g}, {WIDE_RANGES[n][1]:g})" for n in names
        )
        text = (
            f"{k} draws, seed {seed}: {ranges}, independent (uniform in the logarithm; from "
            "below the real-data fit A_r = 0.55, B_r = 0.23 to the top of the sensitivity "
            "ranges); every other parameter at the run's own"
        )
        return _named_draws("wide", seed, base, names, values, text)
    path = Path(source)
    rows, digest = _read_draws_file(path, base)
    if len(rows) < k:
        raise ParameterError(
            f"{path}: {len(rows)} parameter sets, fewer than the {k} draws asked for"
        )
    chosen = rng.choice(len(rows), size=k, replace=False)
    text = (
        f"{k} of the {len(rows)} parameter sets of {path.name} (SHA-256 {digest[:12]}…), "
        f"chosen without replacement with seed {seed}; every field the file does not name "
        "at the run's own"
    )
    return ParamDraws(
        source=str(path),
        seed=seed,
        params=tuple(rows[int(i)] for i in chosen),
        description=text,
        file_sha256=digest,
    )


def _named_draws(
    source: str, seed: int, base: SRFMParams, names: list[str], values: Any, text: str
) -> ParamDraws:
    """The draws of a named distribution: row k of ``values`` sets the fields ``names``."""
    params = tuple(
        base.replace(**{n: float(v) for n, v in zip(names, row, strict=True)}) for row in values
    )
    return ParamDraws(source=source, seed=seed, params=params, description=text)


def _read_draws_file(path: Path, base: SRFMParams) -> tuple[list[SRFMParams], str]:
    data = read_input_bytes(
        path, max_bytes=MAX_DOCUMENT_BYTES, error=ParameterError, what="parameter draws file"
    )
    digest = hashlib.sha256(data).hexdigest()
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise ParameterError(f"{path}: not UTF-8 text ({exc})") from None
    reader = csv.reader(io.StringIO(text))
    header = [h.strip() for h in next(reader, [])]
    check_columns(header, f"{path}, line 1", ParameterError)
    known = set(base.as_dict())
    unknown = [h for h in header if h not in known]
    if not header or unknown:
        raise ParameterError(
            f"{path}: the header must name SRFM parameters ({', '.join(sorted(known))}); "
            f"got {plain(unknown or header)}"
        )
    rows = []
    for line, row in enumerate(reader, start=2):
        if not any(cell.strip() for cell in row):
            continue
        if len(row) != len(header):
            raise ParameterError(
                f"{path}, line {line}: {len(row)} values for {len(header)} columns"
            )
        try:
            values = {h: float(cell) for h, cell in zip(header, row, strict=True)}
            rows.append(base.replace(**values))
        except (ValueError, SrfmError) as exc:
            raise ParameterError(f"{path}, line {line}: {exc}") from None
    return rows, digest


def draw_folder(out: Path, k: int) -> Path:
    """The results folder of draw ``k`` inside the results folder ``out``."""
    return out / DRAWS_DIR / f"draw-{k:03d}"


def check_param_draws(out: Path, draws: ParamDraws) -> None:
    """Write ``OUT/param_draws.json``, or check that the one there holds these draws.

    Raises:
        BenchmarkError: the folder holds other draws (naming what differs).
    """
    path = out / PARAM_DRAWS
    doc = draws.document()
    if path.is_file():
        old = _read_json(path)
        for key in ("source", "file_sha256", "seed", "k", "draws"):
            if not isinstance(old, dict) or old.get(key) != doc[key]:
                raise BenchmarkError(
                    f"{path}: this folder holds other parameter draws ({key} differs); "
                    "use a new --out, or the same --param-draws options"
                )
        return
    atomic_write_text(path, json.dumps(doc, indent=1) + "\n")


def _read_json(path: Path) -> Any:
    data = read_input_bytes(
        path, max_bytes=MAX_DOCUMENT_BYTES * 4, error=BenchmarkError, what="file"
    )
    try:
        return json.loads(data.decode("utf-8"))
    except (UnicodeDecodeError, ValueError, RecursionError) as exc:
        raise BenchmarkError(f"{path}: damaged ({exc})") from None


def rank_probabilities(means: ArrayLike) -> NDArray[np.float64]:
    """P(planner p ranks r) from the planners' means in each draw.

    Args:
        means: (K, P) the mean of each of P planners in each of K draws; lower ranks
            first; NaN ranks after every number.

    Returns:
        (P, P): row p, column r (0 = first) the share of the draws in which planner p
        ranks r + 1. Planners tied in a draw share the ranks they span equally (two tied
        for first: each half first, half second), so every row and every column sums
        to 1.
    """
    x = np.asarray(means, dtype=np.float64)
    if x.ndim != 2 or x.shape[0] == 0 or x.shape[1] == 0:
        raise ParameterError(f"need (draws, planners) means, got shape {x.shape}")
    k, p = x.shape
    key = np.where(np.isnan(x), np.inf, x)
    probs = np.zeros((p, p))
    for row in key:
        for j in range(p):
            below = int(np.count_nonzero(row < row[j]))
            tied = int(np.count_nonzero(row == row[j]))
            probs[j, below : below + tied] += 1.0 / tied
    out: NDArray[np.float64] = probs / k
    return out


@attrs.frozen(kw_only=True)
class RankTable:
    """Per scenario: each planner's rank probabilities and the interval of its mean
    deviation over the draws.

    Attributes:
        scenarios, planners: the rows, in table order.
        n_draws: K.
        n_seeds: the seeds of each draw's mean.
        probabilities: ``probabilities[scenario][planner]``: P(rank 1), …, P(rank P).
        means: ``means[scenario][planner]``: the K per-draw means, in draw order.
        description: the distribution of the draws, in words.
    """

    scenarios: tuple[str, ...]
    planners: tuple[str, ...]
    n_draws: int
    n_seeds: int
    probabilities: Mapping[str, Mapping[str, tuple[float, ...]]]
    means: Mapping[str, Mapping[str, tuple[float, ...]]]
    description: str

    def probability_interval(self, scenario: str, planner: str, rank: int) -> tuple[float, float]:
        """The Monte-Carlo interval of P(planner takes ``rank``) (1 = first): Wilson's
        95 % score interval over the K draws (a planner tied in a draw counts the share
        of the rank it holds). It says how far the probability could move with more
        draws from the same distribution, not how the seeds' sampling moves it."""
        share = self.probabilities[scenario][planner][rank - 1]
        _, low, high = wilson(share * self.n_draws, self.n_draws)
        return low, high

    def interval(self, scenario: str, planner: str) -> tuple[float, float, float]:
        """(low, median, high): the :data:`INTERVAL` percentiles and the median of the
        planner's mean deviation over the draws (linear interpolation)."""
        x = np.asarray(self.means[scenario][planner], dtype=np.float64)
        low, mid, high = np.percentile(x, [INTERVAL[0], 50.0, INTERVAL[1]])
        return float(low), float(mid), float(high)


def rank_table(
    draw_means: Sequence[Mapping[str, Mapping[str, float]]],
    *,
    scenarios: Sequence[str],
    planners: Sequence[str],
    n_seeds: int,
    description: str,
) -> RankTable:
    """The :class:`RankTable` of K draws' means (``draw_means[k][scenario][planner]``)."""
    probabilities: dict[str, dict[str, tuple[float, ...]]] = {}
    means: dict[str, dict[str, tuple[float, ...]]] = {}
    for scenario in scenarios:
        x = np.array([[d[scenario][p] for p in planners] for d in draw_means], dtype=np.float64)
        probs = rank_probabilities(x)
        probabilities[scenario] = {
            p: tuple(float(v) for v in probs[j]) for j, p in enumerate(planners)
        }
        means[scenario] = {p: tuple(float(v) for v in x[:, j]) for j, p in enumerate(planners)}
    return RankTable(
        scenarios=tuple(scenarios),
        planners=tuple(planners),
        n_draws=len(draw_means),
        n_seeds=n_seeds,
        probabilities=probabilities,
        means=means,
        description=description,
    )


def _ordinal(r: int) -> str:
    return {1: "1st", 2: "2nd", 3: "3rd"}.get(r, f"{r}th")


def rankings_legend(table: RankTable) -> str:
    """What the rank tables show, in one paragraph."""
    return (
        f"Parameter draws: {table.description}. In each of the {table.n_draws} draws the "
        f"planners are ranked by their mean Fréchet deviation over the same {table.n_seeds} "
        "seeds (lowest first); a cell is the share of the draws in which the planner took "
        "that rank (planners tied in a draw share the ranks they span), so every row and "
        "every column sums to 1. The per-draw means carry the seeds' sampling error as well "
        "as the parameters'. P(1st) [95 %]: the share of the draws in which the planner "
        f"ranks first with its Monte-Carlo interval (Wilson's, over the {table.n_draws} "
        "draws). Interval: the 2.5–97.5 % percentiles of the planner's mean deviation over "
        "the draws, median in the middle."
    )


def rankings_markdown(table: RankTable) -> str:
    """``rankings.md``: a planner × rank table per scenario, with the intervals."""
    ranks = [_ordinal(r + 1) for r in range(len(table.planners))]
    lines = ["# Rankings under the model's uncertainty", "", rankings_legend(table), ""]
    for scenario in table.scenarios:
        lines += [
            f"## {scenario}",
            "",
            "| Planner | "
            + " | ".join(ranks)
            + " | P(1st) [95 %] | Fréchet dev. (m): 2.5 % · median · 97.5 % |",
            "|---|" + "--:|" * len(ranks) + "--:|--:|",
        ]
        for planner in table.planners:
            probs = " | ".join(f"{v:.2f}" for v in table.probabilities[scenario][planner])
            first = table.probabilities[scenario][planner][0]
            p_low, p_high = table.probability_interval(scenario, planner, 1)
            low, mid, high = table.interval(scenario, planner)
            lines.append(
                f"| {planner} | {probs} | {first:.2f} [{p_low:.2f}, {p_high:.2f}] "
                f"| {low:.3f} · {mid:.3f} · {high:.3f} |"
            )
        lines.append("")
    return "\n".join(lines)


def rankings_document(table: RankTable) -> dict[str, Any]:
    """``rankings.json``: every probability, interval and per-draw mean."""
    return {
        "schema": _RANKINGS_SCHEMA,
        "metric": RANK_METRIC,
        "n_draws": table.n_draws,
        "n_seeds": table.n_seeds,
        "interval_percentiles": list(INTERVAL),
        "probability_level": PROBABILITY_LEVEL,
        "description": table.description,
        "legend": rankings_legend(table),
        "planners": list(table.planners),
        "scenarios": {
            s: {
                p: {
                    "rank_probabilities": list(table.probabilities[s][p]),
                    "rank_probability_intervals": [
                        list(table.probability_interval(s, p, r + 1))
                        for r in range(len(table.planners))
                    ],
                    "interval": list(table.interval(s, p)),
                    "draw_means": list(table.means[s][p]),
                }
                for p in table.planners
            }
            for s in table.scenarios
        },
    }


def _draw_means(
    folder: Path, scenarios: Sequence[str], planners: Sequence[str], seeds: Sequence[int]
) -> dict[str, dict[str, float]] | None:
    """A finished draw's mean deviation per (scenario, planner), from its summary.json;
    None while the draw is not finished for this request."""
    path = folder / "summary.json"
    if not path.is_file():
        return None
    summary = _read_json(path)
    request = summary.get("request", {}) if isinstance(summary, dict) else {}
    if (
        request.get("scenarios") != list(scenarios)
        or request.get("planners") != list(planners)
        or request.get("seeds") != list(seeds)
    ):
        return None
    cells = summary["table"]["scenarios"]
    return {
        s: {
            p: math.nan
            if cells[s][p][RANK_METRIC]["mean"] is None
            else cells[s][p][RANK_METRIC]["mean"]
            for p in planners
        }
        for s in scenarios
    }


def render_rankings(
    out: Path, scenarios: Sequence[str], planners: Sequence[str], seeds: Sequence[int]
) -> dict[str, bytes]:
    """``rankings.md`` and ``rankings.json`` of the folder's parameter draws, once every
    draw is finished for this request; nothing (an empty dict) for a folder without
    draws or while one is unfinished."""
    path = out / PARAM_DRAWS
    if not path.is_file():
        return {}
    doc = _read_json(path)
    if (
        not isinstance(doc, dict)
        or doc.get("schema") != _SCHEMA
        or not isinstance(doc.get("k"), int)
    ):
        raise BenchmarkError(f"{path}: damaged parameter draws file; use a new --out")
    draw_means = []
    for k in range(doc["k"]):
        means = _draw_means(draw_folder(out, k), scenarios, planners, seeds)
        if means is None:
            return {}
        draw_means.append(means)
    table = rank_table(
        draw_means,
        scenarios=scenarios,
        planners=planners,
        n_seeds=len(seeds),
        description=str(doc.get("description", "")),
    )
    return {
        RANKINGS_MD: rankings_markdown(table).encode("utf-8"),
        RANKINGS_JSON: (json.dumps(rankings_document(table), indent=1) + "\n").encode("utf-8"),
    }
