"""The crowd's own sensitivity: a crowd beside a copy of itself with one start nudged.

The deviation of a benchmark episode is the distance between the crowd with the robot
and the crowd without it. In a crowd whose dynamics amplify small differences, part of
that distance is the crowd model's own sensitivity and not the robot's doing. This
module measures that part with no robot at all: the counterfactual crowd of an episode
(nobody feels the robot) beside a copy in which one pedestrian starts ``NUDGE_M``
(1 mm) further along x. Nothing else differs, so whatever distance grows between the
two over the horizon is the crowd's own amplification of an imperceptible change.

It depends on the scenario, the seed and the parameters only (no planner, no robot
force), so the benchmark computes it once per (scenario, seed, parameter set)
(docs/metrics.md, "Noise floor").
"""

from __future__ import annotations

from typing import Final

import attrs
import numpy as np
from numpy.typing import NDArray

from srfm._validate import seed as check_seed
from srfm.errors import SimulationError
from srfm.models.params import SRFMParams
from srfm.scenarios import Scenario, episode_setup
from srfm.sim.engine import EpisodeEngine

__all__ = ["NUDGE_M", "NudgedTwins", "nudged_pedestrian", "nudged_twins"]

FloatArray = NDArray[np.float64]

NUDGE_M: Final = 1e-3
"""How far (m) the nudged pedestrian's start is moved, along +x: far below what a
tracker measures of a person (JRDB's labels are given to the centimetre) and a third
of a per mille of the paper scenarios' per-seed start noise."""


@attrs.frozen(eq=False)
class NudgedTwins:
    """Two robot-blind crowds of one episode set-up.

    Attributes:
        scenario: scenario name.
        seed: episode seed.
        nudged: the pedestrian whose start was moved.
        nudge_m: by how much (m), along +x.
        reference_pos: (T + 1, N, 2) the crowd as set up (the benchmark's
            counterfactual crowd).
        nudged_pos: (T + 1, N, 2) the copy with the one start moved.
        ped_enter_step: (N,) entry samples, None when everyone is there at sample 0.
    """

    scenario: str
    seed: int
    nudged: int
    nudge_m: float
    reference_pos: FloatArray
    nudged_pos: FloatArray
    ped_enter_step: NDArray[np.int64] | None


def nudged_pedestrian(seed: int, n_start: int) -> int:
    """The pedestrian nudged in episode ``seed``: ``seed mod n_start``, among the
    ``n_start`` pedestrians there first (at sample 0, or, in a scenario whose people
    all enter later, at the first sample anyone enters), so that the seeds of a scenario
    nudge each of them in turn."""
    if n_start < 1:
        raise SimulationError("the noise floor needs a pedestrian in the scenario")
    return seed % n_start


def first_present(enter_step: NDArray[np.int64] | None, n: int) -> int:
    """How many pedestrians are there first: everyone when nobody enters later, else
    those of the earliest entry sample (the engine keeps pedestrians in entry order, so
    they are the first ones)."""
    if enter_step is None or len(enter_step) == 0:
        return n
    return int(np.count_nonzero(enter_step == enter_step.min()))


def nudged_twins(
    scenario: Scenario,
    seed: int,
    params: SRFMParams | None = None,
    *,
    nudge_m: float = NUDGE_M,
    reference: FloatArray | None = None,
) -> NudgedTwins:
    """Simulate the crowd of episode ``seed`` twice, blind to the robot, one start
    nudged by ``nudge_m`` along +x in the second (:func:`nudged_pedestrian`).

    The episode engine runs both (the same steps, entries, routes and crowd substeps
    as a benchmark episode), the robot at rest at its start and felt by neither crowd.
    ``reference``: the crowd as set up, already simulated (an episode's
    ``counterfactual_pos`` with the same parameters, which no robot changes): then only
    the nudged copy is stepped, with the same bits.

    Raises:
        SimulationError: a scenario without pedestrians, or a nudge that is not a
            finite number > 0.
    """
    seed = check_seed(seed, SimulationError)
    if not (isinstance(nudge_m, float) and np.isfinite(nudge_m) and nudge_m > 0.0):
        raise SimulationError(f"nudge_m must be a finite number > 0, got {nudge_m!r}")
    setup = episode_setup(scenario, seed)
    engine = EpisodeEngine(setup, params, robot_felt=False, counterfactual=reference is None)
    # A pedestrian who enters later waits at its start in the crowd's arrays (outside
    # the first n_present the kernels see), so its start is moved the same way.
    who = nudged_pedestrian(seed, first_present(setup.ped_enter_step, engine.factual.n))
    engine.factual.pos[who, 0] += nudge_m
    steps = scenario.horizon_steps
    n = engine.factual.n
    if reference is not None and reference.shape != (steps + 1, n, 2):
        raise SimulationError(
            f"reference must be the crowd's {steps + 1} samples of {n} pedestrians, "
            f"got shape {list(reference.shape)}"
        )
    simulate = reference is None
    nudged = np.empty((steps + 1, n, 2))
    crowd = np.empty((steps + 1, n, 2)) if reference is None else reference
    nudged[0] = engine.factual.pos
    if simulate:
        crowd[0] = engine.counterfactual.pos
    for k in range(1, steps + 1):
        engine.advance(0.0, 0.0)
        nudged[k] = engine.factual.pos
        if simulate:
            crowd[k] = engine.counterfactual.pos
    enter = setup.ped_enter_step
    return NudgedTwins(
        scenario=scenario.name,
        seed=seed,
        nudged=who,
        nudge_m=nudge_m,
        reference_pos=crowd,
        nudged_pos=nudged,
        ped_enter_step=None if enter is None else enter.copy(),
    )
