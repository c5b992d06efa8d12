"""The names of the robot force's forms, importable without NumPy (the command line
lists them in its options): :data:`ROBOT_FORMS`, in the order of their kernel codes."""

from __future__ import annotations

from typing import Final

__all__ = ["ROBOT_FORMS"]

ROBOT_FORMS: Final = ("exponential", "ttc", "collision_prediction", "elliptical", "sidestep")
"""The forms of the robot force (:class:`srfm.SRFMParams` ``robot_form``); a form's
kernel code is its index here."""
