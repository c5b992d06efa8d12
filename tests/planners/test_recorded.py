"""The recorded-robot planner and the scenario of a recorded scene (issue 15, item 4)."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import attrs
import numpy as np
import pytest

import srfm
from srfm.benchmark import default_planners
from srfm.errors import PlannerError, ScenarioError
from srfm.planners import make_planner
from srfm.planners.recorded import (
    RecordedRobotPlanner,
    recorded_encounter,
    recorded_scenario_doc,
    scenario_toml,
)
from tests.datasets._synthetic import simulate_scene

TRUE = srfm.SRFMParams(tau=0.6, a_robot=4.0, b_robot=0.6)


def test_replays_the_recorded_robot_in_the_twin_episode() -> None:
    scene = simulate_scene(TRUE, 7, name="rec", robot=True, n_per_side=2)
    scenario, planner = recorded_encounter(scene)
    assert scenario.n_pedestrians == 4
    assert scenario.robot.kinematics == "holonomic"
    rec = srfm.run_episode(scenario, 0, planner)
    end = rec.end_step
    assert end > 10
    robot = rec.robot_pose[: end + 1, :2]
    wanted = np.array([planner.position_at(t) for t in rec.time_s[: end + 1]])
    np.testing.assert_allclose(robot, wanted, atol=1e-9)
    # the recorded robot drives at 0.5 m/s along y = 7 from x = 16
    assert robot[0].tolist() == pytest.approx([16.0, 7.0])
    assert np.allclose(robot[:, 1], 7.0)
    # the twins: the factual crowd feels the recorded robot, the counterfactual does not
    assert not np.array_equal(rec.factual_pos, rec.counterfactual_pos)
    # the pedestrians start where they were first observed
    first = np.array([scene.track(a)[2][0] for a in scene.agent_ids[:4]])
    np.testing.assert_allclose(rec.factual_pos[0], first)


def test_bad_input_is_refused() -> None:
    with pytest.raises(PlannerError, match="n >= 2"):
        RecordedRobotPlanner([0.0], [[0.0, 0.0]])
    with pytest.raises(PlannerError, match="finite"):
        RecordedRobotPlanner([0.0, 1.0], [[0.0, 0.0], [np.nan, 0.0]])
    with pytest.raises(PlannerError, match="increase strictly"):
        RecordedRobotPlanner([0.0, 0.0], [[0.0, 0.0], [1.0, 0.0]])
    with pytest.raises(PlannerError, match="start at 0"):
        RecordedRobotPlanner([1.0, 2.0], [[0.0, 0.0], [1.0, 0.0]])
    scene = simulate_scene(TRUE, 7, name="rec", robot=True, n_per_side=1)
    scenario, planner = recorded_encounter(scene)
    unicycle = attrs.evolve(scenario, robot=attrs.evolve(scenario.robot, kinematics="unicycle"))
    with pytest.raises(PlannerError, match="holonomic"):
        srfm.run_episode(unicycle, 0, planner)
    with pytest.raises(ScenarioError, match="no robot"):
        recorded_encounter(simulate_scene(TRUE, 7, name="x", n_per_side=1))


def test_real_recording() -> None:
    from srfm.datasets import navwareset
    from tests.datasets.conftest import data_dir

    folder = data_dir() / "navwareset"
    if not folder.is_dir():
        pytest.skip(f"{folder} not found; set SRFM_DATA_DIR to the shared data folder")
    path = sorted(folder.glob("*.csv"))[0]
    scenario, planner = recorded_encounter(navwareset.read_file(path))
    rec = srfm.run_episode(scenario, 0, planner)
    assert rec.outcome == "goal_reached"
    end = rec.end_step
    wanted = np.array([planner.position_at(t) for t in rec.time_s[: end + 1]])
    np.testing.assert_allclose(rec.robot_pose[: end + 1, :2], wanted, atol=1e-9)


def test_scenario_file_round_trip_replays_bit_for_bit(tmp_path: Path) -> None:
    """The scenario file `srfm data scenario` writes reads back to the same scenario,
    and the registered `recorded` planner on it gives the Python API's episode."""
    scene = simulate_scene(TRUE, 7, name="rec", robot=True, n_per_side=2)
    scenario, planner = recorded_encounter(scene)
    path = tmp_path / "rec.toml"
    path.write_text(scenario_toml(recorded_scenario_doc(scene)))
    loaded = srfm.load_scenario(path)
    assert loaded.schema_version == 2
    recording = loaded.robot_recording
    assert recording is not None
    assert scenario.robot_recording is not None
    assert np.array_equal(recording.times_s, scenario.robot_recording.times_s)
    assert np.array_equal(recording.xy, scenario.robot_recording.xy)
    assert np.array_equal(loaded.ped_starts, scenario.ped_starts)
    a = srfm.run_episode(scenario, 0, planner)
    b = srfm.run_episode(loaded, 0, make_planner("recorded"))
    assert a.end_step == b.end_step
    assert np.array_equal(a.robot_pose, b.robot_pose)
    assert np.array_equal(a.factual_pos, b.factual_pos)
    assert np.array_equal(a.counterfactual_pos, b.counterfactual_pos)


