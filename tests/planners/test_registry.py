"""The planner registry and the straight baseline."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from typing import Any

import attrs
import numpy as np
import pytest
from numpy.typing import NDArray

import srfm
from srfm.metrics import episode_metrics
from srfm.planners import (
    Observation,
    Planner,
    PlannerContext,
    StraightPlanner,
    available_planners,
    make_planner,
    register_planner,
)
from srfm.planners._registry import _REGISTRY


def test_straight_is_registered_and_fresh_each_time() -> None:
    names = [p.name for p in available_planners()]
    assert "straight" in names
    a, b = make_planner("straight"), make_planner("straight")
    assert a is not b
    assert isinstance(a, Planner)


def test_unknown_and_duplicate_names() -> None:
    with pytest.raises(srfm.PlannerError, match=r"unknown planner 'nope'; known: .*straight"):
        make_planner("nope")
    with pytest.raises(srfm.PlannerError, match="already registered"):
        register_planner("straight", StraightPlanner, "again")
    with pytest.raises(srfm.PlannerError, match="planner name must be"):
        register_planner("bad name", StraightPlanner, "spaces")


def test_register_a_user_planner() -> None:
    register_planner("test-straight-copy", StraightPlanner, "a copy for this test")
    try:
        record = srfm.run_episode("footpath", 0, planner="test-straight-copy")
        assert record.outcome == "goal_reached"
    finally:
        del _REGISTRY["test-straight-copy"]


@pytest.mark.parametrize("name", srfm.EVALUATION_SCENARIOS)
def test_straight_reaches_the_goal_at_top_speed(name: str) -> None:
    record = srfm.run_episode(name, 0, planner="straight")
    assert record.outcome == "goal_reached"
    speeds = np.linalg.norm(record.robot_vel[1 : record.end_step + 1], axis=1)
    assert np.median(speeds) == pytest.approx(0.5)
    straight_line = np.linalg.norm(record.robot_goal - record.robot_pose[0, :2])
    assert record.robot_path_length_m() < straight_line


class Mine(StraightPlanner):
    """Straight, under its own class name: ``module:attribute`` specs name it."""

    name = "mine-own-name"


@attrs.frozen
class FrozenStraight:
    """A frozen planner (slots, read-only name) that delegates to StraightPlanner."""

    inner: StraightPlanner = attrs.field(factory=StraightPlanner)
    name: str = "frozen-straight"
    detection_range_m: float | None = 0.0

    def reset(self, context: PlannerContext, rng: np.random.Generator) -> None:
        self.inner.reset(context, rng)

    def act(self, observation: Observation) -> NDArray[np.float64]:
        return self.inner.act(observation)


@pytest.fixture
def registered() -> Iterator[Callable[..., None]]:
    names: list[str] = []

    def register(name: str, factory: Callable[[], Any]) -> None:
        register_planner(name, factory, "for this test")
        names.append(name)

    yield register
    for name in names:
        del _REGISTRY[name]


def _same_episode(a: srfm.EpisodeRecord, b: srfm.EpisodeRecord) -> None:
    assert a.arrays().keys() == b.arrays().keys()
    for key, value in a.arrays().items():
        np.testing.assert_array_equal(value, b.arrays()[key], err_msg=key)
    assert (a.outcome, a.end_step, a.events) == (b.outcome, b.end_step, b.events)


def test_the_registered_name_is_the_name(registered: Callable[..., None]) -> None:
    registered("test-mine", StraightPlanner)
    planner = make_planner("test-mine")
    assert isinstance(planner, StraightPlanner)
    assert planner.name == "test-mine"
    assert StraightPlanner.name == make_planner("straight").name == "straight"
    record = srfm.run_episode("footpath", 0, planner="test-mine")
    assert record.planner == "test-mine"
    assert episode_metrics(record).planner == "test-mine"
    _same_episode(record, srfm.run_episode("footpath", 0, planner="straight"))


def test_a_planner_with_a_read_only_name_is_renamed_by_a_wrapper(
    registered: Callable[..., None],
) -> None:
    registered("test-frozen", FrozenStraight)
    planner = make_planner("test-frozen")
    assert planner.name == "test-frozen"
    assert isinstance(planner, Planner)
    assert planner.detection_range_m == 0.0
    record = srfm.run_episode("footpath", 0, planner=planner)
    assert record.planner == "test-frozen"
    _same_episode(record, srfm.run_episode("footpath", 0, planner="straight"))
    # registered under its own name, the planner itself is returned
    registered("frozen-straight", FrozenStraight)
    assert isinstance(make_planner("frozen-straight"), FrozenStraight)


def test_a_factory_must_return_a_planner(registered: Callable[..., None]) -> None:
    registered("test-none", lambda: None)
    with pytest.raises(
        srfm.PlannerError,
        match=r"planner 'test-none' \(NoneType\) lacks the Planner protocol .*: "
        r"no reset\(\) method; no act\(\) method",
    ):
        make_planner("test-none")
    registered("test-object", object)
    with pytest.raises(srfm.PlannerError, match=r"'test-object' \(object\) lacks the Planner"):
        make_planner("test-object")


def test_module_attribute_specs_are_named_by_the_spec() -> None:
    spec = "tests.planners.test_registry:Mine"
    planner = make_planner(spec)
    assert isinstance(planner, Mine)
    assert planner.name == spec
    assert Mine.name == "mine-own-name"
    record = srfm.run_episode("footpath", 0, planner=spec)
    assert record.planner == spec
    _same_episode(record, srfm.run_episode("footpath", 0, planner="straight"))
    with pytest.raises(
        srfm.PlannerError, match=r"'tests.planners.test_registry:Nope'.*no callable"
    ):
        make_planner("tests.planners.test_registry:Nope")
    with pytest.raises(
        srfm.PlannerError,
        match=r"'tests.planners.test_registry:not_a_planner' \(dict\) lacks the Planner "
        r"protocol .*: no reset\(\) method; no act\(\) method",
    ):
        make_planner("tests.planners.test_registry:not_a_planner")


def not_a_planner() -> dict[str, str]:
    return {"name": "dict"}
