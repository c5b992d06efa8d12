"""The protocol of issue 40: fitting the sidestep robot response to NavWareSet's people.

docs/robot_response.md states the protocol in words; this module holds its numbers
(:data:`PROTOCOL`), committed before any held-out result of the sidestep form was
computed, and the analysis the page's claims rest on. See the page for what each
number means.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any, Final

import attrs
import numpy as np
from numpy.typing import NDArray

from srfm.errors import ParameterError
from srfm.fitting._fit import _residual_fn
from srfm.fitting._protocol import paired_test
from srfm.fitting._windows import WindowConfig, Windows
from srfm.models.params import SRFMParams

__all__ = [
    "PROTOCOL",
    "ResponseProtocol",
    "StartFit",
    "best_fit",
    "fit_sidestep",
    "identification",
    "profile_costs",
    "profile_grid",
    "relative_change",
    "spread_starts",
    "success",
]

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]


@attrs.frozen(kw_only=True)
class ResponseProtocol:
    """The pre-registered numbers of the sidestep fit (docs/robot_response.md).

    Attributes:
        date: the day the protocol was written (UTC).
        windows: the encounter windows (issue 28's, unchanged).
        fields: the fitted parameters of the ``sidestep`` form, the cap included.
        bounds: per field, the search interval.
        log_fields: the fields whose starts are spread on a log scale, over
            [upper bound / ``log_span``, upper bound].
        log_span: see ``log_fields``.
        n_starts: the spread starts (scrambled Sobol points over the bounds), besides
            the form's defaults.
        start_seed: the Sobol sequence's seed.
        spread_nfev: the model evaluations (scipy's ``max_nfev``) of every start of a
            held-out fold before the lowest-cost start is refined.
        refine_nfev: the largest ``max_nfev`` of a refined start, and of every start
            of a full fit (all of a set's scenes).
        tolerance: scipy's ``ftol``, ``xtol``, ``gtol``.
        profile_points: grid points of each parameter's profile.
        profile_nfev: ``max_nfev`` of each profile point's fit of the other fields.
        identified_rise: a parameter is identified when its profile cost rises by at
            least this fraction of the minimum on each side of the fit within the
            bounds (on the one side there is, for a fit at a bound).
        n_boot: bootstrap resamples over scenes of each relative change.
        boot_seed: first seed of the bootstraps (one more per row).
        pass_margin, offset_margin: the success margins: at least this relative
            reduction of the pooled |pass-distance error| and |path-offset error|
            against robot ignored.
        ade_margin: the ADE margin of the two one-sided tests (equivalent or better).
        alpha: the level of the Holm-corrected decisive tests.
        no_overlap: the contact-only baseline: the exponential robot force with these
            (A_r m/s², B_r m, λ_r).
    """

    date: str
    windows: WindowConfig
    fields: tuple[str, ...]
    bounds: dict[str, tuple[float, float]]
    log_fields: tuple[str, ...]
    log_span: float
    n_starts: int
    start_seed: int
    spread_nfev: int
    refine_nfev: int
    tolerance: float
    profile_points: int
    profile_nfev: int
    identified_rise: float
    n_boot: int
    boot_seed: int
    pass_margin: float
    offset_margin: float
    ade_margin: float
    alpha: float
    no_overlap: tuple[float, float, float]


PROTOCOL: Final = ResponseProtocol(
    date="2026-12-05",
    windows=WindowConfig(align="encounter", lead_s=3.0, goal="heading", min_start_speed_mps=0.3),
    fields=("ss_a", "ss_miss", "ss_horizon", "ss_speed_gain", "robot_force_cap"),
    bounds={
        "ss_a": (0.0, 5.0),
        "ss_miss": (0.1, 3.0),
        "ss_horizon": (0.3, 8.0),
        "ss_speed_gain": (-3.0, 3.0),
        "robot_force_cap": (0.02, 20.0),
    },
    log_fields=("ss_a", "robot_force_cap"),
    log_span=500.0,
    n_starts=8,
    start_seed=2040,
    spread_nfev=15,
    refine_nfev=100,
    tolerance=1e-6,
    profile_points=9,
    profile_nfev=30,
    identified_rise=0.01,
    n_boot=2000,
    boot_seed=2040,
    pass_margin=0.10,
    offset_margin=0.05,
    ade_margin=0.02,
    alpha=0.05,
    no_overlap=(20.0, 0.02, 1.0),
)
"""The protocol of docs/robot_response.md, written on 2026-12-05 before any held-out
number of the sidestep form."""


# --------------------------------------------------------------------------------------
# Starts, fits, profiles


@attrs.frozen(kw_only=True)
class StartFit:
    """One start of a multi-start fit.

    Attributes:
        start: the start point, field -> value.
        end: where the fit ended.
        cost: its cost, ½ Σ r² (m²) over the fitted windows.
        nfev: scipy's evaluations of the residual (besides the Jacobian's).
        refined: True for the start a held-out fold ran on to convergence.
    """

    start: dict[str, float]
    end: dict[str, float]
    cost: float
    nfev: int
    refined: bool = False


def spread_starts(protocol: ResponseProtocol = PROTOCOL) -> list[dict[str, float]]:
    """The starts of every fit: the form's defaults, then ``n_starts`` scrambled Sobol
    points over the bounds (log-spaced for ``log_fields``). Deterministic."""
    from scipy.stats import qmc

    defaults = SRFMParams(robot_form="sidestep")
    starts = [{f: float(getattr(defaults, f)) for f in protocol.fields}]
    sobol = qmc.Sobol(d=len(protocol.fields), scramble=True, seed=protocol.start_seed)
    for u in sobol.random(protocol.n_starts):
        point: dict[str, float] = {}
        for f, x in zip(protocol.fields, u, strict=True):
            lo, hi = _start_range(f, protocol)
            if f in protocol.log_fields:
                point[f] = float(math.exp(math.log(lo) + x * (math.log(hi) - math.log(lo))))
            else:
                point[f] = float(lo + x * (hi - lo))
        starts.append(point)
    return starts


def _start_range(field: str, protocol: ResponseProtocol) -> tuple[float, float]:
    lo, hi = protocol.bounds[field]
    if field in protocol.log_fields:
        return max(lo, hi / protocol.log_span), hi
    return lo, hi


def _fit_windows(windows: Windows, subset: IntArray) -> IntArray:
    subset = np.ascontiguousarray(subset, dtype=np.int64)
    return subset[windows.interaction[subset]]


def _solve(
    windows: Windows,
    sel: IntArray,
    base: SRFMParams,
    fields: Sequence[str],
    x0: dict[str, float],
    max_nfev: int,
    protocol: ResponseProtocol,
) -> StartFit:
    from scipy.optimize import least_squares

    lower = np.array([protocol.bounds[f][0] for f in fields])
    upper = np.array([protocol.bounds[f][1] for f in fields])
    start = np.clip([x0[f] for f in fields], lower, upper)
    fun = _residual_fn(windows, sel, base, fields, "srfm")
    sol = least_squares(
        fun,
        start,
        bounds=(lower, upper),
        method="trf",
        x_scale="jac",
        diff_step=1e-3,
        ftol=protocol.tolerance,
        xtol=protocol.tolerance,
        gtol=protocol.tolerance,
        max_nfev=max_nfev,
    )
    return StartFit(
        start={f: float(v) for f, v in zip(fields, start, strict=True)},
        end={f: float(v) for f, v in zip(fields, sol.x, strict=True)},
        cost=float(sol.cost),
        nfev=int(sol.nfev),
    )


def fit_sidestep(
    windows: Windows,
    base: SRFMParams,
    subset: IntArray,
    *,
    full: bool,
    protocol: ResponseProtocol = PROTOCOL,
) -> list[StartFit]:
    """Fit every field of ``protocol`` of the ``sidestep`` form on the windows ``subset``
    (the interaction windows among them), the pedestrian part held at ``base``, from
    every start of :func:`spread_starts`.

    ``full``: every start runs to convergence (``refine_nfev``); otherwise each runs
    ``spread_nfev`` evaluations and the lowest-cost one is run on to convergence (its
    entry then holds the refined end, ``refined=True``).

    Returns:
        One :class:`StartFit` per start, in the order of :func:`spread_starts`; the fit
        is the entry of lowest cost (:func:`best_fit`).
    """
    sel = _fit_windows(windows, subset)
    if sel.size == 0:
        raise ParameterError("no interaction windows to fit the sidestep form on")
    base = base.replace(robot_form="sidestep")
    budget = protocol.refine_nfev if full else protocol.spread_nfev
    fits = [
        _solve(windows, sel, base, protocol.fields, s, budget, protocol)
        for s in spread_starts(protocol)
    ]
    if not full:
        i = int(np.argmin([f.cost for f in fits]))
        more = _solve(
            windows, sel, base, protocol.fields, fits[i].end, protocol.refine_nfev, protocol
        )
        fits[i] = StartFit(
            start=fits[i].start,
            end=more.end,
            cost=more.cost,
            nfev=fits[i].nfev + more.nfev,
            refined=True,
        )
    return fits


def best_fit(fits: Sequence[StartFit]) -> StartFit:
    """The start of lowest cost (the first of equal ones)."""
    return min(fits, key=lambda f: f.cost)


def profile_grid(field: str, protocol: ResponseProtocol = PROTOCOL) -> FloatArray:
    """The values at which ``field``'s profile is computed: ``profile_points`` evenly
    over its bounds (log-spaced over the start range for ``log_fields``)."""
    lo, hi = (
        _start_range(field, protocol) if field in protocol.log_fields else protocol.bounds[field]
    )
    if field in protocol.log_fields:
        return np.geomspace(lo, hi, protocol.profile_points)
    return np.linspace(lo, hi, protocol.profile_points)


def profile_costs(
    windows: Windows,
    base: SRFMParams,
    subset: IntArray,
    fitted: dict[str, float],
    field: str,
    protocol: ResponseProtocol = PROTOCOL,
) -> FloatArray:
    """The profile of ``field``: at every value of :func:`profile_grid`, the cost with
    the other fields refitted from ``fitted`` (``profile_nfev`` evaluations)."""
    sel = _fit_windows(windows, subset)
    others = [f for f in protocol.fields if f != field]
    out = np.zeros(protocol.profile_points)
    for k, value in enumerate(profile_grid(field, protocol)):
        held = base.replace(robot_form="sidestep", **{field: float(value)})
        out[k] = _solve(windows, sel, held, others, fitted, protocol.profile_nfev, protocol).cost
    return out


def identification(
    field: str,
    fitted: float,
    grid: FloatArray,
    costs: FloatArray,
    min_cost: float,
    protocol: ResponseProtocol = PROTOCOL,
) -> str:
    """``"identified"``, ``"identified at its bound"`` or ``"not identified"``: whether
    the profile ``costs`` over ``grid`` rises by ``identified_rise`` × ``min_cost`` on
    each side of ``fitted`` (on the one side there is when ``fitted`` is at a bound or
    beyond the grid's end)."""
    lo, hi = protocol.bounds[field]
    tol = 1e-6 * (hi - lo)
    need = protocol.identified_rise * min_cost
    below = costs[grid < fitted - tol]
    above = costs[grid > fitted + tol]
    rises = [float(side.max()) - min_cost for side in (below, above) if side.size]
    at_bound = fitted <= lo + tol or fitted >= hi - tol or len(rises) < 2
    if rises and min(rises) >= need:
        return "identified at its bound" if at_bound else "identified"
    return "not identified"


# --------------------------------------------------------------------------------------
# Held-out comparisons


def relative_change(
    model: FloatArray,
    base: FloatArray,
    of_window: IntArray,
    track: IntArray,
    scenes: Sequence[int],
    seed: int,
    protocol: ResponseProtocol = PROTOCOL,
) -> dict[str, Any]:
    """mean(model) / mean(base) − 1 over the windows of ``scenes`` (both finite), its
    95 % and 90 % percentile intervals by a bootstrap over the scenes (``n_boot``
    resamples, ``seed``), the Wilcoxon signed-rank p over the scenes' mean errors
    (paired), and n (windows / tracks / scenes)."""
    ok = np.isfinite(model) & np.isfinite(base)
    sums = np.array(
        [[model[ok & (of_window == g)].sum(), base[ok & (of_window == g)].sum()] for g in scenes]
    )
    counts = np.array([np.count_nonzero(ok & (of_window == g)) for g in scenes])
    if sums.size == 0 or sums[:, 1].sum() <= 0.0:
        raise ParameterError("no windows with a finite error to compare")
    est = sums[:, 0].sum() / sums[:, 1].sum() - 1.0
    rng = np.random.default_rng(seed)
    k = len(scenes)
    draws = rng.multinomial(k, np.full(k, 1.0 / k), size=protocol.n_boot)
    boot = (draws @ sums[:, 0]) / (draws @ sums[:, 1]) - 1.0
    keep = counts > 0
    mean_model = sums[keep, 0] / counts[keep]
    mean_base = sums[keep, 1] / counts[keep]
    test = paired_test(mean_base, mean_model)
    sel = np.flatnonzero(ok & np.isin(of_window, list(scenes)))
    return {
        "model_m": float(model[sel].mean()),
        "base_m": float(base[sel].mean()),
        "rel": float(est),
        "ci95": [float(x) for x in np.percentile(boot, [2.5, 97.5])],
        "ci90": [float(x) for x in np.percentile(boot, [5.0, 95.0])],
        "p": test.p,
        "n_windows": int(sel.size),
        "n_tracks": int(np.unique(track[sel]).size),
        "n_scenes": int(np.count_nonzero(keep)),
    }


def success(
    pass_row: dict[str, Any],
    offset_row: dict[str, Any],
    ade_row: dict[str, Any],
    protocol: ResponseProtocol = PROTOCOL,
) -> dict[str, bool]:
    """The criterion of the protocol on one set's rows (each with ``rel``, ``ci90`` and,
    for the two decisive ones, ``p_holm``): each part and ``met``, all of them."""
    parts = {
        "pass": pass_row["rel"] <= -protocol.pass_margin and pass_row["p_holm"] < protocol.alpha,
        "offset": offset_row["rel"] <= -protocol.offset_margin
        and offset_row["p_holm"] < protocol.alpha,
        "ade": ade_row["ci90"][1] < protocol.ade_margin,
    }
    return {**parts, "met": all(parts.values())}