def test_recorded_planner_needs_a_recording() -> None:
    assert "recorded" in {p.name for p in srfm.planners.available_planners()}
    assert "recorded" not in default_planners()
    scenario = srfm.load_scenario("footpath")
    with pytest.raises(PlannerError, match=r"'footpath' has no robot recording"):
        srfm.run_episode(scenario, 0, make_planner("recorded"))


def _recording_doc() -> dict[str, Any]:
    scene = simulate_scene(TRUE, 7, name="rec", robot=True, n_per_side=1)
    return recorded_scenario_doc(scene)


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (lambda d: d.update(schema_version=1), "robot.recording: needs schema_version = 2"),
        (lambda d: d["robot"]["recording"].update(times_s=[0.0]), "times_s: must be a list"),
        (lambda d: d["robot"]["recording"]["times_s"].__setitem__(0, 0.5), r"times_s\[0\]"),
        (lambda d: d["robot"]["recording"]["times_s"].__setitem__(2, 0.0), r"times_s\[2\]"),
        (lambda d: d["robot"]["recording"]["times_s"].__setitem__(3, "x"), r"times_s\[3\]"),
        (lambda d: d["robot"]["recording"]["xy"].pop(), "needs one"),
        (lambda d: d["robot"]["recording"]["xy"].__setitem__(4, [1e6, 0.0]), "inside the world"),
        (lambda d: d["robot"]["recording"]["xy"].__setitem__(4, [math.nan, 0.0]), "finite"),
        (lambda d: d["robot"].update(start=[16.5, 7.0]), r"xy\[0\]: must be robot.start"),
        (lambda d: d["robot"]["recording"].update(extra=1), "unknown key 'robot.recording.extra'"),
    ],
)
def test_bad_recordings_are_refused(edit: Any, message: str) -> None:
    doc = _recording_doc()
    srfm.scenarios.parse_scenario(doc, "ok.toml")
    edit(doc)
    with pytest.raises(ScenarioError, match=message):
        srfm.scenarios.parse_scenario(doc, "bad.toml")


def test_scenario_toml_refuses_what_toml_cannot_hold() -> None:
    doc = _recording_doc()
    doc["simulation"]["dt_s"] = math.inf
    with pytest.raises(ScenarioError, match=r"simulation\.dt_s"):
        scenario_toml(doc)
    with pytest.raises(ScenarioError, match="not a bare TOML key"):
        scenario_toml({"a b": 1})


def test_cli_dataset_to_scenario_to_simulate_and_benchmark(tmp_path: Path) -> None:
    """`srfm data scenario` on a dataset MCAP, then `srfm simulate` and `srfm benchmark`
    with the `recorded` planner on the written file."""
    from click.testing import CliRunner

    from srfm.cli import main
    from srfm.datasets import write_mcap

    scenes = [
        simulate_scene(TRUE, 7, name="with-robot", robot=True, n_per_side=2),
        simulate_scene(TRUE, 8, name="no-robot", n_per_side=1),
    ]
    mcap = tmp_path / "d.mcap"
    write_mcap(mcap, scenes, dataset="synthetic")
    out = tmp_path / "scenes"
    runner = CliRunner()
    result = runner.invoke(main, ["data", "scenario", str(mcap), str(out)])
    assert result.exit_code == 0, result.output
    assert "skipped 1 scene(s) without a robot" in result.output
    files = sorted(out.glob("*.toml"))
    assert [f.name for f in files] == ["recorded-with-robot.toml"]
    before = files[0].read_bytes()
    again = runner.invoke(main, ["data", "scenario", str(mcap), str(out)])
    assert again.exit_code != 0
    assert "exists; pass --force" in again.output
    assert files[0].read_bytes() == before
    bad = runner.invoke(main, ["data", "scenario", str(mcap), str(out), "--scene", "nope"])
    assert bad.exit_code != 0
    assert "no scene 'nope'" in bad.output
    none = runner.invoke(
        main, ["data", "scenario", str(mcap), str(tmp_path / "x"), "--scene", "no-robot"]
    )
    assert none.exit_code != 0
    assert "has no robot to replay" in none.output
    assert not (tmp_path / "x").exists()

    sim = runner.invoke(
        main, ["simulate", "--scenario", str(files[0]), "--planner", "recorded", "--json"]
    )
    assert sim.exit_code == 0, sim.output
    summary = json.loads(sim.output)
    scenario, planner = recorded_encounter(scenes[0])
    rec = srfm.run_episode(scenario, 0, planner)
    assert summary["end_step"] == rec.end_step
    bench = runner.invoke(
        main,
        ["benchmark", "-s", str(files[0]), "-p", "recorded", "--seeds", "0", "--out",
         str(tmp_path / "b"), "-j", "1", "--no-logs", "--no-figures"],
    )  # fmt: skip
    assert bench.exit_code == 0, bench.output
    row = (tmp_path / "b" / "episodes.csv").read_text().splitlines()
    assert len(row) == 2
    assert "recorded-with-robot" in row[1]
    assert ",recorded," in row[1]
