"""Built-in scenarios, the TOML schema, per-seed noise and the random generator."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import srfm
from srfm.scenarios import (
    BUILTIN_SCENARIOS,
    EVALUATION_SCENARIOS,
    FLOW_SCENARIOS,
    FRANCIS_SCENARIOS,
    NAVWARESET_SCENARIOS,
    episode_setup,
    load_scenario,
    next_goal,
)
from tests.conftest import write_scenario

MINIMAL = """
schema_version = 1
name = "mine"
description = "a user scenario"

[robot]
start = [1.0, 1.0]
goal = [5.0, 1.0]

[pedestrians]
starts = [[3.0, 3.0], [4.0, 4.0]]
goals = [[3.0, 0.5], [0.5, 4.0]]
"""


def test_every_paper_builtin_loads_with_paper_defaults() -> None:
    library = (*FRANCIS_SCENARIOS, *NAVWARESET_SCENARIOS, *FLOW_SCENARIOS)
    assert (*EVALUATION_SCENARIOS, "random", *library) == BUILTIN_SCENARIOS
    for name in (*EVALUATION_SCENARIOS, "random"):
        s = load_scenario(name)
        assert s.name == name
        assert s.n_pedestrians == 10
        assert s.horizon_steps == 750
        assert s.dt_s == 1.0 / 15.0
        assert (s.world.x_min, s.world.x_max, s.world.y_min, s.world.y_max) == (0, 15, 0, 15)
        assert s.robot.max_speed_mps == 0.5
        assert s.robot.max_angular_speed_radps == math.pi
        assert s.robot.radius_m == 0.2
        assert s.ped_radius_m == 0.3
        assert s.ped_desired_speed_mps == 1.25


def test_coordinates_follow_the_design() -> None:
    footpath = load_scenario("footpath")
    assert footpath.robot_start.tolist() == [2.0, 8.0]
    assert footpath.robot_goal.tolist() == [12.0, 9.0]
    assert footpath.ped_starts[0].tolist() == [0.5, 7.4]
    assert footpath.ped_goals[9].tolist() == [3.5, 11.0]
    cross = load_scenario("cross_footpath")
    np.testing.assert_array_equal(cross.ped_starts, footpath.ped_starts)
    np.testing.assert_array_equal(cross.ped_goals, footpath.ped_goals)
    assert cross.robot_start.tolist() == [5.8, 2.5]
    crosswalk = load_scenario("crosswalk")
    assert crosswalk.ped_starts[5].tolist() == [10.5, 10.75]
    assert crosswalk.ped_goals[2].tolist() == [13.9, 0.75]
    circle = load_scenario("circle")
    for k in range(10):
        np.testing.assert_array_equal(circle.ped_goals[k], circle.ped_starts[(k + 5) % 10])
    concert = load_scenario("concert")
    np.testing.assert_array_equal(concert.ped_goals, concert.ped_starts)
    assert concert.robot_start.tolist() == [7.0, 2.0]


@pytest.mark.parametrize("name", EVALUATION_SCENARIOS)
def test_seed_noise_moves_start_and_goal_together(name: str) -> None:
    s = load_scenario(name)
    a = episode_setup(s, 7)
    offsets = a.crowd.pos - s.ped_starts
    np.testing.assert_allclose(a.crowd.goal - s.ped_goals, offsets, atol=1e-12)
    assert np.all(np.abs(offsets) <= 0.5)
    expected = np.random.default_rng(7).uniform(-0.5, 0.5, size=(10, 2))
    np.testing.assert_array_equal(offsets, (s.ped_starts + expected) - s.ped_starts)
    b = episode_setup(s, 8)
    assert not np.array_equal(a.crowd.pos, b.crowd.pos)
    np.testing.assert_array_equal(episode_setup(s, 7).crowd.pos, a.crowd.pos)
    # the robot is not perturbed and faces its goal
    np.testing.assert_array_equal(a.robot_start, s.robot_start)
    want = math.atan2(*(s.robot_goal - s.robot_start)[::-1])
    assert a.robot_heading_rad == pytest.approx(want)


def test_random_scenario_respects_its_constraints() -> None:
    s = load_scenario("random")
    spec = s.random
    assert spec is not None
    for seed in range(200):
        e = episode_setup(s, seed)
        assert math.dist(e.robot_start, e.robot_goal) >= 5.0
        d_start = np.linalg.norm(e.crowd.pos - e.robot_start, axis=1)
        assert np.all(d_start >= 2.0)
        assert np.all(np.linalg.norm(e.crowd.goal - e.crowd.pos, axis=1) >= 7.0)
        assert np.all(np.linalg.norm(e.crowd.goal - e.robot_goal, axis=1) >= 2.0)
        for p in (*e.crowd.pos, *e.crowd.goal, e.robot_start, e.robot_goal):
            assert 0.5 <= p[0] <= 14.5
            assert 0.5 <= p[1] <= 14.5
    assert not np.array_equal(episode_setup(s, 1).crowd.pos, episode_setup(s, 2).crowd.pos)


def test_regoal_draws_depend_on_seed_pedestrian_and_count_only() -> None:
    s = load_scenario("random")
    e = episode_setup(s, 3)
    prev = e.crowd.goal[4].copy()
    g1 = next_goal(e, 4, 1, prev)
    assert math.dist(g1, prev) >= 7.0
    assert math.dist(g1, e.robot_goal) >= 2.0
    np.testing.assert_array_equal(next_goal(e, 4, 1, prev), g1)
    assert not np.array_equal(next_goal(e, 4, 2, prev), g1)
    assert not np.array_equal(next_goal(e, 5, 1, prev), g1)
    with pytest.raises(srfm.ScenarioError, match="only random scenarios"):
        next_goal(episode_setup(load_scenario("footpath"), 0), 0, 1, prev)


def test_regoaling_happens_in_a_random_episode() -> None:
    record = srfm.run_episode("random", seed=0)
    arrivals = [e for e in record.events if e.kind == "ped_arrival" and e.twin == "factual"]
    assert len(arrivals) > 10  # more arrivals than pedestrians: goals were renewed
    first = arrivals[0]
    before = record.factual_goal[first.step - 1, first.agent]
    after = record.factual_goal[first.step, first.agent]
    assert math.dist(before, after) >= 7.0


def test_user_file_loads_with_defaults(tmp_path: Path) -> None:
    path = write_scenario(tmp_path / "mine.toml", MINIMAL)
    s = load_scenario(path)
    assert s.name == "mine"
    assert s.n_pedestrians == 2
    assert s.horizon_steps == 750
    assert s.robot.kinematics == "unicycle"
    assert s.noise_m == 0.5
    assert s.source == str(path)
    assert load_scenario(str(path)).name == "mine"
    record = srfm.run_episode(s, 0)
    assert record.factual_pos.shape == (751, 2, 2)


BAD_CASES = [
    ("extra = 1\n", "unknown key 'extra'"),
    ("[simulation]\nhorizon = 5\n", "unknown key 'simulation.horizon'"),
    ("[simulation]\nhorizon_steps = 0\n", r"simulation\.horizon_steps: must be in \[1,"),
    ("[simulation]\nhorizon_steps = 2.5\n", "simulation.horizon_steps: must be an integer"),
    ("[simulation]\ndt_s = nan\n", "simulation.dt_s: must be finite"),
    ("[simulation]\ndt_s = -0.1\n", r"simulation\.dt_s: must be > 0"),
    ("[simulation]\ndt_s = 1e308\n", r"simulation\.dt_s: must be <= 1, got 1e\+308"),
    ("[world]\nx_max = -1.0\n", "x_max > x_min"),
]


@pytest.mark.parametrize(("extra", "message"), BAD_CASES)
def test_schema_errors_name_file_and_key(tmp_path: Path, extra: str, message: str) -> None:
    # Top-level keys must come before the tables in TOML.
    lines = MINIMAL.strip().split("\n")
    head, tail = lines[:3], lines[3:]
    if extra.startswith("["):
        body = "\n".join(lines) + "\n" + extra
    else:
        body = "\n".join(head) + "\n" + extra + "\n".join(tail) + "\n"
    path = write_scenario(tmp_path / "bad.toml", body)
    with pytest.raises(srfm.ScenarioError, match=message) as info:
        load_scenario(path)
    assert "bad.toml" in str(info.value)
    assert isinstance(info.value, ValueError)


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        ("start = [1.0, 1.0]", 'start = [1.0, "a"]', r"robot\.start: must hold numbers"),
        ("start = [1.0, 1.0]", "start = [1.0]", r"robot\.start: must be a list of 2 numbers"),
        ("start = [1.0, 1.0]", "start = [nan, 1.0]", r"robot\.start: must be finite"),
        (
            "goals = [[3.0, 0.5], [0.5, 4.0]]",
            "goals = [[3.0, 0.5]]",
            r"pedestrians\.goals: needs one goal per start",
        ),
        (
            "goals = [[3.0, 0.5], [0.5, 4.0]]",
            "goals = [[3.0, 0.5], [0.5, 4.0]]\nradius_m = -0.3",
            r"pedestrians\.radius_m: must be >= 0",
        ),
        (
            "goals = [[3.0, 0.5], [0.5, 4.0]]",
            "goals = [[3.0, 0.5], [0.5, 4.0]]\nnoise_m = 1e308",
            r"pedestrians\.noise_m: must be <= 15, got 1e\+308",
        ),
        (
            "goals = [[3.0, 0.5], [0.5, 4.0]]",
            "goals = [[3.0, 0.5], [0.5, 4.0]]\ndesired_speed_mps = [1.0, 1e4]",
            r"pedestrians\.desired_speed_mps\[1\]: must be in \[0, 12\.5\], got 10000\.0",
        ),
        (
            "goals = [[3.0, 0.5], [0.5, 4.0]]",
            "goals = [[3.0, 0.5], [0.5, 4.0]]\nradius_m = [0.3]",
            r"pedestrians\.radius_m: needs one value per pedestrian",
        ),
        (
            "goals = [[3.0, 0.5], [0.5, 4.0]]",
            "goals = [[3.0, 0.5], [0.5, 4.0]]\nspeed = 1",
            r"unknown key 'pedestrians\.speed'",
        ),
        (
            "goal = [5.0, 1.0]",
            'goal = [5.0, 1.0]\nkinematics = "diff"',
            r"robot\.kinematics: must be one of",
        ),
        ("goal = [5.0, 1.0]", "goal = [5.0, 1.0]\nradius_m = 0", r"robot\.radius_m: must be > 0"),
        ('name = "mine"', 'name = "My Scenario"', r"name: must match"),
        (
            "schema_version = 1",
            "schema_version = 3",
            r"schema_version: must be one of 1, 2 .*got 3",
        ),
        ("start = [1.0, 1.0]", "start = [-3.0, 1.0]", r"robot\.start: must lie inside the world"),
        ("goal = [5.0, 1.0]", "goal = [5.0, 16.0]", r"robot\.goal: must lie inside the world"),
        (
            "schema_version = 1",
            "schema_version = 1.0",
            r"schema_version: must be one of 1, 2 .*got 1\.0",
        ),
        (
            "schema_version = 1",
            "schema_version = true",
            r"schema_version: must be one of 1, 2 .*got True",
        ),
        ("[robot]\nstart = [1.0, 1.0]\n", "", r"robot\.start: is required"),
    ],
)
def test_malformed_values_are_rejected(tmp_path: Path, old: str, new: str, message: str) -> None:
    assert old in MINIMAL
    path = write_scenario(tmp_path / "bad.toml", MINIMAL.replace(old, new, 1))
    with pytest.raises(srfm.ScenarioError, match=message):
        load_scenario(path)


def test_random_kind_rules(tmp_path: Path) -> None:
    body = MINIMAL.replace('description = "a user scenario"', 'description = "x"\nkind = "random"')
    with pytest.raises(srfm.ScenarioError, match=r"robot\.start: is drawn per seed"):
        load_scenario(write_scenario(tmp_path / "r.toml", body))
    no_robot = body.replace("start = [1.0, 1.0]\ngoal = [5.0, 1.0]\n", "")
    with pytest.raises(srfm.ScenarioError, match="must not be given for kind = 'random'"):
        load_scenario(write_scenario(tmp_path / "r2.toml", no_robot))
    only_noise = (
        'schema_version = 1\nname = "r"\ndescription = "x"\nkind = "random"\n'
        "[pedestrians]\nnoise_m = 0.2\n"
    )
    with pytest.raises(srfm.ScenarioError, match=r"pedestrians\.noise_m: is only allowed with"):
        load_scenario(write_scenario(tmp_path / "r3.toml", only_noise))
    lists = only_noise.replace("noise_m = 0.2", "radius_m = [0.3, 0.3]")
    with pytest.raises(srfm.ScenarioError, match=r"radius_m: lists .* need listed starts"):
        load_scenario(write_scenario(tmp_path / "r4.toml", lists))
    with pytest.raises(srfm.ScenarioError, match="only allowed with kind = 'random'"):
        load_scenario(write_scenario(tmp_path / "f.toml", MINIMAL + "\n[random]\ncount = 3\n"))
    impossible = (
        'schema_version = 1\nname = "r"\ndescription = "x"\nkind = "random"\n'
        "[random]\nped_min_start_goal_m = 100.0\n"
    )
    s = load_scenario(write_scenario(tmp_path / "imp.toml", impossible))
    with pytest.raises(srfm.ScenarioError, match="could not draw the goal of pedestrian 0"):
        episode_setup(s, 0)


def test_unknown_name_missing_file_and_bad_toml(tmp_path: Path) -> None:
    with pytest.raises(srfm.ScenarioError, match="unknown scenario 'nowhere'"):
        load_scenario("nowhere")
    with pytest.raises(srfm.ScenarioError, match="scenario file not found"):
        load_scenario(tmp_path / "missing.toml")
    broken = write_scenario(tmp_path / "broken.toml", "name = [")
    with pytest.raises(srfm.ScenarioError, match=r"broken\.toml: not valid TOML"):
        load_scenario(broken)


@pytest.mark.parametrize("seed", [-1, 1.5, "3", True, 2**32, 10**300])
def test_bad_seed(seed: object) -> None:
    with pytest.raises(srfm.ScenarioError, match="seed must be a non-negative integer"):
        episode_setup(load_scenario("footpath"), seed)  # type: ignore[arg-type]


def test_obstacles_in_a_scenario(tmp_path: Path) -> None:
    body = MINIMAL + "\n[obstacles]\nwalls = [[0.0, 6.0, 15.0, 6.0]]\npillars = [[7.0, 7.0, 0.5]]\n"
    s = load_scenario(write_scenario(tmp_path / "o.toml", body))
    assert s.obstacles.segments.tolist() == [[0.0, 6.0, 15.0, 6.0]]
    assert s.obstacles.circles.tolist() == [[7.0, 7.0, 0.5]]
    bad = MINIMAL + "\n[obstacles]\npillars = [[7.0, 7.0, -0.5]]\n"
    with pytest.raises(srfm.ScenarioError, match=r"pillars\[0\]: values must be in \[0, 1000\] m"):
        load_scenario(write_scenario(tmp_path / "b.toml", bad))
