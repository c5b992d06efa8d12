"""One rule for physical bounds (srfm._validate.BOUNDS), applied to scenario
files, command-line options and every dataset reader; integers that must fit int64 are
checked before they are converted, so nothing overflows into a misleading message."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

import srfm
from srfm._validate import BOUNDS, physical
from srfm.datasets import eth_ucy, jrdb, navwareset
from srfm.fitting import WindowConfig
from srfm.models.state import MAX_RADIUS_M, MAX_SPEED_MPS
from srfm.scenarios import load_scenario
from tests.reliability.conftest import ETH, NAVWARE, TINY, cli


def test_the_bounds_agree_with_the_pedestrian_bounds_of_the_models() -> None:
    assert BOUNDS["radius"][1] == MAX_RADIUS_M
    assert BOUNDS["speed"][1] == MAX_SPEED_MPS


@pytest.mark.parametrize("kind", sorted(BOUNDS))
def test_physical_accepts_its_range_and_nothing_else(kind: str) -> None:
    lo, hi, _unit = BOUNDS[kind]
    assert physical(lo, "x", kind, srfm.ParameterError) == lo
    assert physical(hi, "x", kind, srfm.ParameterError) == hi
    for bad in (hi * 1.0001 + 1.0, lo - abs(lo) * 0.0001 - 1.0, 1e300, float("nan"), "1"):
        with pytest.raises(srfm.ParameterError, match=r"x must be"):
            physical(bad, "x", kind, srfm.ParameterError)
    with pytest.raises(srfm.ParameterError, match=re.escape(f"x must be in ({lo:g}")):
        physical(lo, "x", kind, srfm.ParameterError, strict=True)


@pytest.mark.parametrize(
    ("old", "new", "match"),
    [
        ("[robot]\n", "[robot]\nradius_m = 1e300\n", r"robot\.radius_m: must be <= 1000"),
        ("[robot]\n", "[robot]\nmax_speed_mps = 1e4\n", r"robot\.max_speed_mps: must be <= 1000"),
        ("start = [2.0, 8.0]", "start = [1e300, 8.0]", "world"),
        ("[simulation]\n", "[world]\nx_max = 1e300\n[simulation]\n",
         r"world\.x_max: must be <= 1e\+07"),
        ("[[1.0, 1.0], [5.0, 5.0]]", "[[1e300, 1.0], [5.0, 5.0]]", r"starts\[0\]: values must be"),
        ("goals = [[10.0, 10.0], [1.0, 9.0]]\n", "goals = [[10.0, 10.0], [1.0, 9.0]]\n"
         "[obstacles]\npillars = [[7.0, 7.0, 1e300]]\n",
         r"pillars\[0\]: values must be in \[0, 1000\]"),
        ("goals = [[10.0, 10.0], [1.0, 9.0]]\n", "goals = [[10.0, 10.0], [1.0, 9.0]]\n"
         "[obstacles]\nwalls = [[0.0, 0.0, 1e300, 0.0]]\n", r"walls\[0\]: values must be"),
        ("goals = [[10.0, 10.0], [1.0, 9.0]]\n", "goals = [[10.0, 10.0], [1.0, 9.0]]\n"
         "goal_radius_m = 1e300\n", r"goal_radius_m: must be <= 1000"),
    ],
)  # fmt: skip
def test_scenario_values_beyond_the_physical_bounds(
    tmp_path: Path, old: str, new: str, match: str
) -> None:
    assert old in TINY
    path = tmp_path / "s.toml"
    path.write_text(TINY.replace(old, new, 1), encoding="utf-8")
    with pytest.raises(srfm.ScenarioError, match=match):
        load_scenario(path)


@pytest.mark.parametrize(
    ("option", "value"),
    [("--ped-radius", "1e308"), ("--robot-radius", "1e4"), ("--horizon", "1e300"),
     ("--interaction-radius", "inf"), ("--stride", "nan")],
)  # fmt: skip
def test_window_options_beyond_the_bounds(tmp_path: Path, option: str, value: str) -> None:
    res = cli("ade", str(tmp_path / "d.mcap"), option, value)
    assert res.exit_code == 2
    assert "window option" in res.output
    assert "must be" in res.output
    with pytest.raises(srfm.ParameterError):
        WindowConfig(ped_radius_m=float(value) if option == "--ped-radius" else 0.3,
                     robot_radius_m=float(value) if option == "--robot-radius" else 0.2,
                     horizon_s=float(value) if option == "--horizon" else 4.8,
                     interaction_radius_m=float(value) if option == "--interaction-radius" else 3,
                     stride_s=float(value) if option == "--stride" else 0.4)  # fmt: skip


@pytest.mark.parametrize(
    ("text", "dt", "match"),
    [
        ("9223372036854775808 1 1.0 2.0\n", 0.4, r"frame \(column 1\) must be in"),
        ("0 99999999999999999999 1.0 2.0\n", 0.4, r"pedestrian id \(column 2\) must be in"),
        (
            "0 1 1.0 2.0\n10 1 1.1 2.0\n1000000000000000 1 1.5 2.0\n",
            0.4,
            "beyond the int64 nanosecond clock",
        ),
        ("0 1 1.0 2.0\n10 1 1.5 2.0\n", 1e300, r"dt_s must be in \(0, 86400\] s"),
        ("0 1 1e300 2.0\n", 0.4, r"x \(column 3\) must be in \[-1e\+07, 1e\+07\] m"),
    ],
)
def test_eth_ucy_numbers_that_overflow(tmp_path: Path, text: str, dt: float, match: str) -> None:
    path = tmp_path / "e.txt"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(srfm.DatasetError, match=match):
        eth_ucy.read_file(path, dt)


def test_eth_ucy_dt_option_beyond_the_bound(tmp_path: Path) -> None:
    path = tmp_path / "e.txt"
    path.write_text(ETH, encoding="utf-8")
    res = cli("data", "convert", "eth-ucy", str(path), str(tmp_path / "o.mcap"), "--dt", "1e300")
    assert res.exit_code == 2
    assert "negative" not in res.output
    assert "(0, 86400] s" in res.output


@pytest.mark.parametrize(
    ("old", "new", "match"),
    [
        ("1200000000,", "99999999999999999999,", r"timestamp \(ns\) must be in \[0, 2\^63 - 1\]"),
        ("1200000000,", "1e30,", r"timestamp \(ns\) must be in"),
        ("1.2,2.0,5.0", "1e300,2.0,5.0", r"x must be in \[-1e\+07, 1e\+07\] m"),
        ("5.0,5.2", "5.0,-1e9", r"robot_y must be in"),
    ],
)
def test_navwareset_numbers_that_overflow(tmp_path: Path, old: str, new: str, match: str) -> None:
    path = tmp_path / "n.csv"
    path.write_text(NAVWARE.replace(old, new), encoding="utf-8")
    with pytest.raises(srfm.DatasetError, match=match):
        navwareset.read_file(path)


def _jrdb(tmp_path: Path, frame: str, stamp: object, cx: float = 1.0) -> Path:
    labels = tmp_path / "labels" / "labels_3d" / "seq.json"
    labels.parent.mkdir(parents=True)
    box = {"cx": cx, "cy": 0.0}
    labels.write_text(
        json.dumps({"labels": {f"{frame}.pcd": [{"label_id": "pedestrian:1", "box": box}]}}),
        encoding="utf-8",
    )
    stamps = tmp_path / "timestamps" / "seq" / "frames_pc.json"
    stamps.parent.mkdir(parents=True)
    cloud = {"name": "upper_velodyne", "url": f"x/{frame}.pcd", "timestamp": stamp}
    stamps.write_text(json.dumps({"data": [{"pointclouds": [cloud]}]}), encoding="utf-8")
    return labels


@pytest.mark.parametrize(
    ("frame", "stamp", "cx", "match"),
    [
        ("9" * 30, 1.0, 1.0, "frame number must be in"),
        ("000001", 1e300, 1.0, r"timestamp must be in \[0, "),
        ("000001", 1.0, 1e300, r"box\.cx: must be in \[-1e\+07, 1e\+07\] m"),
    ],
)
def test_jrdb_numbers_that_overflow(
    tmp_path: Path, frame: str, stamp: float, cx: float, match: str
) -> None:
    with pytest.raises(srfm.DatasetError, match=match):
        jrdb.read_sequence(_jrdb(tmp_path, frame, stamp, cx))


@pytest.mark.parametrize(
    ("field", "value", "message"),
    [
        ("radius_m", 1e9, r"robot\.radius_m must be in \(0, 1000\] m"),
        ("radius_m", 0.0, r"robot\.radius_m must be in \(0, 1000\] m"),
        ("goal_radius_m", -1.0, r"robot\.goal_radius_m must be in"),
        ("max_speed_mps", 5e3, r"robot\.max_speed_mps must be in \(0, 1000\] m/s"),
        ("max_angular_speed_radps", 1e4, r"robot\.max_angular_speed_radps must be in"),
        ("max_accel_mps2", 1e7, r"robot\.max_accel_mps2 must be in"),
        ("max_angular_accel_radps2", float("inf"), r"robot\.max_angular_accel_radps2 must be"),
        ("max_speed_mps", "fast", r"robot\.max_speed_mps must be a number"),
    ],
)
def test_robot_config_physical_bounds(field: str, value: object, message: str) -> None:
    """RobotConfig takes its bounds from the one table (srfm._validate.BOUNDS)."""
    with pytest.raises(srfm.ParameterError, match=message):
        srfm.RobotConfig(**{field: value})


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"circles": [[7.0, 7.0, 1e300]]}, r"pillar radius must be in \[0, 1000\] m, got 1e\+300"),
        ({"circles": [[1e9, 7.0, 0.5]]}, r"pillar centres must be in \[-1e\+07, 1e\+07\] m"),
        ({"segments": [[0.0, 0.0, 1e300, 1.0]]}, r"wall coordinates must be in .* index \(0, 2\)"),
    ],
)
def test_obstacles_built_in_python_have_the_same_bounds(
    kwargs: dict[str, object], message: str
) -> None:
    """The API path (Obstacles.create) applies the bounds a scenario file gets."""
    with pytest.raises(srfm.SimulationError, match=message):
        srfm.Obstacles.create(**kwargs)
    srfm.Obstacles.create(circles=[[7.0, 7.0, 1000.0]], segments=[[-1e7, 0.0, 1e7, 0.0]])


@pytest.mark.parametrize("field", ["pos", "goal"])
def test_crowd_positions_built_in_python_have_the_coordinate_bound(field: str) -> None:
    values = {"pos": [[0.0, 0.0], [1.0, 1.0]], "goal": [[5.0, 5.0], [6.0, 6.0]]}
    values[field] = [[0.0, 0.0], [1.0, 1e300]]
    with pytest.raises(srfm.SimulationError, match=rf"{field} must be in \[-1e\+07, 1e\+07\] m"):
        srfm.CrowdState.create(**values)
    srfm.CrowdState.create(pos=[[-1e7, 1e7]], goal=[[1e7, -1e7]])
