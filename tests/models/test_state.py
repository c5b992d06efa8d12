"""Crowd state and obstacles: validation, immutability of what must not change."""

from __future__ import annotations

import attrs
import numpy as np
import pytest

import srfm


def _arrays(n: int = 3) -> dict[str, np.ndarray]:
    return {
        "pos": np.zeros((n, 2)),
        "vel": np.zeros((n, 2)),
        "goal": np.ones((n, 2)),
        "radius": np.full(n, 0.3),
        "v0": np.full(n, 1.25),
        "vmax": np.full(n, 1.25),
    }


def test_fields_cannot_be_reassigned() -> None:
    crowd = srfm.CrowdState.create(pos=[[0.0, 0.0]], goal=[[1.0, 0.0]])
    with pytest.raises(attrs.exceptions.FrozenInstanceError):
        crowd.pos = np.zeros((5, 2))  # type: ignore[misc]


@pytest.mark.parametrize(
    ("field", "value", "message"),
    [
        ("goal", np.ones((1, 2)), r"goal must have shape \(3, 2\), got \(1, 2\)"),
        ("pos", np.zeros((3, 2), dtype=np.int64), "pos must be a float64 numpy array"),
        ("vel", [[0.0, 0.0]] * 3, "vel must be a float64 numpy array"),
        ("pos", np.zeros((2, 3)).T, "pos must be C-contiguous"),
        ("vel", np.full((3, 2), np.nan), "vel must be finite, got nan"),
        (
            "radius",
            np.array([0.3, -0.1, 0.3]),
            r"radius must be in \[0, 1000\], got -0.1 for pedestrian 1",
        ),
        ("vmax", np.array([1.0, 1.0, 1e9]), r"vmax must be in \[0, 1000\], got 1000000000\.0"),
    ],
)
def test_constructor_checks_every_array(field: str, value: object, message: str) -> None:
    arrays: dict[str, object] = dict(_arrays())
    arrays[field] = value
    with pytest.raises(srfm.SimulationError, match=message):
        srfm.CrowdState(**arrays)  # type: ignore[arg-type]


def test_create_converts_and_broadcasts() -> None:
    crowd = srfm.CrowdState.create(pos=[[0, 0], [1, 1]], goal=[[2, 2], [3, 3]], radius=0.25)
    assert crowd.pos.dtype == np.float64
    assert crowd.radius.tolist() == [0.25, 0.25]
    assert crowd.vmax.tolist() == crowd.v0.tolist() == [1.25, 1.25]
    assert crowd.copy().pos is not crowd.pos


def test_obstacles_are_validated_and_read_only() -> None:
    source = np.array([[0.0, 0.0, 1.0, 0.0]])
    obs = srfm.Obstacles.create(segments=source, circles=[[1.0, 1.0, 0.5]])
    source[0, 0] = 9.0
    assert obs.segments[0, 0] == 0.0  # a private copy
    with pytest.raises(ValueError, match="read-only"):
        obs.circles[0, 2] = 3.0
    with pytest.raises(srfm.SimulationError, match=r"pillar radius must be in \[0, 1000\] m"):
        srfm.Obstacles(circles=np.array([[0.0, 0.0, -1.0]]))
    with pytest.raises(srfm.SimulationError, match=r"segments must have shape \(n, 4\)"):
        srfm.Obstacles(segments=np.zeros((2, 3)))
    assert srfm.Obstacles().empty


def test_unpickled_obstacles_stay_read_only() -> None:
    # issue 19: pickle gives writable arrays; Obstacles is rebuilt through its constructor
    import pickle

    obs = srfm.Obstacles.create(segments=[[0.0, 0.0, 1.0, 0.0]], circles=[[1.0, 1.0, 0.5]])
    copy = pickle.loads(pickle.dumps(obs))
    assert np.array_equal(copy.segments, obs.segments)
    assert np.array_equal(copy.circles, obs.circles)
    with pytest.raises(ValueError, match="read-only"):
        copy.segments[0, 0] = 3.0
    with pytest.raises(ValueError, match="read-only"):
        copy.circles[0, 2] = 3.0


def test_a_builtin_scenario_cannot_be_changed_in_place() -> None:
    scenario = srfm.load_scenario("footpath")
    before = srfm.run_episode("footpath", 0).factual_pos
    for arr in (scenario.ped_starts, scenario.ped_goals, scenario.robot_start, scenario.robot_goal):
        with pytest.raises(ValueError, match="read-only"):
            arr[0] += 1.0
    assert np.array_equal(srfm.run_episode("footpath", 0).factual_pos, before)


@pytest.mark.parametrize("b", [{"b_ped": 1e-4}, {"b_robot": 1e-4}, {"b_obs": 1e-5}])
def test_extreme_ranges_give_finite_forces_and_steps(b: dict[str, float]) -> None:
    # Deep overlaps with tiny B would overflow exp() without the kernels' cap.
    params = srfm.SRFMParams(**b)
    crowd = srfm.CrowdState.create(pos=[[0.0, 0.0], [0.1, 0.0]], goal=[[5.0, 0.0], [-5.0, 0.0]])
    robot = srfm.RobotBody(x=0.05, y=0.01)
    walls = srfm.Obstacles.create(segments=[[-1.0, 0.02, 1.0, 0.02]], circles=[[0.0, 0.0, 5.0]])
    forces = srfm.force_components(crowd, params, robot, walls)
    assert np.all(np.isfinite(forces.total))
    srfm.step_crowd(crowd, 1 / 15, params, robot, walls)
    assert np.all(np.isfinite(crowd.pos))
    assert np.all(np.linalg.norm(crowd.vel, axis=1) <= 1.25 + 1e-12)
