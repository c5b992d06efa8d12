"""One validation for every scenario schema version: a scene that cannot start is
refused in version 1 as in version 2, naming the file and the key. Before issue 33 a
version-1 file was accepted with pedestrians overlapping each other or the robot, a
robot inside a pillar, a pedestrian on a pillar's centre, a goal outside the world, a
desired speed of 1000 m/s or a zero-length wall (version 2 accepted the last three
too); every built-in scenario still loads, to the same scenario."""

from __future__ import annotations

import tracemalloc
from pathlib import Path

import numpy as np
import pytest

import srfm.scenarios
from srfm.benchmark._results import fingerprint
from srfm.errors import ScenarioError
from srfm.scenarios import load_scenario
from tests.reliability.conftest import assert_one_line, cli

BASE = {
    "robot": "start = [2.0, 8.0]\ngoal = [12.0, 9.0]\n",
    "pedestrians": "starts = [[5.0, 5.0], [8.0, 5.0]]\ngoals = [[10.0, 5.0], [3.0, 5.0]]\n",
    "obstacles": "",
}

# (what, table, its text, the message)
BROKEN = [
    (
        "two pedestrians overlap",
        "pedestrians",
        "starts = [[5.0, 5.0], [5.2, 5.0]]\ngoals = [[10.0, 5.0], [3.0, 5.0]]\n",
        "pedestrians.starts[1]: overlaps pedestrians.starts[0] at the start",
    ),
    (
        "a pedestrian overlaps the robot",
        "pedestrians",
        "starts = [[2.1, 8.0], [8.0, 5.0]]\ngoals = [[10.0, 5.0], [3.0, 5.0]]\n",
        "pedestrians.starts[0]: overlaps robot.start at the start",
    ),
    (
        "the robot inside a pillar",
        "obstacles",
        "pillars = [[2.0, 8.0, 1.0]]\n",
        "robot.start: [2.0, 8.0] is 0 m from a wall or pillar",
    ),
    (
        "a pedestrian on a pillar's centre",
        "obstacles",
        "pillars = [[5.0, 5.0, 0.1]]\n",
        "pedestrians.starts[0]: [5.0, 5.0] is 0 m from a wall or pillar",
    ),
    (
        "a goal in a pillar",
        "obstacles",
        "pillars = [[10.0, 5.0, 0.5]]\n",
        "pedestrians.goals[0]: [10.0, 5.0] is 0 m from a wall or pillar",
    ),
    (
        "a goal outside the world",
        "pedestrians",
        "starts = [[5.0, 5.0], [8.0, 5.0]]\ngoals = [[100.0, 5.0], [3.0, 5.0]]\n",
        "pedestrians.goals[0]: [100.0, 5.0] lies outside the world",
    ),
    (
        "a start outside the world",
        "pedestrians",
        "starts = [[5.0, 5.0], [8.0, -0.5]]\ngoals = [[10.0, 5.0], [3.0, 5.0]]\n",
        "pedestrians.starts[1]: [8.0, -0.5] lies outside the world",
    ),
    (
        "a desired speed of 1000 m/s",
        "pedestrians",
        BASE["pedestrians"] + "desired_speed_mps = 1000.0\n",
        "pedestrians.desired_speed_mps: must be <= 12.5, got 1000.0",
    ),
    (
        "a top speed of 1000 m/s for one pedestrian",
        "pedestrians",
        BASE["pedestrians"] + "max_speed_mps = [1.25, 1000.0]\n",
        "pedestrians.max_speed_mps[1]: must be in [0, 12.5], got 1000.0",
    ),
    (
        "a zero-length wall",
        "obstacles",
        "walls = [[7.0, 1.0, 7.0, 1.0]]\n",
        "obstacles.walls[0]: has zero length (both ends at [7.0, 1.0])",
    ),
    (
        "a goal walled in",
        "obstacles",
        "walls = [[9.0, 4.0, 11.0, 4.0], [11.0, 4.0, 11.0, 6.0], [11.0, 6.0, 9.0, 6.0],"
        " [9.0, 6.0, 9.0, 4.0]]\n",
        "pedestrians.goals[0]: unreachable",
    ),
]


def _scenario(version: int, **tables: str) -> str:
    text = f'schema_version = {version}\nname = "scene"\ndescription = "x"\n'
    for table in ("robot", "pedestrians", "obstacles"):
        text += f"[{table}]\n{tables.get(table, BASE[table])}"
    return text


