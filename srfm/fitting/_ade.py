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

__all__ = ["ADE_ROWS", "AdeRow", "evaluate_ade", "window_errors"]

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
    err = displacement_errors(windows, sel, predict(windows, params, sel, mode))
    steps = windows.steps[sel]
    ends = np.cumsum(steps)
    ade = np.add.reduceat(err, ends - steps) / steps
    return ade, err[ends - 1]


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
