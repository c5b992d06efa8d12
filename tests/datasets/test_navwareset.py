"""NavWareSet adapter: one pedestrian and the robot per file; malformed files."""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest

from srfm.datasets import DatasetWarning, navwareset, read_mcap, write_mcap
from srfm.errors import DatasetError

HEADER = "timestamp,x,y,column,robot_x,robot_y\n"
YAW_HEADER = "timestamp,x,y,column,robot_x,robot_y,robot_yaw_rad\n"
FULL_HEADER = "timestamp,robot_x,robot_y,robot_yaw_rad,x1,y1,x2\n"
QUANT = "navwareset_quant"


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
        ("100,1,2,3,4,5\n200,1,2,3,4,5\n", r"t\.csv:1: the first line is data, not a header"),
        ("timestamp,x,y,robot_x,robot_y,robot_yaw\n", r"t\.csv:1: unknown column 'robot_yaw'"),
        ("timestamp,x,y,robot_x,robot_y,x1,y1\n", r"t\.csv:1: header mixes format 1"),
        (YAW_HEADER + "100,1,2,3,4,5,abc\n", r"t\.csv:2: robot_yaw_rad is not a number: 'abc'"),
        (YAW_HEADER + "100,1,2,3,4,5,nan\n", r"t\.csv:2: robot_yaw_rad must be finite"),
        (
            YAW_HEADER + "100,1,2,3,4,5,180.0\n",
            r"t\.csv:2: robot_yaw_rad must be in .* \(degrees\?\)",
        ),
        (YAW_HEADER + "100,1,2,3,4,5,\n", r"t\.csv:2: robot_yaw_rad is not a number: ''"),
        (FULL_HEADER + "100,1,2,0.5,3,4\n", r"t\.csv:1: missing column 'y2'"),
        ("timestamp,robot_x,robot_y,x1,y1,x3,y3\n", r"t\.csv:1: column 'x3' without"),
        (FULL_HEADER.replace("robot_x,", "") + "1\n", r"t\.csv:1: missing column 'robot_x'"),
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


def test_robot_yaw_and_condition_survive_the_mcap_round_trip(tmp_path: Path) -> None:
    folder = tmp_path / "34_poses"
    folder.mkdir()
    path = folder / "track_scene34_col2_from_100_to_200.csv"
    path.write_text(
        YAW_HEADER + "100000000,3.0,1.0,2,8.0,0.5,-3.1\n200000000,3.1,1.0,2,7.9,0.5,-3.0\n"
    )
    scene = navwareset.read_file(path)
    assert scene.track_yaw("robot").tolist() == [-3.1, -3.0]
    assert np.isnan(scene.track_yaw("pedestrian:2")).all()
    src = scene.source
    assert (src["navwareset_scene"], src["format"]) == ("34", "1")
    assert navwareset.condition_of(scene) == ("frontal_approach", "hsr", False)
    write_mcap(tmp_path / "n.mcap", [scene], dataset="navwareset")
    back = read_mcap(tmp_path / "n.mcap").scenes[0]
    assert back.equals(scene)
    assert back.track_yaw("robot").tolist() == [-3.1, -3.0]
    assert navwareset.condition_of(back) == ("frontal_approach", "hsr", False)


def test_the_condition_table() -> None:
    assert navwareset.CONDITIONS[46] == ("circular_crossing", "jackal", True)
    # The README's table lists 32 scenes (its prose says 33); so does the folder.
    assert len(navwareset.CONDITIONS) == 32


def test_full_scene_format_keeps_the_robot_yaw(tmp_path: Path) -> None:
    f = tmp_path / "track_scene6_all_from_1_to_2.csv"
    f.write_text(
        FULL_HEADER.rstrip()
        + ",y2\n1000000000,5,-4,1.3,3,0.5,2,-2\n1100000000,5.1,-4,1.4,3.1,0.5,2,-2.1\n"
    )
    tr = navwareset.read_file(f)
    assert tr.track_yaw("robot").tolist() == [1.3, 1.4]
    assert np.isnan(tr.track_yaw("pedestrian:2")).all()
    assert tr.source["format"] == "2"
    assert navwareset.condition_of(tr) == ("circular_crossing", "hsr", True)


@pytest.mark.parametrize(
    ("folder", "name", "number"),
    [
        ("12_poses", "track_scene12_col1_from_1_to_2.csv", 12),
        ("x", "s_track_scene21_col2_from_1_to_2.csv", 21),
        ("13_poses", "any.csv", 13),
        ("data", "13_full_scene_robot_and_participants.csv", 13),
        ("data", "track.csv", None),
    ],
)
def test_scene_number(tmp_path: Path, folder: str, name: str, number: int | None) -> None:
    assert navwareset.scene_number(tmp_path / folder / name) == number


