"""The Social Robot Force Model: parameters, force kernels and the crowd step."""

from typing import TYPE_CHECKING

from srfm._lazy import lazy_names

# Imported on first use (srfm/_lazy.py): the parameters without the numba kernels.
if TYPE_CHECKING:
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

_LAZY: dict[str, str] = {
    "ForceComponents": "srfm.models.forces",
    "RobotBody": "srfm.models.forces",
    "force_components": "srfm.models.forces",
    "step_crowd": "srfm.models.forces",
    "PRESETS": "srfm.models.params",
    "ROBOT_FORMS": "srfm.models.params",
    "SRFMParams": "srfm.models.params",
    "load_params": "srfm.models.params",
    "save_params": "srfm.models.params",
}

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

__getattr__, __dir__ = lazy_names(__name__, _LAZY, globals())
