"""The observation's range beams: what a planar range sensor sees of walls and pillars."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely

import srfm
from srfm.errors import ParameterError
from srfm.planners._observation import OBS_PEDS, PED_FEATURES, EnvConfig, beam_range, obs_size


def _reference(
    x: float, y: float, angle: float, segments: np.ndarray, circles: np.ndarray, rmax: float
) -> float:
    """The first hit along the ray, from shapely's intersections (pillars as fine polygons)."""
    ray = shapely.LineString([(x, y), (x + rmax * math.cos(angle), y + rmax * math.sin(angle))])
    shapes = [shapely.LineString([(a, b), (c, d)]) for a, b, c, d in segments]
    shapes += [shapely.Point(cx, cy).buffer(r, quad_segs=512).exterior for cx, cy, r in circles]
    best = rmax
    origin = shapely.Point(x, y)
    for shape in shapes:
        hit = ray.intersection(shape)
        if not hit.is_empty:
            best = min(best, origin.distance(hit))
    return best


def test_beam_range_matches_a_shapely_reference() -> None:
    rng = np.random.default_rng(11)
    checked = 0
    for _ in range(300):
        segments = rng.uniform(0.0, 10.0, (int(rng.integers(0, 6)), 4))
        circles = np.column_stack([rng.uniform(0.0, 10.0, (3, 2)), rng.uniform(0.2, 1.5, 3)])
        circles = circles[: int(rng.integers(0, 4))]
        x, y = rng.uniform(0.0, 10.0, 2)
        angle = rng.uniform(-math.pi, math.pi)
        got = beam_range(x, y, math.cos(angle), math.sin(angle), segments, circles, 6.0)
        want = _reference(x, y, angle, segments, circles, 6.0)
        assert got == pytest.approx(want, abs=2e-4)
        checked += got < 6.0
    assert checked > 60  # a good share of the rays hit something


def test_beam_range_edge_cases() -> None:
    wall = np.array([[2.0, -1.0, 2.0, 1.0]])
    none = np.zeros((0, 3))
    assert beam_range(0.0, 0.0, 1.0, 0.0, wall, none, 5.0) == 2.0
    assert beam_range(0.0, 0.0, -1.0, 0.0, wall, none, 5.0) == 5.0  # behind the robot
    assert beam_range(0.0, 0.0, 0.0, 1.0, wall, none, 5.0) == 5.0  # parallel
    assert beam_range(0.0, 0.0, 1.0, 0.0, wall, none, 1.5) == 1.5  # beyond the range
    pillar = np.array([[3.0, 0.0, 1.0]])
    assert beam_range(0.0, 0.0, 1.0, 0.0, np.zeros((0, 4)), pillar, 5.0) == 2.0
    assert beam_range(3.0, 0.0, 1.0, 0.0, np.zeros((0, 4)), pillar, 5.0) == 1.0  # inside


def test_env_beams_see_the_corridor_walls() -> None:
    """In narrow_hallway the robot starts between two walls: the left and right beams
    give the distance to them, the forward beam sees nothing within range."""
    from srfm.rl import SocialNavEnv

    beams = 8
    env = SocialNavEnv("narrow_hallway", EnvConfig(range_beams=beams, range_max_m=4.0))
    obs, _ = env.reset(seed=0)
    assert obs.shape == (obs_size(10, beams),)
    r = env.robot_state
    scan = obs[OBS_PEDS + PED_FEATURES * 10 :]
    walls = env.scenario.obstacles
    for j in range(beams):
        angle = r.theta + 2.0 * math.pi * j / beams
        want = _reference(r.x, r.y, angle, walls.segments, walls.circles, 4.0) / 4.0
        assert scan[j] == pytest.approx(want, abs=1e-5)
    assert scan[0] == 1.0
    assert scan[2] < 1.0  # the left wall
    assert scan[6] < 1.0  # the right wall


def test_no_walls_no_echo_and_default_layout_unchanged() -> None:
    from srfm.rl import SocialNavEnv

    env = SocialNavEnv("crosswalk", EnvConfig(range_beams=16))
    obs, _ = env.reset(seed=2)
    assert np.all(obs[-16:] == 1.0)
    plain = SocialNavEnv("crosswalk")
    base, _ = plain.reset(seed=2)
    assert base.shape == (69,)
    assert obs[:69].tobytes() == base.tobytes()


@pytest.mark.parametrize(
    ("options", "word"),
    [
        ({"range_beams": -1}, "range_beams"),
        ({"range_beams": 1.5}, "range_beams"),
        ({"range_beams": 361}, "range_beams"),
        ({"range_max_m": 0.0}, "range_max_m"),
        ({"range_max_m": float("nan")}, "range_max_m"),
    ],
)
def test_bad_beam_options_are_refused(options: dict[str, float], word: str) -> None:
    with pytest.raises(ParameterError, match=word):
        EnvConfig(**options)


def test_planner_builder_sees_pillars() -> None:
    scenario = srfm.load_scenario("crowd_navigation")
    assert scenario.obstacles.circles.shape[0] > 0
    from srfm.rl import SocialNavEnv

    env = SocialNavEnv(scenario, EnvConfig(range_beams=72, range_max_m=20.0))
    obs, _ = env.reset(seed=0)
    assert obs[-72:].min() < 1.0


def test_training_pool_runs_library_scenarios_by_seed() -> None:
    """A share of the mixed episodes runs library scenarios, chosen from the episode seed
    alone (the same seed gives the same scenario and the same observation)."""
    from srfm.rl import SocialNavEnv
    from srfm.scenarios.training import LIBRARY_HELDOUT, LIBRARY_TRAINING

    assert not set(LIBRARY_TRAINING) & set(LIBRARY_HELDOUT)
    config = EnvConfig(range_beams=16, action_repeat=4)
    env = SocialNavEnv("mixed", config, library=LIBRARY_TRAINING, library_share=0.5)
    names = []
    for seed in range(40):
        env.reset(seed=seed)
        names.append(env.layout.name)
        for _ in range(3):
            env.step(np.array([1.0, 0.0], dtype=np.float32))
    library = [n for n in names if n in LIBRARY_TRAINING]
    assert 8 <= len(library) <= 32
    assert all(n in LIBRARY_TRAINING or n.startswith("mixed/") for n in names)
    again = SocialNavEnv("mixed", config, library=LIBRARY_TRAINING, library_share=0.5)
    for seed in (3, 17, 5):
        first, _ = env.reset(seed=seed)
        second, _ = again.reset(seed=seed)
        assert env.layout.name == again.layout.name
        assert first.tobytes() == second.tobytes()


@pytest.mark.parametrize(
    ("kwargs", "word"),
    [
        ({"library": ("nowhere",), "library_share": 0.5}, "nowhere"),
        ({"library": ("frontal_approach",), "library_share": 1.5}, "library_share"),
        ({"library": (), "library_share": 0.5}, "empty"),
        ({"library": "frontal_approach", "library_share": 0.5}, "sequence"),
    ],
)
def test_bad_training_pools_are_refused(kwargs: dict[str, object], word: str) -> None:
    from srfm.rl import SocialNavEnv

    with pytest.raises(ParameterError, match=word):
        SocialNavEnv("mixed", **kwargs)  # type: ignore[arg-type]
    with pytest.raises(ParameterError, match="mixed"):
        SocialNavEnv("crosswalk", library=("frontal_approach",), library_share=0.5)
