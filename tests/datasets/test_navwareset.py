"""NavWareSet adapter: one pedestrian and the robot per file; malformed files."""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest

from srfm.datasets import DatasetWarning, navwareset
from srfm.errors import DatasetError

HEADER = "timestamp,x,y,column,robot_x,robot_y\n"


def test_small_file(tmp_path: Path) -> None:
    path = tmp_path / "track.csv"
    path.write_text(
        HEADER
        + "1.7308255599301187e+18,3.39,-0.46,2,8.8,-0.2\n"
        + "1730825560030145300,3.49,-0.45,2,8.7,-0.2\n"
    )
    scene = navwareset.read_file(path)
    assert scene.agent_ids == ("pedestrian:2", "robot")
    assert scene.kinds == ("pedestrian", "robot")
    assert scene.frame.tolist() == [0, 0, 1, 1]
    # A float timestamp is the float's exact integer value; an integer one stays exact.
    assert scene.t_ns.tolist() == [1730825559930118656] * 2 + [1730825560030145300] * 2
    assert scene.track("robot")[2].tolist() == [[8.8, -0.2], [8.7, -0.2]]
    assert scene.track("pedestrian:2")[2].tolist() == [[3.39, -0.46], [3.49, -0.45]]


def test_column_is_optional(tmp_path: Path) -> None:
    path = tmp_path / "t.csv"
    path.write_text("robot_y,robot_x,y,x,timestamp\n0,1,2,3,100000000\n0,1,2,3.1,200000000\n")
    scene = navwareset.read_file(path)
    assert scene.agent_ids == ("pedestrian", "robot")
    assert scene.track("pedestrian")[2].tolist() == [[3.0, 2.0], [3.1, 2.0]]


def test_wrong_time_unit_warns(tmp_path: Path) -> None:
    path = tmp_path / "t.csv"
    path.write_text(HEADER + "100,0,0,1,5,5\n200,0.1,0,1,5,5\n")  # 0.1 m per 100 ns
    with pytest.warns(DatasetWarning, match="check the timestamp unit"):
        navwareset.read_file(path)


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("", r"t\.csv: empty file"),
        (HEADER, r"t\.csv: no data rows"),
        ("timestamp,x,y,robot_x\n1,2,3,4\n", r"t\.csv:1: missing column 'robot_y'"),
        (HEADER + "100,1,2,3,x,5\n", r"t\.csv:2: robot_x is not a number: 'x'"),
        (HEADER + "100,1,NaN,3,4,5\n", r"t\.csv:2: y must be finite"),
        (HEADER + "200,1,2,3,4,5\n100,1,2,3,4,5\n", r"t\.csv:3: timestamps go backwards"),
        (HEADER + "100,1,2,3,4\n", r"t\.csv:2: expected 6 fields, got 5"),
        (HEADER + "-5,1,2,3,4,5\n", r"t\.csv:2: timestamp must be >= 0"),
    ],
)
def test_malformed_files(tmp_path: Path, text: str, match: str) -> None:
    path = tmp_path / "t.csv"
    path.write_text(text)
    with pytest.raises(DatasetError, match=match):
        navwareset.read_file(path)


def test_real_files(real_data: Path) -> None:
    folder = real_data / "navwareset"
    scenes = navwareset.read_navwareset(folder)
    files = sorted(folder.glob("*.csv"))
    assert len(scenes) == len(files) == 12
    for scene, path in zip(scenes, files, strict=True):
        with path.open() as fh:
            rows = list(csv.DictReader(fh))
        assert scene.scene == path.stem
        assert scene.n_samples == 2 * len(rows)
        # The file name carries the first and last timestamps in integer nanoseconds.
        first_ns = int(path.stem.split("_from_")[1].split("_to_")[0])
        last_ns = int(path.stem.split("_to_")[1])
        frames, times = scene.frames()
        assert (times[0], times[-1]) == (first_ns, last_ns)
        assert frames.tolist() == list(range(len(rows)))
        ped = next(a for a in scene.agent_ids if a.startswith("pedestrian:"))
        assert ped == f"pedestrian:{rows[0]['column']}"
        xy = scene.track(ped)[2]
        assert xy[-1].tolist() == [float(rows[-1]["x"]), float(rows[-1]["y"])]
        robot = scene.track("robot")[2]
        assert np.array_equal(robot[:, 0], [float(r["robot_x"]) for r in rows])
        # Genuine interaction tracks: the pedestrian passes within a metre of the robot.
        assert np.linalg.norm(xy - robot, axis=1).min() < 1.0


def test_full_scene_format_reads_every_pedestrian_and_the_robot(tmp_path: Path) -> None:
    f = tmp_path / "13_full.csv"
    f.write_text(
        "timestamp,robot_x,robot_y,robot_yaw_rad,x1,y1,x2,y2\n"
        "1000000000,5.0,-4.0,1.3,3.0,0.5,2.0,-2.0\n"
        "1100000000,5.1,-4.0,1.3,3.1,0.5,2.0,-2.1\n"
    )
    tr = navwareset.read_file(f)
    assert tuple(tr.agent_ids) == ("pedestrian:1", "pedestrian:2", "robot")
    expected = {
        "pedestrian:1": [[3.0, 0.5], [3.1, 0.5]],
        "pedestrian:2": [[2.0, -2.0], [2.0, -2.1]],
        "robot": [[5.0, -4.0], [5.1, -4.0]],
    }
    for a, name in enumerate(tr.agent_ids):
        sel = tr.agent == a
        order = np.argsort(tr.t_ns[sel])
        assert tr.xy[sel][order].tolist() == expected[name]


def test_full_scene_format_rejects_text_in_a_pedestrian_column(tmp_path: Path) -> None:
    f = tmp_path / "13_full.csv"
    f.write_text("timestamp,robot_x,robot_y,x1,y1\n1000000000,5.0,-4.0,abc,0.5\n")
    with pytest.raises(DatasetError, match=r"13_full.csv:2: x1 is not a number: 'abc'"):
        navwareset.read_file(f)


def test_full_scene_format_names_a_missing_y_column(tmp_path: Path) -> None:
    f = tmp_path / "13_full.csv"
    f.write_text("timestamp,robot_x,robot_y,x1,y1,x2\n1000000000,5.0,-4.0,1,0.5,2\n")
    with pytest.raises(DatasetError, match=r"missing column 'y2'"):
        navwareset.read_file(f)


def test_list_sources_finds_the_files_of_subfolders(tmp_path: Path) -> None:
    (tmp_path / "01_poses").mkdir()
    (tmp_path / "01_poses" / "a.csv").write_text("timestamp,x,y,robot_x,robot_y\n")
    (tmp_path / "b.csv").write_text("timestamp,x,y,robot_x,robot_y\n")
    (tmp_path / "notes.txt").write_text("not data\n")
    found = navwareset.list_sources(tmp_path)
    assert [p.relative_to(tmp_path).as_posix() for p in found] == ["01_poses/a.csv", "b.csv"]
