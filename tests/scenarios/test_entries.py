"""Pedestrians entering during the run, in the schema and the per-seed set-up (issue 17):
``enter_s``, ``enter_noise_s``, group entry times and ``[[pedestrians.sources]]``."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import srfm
from srfm.scenarios import entry_times, episode_setup, load_scenario
from tests.scenarios.test_scenarios import write_scenario

HEAD = """schema_version = 2
name = "entries"
description = "x"
[simulation]
horizon_steps = 300
[world]
x_max = 20.0
y_max = 10.0
[robot]
start = [1.0, 1.0]
goal = [19.0, 1.0]
[regions]
exit = [15.0, 6.0, 19.0, 9.0]
"""
DT = 1.0 / 15.0
HORIZON_S = 300 * DT

# Two listed pedestrians (the second enters at 5 s), a group of two entering at 8 s and
# a source of six entering at 0.5 per second from 2 s, walking to the exit region.
PEDS = """[pedestrians]
noise_m = 0.0
starts = [[3.0, 5.0], [10.0, 8.0]]
goals = [[17.0, 5.0], [10.0, 2.0]]
enter_s = [0.0, 5.0]
enter_noise_s = 1.5
[[pedestrians.groups]]
start = [2.0, 8.0]
goal = [18.0, 8.0]
size = 2
enter_s = 8.0
[[pedestrians.sources]]
start = [1.0, 6.0]
goal_region = "exit"
count = 6
rate_per_s = 0.5
start_s = 2.0
headway_s = 1.5
"""


def _load(tmp_path: Path, peds: str = PEDS, head: str = HEAD) -> srfm.Scenario:
    return load_scenario(write_scenario(tmp_path / "entries.toml", head + peds))


def test_the_schema_reads_entry_times_groups_and_sources(tmp_path: Path) -> None:
    s = _load(tmp_path)
    assert s.n_pedestrians == 2 + 2 + 6
    assert s.ped_enter_s is not None
    np.testing.assert_array_equal(s.ped_enter_s, [0.0, 5.0, 8.0, 8.0, *[2.0] * 6])
    assert s.ped_enter_noise_s == 1.5
    (source,) = s.ped_sources
    assert (source.first, source.count, source.rate_per_s) == (4, 6, 0.5)
    assert (source.start_s, source.headway_s, source.window_s) == (2.0, 1.5, 12.0)
    assert source.goal_box == (15.0, 6.0, 19.0, 9.0)
    # the six members share the start: allowed, they never stand there together
    assert s.ped_starts is not None
    np.testing.assert_array_equal(s.ped_starts[4:], np.tile([1.0, 6.0], (6, 1)))


def test_a_scenario_without_entries_is_unchanged(tmp_path: Path) -> None:
    plain = PEDS.split("enter_s = [0.0, 5.0]")[0] + "\n"
    s = _load(tmp_path, plain)
    assert s.ped_enter_s is None
    setup = episode_setup(s, 3)
    assert setup.ped_enter_step is None
    assert setup.ped_order is None
    assert setup.n_present(0) == 2
    assert entry_times(s, 3) is None
    zeros = _load(tmp_path, plain + "enter_s = [0.0, 0.0]\n")
    assert zeros.ped_enter_s is None  # all there at the start: no entries


def test_entry_times_per_seed(tmp_path: Path) -> None:
    s = _load(tmp_path)
    a = entry_times(s, 7)
    assert a is not None
    np.testing.assert_array_equal(a, entry_times(s, 7))  # a function of the seed alone
    b = entry_times(s, 8)
    assert b is not None
    assert not np.array_equal(a, b)
    for seed in range(40):
        t = entry_times(s, seed)
        assert t is not None
        assert t[0] == 0.0  # there at the start: no noise
        assert 5.0 - 1.5 <= t[1] <= 5.0 + 1.5
        assert t[2] == t[3]  # a group enters together
        assert 8.0 - 1.5 <= t[2] <= 8.0 + 1.5
        src = t[4:]
        assert np.all(src >= 2.0)
        assert np.all(src <= 2.0 + 12.0)
        assert np.all(np.diff(src) >= 1.5 - 1e-9)  # the headway
        assert np.all(t[1:] >= DT)
        assert np.all(t <= HORIZON_S - DT)


def test_source_times_spread_over_the_window(tmp_path: Path) -> None:
    """Over seeds the members' times are those of uniform order statistics shifted by
    the headway: the k-th member's mean is start_s + (k + 1) / (count + 1) * span + k h."""
    s = _load(tmp_path)
    times = np.array([entry_times(s, seed)[4:] for seed in range(400)])  # type: ignore[index]
    span = 12.0 - 5 * 1.5
    expected = 2.0 + np.arange(1, 7) / 7.0 * span + 1.5 * np.arange(6)
    # the standard error of each mean is below 0.04 s over 400 seeds
    np.testing.assert_allclose(times.mean(axis=0), expected, atol=0.2)