def test_scene_number_of_file_and_folder_must_agree(tmp_path: Path) -> None:
    folder = tmp_path / "12_poses"
    folder.mkdir()
    path = folder / "track_scene1_col1_from_1_to_2.csv"
    path.write_text(HEADER + "100,1,2,3,4,5\n")
    with pytest.raises(DatasetError, match=r"file name says scene 1 but the folder '12_poses'"):
        navwareset.read_file(path)


def test_a_scene_outside_the_table_has_no_condition(tmp_path: Path) -> None:
    path = tmp_path / "track_scene4_col1_from_1_to_2.csv"
    path.write_text(HEADER + "100,1,2,3,4,5\n")
    scene = navwareset.read_file(path)
    assert scene.source["navwareset_scene"] == "4"
    assert navwareset.condition_of(scene) is None


def test_drop_supersets_keeps_the_slices(tmp_path: Path) -> None:
    full = tmp_path / "13_full_scene.csv"
    rows = "".join(f"{t}00000000,5,-4,0,{t / 10},0.5,2,-2\n" for t in range(1, 9))
    full.write_text("timestamp,robot_x,robot_y,robot_yaw_rad,x1,y1,x2,y2\n" + rows)
    parts = []
    for lo, hi in ((1, 3), (4, 6)):
        p = tmp_path / f"track_scene13_all_from_{lo}_to_{hi}.csv"
        sub = "".join(f"{t}00000000,5,-4,0,{t / 10},0.5,2,-2\n" for t in range(lo, hi + 1))
        p.write_text("timestamp,robot_x,robot_y,robot_yaw_rad,x1,y1,x2,y2\n" + sub)
        parts.append(p)
    other = tmp_path / "track_scene12_col1_from_1_to_9.csv"
    other.write_text(HEADER + "".join(f"{t}00000000,1,2,3,4,5\n" for t in range(1, 10)))
    scenes = [navwareset.read_file(f) for f in (full, *parts, other)]
    kept, dropped = navwareset.drop_supersets(scenes)
    assert dropped == ["13_full_scene"]
    assert [s.scene for s in kept] == [p.stem for p in (*parts, other)]


def _quant(real_data: Path) -> Path:
    folder = real_data / QUANT
    if not folder.is_dir():
        pytest.skip(f"{folder} not found: the NavWareSet selection is not in the shared data")
    return folder


def test_real_quant_selection(real_data: Path) -> None:
    """All 32 scenes read, with their conditions; the robots drive at their speeds and
    head where they drive; scene 13's slices are excerpts of the full recording (the
    pedestrians exactly, the robot's pose to the last digits of its float text)."""
    folder = _quant(real_data)
    scenes, dropped = navwareset.drop_supersets(navwareset.read_navwareset(folder))
    assert dropped == ["13_full_scene_robot_and_participants"]
    numbers = {int(s.source["navwareset_scene"]) for s in scenes}
    assert numbers == set(navwareset.CONDITIONS)
    assert all(navwareset.condition_of(s) is not None for s in scenes)
    assert sum(k == "pedestrian" for s in scenes for k in s.kinds) == 803
    speeds: dict[str, list[float]] = {"hsr": [], "jackal": []}
    heading_error: list[np.ndarray] = []
    for s in scenes:
        _, t, xy = s.track("robot")
        yaw = s.track_yaw("robot")
        assert np.isfinite(yaw).all()
        v = np.diff(xy, axis=0) / np.diff(t * 1e-9)[:, None]
        speed = np.linalg.norm(v, axis=1)
        moving = speed > 0.2
        speeds[s.source["robot"]].append(float(np.median(speed[moving])))
        error = np.angle(np.exp(1j * (np.arctan2(v[:, 1], v[:, 0]) - yaw[:-1])))
        heading_error.append(np.abs(error[moving]))
    assert np.median(speeds["hsr"]) < 0.45 < 0.7 < np.median(speeds["jackal"])
    assert np.median(np.concatenate(heading_error)) < 0.1  # rad
    full = navwareset.read_file(folder / "13_full_scene_robot_and_participants.csv")
    for s in (s for s in scenes if s.source["navwareset_scene"] == "13"):
        for agent in s.agent_ids:
            _, t, xy = s.track(agent)
            _, tf, xyf = full.track(agent)
            k = np.searchsorted(tf, t)
            assert np.array_equal(tf[k], t)
            if agent == "robot":
                assert np.abs(xyf[k] - xy).max() < 1e-12
            else:
                assert np.array_equal(xyf[k], xy)
