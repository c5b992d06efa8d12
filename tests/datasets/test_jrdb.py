"""JRDB adapter on synthetic JRDB-format files (real JRDB cannot be shipped)."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from srfm.datasets import DatasetWarning, jrdb, read_mcap, write_mcap
from srfm.errors import DatasetError
from tests.datasets._synthetic import STANDING_WORLD, write_jrdb


def test_standing_pedestrian_stays_still_in_world_frame(tmp_path: Path) -> None:
    truth = write_jrdb(tmp_path)
    poses = truth["poses"]
    assert isinstance(poses, np.ndarray)
    # The fixture is only a test if the robot really moves and turns.
    assert np.linalg.norm(poses[-1, :2] - poses[0, :2]) > 3.0
    assert np.ptp(poses[:, 2]) > 1.0
    (scene,) = jrdb.read_jrdb(tmp_path, odometry=tmp_path / "odometry")
    assert scene.frame_of_reference == "world"
    _, _, standing = scene.track("pedestrian:3")
    assert np.abs(standing - np.array(STANDING_WORLD)).max() < 1e-9
    _, _, walker = scene.track("pedestrian:12")
    assert np.abs(walker - truth["walker"][10:]).max() < 1e-9  # type: ignore[index]
    _, _, robot = scene.track("robot")
    assert np.abs(robot - poses[:, :2]).max() < 1e-12


def test_yaw_pose_layout_gives_the_same_world(tmp_path: Path) -> None:
    write_jrdb(tmp_path / "q")
    write_jrdb(tmp_path / "y", pose_layout="yaw")
    (a,) = jrdb.read_jrdb(tmp_path / "q", odometry=tmp_path / "q" / "odometry")
    (b,) = jrdb.read_jrdb(tmp_path / "y", odometry=tmp_path / "y" / "odometry")
    assert np.abs(a.xy - b.xy).max() < 1e-9


def test_frames_ids_and_timestamps_round_trip_through_mcap(tmp_path: Path) -> None:
    truth = write_jrdb(tmp_path, first_frame=40)
    (scene,) = jrdb.read_jrdb(tmp_path, odometry=tmp_path / "odometry")
    path = tmp_path / "jrdb.mcap"
    write_mcap(path, [scene], dataset="jrdb")
    (back,) = read_mcap(path).scenes
    assert back.equals(scene)
    assert back.scene == truth["sequence"]
    frames, times = back.frames()
    assert frames.tolist() == truth["frames"].tolist()  # type: ignore[attr-defined]
    assert times.tolist() == truth["t_ns"].tolist()  # type: ignore[attr-defined]
    assert set(back.agent_ids) == {"robot", "pedestrian:3", "pedestrian:12"}
    # The occluded frames of pedestrian 3 stay missing; the walker starts at frame 50.
    f3 = back.track("pedestrian:3")[0]
    assert f3.size == sum(1 for k in range(90) if k % 7 != 3)
    assert back.track("pedestrian:12")[0][0] == 50
    assert back.source["odometry"] == f"{truth['sequence']}.json"


def test_robot_frame_mode_without_odometry(tmp_path: Path) -> None:
    write_jrdb(tmp_path)
    (scene,) = jrdb.read_jrdb(tmp_path)
    assert scene.frame_of_reference == "robot"
    assert np.all(scene.track("robot")[2] == 0.0)
    # In the robot's moving frame the standing pedestrian appears to move.
    standing = scene.track("pedestrian:3")[2]
    assert np.ptp(standing, axis=0).max() > 1.0
    assert scene.source["odometry"] == "none (robot frame)"


def test_single_label_file_and_missing_timestamps(tmp_path: Path) -> None:
    truth = write_jrdb(tmp_path)
    labels = truth["labels"]
    assert isinstance(labels, Path)
    (scene,) = jrdb.read_jrdb(labels, odometry=truth["odometry"])  # type: ignore[arg-type]
    assert scene.source["timestamps"] == "frames_pc.json"
    lone = tmp_path / "elsewhere" / labels.name
    lone.parent.mkdir()
    lone.write_text(labels.read_text())
    with pytest.warns(DatasetWarning, match="no timestamps file"):
        (scene,) = jrdb.read_jrdb(lone)
    assert scene.frames()[1][:3].tolist() == [0, round(1e9 / 15), round(2e9 / 15)]


def _mutate(path: Path, change: Any) -> None:
    data = json.loads(path.read_text())
    change(data)
    path.write_text(json.dumps(data))


def _label(data: dict[str, Any], frame: str = "000004.pcd", j: int = 0) -> dict[str, Any]:
    return data["labels"][frame][j]  # type: ignore[no-any-return]


@pytest.mark.parametrize(
    ("target", "change", "match"),
    [
        ("labels", lambda d: d.pop("labels"), r"missing key 'labels'"),
        ("labels", lambda d: d.update(labels={}), r"no frames under 'labels'"),
        (
            "labels",
            lambda d: _label(d)["box"].pop("cx"),
            r"labels\['000004\.pcd'\]\[0\]\.box: missing key 'cx'",
        ),
        (
            "labels",
            lambda d: _label(d)["box"].update(cy="1.5"),
            r"labels\['000004\.pcd'\]\[0\]\.box\.cy: expected a number, got '1\.5'",
        ),
        (
            "labels",
            lambda d: _label(d)["box"].update(cx=math.nan),
            r"labels\['000004\.pcd'\]\[0\]\.box\.cx: expected a finite number",
        ),
        ("labels", lambda d: _label(d).pop("label_id"), r"\[0\]: missing key 'label_id'"),
        ("labels", lambda d: d["labels"].update({"frame9.pcd": []}), r"frame name must be"),
        (
            "timestamps",
            lambda d: d["data"][20]["pointclouds"][1].update(timestamp=1.0),
            r"frames_pc\.json: timestamps go backwards: frame 20 at 1\.0+ s is not after frame 19",
        ),
        ("timestamps", lambda d: d.pop("data"), r"frames_pc\.json: missing key 'data'"),
        ("timestamps", lambda d: d["data"].pop(30), r"no timestamp for frame '000030\.pcd'"),
        ("odometry", lambda d: d["odometry"].pop("000007.pcd"), r"no robot pose for frame"),
        (
            "odometry",
            lambda d: d["odometry"]["000002.pcd"]["orientation"].pop("w"),
            r"odometry\['000002\.pcd'\]\.orientation: missing key 'w'",
        ),
    ],
)
def test_malformed_input_names_file_and_location(
    tmp_path: Path, target: str, change: Any, match: str
) -> None:
    truth = write_jrdb(tmp_path)
    _mutate(truth[target], change)  # type: ignore[arg-type]
    with pytest.raises(DatasetError, match=match):
        jrdb.read_jrdb(tmp_path, odometry=tmp_path / "odometry")


def test_invalid_and_empty_json(tmp_path: Path) -> None:
    truth = write_jrdb(tmp_path)
    labels = truth["labels"]
    assert isinstance(labels, Path)
    labels.write_text('{"labels": {\n  "000000.pcd": [,]\n}}')
    with pytest.raises(DatasetError, match=r"\.json:2:\d+: not valid JSON"):
        jrdb.read_jrdb(tmp_path)
    labels.write_text("")
    with pytest.raises(DatasetError, match="empty file"):
        jrdb.read_jrdb(tmp_path)


def test_one_odometry_file_for_many_sequences_is_an_error(tmp_path: Path) -> None:
    a = write_jrdb(tmp_path, sequence="a")
    write_jrdb(tmp_path, sequence="b")
    with pytest.raises(DatasetError, match="one odometry file given for 2 sequences"):
        jrdb.read_jrdb(tmp_path, odometry=a["odometry"])  # type: ignore[arg-type]
    # A folder of per-sequence files works, also in a train/ sub-folder.
    (tmp_path / "odometry" / "train").mkdir()
    (tmp_path / "odometry" / "b.json").rename(tmp_path / "odometry" / "train" / "b.json")
    scenes = jrdb.read_jrdb(tmp_path, odometry=tmp_path / "odometry")
    assert [s.scene for s in scenes] == ["a", "b"]
    assert all(s.frame_of_reference == "world" for s in scenes)