def test_the_set_up_orders_pedestrians_by_entry(tmp_path: Path) -> None:
    s = _load(tmp_path)
    assert s.ped_starts is not None
    setup = episode_setup(s, 5)
    t = entry_times(s, 5)
    assert t is not None
    assert setup.ped_enter_step is not None
    assert setup.ped_order is not None
    assert np.all(np.diff(setup.ped_enter_step) >= 0)
    np.testing.assert_array_equal(
        setup.ped_enter_step, np.rint(t[setup.ped_order] / DT).astype(np.int64)
    )
    assert setup.ped_order[0] == 0  # the one there at the start comes first
    np.testing.assert_array_equal(setup.crowd.pos, s.ped_starts[setup.ped_order])
    assert sorted(setup.ped_order.tolist()) == list(range(10))
    assert setup.n_present(0) == 1
    assert setup.n_present(10_000) == 10
    k = int(setup.ped_enter_step[3])
    assert setup.n_present(k) >= 4
    assert setup.n_present(k - 1) <= 3
    # the source members' goals are drawn in the region, per seed
    members = [i for i, j in enumerate(setup.ped_order) if j >= 4]
    goals = setup.crowd.goal[members]
    assert np.all((goals >= [15.0, 6.0]) & (goals <= [19.0, 9.0]))
    assert len({tuple(g) for g in goals}) == 6
    again = episode_setup(s, 5)
    np.testing.assert_array_equal(again.crowd.goal, setup.crowd.goal)
    assert not np.array_equal(episode_setup(s, 6).crowd.goal[members], goals)


def test_routes_waits_and_standing_follow_the_order(tmp_path: Path) -> None:
    peds = """[pedestrians]
noise_m = 0.0
starts = [[3.0, 5.0], [10.0, 8.0]]
goals = [[17.0, 5.0], [10.0, 2.0]]
routes = [[], [[12.0, 6.0]]]
waits_s = [[], [2.0]]
enter_s = [6.0, 0.0]
standing = [[5.0, 8.0]]
"""
    s = _load(tmp_path, peds)
    setup = episode_setup(s, 0)
    assert setup.ped_order is not None
    np.testing.assert_array_equal(setup.ped_order, [1, 2, 0])
    assert setup.ped_routes is not None
    assert setup.ped_waits_s is not None
    np.testing.assert_array_equal(setup.ped_routes[0], [[12.0, 6.0]])
    np.testing.assert_array_equal(setup.ped_waits_s[0], [2.0])
    assert setup.ped_routes[2].shape == (0, 2)
    assert setup.ped_standing == (1,)
    assert s.ped_standing == (2,)


BAD = [
    ("enter_s = [0.0]", r"pedestrians\.enter_s: needs one entry time per listed pedestrian \(2\)"),
    ("enter_s = [0.0, -1.0]", r"pedestrians\.enter_s\[1\]: must be in \[0, 20\) s"),
    ("enter_s = [0.0, nan]", r"pedestrians\.enter_s\[1\]: must be in \[0, 20\) s"),
    ("enter_s = [0.0, 20.0]", r"pedestrians\.enter_s\[1\]: must be in \[0, 20\) s"),
    ('enter_s = [0.0, "5"]', r"pedestrians\.enter_s\[1\]: must be a number of seconds"),
    ("enter_noise_s = -1.0", r"pedestrians\.enter_noise_s: must be >= 0"),
]


@pytest.mark.parametrize(("line", "message"), BAD)
def test_bad_entry_times_are_named(tmp_path: Path, line: str, message: str) -> None:
    peds = """[pedestrians]
starts = [[3.0, 5.0], [10.0, 8.0]]
goals = [[17.0, 5.0], [10.0, 2.0]]
"""
    with pytest.raises(srfm.ScenarioError, match=r"entries\.toml: " + message):
        _load(tmp_path, peds + line + "\n")


