"""run_episode checks the planner protocol before the first step."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

import srfm
from srfm.planners import Observation, PlannerContext, check_planner


class Counting:
    """A complete planner that counts its calls (to show none happen before the check)."""

    name = "counting"
    detection_range_m: float | None = None

    def __init__(self) -> None:
        self.calls = 0

    def reset(self, context: PlannerContext, rng: np.random.Generator) -> None:
        self.calls += 1

    def act(self, observation: Observation) -> np.ndarray:
        self.calls += 1
        return np.zeros(2)


class Nameless:
    detection_range_m = None

    def __init__(self) -> None:
        self.calls = 0

    def reset(self, context: PlannerContext, rng: np.random.Generator) -> None:
        self.calls += 1

    def act(self, observation: Observation) -> np.ndarray:
        self.calls += 1
        return np.zeros(2)


class NoneName(Counting):
    name = None  # type: ignore[assignment]


class NoReset:
    name = "no-reset"
    detection_range_m = None

    def act(self, observation: Observation) -> np.ndarray:
        raise AssertionError("act called before the protocol was checked")


class ActNotCallable(Counting):
    act = 1.0  # type: ignore[assignment]


class Empty:
    pass


@pytest.mark.parametrize(
    ("planner", "missing"),
    [
        (Nameless(), r"planner Nameless lacks the Planner protocol .*: no 'name' attribute"),
        (NoneName(), r"'name' must be a non-empty string, got None"),
        (NoReset(), r"planner 'no-reset' lacks the Planner protocol .*: no reset\(\) method$"),
        (ActNotCallable(), r"'act' is not callable"),
        (Empty(), r"planner Empty .*: no 'name' attribute; no reset\(\) method; no act\(\) method"),
    ],
)
def test_an_incomplete_planner_fails_before_the_first_step(planner: Any, missing: str) -> None:
    with pytest.raises(srfm.PlannerError, match=missing):
        srfm.run_episode("footpath", 0, planner=planner)
    assert getattr(planner, "calls", 0) == 0  # neither reset nor act was called
    with pytest.raises(srfm.PlannerError, match=missing):
        check_planner(planner)


def test_a_planner_without_detection_range_observes_everyone() -> None:
    class Blind:
        name = "blind"

        def reset(self, context: PlannerContext, rng: np.random.Generator) -> None:
            pass

        def act(self, observation: Observation) -> np.ndarray:
            return np.zeros(2)

    check_planner(Blind())
    record = srfm.run_episode("footpath", 0, planner=Blind())
    assert record.planner == "blind"
    assert record.outcome == "timeout"


def test_a_complete_planner_runs() -> None:
    planner = Counting()
    record = srfm.run_episode("footpath", 0, planner=planner)
    assert record.planner == "counting"
    assert planner.calls == 1 + np.count_nonzero(record.robot_active[:-1])  # reset + acts


@pytest.mark.parametrize(
    ("scenario", "planner"), [("crosswalk", "dwa"), ("narrow_doorway", "orca"), ("circle", "vo")]
)
def test_first_command_is_the_episode_s_first_command(scenario: str, planner: str) -> None:
    """first_command (the benchmark's warm-up of a planner's kernels) asks what the
    episode asks first: the same command, bit for bit (a walled scenario: the planner
    steers to the route's first waypoint in both)."""
    from srfm.sim.episode import first_command

    record = srfm.run_episode(scenario, 3, planner)
    command = first_command(srfm.load_scenario(scenario), 3, planner)
    assert np.array_equal(np.asarray(command, dtype=np.float64), record.robot_cmd[0])
