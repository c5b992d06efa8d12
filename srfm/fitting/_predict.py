"""Predictions over windows: the SRFM variants of the paper and a constant-velocity baseline."""

from __future__ import annotations

from typing import Final, Literal

import numpy as np
from numpy.typing import NDArray

from srfm._text import plain
from srfm.errors import ParameterError
from srfm.fitting._kernels import replay_windows
from srfm.fitting._windows import Windows
from srfm.models.params import SRFMParams

__all__ = ["MODES", "Mode", "displacement_errors", "predict"]

Mode = Literal["sfm", "robot_as_pedestrian", "srfm", "constant_velocity"]

MODES: Final[dict[str, str]] = {
    "constant_velocity": "x(t) = x0 + v0 t (no forces)",
    "sfm": "f_a + f_p (pedestrians); robot ignored",
    "robot_as_pedestrian": "f_a + f_p (pedestrians) + f_p (robot)",
    "srfm": "f_a + f_p (pedestrians) + f_r (robot)",
}


def predict(
    windows: Windows, params: SRFMParams, sel: NDArray[np.int64], mode: Mode
) -> NDArray[np.float64]:
    """Predicted positions of the windows in ``sel``.

    Args:
        windows: the windows (:func:`srfm.fitting.build_windows`).
        params: model parameters (ignored by ``constant_velocity``).
        sel: (Q,) window indices.
        mode: ``sfm`` (goal + pedestrian forces, the robot ignored),
            ``robot_as_pedestrian`` (the robot repels with the pedestrian force A_p, B_p,
            λ), ``srfm`` (the robot force A_r, B_r, λ_r), or ``constant_velocity``.

    Returns:
        (R, 2) positions (m), the rows :meth:`Windows.rows` gives for ``sel``.
    """
    if mode not in MODES:
        raise ParameterError(f"unknown prediction mode {plain(mode)}; known: {', '.join(MODES)}")
    sel = np.ascontiguousarray(sel, dtype=np.int64)
    rows = windows.rows(sel)
    if mode == "constant_velocity":
        w = np.repeat(sel, windows.steps[sel])
        return windows.pos[w] + windows.vel[w] * windows.step_time[rows, None]
    if mode == "robot_as_pedestrian":
        params = params.replace(
            a_robot=params.a_ped, b_robot=params.b_ped, lambda_robot=params.lambda_ped
        )
    out = np.zeros_like(windows.observed)
    replay_windows(sel, *windows.replay_bundles(), params.for_kernels(), mode != "sfm", out)
    return out[rows]


def displacement_errors(
    windows: Windows, sel: NDArray[np.int64], predicted: NDArray[np.float64]
) -> NDArray[np.float64]:
    """(R,) Euclidean distance (m) between predicted and observed positions, row by row."""
    rows = windows.rows(np.ascontiguousarray(sel, dtype=np.int64))
    return np.asarray(np.linalg.norm(predicted - windows.observed[rows], axis=1))
