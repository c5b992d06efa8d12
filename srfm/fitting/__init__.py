"""SRFM parameter learning from dataset trajectories, and ADE/FDE evaluation.

Tracks are cut into prediction windows (:func:`build_windows`); in each window one
pedestrian is simulated with the SRFM from its observed state while its neighbours and
the robot are replayed as observed (:func:`predict`). :func:`fit_params` learns the
pedestrian and robot parameters by nonlinear least squares on those predictions, as in
the paper; :func:`evaluate_ade` reports the paper's ADE table. See ``docs/fitting.md``.
"""

from srfm.fitting._ade import ADE_ROWS, AdeRow, evaluate_ade, pass_errors, window_errors
from srfm.fitting._encounters import Encounter, replay_encounter
from srfm.fitting._fit import (
    BOUNDS,
    FORM_FIT_FIELDS,
    STAGE_FIELDS,
    FitResult,
    StageResult,
    fit_params,
)
from srfm.fitting._predict import MODES, displacement_errors, predict
from srfm.fitting._protocol import (
    EVAL_WINDOWS,
    FIT_WINDOWS,
    ROBOT_FIELDS,
    TABLE2_MODES,
    PairedTest,
    SceneGroups,
    WindowMetrics,
    bootstrap_robot_part,
    fit_robot_part,
    heldout_errors,
    heldout_metrics,
    holm,
    leave_one_scene_out,
    paired_test,
    scene_groups,
    window_metrics,
)
from srfm.fitting._response import (
    PROTOCOL,
    ResponseProtocol,
    StartFit,
    best_fit,
    fit_sidestep,
    identification,
    profile_costs,
    profile_grid,
    relative_change,
    spread_starts,
    success,
)
from srfm.fitting._windows import ALIGNS, GOALS, WindowConfig, Windows, build_windows

__all__ = [
    "ADE_ROWS",
    "ALIGNS",
    "BOUNDS",
    "EVAL_WINDOWS",
    "FIT_WINDOWS",
    "FORM_FIT_FIELDS",
    "GOALS",
    "MODES",
    "PROTOCOL",
    "ROBOT_FIELDS",
    "STAGE_FIELDS",
    "TABLE2_MODES",
    "AdeRow",
    "Encounter",
    "FitResult",
    "PairedTest",
    "ResponseProtocol",
    "SceneGroups",
    "StageResult",
    "StartFit",
    "WindowConfig",
    "WindowMetrics",
    "Windows",
    "best_fit",
    "bootstrap_robot_part",
    "build_windows",
    "displacement_errors",
    "evaluate_ade",
    "fit_params",
    "fit_robot_part",
    "fit_sidestep",
    "heldout_errors",
    "heldout_metrics",
    "holm",
    "identification",
    "leave_one_scene_out",
    "paired_test",
    "pass_errors",
    "predict",
    "profile_costs",
    "profile_grid",
    "relative_change",
    "replay_encounter",
    "scene_groups",
    "spread_starts",
    "success",
    "window_errors",
    "window_metrics",
]
