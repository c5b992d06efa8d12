"""The Social Robot Force Model: parameters, force kernels and the crowd step."""

from srfm.models.forces import (
    ForceComponents,
    RobotBody,
    force_components,
    step_crowd,
)
from srfm.models.params import (
    PRESETS,
    ROBOT_FORMS,
    SRFMParams,
    load_params,
    save_params,
)

__all__ = [
    "PRESETS",
    "ROBOT_FORMS",
    "ForceComponents",
    "RobotBody",
    "SRFMParams",
    "force_components",
    "load_params",
    "save_params",
    "step_crowd",
]
