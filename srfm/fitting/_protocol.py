"""The real-data protocol for the robot force: scene groups, held-out fits, bootstrap.

The pedestrian part (A_p, B_p, λ, τ) is fitted once on pedestrian-only data; the robot
part (A_r, B_r, λ_r) on NavWareSet interaction windows with the pedestrian part held.
Everything that resamples or holds data out does it by *recorded scene* (all tracks of
one NavWareSet scene number go together), never by window or track, so no two windows
of one track are ever split between training and test. See ``docs/fitting.md``.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Final

import attrs
import numpy as np
from numpy.typing import NDArray

from srfm._text import plain
from srfm.datasets._trajectories import Trajectories
from srfm.errors import ParameterError
from srfm.fitting._ade import displacement_summary, pass_errors
from srfm.fitting._fit import fit_params
from srfm.fitting._predict import Mode, predict
from srfm.fitting._windows import WindowConfig, Windows
from srfm.models.params import SRFMParams

__all__ = [
    "EVAL_WINDOWS",
    "FIT_WINDOWS",
    "ROBOT_FIELDS",
    "TABLE2_MODES",
    "PairedTest",
    "SceneGroups",
    "WindowMetrics",
    "bootstrap_robot_part",
    "fit_robot_part",
    "heldout_errors",
    "heldout_metrics",
    "holm",
    "leave_one_scene_out",
    "paired_test",
    "scene_groups",
    "window_metrics",
]

IntArray = NDArray[np.int64]

ROBOT_FIELDS: Final = ("a_robot", "b_robot", "lambda_robot")
# Fitting windows: start every 1.2 s while the pedestrian walks (>= 0.3 m/s).
FIT_WINDOWS: Final = WindowConfig(stride_s=1.2, min_start_speed_mps=0.3)
# Test windows: the same, but one every 4.8 s (the horizon): no two test windows of a
# track overlap, so the paired tests compare non-overlapping stretches of motion.
EVAL_WINDOWS: Final = WindowConfig(stride_s=4.8, min_start_speed_mps=0.3)


@attrs.frozen(kw_only=True, eq=False)
class SceneGroups:
    """The recorded scenes of a set of windows.

    Attributes:
        keys: (G,) the group of each recorded scene: the NavWareSet scene number
            (``navwareset_scene``) or, for other data, the scene's name.
        scenario, robot: (G,) the scene's condition ("" when unknown).
        compliant: (G,) socially compliant robot (False when unknown).
        of_window: (W,) group index of each window.
    """

    keys: tuple[str, ...]
    scenario: tuple[str, ...]
    robot: tuple[str, ...]
    compliant: tuple[bool, ...]
    of_window: IntArray

    @property
    def n_groups(self) -> int:
        """Number of recorded scenes G."""
        return len(self.keys)

    def windows_of(self, groups: Sequence[int] | IntArray) -> IntArray:
        """Window indices of the given groups, group by group; a group listed twice
        gives its windows twice (a bootstrap resample)."""
        order = np.argsort(self.of_window, kind="stable")
        bounds = np.searchsorted(self.of_window[order], np.arange(self.n_groups + 1))
        parts = [order[bounds[g] : bounds[g + 1]] for g in groups]
        if not parts:
            return np.zeros(0, dtype=np.int64)
        return np.concatenate(parts).astype(np.int64)

    def where(self, predicate: Callable[[str, str, bool], bool]) -> list[int]:
        """Indices of the groups whose (scenario, robot, compliant) satisfy ``predicate``."""
        return [
            g
            for g in range(self.n_groups)
            if predicate(self.scenario[g], self.robot[g], self.compliant[g])
        ]


def scene_groups(windows: Windows, scenes: Sequence[Trajectories]) -> SceneGroups:
    """Group the windows by recorded scene (``scenes`` as passed to ``build_windows``)."""
    if len(scenes) != len(windows.scene_names):
        raise ParameterError(
            f"{len(scenes)} scenes given but the windows were built from {len(windows.scene_names)}"
        )
    keys: list[str] = []
    info: list[tuple[str, str, bool]] = []
    index: dict[str, int] = {}
    of_scene = np.zeros(len(scenes), dtype=np.int64)
    for i, s in enumerate(scenes):
        key = s.source.get("navwareset_scene", s.scene)
        if key not in index:
            index[key] = len(keys)
            keys.append(key)
            info.append(
                (
                    s.source.get("scenario", ""),
                    s.source.get("robot", ""),
                    s.source.get("compliant", "") == "true",
                )
            )
        of_scene[i] = index[key]
    return SceneGroups(
        keys=tuple(keys),
        scenario=tuple(x[0] for x in info),
        robot=tuple(x[1] for x in info),
        compliant=tuple(x[2] for x in info),
        of_window=of_scene[windows.scene].astype(np.int64),
    )


def fit_robot_part(
    windows: Windows,
    base: SRFMParams,
    subset: IntArray | None = None,
    *,
    multi_start: bool = True,
    extra_starts: Sequence[SRFMParams] = (),
    max_nfev: int = 200,
    tolerance: float = 1e-6,
    fields: Sequence[str] = ROBOT_FIELDS,
) -> SRFMParams:
    """Fit the robot part (``fields``: A_r, B_r, λ_r by default) on the interaction
    windows of ``subset`` (all when None), the pedestrian part held at ``base``;
    ``base``'s robot part (and whatever it holds that is not fitted, such as the form of
    the robot force) is the first start."""
    result = fit_params(
        windows,
        start=base,
        stages=("robot",),
        fields={"robot": tuple(fields)},
        subset=subset,
        multi_start=multi_start,
        extra_starts=extra_starts,
        max_nfev=max_nfev,
        tolerance=tolerance,
    )
    if result.stages[0].skipped:
        raise ParameterError(f"cannot fit the robot part: {result.stages[0].message}")
    return result.params


def leave_one_scene_out(
    windows: Windows,
    groups: SceneGroups,
    base: SRFMParams,
    *,
    n_folds: int | None = None,
    start: SRFMParams | None = None,
    multi_start: bool = True,
    tolerance: float = 1e-6,
    log: Callable[[str], None] | None = None,
) -> list[SRFMParams]:
    """Scene-level cross-validation of the robot part.

    Scene g (in group order) belongs to fold g mod ``n_folds`` (every scene its own
    fold when None: leave one scene out). Each fold's robot part is fitted on the
    windows of every other fold, from ``base``, the published presets and ``start``
    (e.g. the fit on all scenes), keeping the lowest cost; without ``multi_start``,
    from ``base`` with ``start``'s robot part alone (when ``start`` is given).

    Returns:
        G parameter sets, in group order: entry g is the fit that held scene g out.
    """
    k = groups.n_groups if n_folds is None else n_folds
    if isinstance(k, bool) or not isinstance(k, int) or not 2 <= k <= groups.n_groups:
        raise ParameterError(
            f"n_folds must be an integer in [2, {groups.n_groups}] (the number of scenes), "
            f"got {plain(n_folds)}"
        )
    out: list[SRFMParams | None] = [None] * groups.n_groups
    for fold in range(k):
        held = [g for g in range(groups.n_groups) if g % k == fold]
        train = groups.windows_of([g for g in range(groups.n_groups) if g % k != fold])
        first = base if multi_start or start is None else base.replace(**_robot(start))
        params = fit_robot_part(
            windows,
            first,
            train,
            multi_start=multi_start,
            extra_starts=(start,) if start is not None and multi_start else (),
            tolerance=tolerance,
        )
        for g in held:
            out[g] = params
        if log is not None:
            names = ", ".join(groups.keys[g] for g in held)
            log(f"held out scene(s) {names}: " + _fmt(params))
    return [p for p in out if p is not None]


def bootstrap_robot_part(
    windows: Windows,
    groups: SceneGroups,
    base: SRFMParams,
    start: SRFMParams,
    *,
    n_boot: int,
    seed: int,
    among: Sequence[int] | None = None,
    tolerance: float = 1e-6,
    log: Callable[[str], None] | None = None,
    fields: Sequence[str] = ROBOT_FIELDS,
) -> NDArray[np.float64]:
    """Bootstrap over recorded scenes: ``n_boot`` resamples (with replacement) of the
    scenes in ``among`` (all when None), each fitted from ``start`` alone (the fit on
    the full sample) with the pedestrian part held at ``base``.

    Returns:
        (n_boot, len(fields)) the fitted ``fields`` (A_r, B_r, λ_r by default).
        Deterministic for a given ``seed``.
    """
    if isinstance(n_boot, bool) or not isinstance(n_boot, int) or n_boot < 1:
        raise ParameterError(f"n_boot must be a positive integer, got {plain(n_boot)}")
    pool = np.arange(groups.n_groups) if among is None else np.asarray(among, dtype=np.int64)
    if pool.size == 0:
        raise ParameterError("no scenes to bootstrap over")
    rng = np.random.default_rng(seed)
    out = np.zeros((n_boot, len(fields)))
    for b in range(n_boot):
        draw = rng.choice(pool, size=pool.size, replace=True)
        params = fit_robot_part(
            windows,
            base.replace(**_robot(start)).replace(**{f: getattr(start, f) for f in fields}),
            groups.windows_of(draw),
            multi_start=False,
            tolerance=tolerance,
            fields=fields,
        )
        out[b] = [getattr(params, f) for f in fields]
        if log is not None:
            log(f"bootstrap {b + 1}/{n_boot}: " + _fmt(params))
    return out


def _robot(params: SRFMParams) -> dict[str, float]:
    return {f: getattr(params, f) for f in ROBOT_FIELDS}


def _fmt(params: SRFMParams) -> str:
    return ", ".join(f"{f} = {getattr(params, f):.4g}" for f in ROBOT_FIELDS)


# Table 2's models, in its column order.
TABLE2_MODES: Final[tuple[Mode, ...]] = (
    "constant_velocity",
    "sfm",
    "robot_as_pedestrian",
    "srfm",
)


@attrs.frozen(kw_only=True, eq=False)
class WindowMetrics:
    """Per-window prediction errors of one model, each (W,).

    Attributes:
        ade, fde: average and final displacement error (m).
        pass_distance: predicted minus observed minimum centre distance to the robot
            over the window (m); NaN when the robot is observed at none of its samples.
        path_offset: predicted minus observed lateral position at the pass, relative to
            the line through the window start along the initial velocity (m, positive
            to the left of it); NaN as ``pass_distance`` or with a zero initial velocity.
            See :func:`srfm.fitting.pass_errors`.
    """

    ade: NDArray[np.float64]
    fde: NDArray[np.float64]
    pass_distance: NDArray[np.float64]
    path_offset: NDArray[np.float64]


def window_metrics(
    windows: Windows, sel: IntArray, params: SRFMParams, mode: Mode
) -> WindowMetrics:
    """Per-window ADE, FDE, pass-distance and path-offset errors, each (Q,), of one model
    on the windows ``sel`` (:class:`WindowMetrics`; signed pass-distance and path-offset
    errors, predicted minus observed)."""
    sel = np.ascontiguousarray(sel, dtype=np.int64)
    if sel.size == 0:
        empty = np.zeros(0)
        return WindowMetrics(ade=empty, fde=empty, pass_distance=empty, path_offset=empty)
    predicted = predict(windows, params, sel, mode)
    ade, fde = displacement_summary(windows, sel, predicted)
    distance, offset = pass_errors(windows, sel, predicted)
    return WindowMetrics(ade=ade, fde=fde, pass_distance=distance, path_offset=offset)


def heldout_metrics(
    windows: Windows,
    groups: SceneGroups,
    base: SRFMParams,
    per_group: Sequence[SRFMParams],
) -> dict[str, WindowMetrics]:
    """Per-window ADE, FDE, pass-distance and path-offset errors of every
    :data:`TABLE2_MODES` model.

    The pedestrian part is ``base``'s in every model; the SRFM's robot part for the
    windows of scene g is ``per_group[g]``'s (the fit that held scene g out).
    """
    if len(per_group) != groups.n_groups:
        raise ParameterError(
            f"need one parameter set per scene ({groups.n_groups}), got {len(per_group)}"
        )
    out: dict[str, WindowMetrics] = {}
    every = np.arange(windows.n_windows, dtype=np.int64)
    for mode in TABLE2_MODES:
        cols = [np.full(windows.n_windows, np.nan) for _ in range(4)]
        if mode == "srfm":
            parts = [
                (groups.windows_of([g]), base.replace(**_robot(per_group[g])))
                for g in range(groups.n_groups)
            ]
        else:
            parts = [(every, base)]
        for sel, params in parts:
            m = window_metrics(windows, sel, params, mode)
            cols[0][sel], cols[1][sel] = m.ade, m.fde
            cols[2][sel], cols[3][sel] = m.pass_distance, m.path_offset
        out[mode] = WindowMetrics(
            ade=cols[0], fde=cols[1], pass_distance=cols[2], path_offset=cols[3]
        )
    return out


def heldout_errors(
    windows: Windows,
    groups: SceneGroups,
    base: SRFMParams,
    per_group: Sequence[SRFMParams],
) -> dict[str, tuple[NDArray[np.float64], NDArray[np.float64]]]:
    """Per-window ADE and FDE (m) of every :data:`TABLE2_MODES` model, each (W,): the
    first two columns of :func:`heldout_metrics`."""
    return {
        mode: (m.ade, m.fde)
        for mode, m in heldout_metrics(windows, groups, base, per_group).items()
    }


@attrs.frozen(kw_only=True)
class PairedTest:
    """Wilcoxon signed-rank test of model b against model a over the same windows.

    Attributes:
        n: number of pairs.
        mean_a, mean_b: the mean of each (m).
        median_diff: median of b − a (m); negative: b is better.
        p: two-sided p (NaN with fewer than two pairs; 1 when every difference is 0).
    """

    n: int
    mean_a: float
    mean_b: float
    median_diff: float
    p: float


def paired_test(a: NDArray[np.float64], b: NDArray[np.float64]) -> PairedTest:
    """Wilcoxon signed-rank test (scipy, two-sided) of ``b`` against ``a``, paired."""
    from scipy import stats

    a = np.asarray(a, dtype=np.float64).ravel()
    b = np.asarray(b, dtype=np.float64).ravel()
    if a.shape != b.shape:
        raise ParameterError(f"paired samples differ in size: {a.size} and {b.size}")
    n = int(a.size)
    if n == 0:
        return PairedTest(n=0, mean_a=math.nan, mean_b=math.nan, median_diff=math.nan, p=math.nan)
    d = b - a
    if n < 2:
        p = math.nan
    elif not np.any(d != 0):
        p = 1.0
    else:
        p = float(stats.wilcoxon(b, a).pvalue)
    return PairedTest(
        n=n,
        mean_a=float(a.mean()),
        mean_b=float(b.mean()),
        median_diff=float(np.median(d)),
        p=p,
    )


def holm(p: Sequence[float]) -> list[float]:
    """Holm–Bonferroni adjusted p-values of one family of tests, in the given order
    (a NaN p is not a test: it stays NaN and does not count in the family's size);
    :func:`srfm.metrics.stats.adjust_p_values` with ``"holm"``, as a list."""
    from srfm.metrics.stats import adjust_p_values

    return [float(x) for x in adjust_p_values(list(p), "holm")]