@pytest.mark.parametrize("version", [1, 2])
@pytest.mark.parametrize(("what", "table", "body", "message"), BROKEN, ids=[b[0] for b in BROKEN])
def test_a_scene_that_cannot_start_is_refused_in_every_version(
    tmp_path: Path, version: int, what: str, table: str, body: str, message: str
) -> None:
    path = tmp_path / "scene.toml"
    path.write_text(_scenario(version, **{table: body}), encoding="utf-8")
    with pytest.raises(ScenarioError) as caught:
        load_scenario(path)
    assert str(caught.value).startswith(f"{path}: ")
    assert message in str(caught.value)
    assert_one_line(cli("simulate", "--scenario", str(path)), message)


@pytest.mark.parametrize("version", [1, 2])
def test_a_scene_that_can_start_loads(tmp_path: Path, version: int) -> None:
    path = tmp_path / "scene.toml"
    path.write_text(_scenario(version, obstacles="pillars = [[7.0, 12.0, 0.5]]\n"))
    assert load_scenario(path).n_pedestrians == 2


# The content of the version-1 built-in scenarios (srfm.benchmark._results.fingerprint,
# which the benchmark's manifest records) before issue 33, when version 1 had none of
# the layout checks: each still loads, to the same scenario.
FINGERPRINTS = {
    "circle": "bc0fce9077d666b855c74ad8e729c884d6bbbb5837e4a1da4558ca85777cb81c",
    "concert": "20adabf31b528bac6073768edc2fe5ce7134211a53a8813dc8fa009738e3c9fb",
    "concert_crowd": "336e40646812dd67647a68af23191f102fd1f2bef9710b4a3e7b1ffa05a681e6",
    "cross_footpath": "9e94671ab9ac86bb1fc140501dcfe41eab07a7ca629664bb0f6c881b0fc84183",
    "crosswalk": "c34464fec90fff2dd936725018f35440d7b2f1bd19302cc934d4c4dde238135a",
    "footpath": "c13dae55a88f48897cc1d669b3dc1ee506820596d87a53fad90ade73afa06f0d",
    "random": "c83bbe5af63170b15b821aa4299309b44dcfd9f460452d279b9e6999b40a940c",
    "station_concourse": "5d64cf27e5b109ec04baf40bca5a4093aec75d69c6d1970add39772334a39d43",
}


def test_every_built_in_scenario_loads_as_before() -> None:
    files = sorted(Path(srfm.scenarios.__file__).parent.glob("*.toml"))
    assert len(files) >= 31
    for path in files:
        scenario = load_scenario(path.stem)
        assert scenario.name == path.stem
        if scenario.schema_version == 1:
            assert fingerprint(scenario) == FINGERPRINTS[path.stem], path.stem


def test_the_overlap_check_of_100000_pedestrians_measures_only_close_pairs() -> None:
    """The check measures only pairs closer than two radii (it formed every pair's
    distance: 10^10 of them, 160 GB, for 100,000 pedestrians). Checked by the memory it
    allocates (tracemalloc sees NumPy's arrays), which no machine's speed changes: a
    check of every pair needs gigabytes, this one a few megabytes."""
    from srfm.scenarios._checks import _worst_overlap

    side = 317
    xs, ys = np.meshgrid(np.arange(side) * 0.7, np.arange(side) * 0.7)
    points = np.stack([xs.ravel(), ys.ravel()], axis=1)[:100_000]
    radii = np.full(points.shape[0], 0.3)
    tracemalloc.start()
    try:
        assert _worst_overlap(points, radii) is None
        points[99_999] = points[12_345] + [0.1, 0.0]
        assert _worst_overlap(points, radii) == (12_345, 99_999, pytest.approx(-0.5))
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 64 * 2**20, peak


def test_the_overlap_check_of_a_small_scene_gives_the_k_d_trees_answer(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Up to _ALL_PAIRS discs every pair is measured (no scipy): the same pair and gap
    as the k-d tree's, ties included."""
    from srfm.scenarios import _checks

    rng = np.random.default_rng(3)
    cases = [rng.uniform(0.0, 4.0, (n, 2)) for n in (2, 5, 40, 200)]
    cases.append(np.array([[0.0, 0.0], [0.5, 0.0], [3.0, 0.0], [3.5, 0.0]]))  # a tie
    answers = []
    for points in cases:
        radii = rng.uniform(0.1, 0.3, points.shape[0]) if len(points) != 4 else np.full(4, 0.3)
        small = _checks._worst_overlap(points, radii)
        with monkeypatch.context() as patch:
            patch.setattr(_checks, "_ALL_PAIRS", 0)
            assert _checks._worst_overlap(points, radii) == small
        answers.append(small)
    assert answers[-1] == (0, 1, pytest.approx(-0.1))
    assert sum(a is not None for a in answers) >= 3
