"""SRFM parameter learning by nonlinear least squares (the paper's procedure, made exact).

Two stages, as in the paper (Agrawal et al. 2024, Sec. III-B):

1. *pedestrian*: A_p, B_p, λ, τ from the non-interaction windows (the pedestrian stays
   farther than 3 m from the robot), with the robot ignored (SFM: f_a + f_p);
2. *robot*: A_r, B_r (and λ_r when asked: ``fields``) from the interaction windows,
   with the pedestrian part held at the stage-1 values (SRFM: f_a + f_p + f_r).

Residual of a window w with H_w predicted samples: r_w = (x̂_w(t_k) − x_w(t_k)) / √H_w
for k = 1..H_w, both coordinates, where x̂ is the replayed simulation
(:func:`srfm.fitting.predict`) and x the observation. Σ‖r‖² is then the sum over
windows of each window's mean squared displacement, so every window weighs the same
whatever its sampling rate. ``scipy.optimize.least_squares`` (trust-region reflective,
bounds below, finite-difference Jacobian) minimises it from each of a few deterministic
starting points (the presets), keeping the lowest cost.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from typing import Final, Literal

import attrs
import numpy as np
from numpy.typing import NDArray

from srfm._text import plain
from srfm.errors import ParameterError
from srfm.fitting._predict import Mode, displacement_errors, predict
from srfm.fitting._windows import Windows
from srfm.models.params import FORM_FIELDS, PRESETS, SRFMParams

__all__ = ["BOUNDS", "FORM_FIT_FIELDS", "STAGE_FIELDS", "FitResult", "StageResult", "fit_params"]

Stage = Literal["pedestrian", "robot"]

STAGE_FIELDS: Final[dict[str, tuple[str, ...]]] = {
    "pedestrian": ("a_ped", "b_ped", "lambda_ped", "tau"),
    "robot": ("a_robot", "b_robot"),
}
# Search bounds: wide around every published value (A in m/s², B in m, τ in s).
BOUNDS: Final[dict[str, tuple[float, float]]] = {
    "a_ped": (0.0, 50.0),
    "b_ped": (0.05, 3.0),
    "lambda_ped": (0.0, 1.0),
    "tau": (0.1, 5.0),
    "a_robot": (0.0, 100.0),
    "b_robot": (0.05, 3.0),
    "lambda_robot": (0.0, 1.0),
    # the other robot-force forms (srfm.models.params.FORM_FIELDS; k in m², A of the
    # collision-prediction force dimensionless, times in s)
    "ttc_k": (0.0, 100.0),
    "ttc_tau0": (0.1, 20.0),
    "cp_a": (0.0, 100.0),
    "cp_b": (0.05, 3.0),
    "ell_a": (0.0, 100.0),
    "ell_b": (0.05, 3.0),
    "ell_dt": (0.0, 5.0),
    "ss_a": (0.0, 5.0),
    "ss_miss": (0.1, 3.0),
    "ss_horizon": (0.3, 8.0),
    "ss_speed_gain": (-3.0, 3.0),
    "robot_force_cap": (0.02, 20.0),
}
# The parameters a robot-stage fit of each robot-force form varies by default: its
# strength and range (the exponential form's λ_r, and the elliptical form's too, only when
# asked: ``srfm fit --fit-lambda-robot``); the forms' force cap and the collision-
# prediction force's time limits are kept.
FORM_FIT_FIELDS: Final[dict[str, tuple[str, ...]]] = {
    "exponential": ("a_robot", "b_robot"),
    "ttc": ("ttc_k", "ttc_tau0"),
    "collision_prediction": ("cp_a", "cp_b"),
    "elliptical": ("ell_a", "ell_b", "ell_dt"),
    "sidestep": ("ss_a", "ss_miss", "ss_horizon", "ss_speed_gain"),
}
_MAX_NFEV: Final = 1_000_000
# The published parameter sets every fit also starts from (not fitted presets such as
# navwareset2025, so that adding a preset does not change what a fit does).
_START_PRESETS: Final = (PRESETS["agrawal2024"], PRESETS["ferrer2013"])
_STAGE_MODE: Final[dict[str, Mode]] = {"pedestrian": "sfm", "robot": "srfm"}
_STAGE_WINDOWS: Final[dict[str, bool]] = {"pedestrian": False, "robot": True}


@attrs.frozen(kw_only=True)
class StageResult:
    """One fitting stage.

    Attributes:
        stage: ``pedestrian`` or ``robot``.
        fitted: the fitted values, field name -> value (empty when skipped).
        start: the starting point that gave the lowest cost.
        n_windows: windows used; n_tracks: distinct pedestrian tracks among them.
        ade_start_m: ADE (m) of the stage's model at ``start`` as passed to
            :func:`fit_params` (before fitting).
        ade_m: ADE (m) at the fitted parameters.
        rms_m: √(mean over windows of the window's mean squared displacement) (m) at
            the fitted parameters: √(Σ‖r‖² / n_windows).
        nfev: model evaluations over all starting points.
        success: scipy reported convergence for the kept solution.
        message: scipy's message, or why the stage was skipped.
        skipped: True when the stage had no windows.
    """

    stage: str
    fitted: dict[str, float]
    start: dict[str, float]
    n_windows: int
    n_tracks: int
    ade_start_m: float
    ade_m: float
    rms_m: float
    nfev: int
    success: bool
    message: str
    skipped: bool = False


@attrs.frozen(kw_only=True)
class FitResult:
    """The fitted parameters and one :class:`StageResult` per requested stage."""

    params: SRFMParams
    stages: tuple[StageResult, ...]


def _residual_fn(
    windows: Windows, sel: NDArray[np.int64], base: SRFMParams, fields: Sequence[str], mode: Mode
) -> Callable[[NDArray[np.float64]], NDArray[np.float64]]:
    rows = windows.rows(sel)
    observed = windows.observed[rows]
    weight = np.repeat(1.0 / np.sqrt(windows.steps[sel].astype(np.float64)), windows.steps[sel])

    def fun(theta: NDArray[np.float64]) -> NDArray[np.float64]:
        params = base.replace(**dict(zip(fields, (float(v) for v in theta), strict=True)))
        diff = predict(windows, params, sel, mode) - observed
        return np.asarray((diff * weight[:, None]).ravel())

    return fun


def _ade(windows: Windows, sel: NDArray[np.int64], params: SRFMParams, mode: Mode) -> float:
    err = displacement_errors(windows, sel, predict(windows, params, sel, mode))
    per_window = np.add.reduceat(err, (np.cumsum(windows.steps[sel]) - windows.steps[sel]))
    return float(np.mean(per_window / windows.steps[sel]))


def fit_params(
    windows: Windows,
    *,
    start: SRFMParams | None = None,
    stages: Sequence[str] = ("pedestrian", "robot"),
    max_nfev: int = 200,
    multi_start: bool = True,
    tolerance: float = 1e-6,
    log: Callable[[str], None] | None = None,
    fields: Mapping[str, Sequence[str]] | None = None,
    subset: NDArray[np.int64] | None = None,
    extra_starts: Sequence[SRFMParams] = (),
) -> FitResult:
    """Learn SRFM parameters from prediction windows by nonlinear least squares.

    Args:
        windows: windows of world-frame scenes (:func:`srfm.fitting.build_windows`).
        start: parameters the fit starts from and keeps for whatever it does not fit
            (λ_r, obstacles, and the parameters of a skipped stage); agrawal2024 when
            omitted. The paper's presets are tried as further starting points.
        stages: ``pedestrian`` and/or ``robot``, run in that order.
        max_nfev: most model evaluations per starting point.
        multi_start: also start from the paper's presets (agrawal2024, ferrer2013) and,
            for a robot force of another form than the paper's (which the presets do
            not parametrise), from ``start`` with that form's strength divided by 10;
            keep the lowest cost. False starts from ``start`` only.
        tolerance: scipy's ``ftol``, ``xtol`` and ``gtol``: stop when the cost or the
            parameters change by less than this fraction.
        log: called with a one-line progress message per starting point.
        fields: per stage, the parameters to fit instead of :data:`STAGE_FIELDS`
            (e.g. ``{"robot": ("a_robot", "b_robot", "lambda_robot")}``); each must
            have :data:`BOUNDS`.
        subset: window indices to fit on (default: all); a window may appear more than
            once (a bootstrap resample), and then weighs as many times. Each stage
            keeps the subset's windows of its kind.
        extra_starts: further starting points, tried after ``start`` and the presets.

    Returns:
        The fitted parameters and per-stage diagnostics. A stage without windows is
        skipped (``StageResult.skipped``) and its parameters stay at ``start``.

    Raises:
        ParameterError: an unknown stage or field, or ``max_nfev`` not an integer in
            [1, 1_000_000].
    """
    from scipy.optimize import least_squares

    unknown = [s for s in stages if s not in STAGE_FIELDS]
    if unknown:
        raise ParameterError(f"unknown fitting stage {plain(unknown[0])}; known: pedestrian, robot")
    if (
        isinstance(max_nfev, bool)
        or not isinstance(max_nfev, int | np.integer)
        or not 1 <= max_nfev <= _MAX_NFEV
    ):
        raise ParameterError(
            f"max_nfev must be an integer in [1, {_MAX_NFEV}], got {plain(max_nfev)}"
        )
    chosen_fields = {**STAGE_FIELDS, **{k: tuple(v) for k, v in (fields or {}).items()}}
    for stage_name, names in chosen_fields.items():
        if stage_name not in STAGE_FIELDS:
            raise ParameterError(f"unknown fitting stage {plain(stage_name)} in fields")
        bad = [f for f in names if f not in BOUNDS]
        if bad or not names:
            raise ParameterError(
                f"cannot fit {bad[0] if bad else 'nothing'!r} in stage {stage_name!r}; "
                f"fittable: {', '.join(BOUNDS)}"
            )
    params = start or SRFMParams()
    results: list[StageResult] = []
    for stage in ("pedestrian", "robot"):
        if stage not in stages:
            continue
        fields_ = chosen_fields[stage]
        mode = _STAGE_MODE[stage]
        if subset is None:
            sel = windows.select(interaction=_STAGE_WINDOWS[stage])
        else:
            subset = np.ascontiguousarray(subset, dtype=np.int64)
            if subset.size and (subset.min() < 0 or subset.max() >= windows.n_windows):
                raise ParameterError(
                    f"subset holds window indices outside [0, {windows.n_windows})"
                )
            sel = subset[windows.interaction[subset] == _STAGE_WINDOWS[stage]]
        n_tracks = int(np.unique(windows.track[sel]).size)
        if sel.size == 0:
            kind = "interaction" if _STAGE_WINDOWS[stage] else "non-interaction"
            results.append(
                StageResult(
                    stage=stage,
                    fitted={},
                    start={f: getattr(params, f) for f in fields_},
                    n_windows=0,
                    n_tracks=0,
                    ade_start_m=math.nan,
                    ade_m=math.nan,
                    rms_m=math.nan,
                    nfev=0,
                    success=False,
                    message=f"skipped: no {kind} windows in the data",
                    skipped=True,
                )
            )
            continue
        lower = np.array([BOUNDS[f][0] for f in fields_])
        upper = np.array([BOUNDS[f][1] for f in fields_])
        starts: list[NDArray[np.float64]] = []
        presets = _START_PRESETS if multi_start else ()
        weaker = _weaker_robot(params, fields_) if multi_start and stage == "robot" else ()
        for candidate in (params, *presets, *weaker, *extra_starts):
            x0 = np.clip([getattr(candidate, f) for f in fields_], lower, upper)
            if not any(np.array_equal(x0, s) for s in starts):
                starts.append(x0)
        fun = _residual_fn(windows, sel, params, fields_, mode)
        best = None
        nfev = 0
        for x0 in starts:
            sol = least_squares(
                fun,
                x0,
                bounds=(lower, upper),
                method="trf",
                x_scale="jac",
                diff_step=1e-3,
                ftol=tolerance,
                xtol=tolerance,
                gtol=tolerance,
                max_nfev=max_nfev,
            )
            nfev += int(sol.nfev)
            if log is not None:
                values = ", ".join(f"{f}={v:.4g}" for f, v in zip(fields_, sol.x, strict=True))
                log(f"{stage}: from {_fmt(fields_, x0)} -> {values} (cost {sol.cost:.6g})")
            if best is None or sol.cost < best[0].cost:
                best = (sol, x0)
        if best is None:  # pragma: no cover - starts always holds the start point
            raise ParameterError("no starting point")
        sol, x0 = best
        start_params = params.replace(**dict(zip(fields_, map(float, x0), strict=True)))
        ade_start = _ade(windows, sel, params, mode)
        fitted = {f: float(v) for f, v in zip(fields_, sol.x, strict=True)}
        params = params.replace(**fitted)
        results.append(
            StageResult(
                stage=stage,
                fitted=fitted,
                start={f: getattr(start_params, f) for f in fields_},
                n_windows=int(sel.size),
                n_tracks=n_tracks,
                ade_start_m=ade_start,
                ade_m=_ade(windows, sel, params, mode),
                rms_m=math.sqrt(2.0 * float(sol.cost) / sel.size),
                nfev=nfev,
                success=bool(sol.success),
                message=str(sol.message),
            )
        )
    return FitResult(params=params, stages=tuple(results))


def _weaker_robot(params: SRFMParams, fields: Sequence[str]) -> tuple[SRFMParams, ...]:
    """For a robot force of another form than the paper's, whose parameters the presets
    do not give: the start with the form's strength divided by 10 (when it is fitted)."""
    if params.robot_form == "exponential":
        return ()
    strength = FORM_FIELDS[params.robot_form][0]
    if strength not in fields:
        return ()
    return (params.replace(**{strength: 0.1 * getattr(params, strength)}),)


def _fmt(fields: Sequence[str], values: NDArray[np.float64]) -> str:
    return "(" + ", ".join(f"{v:.4g}" for v in values) + ")"