SOURCE = """[pedestrians]
starts = [[3.0, 5.0]]
goals = [[17.0, 5.0]]
[[pedestrians.sources]]
start = [1.0, 6.0]
"""
BAD_SOURCES = [
    ("goal = [18.0, 6.0]\ncount = 5\n", r"sources\[0\]\.rate_per_s: is required"),
    (
        "goal = [18.0, 6.0]\ncount = 5\nrate_per_s = 0.25\n",
        r"sources\[0\]\.rate_per_s: 5 entries at 0\.25 per s from 0 s last until 20 s, "
        r"not before the horizon \(20 s\)",
    ),
    (
        "goal = [18.0, 6.0]\ncount = 5\nrate_per_s = 1.0\nheadway_s = 2.0\n",
        r"sources\[0\]\.headway_s: 5 entries 2 s apart need 8 s, more than the 5 s",
    ),
    ("goal = [18.0, 6.0]\ncount = 0\nrate_per_s = 1.0\n", r"sources\[0\]\.count: must be in"),
    ("goal = [18.0, 6.0]\nrate_per_s = 0.0\n", r"sources\[0\]\.rate_per_s: must be > 0"),
    ("goal = [18.0, 6.0]\nrate_per_s = 1.0\nstart_s = 25.0\n", r"sources\[0\]\.start_s: must"),
    ('goal_region = "nowhere"\nrate_per_s = 1.0\n', r"sources\[0\]\.goal_region: no region "),
    (
        'goal = [18.0, 6.0]\ngoal_region = "exit"\nrate_per_s = 1.0\n',
        r"sources\[0\]\.goal: give either goal or goal_region",
    ),
]


@pytest.mark.parametrize(("lines", "message"), BAD_SOURCES)
def test_bad_sources_are_named(tmp_path: Path, lines: str, message: str) -> None:
    with pytest.raises(srfm.ScenarioError, match=r"entries\.toml: pedestrians\." + message):
        _load(tmp_path, SOURCE + lines)


def test_unknown_source_keys_are_named(tmp_path: Path) -> None:
    with pytest.raises(srfm.ScenarioError, match=r"unknown key 'pedestrians\.sources\[0\]\.speed'"):
        _load(tmp_path, SOURCE + "goal = [18.0, 6.0]\nrate_per_s = 1.0\nspeed = 2.0\n")


def test_a_goal_region_by_a_wall_is_refused(tmp_path: Path) -> None:
    peds = (
        SOURCE
        + 'goal_region = "exit"\nrate_per_s = 1.0\n[obstacles]\nwalls = [[14.0, 6.1, 20.0, 6.1]]\n'
    )
    with pytest.raises(
        srfm.ScenarioError, match=r"pedestrians\.sources\[0\]\.goal_region: region 'exit' comes"
    ):
        _load(tmp_path, peds)


def test_version_1_and_random_scenarios_refuse_entries(tmp_path: Path) -> None:
    peds = "[pedestrians]\nstarts = [[3.0, 5.0]]\ngoals = [[17.0, 5.0]]\nenter_s = [1.0]\n"
    v1 = HEAD.replace("schema_version = 2", "schema_version = 1").split("[regions]")[0]
    with pytest.raises(srfm.ScenarioError, match=r"pedestrians\.enter_s: needs schema_version = 2"):
        _load(tmp_path, peds, head=v1)
    random = (
        'schema_version = 2\nname = "r"\ndescription = "x"\nkind = "random"\n'
        "[pedestrians]\nenter_noise_s = 1.0\n"
    )
    with pytest.raises(
        srfm.ScenarioError, match=r"pedestrians\.enter_noise_s: is only allowed with kind = 'fixed'"
    ):
        _load(tmp_path, "", head=random)


def test_starts_overlap_only_among_those_there_at_the_start(tmp_path: Path) -> None:
    peds = "[pedestrians]\nstarts = [[3.0, 5.0], [3.2, 5.0]]\ngoals = [[17.0, 5.0], [17.0, 4.0]]\n"
    with pytest.raises(srfm.ScenarioError, match=r"overlaps pedestrians\.starts\[0\] at the start"):
        _load(tmp_path, peds)
    s = _load(tmp_path, peds + "enter_s = [0.0, 4.0]\n")
    assert s.n_pedestrians == 2


def test_the_library_scenario_with_entries() -> None:
    s = load_scenario("corridor_flow")
    assert s.ped_enter_s is not None
    assert len(s.ped_sources) == 2
    assert all(src.goal_box is not None for src in s.ped_sources)
    setup = episode_setup(s, 0)
    assert setup.n_present(0) == 0  # everyone enters during the run
    assert setup.n_present(s.horizon_steps) == s.n_pedestrians
