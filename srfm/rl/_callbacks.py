"""The callbacks of :func:`srfm.rl.training.train`: stable-baselines3 callbacks (SBX
takes the same), chained in this order by ``train``:

- :class:`K2Curriculum`: sets the environments' k2 from the curriculum;
- :class:`EveryNSteps` with the progress report, the checkpoint and the evaluation of
  the training session (:class:`srfm.rl.training._Session`).

Each acts when the step count reaches or passes a multiple of its period
(:func:`crossed`): with n environments the count moves by n per call.

Imported by ``train`` only, once the ``rl`` extra is found (it imports
stable-baselines3).
"""

from __future__ import annotations

from collections.abc import Callable

from stable_baselines3.common.callbacks import BaseCallback

__all__ = ["EveryNSteps", "K2Curriculum", "crossed"]


def crossed(before: int, now: int, every: int) -> bool:
    """True when the step count, moving from ``before`` to ``now``, reached or passed a
    multiple of ``every`` (with one environment: when ``now`` is one); never for 0."""
    return every > 0 and now // every > before // every


class EveryNSteps(BaseCallback):
    """Calls ``action(steps)`` when the step count crosses a multiple of ``every``
    (0: never).

    Args:
        every: the period (environment steps).
        action: called with the step count.
    """

    def __init__(self, every: int, action: Callable[[int], None]) -> None:
        super().__init__()
        self.every = every
        self.action = action
        self._before = 0

    def _on_training_start(self) -> None:
        self._before = int(self.num_timesteps)

    def _on_step(self) -> bool:
        steps = int(self.num_timesteps)
        before, self._before = self._before, steps
        if crossed(before, steps, self.every):
            self.action(steps)
        return True


class K2Curriculum(EveryNSteps):
    """Sets k2 of the training environments (their ``set_k2``) from ``schedule(steps)``
    at the start of training and when the step count crosses a multiple of ``every``,
    when it changed.

    Args:
        every: the period (environment steps).
        schedule: k2 (1/m) at a step count.
    """

    def __init__(self, every: int, schedule: Callable[[int], float]) -> None:
        super().__init__(every, self._set_k2)
        self.schedule = schedule
        self._k2 = -1.0

    def _on_training_start(self) -> None:
        super()._on_training_start()
        self._k2 = -1.0
        self._set_k2(self._before)

    def _set_k2(self, steps: int) -> None:
        k2 = self.schedule(steps)
        if k2 != self._k2:
            self.training_env.env_method("set_k2", k2)
            self._k2 = k2
