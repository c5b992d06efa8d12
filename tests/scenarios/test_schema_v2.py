"""Scenario schema version 2 (issue 17): routes, waits, groups, standing pedestrians,
speed noise, thick walls, doors, regions, map points, and the layout checks."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import srfm
from srfm.scenarios import episode_setup, load_scenario
from tests.scenarios.test_scenarios import write_scenario

HEAD = """schema_version = 2
name = "v2"
description = "x"
[world]
x_max = 14.0
y_max = 8.0
[robot]
start = [1.0, 1.0]
goal = [13.0, 1.0]
"""


def _load(tmp_path: Path, peds: str, extra: str = "", head: str = HEAD) -> srfm.Scenario:
    return load_scenario(write_scenario(tmp_path / "v2.toml", head + peds + extra))


def test_version_1_refuses_version_2_keys(tmp_path: Path) -> None:
    peds = "[pedestrians]\nstarts = [[2.0, 4.0]]\ngoals = [[12.0, 4.0]]\nroutes = [[[7.0, 6.0]]]\n"
    with pytest.raises(
        srfm.ScenarioError, match=r"v2\.toml: pedestrians\.routes: needs schema_version = 2"
    ):
        _load(tmp_path, peds, head=HEAD.replace("schema_version = 2", "schema_version = 1"))
    walls = (
        "[pedestrians]\nstarts = [[2.0, 4.0]]\ngoals = [[12.0, 4.0]]\n"
        "[obstacles]\ndoors = [[7.0, 3.0, 7.0, 4.0]]\n"
    )
    with pytest.raises(srfm.ScenarioError, match=r"obstacles\.doors: needs schema_version = 2"):
        _load(tmp_path, walls, head=HEAD.replace("schema_version = 2", "schema_version = 1"))


def test_routes_move_with_the_per_seed_offset(tmp_path: Path) -> None:
    s = _load(
        tmp_path,
        "[pedestrians]\nnoise_m = 0.3\nstarts = [[2.0, 4.0], [12.0, 6.0]]\n"
        "goals = [[12.0, 4.0], [2.0, 6.0]]\nroutes = [[[7.0, 6.5], [9.0, 6.5]], []]\n"
        "waits_s = [[1.0, 0.0], []]\nswitch_radius_m = 0.7\n",
    )
    assert s.ped_switch_radius_m == 0.7
    assert s.ped_routes is not None
    np.testing.assert_array_equal(s.ped_routes[0], [[7.0, 6.5], [9.0, 6.5]])
    assert s.ped_routes[1].shape == (0, 2)
    setup = episode_setup(s, 4)
    offset = setup.crowd.pos[0] - s.ped_starts[0]
    assert np.abs(offset).max() > 0.0
    assert setup.ped_routes is not None
    np.testing.assert_allclose(setup.ped_routes[0], s.ped_routes[0] + offset)


def test_a_pedestrian_walks_its_route_and_waits(tmp_path: Path) -> None:
    """Out of its straight line and through both waypoints, with a 2 s stop at the first."""
    peds = (
        "[pedestrians]\nnoise_m = 0.0\nstarts = [[2.0, 2.0]]\ngoals = [[12.0, 2.0]]\n"
        "routes = [[[5.0, 6.0], [9.0, 6.0]]]\nwaits_s = [[2.0, 0.0]]\n"
    )
    s = _load(tmp_path, peds, head=HEAD.replace("start = [1.0, 1.0]", "start = [1.0, 7.5]"))
    record = srfm.run_episode(s, 0, "straight", srfm.SRFMParams().replace(a_robot=0.0))
    path = record.counterfactual_pos[:, 0]
    for wp in ([5.0, 6.0], [9.0, 6.0]):
        assert np.hypot(*(path - wp).T).min() <= s.ped_switch_radius_m
    near = np.hypot(*(path - [5.0, 6.0]).T) <= s.ped_switch_radius_m
    assert near.sum() * s.dt_s >= 2.0
    arrivals = [e for e in record.events if e.kind == "ped_arrival" and e.twin == "counterfactual"]
    assert len(arrivals) == 1  # at the goal only, not at the waypoints
    assert np.hypot(*(path[arrivals[0].step] - [12.0, 2.0])) < 0.5
    # the record's goal is the waypoint being walked to
    assert np.any(np.all(record.counterfactual_goal[:, 0] == [5.0, 6.0], axis=1))


def test_groups_and_standing(tmp_path: Path) -> None:
    s = _load(
        tmp_path,
        "[pedestrians]\nstarts = []\ngoals = []\nstanding = [[7.0, 7.0]]\n"
        "[[pedestrians.groups]]\nstart = [3.0, 4.0]\ngoal = [11.0, 4.0]\n"
        "size = 3\nspacing_m = 1.0\n",
    )
    assert s.n_pedestrians == 4
    # side by side across the walking direction (+x), from its right to its left
    np.testing.assert_allclose(s.ped_starts[:3], [[3.0, 3.0], [3.0, 4.0], [3.0, 5.0]])
    np.testing.assert_allclose(s.ped_goals[:3], [[11.0, 3.0], [11.0, 4.0], [11.0, 5.0]])
    assert s.ped_groups == ((0, 1, 2),)
    assert s.ped_standing == (3,)
    np.testing.assert_array_equal(s.ped_starts[3], s.ped_goals[3])


def test_speed_noise_is_drawn_after_the_offsets(tmp_path: Path) -> None:
    peds = "[pedestrians]\nstarts = [[2.0, 4.0], [12.0, 6.0]]\ngoals = [[12.0, 4.0], [2.0, 6.0]]\n"
    plain = _load(tmp_path, peds)
    noisy = _load(tmp_path, peds + "speed_noise_mps = 0.2\ndesired_speed_mps = 1.0\n")
    a = episode_setup(plain, 3)
    b = episode_setup(noisy, 3)
    np.testing.assert_array_equal(a.crowd.pos, b.crowd.pos)
    rng = np.random.default_rng(3)
    rng.uniform(-0.5, 0.5, size=(2, 2))
    np.testing.assert_array_equal(b.crowd.v0, 1.0 + rng.uniform(-0.2, 0.2, size=2))
    assert np.all(a.crowd.v0 == 1.25)


def test_thick_wall_with_a_door(tmp_path: Path) -> None:
    s = _load(
        tmp_path,
        "[pedestrians]\nstarts = [[2.0, 4.0]]\ngoals = [[12.0, 4.0]]\n",
        "[obstacles]\nwalls = [[7.0, 0.0, 7.0, 8.0, 0.2], [0.0, 7.9, 3.0, 7.9]]\n"
        "doors = [[7.0, 3.4, 7.0, 4.6]]\n[regions]\nleft = [0.0, 0.0, 6.9, 8.0]\n",
    )
    seg = s.obstacles.segments
    assert seg.shape == (9, 4)  # two rectangles and one thin wall
    xs = seg[:, [0, 2]]
    ys = seg[:, [1, 3]]
    thick = np.all((xs >= 6.9 - 1e-9) & (xs <= 7.1 + 1e-9), axis=1)
    assert thick.sum() == 8
    # nothing of the wall between y = 3.4 and 4.6: the door
    assert not np.any((ys[thick].min(axis=1) < 4.6 - 1e-9) & (ys[thick].max(axis=1) > 3.4 + 1e-9))
    assert s.region("left") == (0.0, 0.0, 6.9, 8.0)
    with pytest.raises(srfm.ScenarioError, match=r"no region 'right'; regions: left"):
        s.region("right")
    # a pedestrian goes through the door to its goal
    record = srfm.run_episode(s, 0, "straight", srfm.SRFMParams().replace(a_robot=0.0))
    assert any(e.kind == "ped_arrival" and e.twin == "counterfactual" for e in record.events)


@pytest.mark.parametrize(
    ("peds", "extra", "message"),
    [
        (
            "starts = [[7.0, 3.1]]\ngoals = [[12.0, 4.0]]",
            "walls = [[7.0, 0.0, 7.0, 3.0]]",
            r"v2\.toml: pedestrians\.starts\[0\]: \[7\.0, 3\.1\] is 0\.1 m from a wall",
        ),
        (
            "starts = [[2.0, 4.0]]\ngoals = [[7.1, 6.0]]",
            "walls = [[7.0, 0.0, 7.0, 8.0]]",
            r"pedestrians\.goals\[0\]: \[7\.1, 6\.0\] is 0\.1 m from a wall",
        ),
        (
            "starts = [[2.0, 4.0]]\ngoals = [[5.0, 4.0]]\nroutes = [[[10.0, 4.0]]]",
            "walls = [[7.0, 0.0, 7.0, 8.0]]",
            r"pedestrians\.routes\[0\]\[0\]: unreachable",
        ),
        (
            "starts = [[2.0, 4.0], [2.4, 4.2]]\ngoals = [[12.0, 4.0], [12.0, 6.0]]",
            "",
            r"pedestrians\.starts\[1\]: overlaps pedestrians\.starts\[0\] at the start",
        ),
        (
            "starts = [[1.2, 1.3]]\ngoals = [[12.0, 4.0]]",
            "",
            r"pedestrians\.starts\[0\]: overlaps robot\.start",
        ),
        (
            "starts = [[2.0, 4.0]]\ngoals = [[12.0, 4.0]]",
            "doors = [[3.0, 3.0, 3.0, 4.0]]\nwalls = [[7.0, 0.0, 7.0, 8.0]]",
            r"obstacles\.doors\[0\]: lies on no wall",
        ),
        (
            "starts = [[2.0, 4.0]]\ngoals = [[12.0, 4.0]]",
            "walls = [[7.0, 0.0, 7.0, 8.0, -1.0]]",
            r"obstacles\.walls\[0\]: thickness must be >= 0 m",
        ),
        (
            "starts = [[2.0, 4.0]]\ngoals = [[12.0, 4.0]]\nwaits_s = [[1.0]]",
            "",
            r"pedestrians\.waits_s\[0\]: needs one wait per waypoint \(0\)",
        ),
        (
            'starts = [[2.0, 4.0]]\ngoals = [[12.0, 4.0]]\nroutes = [[[1.0, "a"]]]',
            "",
            r"pedestrians\.routes\[0\]\[0\]: must be \[x, y\]",
        ),
    ],
)
def test_layout_errors_name_file_and_key(
    tmp_path: Path, peds: str, extra: str, message: str
) -> None:
    obstacles = f"[obstacles]\n{extra}\n" if extra else ""
    with pytest.raises(srfm.ScenarioError, match=message):
        _load(tmp_path, f"[pedestrians]\nnoise_m = 0.0\n{peds}\n", obstacles)


def test_bad_region_is_named(tmp_path: Path) -> None:
    peds = "[pedestrians]\nstarts = [[2.0, 4.0]]\ngoals = [[12.0, 4.0]]\n"
    with pytest.raises(srfm.ScenarioError, match=r"regions\.hall: needs x_max > x_min"):
        _load(tmp_path, peds, "[regions]\nhall = [5.0, 0.0, 1.0, 3.0]\n")
    with pytest.raises(srfm.ScenarioError, match=r"regions\.hall: must lie inside the world"):
        _load(tmp_path, peds, "[regions]\nhall = [5.0, 0.0, 100.0, 3.0]\n")
