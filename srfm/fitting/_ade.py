"""ADE/FDE evaluation: the paper's three rows plus constant-velocity baselines."""

from __future__ import annotations

import math
from typing import Final

import attrs
import numpy as np
from numpy.typing import NDArray

from srfm.fitting._predict import MODES, Mode, displacement_errors, predict
from srfm.fitting._windows import Windows
from srfm.models.params import SRFMParams

__all__ = ["ADE_ROWS", "AdeRow", "evaluate_ade", "pass_errors", "window_errors"]

# (model, mode, interaction windows?, the paper's ADE on JRDB in m or None)
ADE_ROWS: Final[tuple[tuple[str, Mode, bool, float | None], ...]] = (
    ("CV", "constant_velocity", False, None),
    ("SFM", "sfm", False, 0.70),
    ("CV", "constant_velocity", True, None),
    ("SFM, robot ignored", "sfm", True, None),
    ("SFM, robot as pedestrian", "robot_as_pedestrian", True, 0.75),
    ("SRFM", "srfm", True, 0.59),
)


@attrs.frozen(kw_only=True)
class AdeRow:
    """One row of the ADE table.

    Attributes:
        model: row label (``SFM``, ``SRFM``, ``CV``, ...).
        mode: prediction mode (:data:`srfm.fitting.MODES`).
        forces: the forces acting, as in the paper's table.
        tracks: ``non-interaction`` or ``interaction`` windows.
        n_windows: windows evaluated; n_tracks: distinct pedestrian tracks among them.
        ade_m: average displacement error (m): per window the mean distance between
            predicted and observed positions over its H samples, then the mean over
            windows; NaN without windows.
        fde_m: final displacement error (m): the mean over windows of the distance at
            the window's last sample.
        paper_ade_m: the paper's ADE on JRDB for this row, or None.
    """

    model: str
    mode: str
    forces: str
    tracks: str
    n_windows: int
    n_tracks: int
    ade_m: float
    fde_m: float
    paper_ade_m: float | None


def window_errors(
    windows: Windows, sel: NDArray[np.int64], params: SRFMParams, mode: Mode
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Per-window ADE and FDE (m), each (Q,), for the windows in ``sel``."""
    if sel.size == 0:
        return np.zeros(0), np.zeros(0)
    return displacement_summary(windows, sel, predict(windows, params, sel, mode))


def displacement_summary(
    windows: Windows, sel: NDArray[np.int64], predicted: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Per-window ADE and FDE (m), each (Q,), of the predictions ``predicted`` (the rows
    :meth:`Windows.rows` gives for ``sel``, as :func:`predict` returns them)."""
    if sel.size == 0:
        return np.zeros(0), np.zeros(0)
    err = displacement_errors(windows, sel, predicted)
    steps = windows.steps[sel]
    ends = np.cumsum(steps)
    ade = np.add.reduceat(err, ends - steps) / steps
    return ade, err[ends - 1]


def pass_errors(
    windows: Windows, sel: NDArray[np.int64], predicted: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Per-window errors of the two quantities the deviation metric depends on, each (Q,),
    predicted minus observed (m), over the window's predicted samples:

    - **pass distance**: the minimum centre distance to the robot (over the samples at
      which the robot is observed);
    - **path offset**: the lateral position at the pass (each path's own closest
      approach to the robot) relative to the line through the window start along the
      initial velocity, positive to the left of that velocity.

    NaN for a window whose robot is observed at none of its predicted samples (or, for
    the path offset, whose initial velocity is zero). ``predicted``: the rows
    :meth:`Windows.rows` gives for ``sel``, as :func:`predict` returns them.
    """
    sel = np.ascontiguousarray(sel, dtype=np.int64)
    rows = windows.rows(sel)
    observed = windows.observed[rows]
    frame = np.repeat(windows.frame0[sel], windows.steps[sel]) + _within(windows, sel) + 1
    on = windows.rb_on[frame]
    robot = windows.rb_a[frame]
    d_obs = np.where(on, np.linalg.norm(observed - robot, axis=1), np.inf)
    d_pred = np.where(on, np.linalg.norm(predicted - robot, axis=1), np.inf)
    distance = np.full(sel.size, np.nan)
    offset = np.full(sel.size, np.nan)
    start = 0
    for q, w in enumerate(sel):
        stop = start + int(windows.steps[w])
        if np.any(on[start:stop]):
            i_obs = start + int(np.argmin(d_obs[start:stop]))
            i_pred = start + int(np.argmin(d_pred[start:stop]))
            distance[q] = d_pred[i_pred] - d_obs[i_obs]
            v = windows.vel[w]
            speed = math.hypot(float(v[0]), float(v[1]))
            if speed > 0.0:
                normal = np.array([-v[1], v[0]]) / speed
                offset[q] = float((predicted[i_pred] - observed[i_obs]) @ normal)
        start = stop
    return distance, offset


def _within(windows: Windows, sel: NDArray[np.int64]) -> NDArray[np.int64]:
    """(R,) the index of each row within its window (0 for the first predicted step)."""
    steps = windows.steps[sel]
    return (np.arange(int(steps.sum())) - np.repeat(np.cumsum(steps) - steps, steps)).astype(
        np.int64
    )


def evaluate_ade(windows: Windows, params: SRFMParams) -> list[AdeRow]:
    """ADE and FDE of every row of :data:`ADE_ROWS` with one parameter set.

    The SFM rows use the pedestrian part of ``params``; ``robot_as_pedestrian`` makes
    the robot repel with the pedestrian force (A_p, B_p, λ); SRFM uses the robot force.
    """
    rows: list[AdeRow] = []
    for model, mode, interaction, paper in ADE_ROWS:
        sel = windows.select(interaction=interaction)
        ade, fde = window_errors(windows, sel, params, mode)
        rows.append(
            AdeRow(
                model=model,
                mode=mode,
                forces=MODES[mode],
                tracks="interaction" if interaction else "non-interaction",
                n_windows=int(sel.size),
                n_tracks=int(np.unique(windows.track[sel]).size),
                ade_m=float(ade.mean()) if ade.size else math.nan,
                fde_m=float(fde.mean()) if fde.size else math.nan,
                paper_ade_m=paper,
            )
        )
    return rows
