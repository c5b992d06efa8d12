"""Planners of a careless user, for the class 7 tests (``tests.reliability.user_planners:X``)."""

from __future__ import annotations

import sys

import numpy as np


class Boom:
    """Raises inside act() at step 3."""

    name = "boom"
    detection_range_m = None

    def reset(self, context: object, rng: object) -> None:
        pass

    def act(self, observation: object) -> np.ndarray:
        if observation.step == 3:  # type: ignore[attr-defined]
            raise ZeroDivisionError("the user's own bug")
        return np.zeros(2)


class ResetBoom(Boom):
    """Raises inside reset()."""

    def reset(self, context: object, rng: object) -> None:
        raise KeyError("missing")


class Exits(Boom):
    """Calls sys.exit(0) inside act(): must not end srfm with exit status 0."""

    def act(self, observation: object) -> np.ndarray:
        sys.exit(0)


class NeedsArguments(Boom):
    """A factory that cannot be called without arguments."""

    def __init__(self, speed: float) -> None:
        self.speed = speed


def exits_in_factory() -> Boom:
    """A factory that ends the process."""
    sys.exit()
