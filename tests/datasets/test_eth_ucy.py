"""ETH/UCY adapter: frames, ids and times; dt per file; speed warning; malformed files."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

from srfm.datasets import DatasetWarning, eth_ucy, read_mcap, write_mcap
from srfm.errors import DatasetError

SMALL = (
    "0\t1.0\t1.0\t2.0\n0\t2.0\t5.0\t5.0\n10\t1.0\t1.5\t2.0\n20\t1.0\t2.0\t2.0\n20\t2.0\t5.0\t4.5\n"
)


def test_small_file_frames_ids_and_times(tmp_path: Path) -> None:
    path = tmp_path / "tiny.txt"
    path.write_text(SMALL)
    scene = eth_ucy.read_file(path, dt_s=0.4)
    assert scene.scene == "tiny"
    assert scene.agent_ids == ("1", "2")
    assert scene.kinds == ("pedestrian", "pedestrian")
    assert scene.robot_index is None
    assert scene.frame.tolist() == [0, 0, 10, 20, 20]
    # frame step 10 -> 0.4 s per step: frame 20 is at 0.8 s.
    assert scene.t_ns.tolist() == [0, 0, 400_000_000, 800_000_000, 800_000_000]
    f, t, xy = scene.track("1")
    assert (f.tolist(), t.tolist()) == ([0, 10, 20], [0, 400_000_000, 800_000_000])
    assert xy.tolist() == [[1.0, 2.0], [1.5, 2.0], [2.0, 2.0]]
    assert scene.source["frame_step"] == "10"
    assert scene.source["dt_s"] == "0.4"
    # Pedestrian 2 is absent at frame 10: its track has a gap, not an invented sample.
    assert scene.track("2")[0].tolist() == [0, 20]


def test_dt_scales_time_and_overrides_by_name(tmp_path: Path) -> None:
    (tmp_path / "a.txt").write_text(SMALL)
    (tmp_path / "b.txt").write_text(SMALL)
    a, b = eth_ucy.read_eth_ucy(tmp_path, dt_s=0.4, dt_overrides={"b.txt": 2 / 3})
    assert a.t_ns[-1] == 800_000_000
    assert b.t_ns[-1] == round(2 * 2 / 3 * 1e9)
    with pytest.raises(DatasetError, match=r"dt given for 'c\.txt'"):
        eth_ucy.read_eth_ucy(tmp_path, dt_overrides={"c.txt": 0.5})


def test_fast_walkers_warn(tmp_path: Path) -> None:
    path = tmp_path / "fast.txt"
    path.write_text("".join(f"{10 * k}\t1\t{1.2 * k}\t0.0\n" for k in range(5)))  # 3 m/s
    with pytest.warns(DatasetWarning, match=r"median pedestrian speed 3\.00 m/s"):
        eth_ucy.read_file(path, dt_s=0.4)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        scene = eth_ucy.read_file(path, dt_s=0.8)  # 1.5 m/s: no warning
    assert float(scene.source["median_speed_mps"]) == pytest.approx(1.5)


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("", r"bad\.txt: no data rows \(empty file\)"),
        ("\n\n", "no data rows"),
        ("0 1 2.0\n", r"bad\.txt:1: expected 4 columns"),
        ("0 1 2.0 3.0\n10 1 abc 3.0\n", r"bad\.txt:2: x \(column 3\) is not a number: 'abc'"),
        ("0 1 2.0 nan\n", r"bad\.txt:1: y \(column 4\) must be finite, got 'nan'"),
        ("0 1 inf 2\n", r"bad\.txt:1: x \(column 3\) must be finite"),
        (
            "10 1 2 3\n0 1 2 3\n",
            r"bad\.txt:2: frames go backwards for pedestrian 1: frame 0 after frame 10",
        ),
        (
            "0 1 2 3\n0 1 2 4\n",
            r"bad\.txt:2: pedestrian 1 appears twice in frame 0 \(also line 1\)",
        ),
        ("0.5 1 2 3\n", r"bad\.txt:1: frame \(column 1\) must be an integer"),
    ],
)
def test_malformed_files_name_file_and_line(tmp_path: Path, text: str, match: str) -> None:
    path = tmp_path / "bad.txt"
    path.write_text(text)
    with pytest.raises(DatasetError, match=match):
        eth_ucy.read_file(path)


def test_rows_by_pedestrian_read_as_rows_by_frame(tmp_path: Path) -> None:
    by_frame = tmp_path / "a.txt"
    by_frame.write_text(SMALL)
    rows = sorted((line.split("\t") for line in SMALL.splitlines()), key=lambda r: r[1])
    by_ped = tmp_path / "b.txt"
    by_ped.write_text("".join("\t".join(r) + "\n" for r in rows))
    assert by_ped.read_text() != SMALL
    a = eth_ucy.read_file(by_frame, dt_s=0.4)
    b = eth_ucy.read_file(by_ped, dt_s=0.4)
    assert np.array_equal(a.frame, b.frame)
    assert np.array_equal(a.agent, b.agent)
    assert np.array_equal(a.xy, b.xy)
    assert np.array_equal(a.t_ns, b.t_ns)


def test_real_pedestrian_major_file(real_data: Path) -> None:
    """UCY zara03 comes pedestrian by pedestrian; every row is read, in frame order."""
    path = real_data / "eth_ucy" / "crowds_zara03.txt"
    raw = np.loadtxt(path)
    assert (np.diff(raw[:, 0]) < 0).any(), "the file is expected to be pedestrian-major"
    scene = eth_ucy.read_file(path, dt_s=0.4)
    assert scene.n_samples == raw.shape[0]
    assert scene.n_agents == np.unique(raw[:, 1]).size
    assert (np.diff(scene.frame) >= 0).all()
    frame, pid, x, y = raw[500]
    f, _, xy = scene.track(str(int(pid)))
    assert xy[int(np.flatnonzero(f == int(frame))[0])].tolist() == [x, y]


def test_missing_source() -> None:
    with pytest.raises(DatasetError, match="no such file or folder"):
        eth_ucy.list_sources("/nonexistent/eth")


def test_real_files(real_data: Path, tmp_path: Path) -> None:
    folder = real_data / "eth_ucy"
    with pytest.warns(DatasetWarning, match=r"biwi_eth\.txt: median pedestrian speed 2\.4"):
        scenes = eth_ucy.read_eth_ucy(folder)
    assert [s.scene for s in scenes] == [
        "biwi_eth",
        "biwi_hotel",
        "crowds_zara03",
        "students003",
        "uni_examples",
    ]
    raw = np.loadtxt(folder / "students003.txt")
    students = scenes[3]
    assert students.n_samples == raw.shape[0]
    assert students.n_agents == np.unique(raw[:, 1]).size
    assert students.frame.min() == raw[:, 0].min()
    assert students.frame.max() == raw[:, 0].max()
    # A row reads back exactly: frame, id and position, at t = frame / 10 * 0.4 s.
    frame, pid, x, y = raw[1234]
    f, t, xy = students.track(str(int(pid)))
    k = int(np.flatnonzero(f == int(frame))[0])
    assert xy[k].tolist() == [x, y]
    assert t[k] == round(frame / 10 * 0.4 * 1e9)
    # The documented fix for biwi_eth: dt = 0.667 s gives a plausible median speed.
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        eth = eth_ucy.read_file(folder / "biwi_eth.txt", dt_s=2 / 3)
    assert 1.3 < float(eth.source["median_speed_mps"]) < 1.6
    path = tmp_path / "eth.mcap"
    write_mcap(path, [*scenes[1:], eth], dataset="eth-ucy")
    back = read_mcap(path).scenes
    assert all(a.equals(b) for a, b in zip([*scenes[1:], eth], back, strict=True))


OBSMAT = (
    "   7.8000000e+02   1.0000000e+00   8.4568443e+00   0.0000000e+00   3.5880664e+00"
    "   1.6717144e+00   0.0000000e+00   1.7629183e-01\n"
    "   7.8600000e+02   1.0000000e+00   9.1255301e+00   0.0000000e+00   3.6585832e+00"
    "   1.6628772e+00   0.0000000e+00   3.2672255e-01\n"
    "   1.1810000e+03   1.0000000e+00   9.5000000e+00   0.0000000e+00   3.7000000e+00"
    "   1.0000000e+00   0.0000000e+00   3.0000000e-01\n"
    "   1.1870000e+03   1.0000000e+00   9.9000000e+00   0.0000000e+00   3.8000000e+00"
    "   1.0000000e+00   0.0000000e+00   3.0000000e-01\n"
)


def test_obsmat_layout(tmp_path: Path) -> None:
    """Eight columns: x from column 3, y from column 5; the frame step is the most common
    gap (6), not the divisor of all gaps (the 395-frame gap would make it 1)."""
    path = tmp_path / "seq_obsmat.txt"
    path.write_text(OBSMAT)
    scene = eth_ucy.read_file(path, dt_s=0.4)
    assert scene.track("1")[2].tolist() == [
        [8.4568443, 3.5880664],
        [9.1255301, 3.6585832],
        [9.5, 3.7],
        [9.9, 3.8],
    ]
    assert scene.source["frame_step"] == "6"
    assert scene.source["layout"] == "obsmat"
    assert np.diff(scene.t_ns).tolist() == [400_000_000, round(395 / 6 * 0.4e9), 400_000_000]


@pytest.mark.parametrize(
    ("text", "match"),
    [
        (OBSMAT.replace("0.0000000e+00   3.5880664e+00", "1.0000000e+00   3.5880664e+00"),
         r"o\.txt:1: z \(column 4\) of the obsmat layout must be 0"),
        (OBSMAT.replace("1.6628772e+00", "nan"), r"o\.txt:2: vx \(column 6\) must be finite"),
        (OBSMAT + "1190 1 2.0 3.0\n", r"o\.txt:5: expected 8 columns \(obsmat"),
        ("1 2 3 4 5 6\n", r"o\.txt:1: expected 4 columns \(frame ped_id x y\) or 8"),
    ],
)  # fmt: skip
def test_malformed_obsmat(tmp_path: Path, text: str, match: str) -> None:
    path = tmp_path / "o.txt"
    path.write_text(text)
    with pytest.raises(DatasetError, match=match):
        eth_ucy.read_file(path)


def test_real_obsmat_files(real_data: Path) -> None:
    folder = real_data / "eth_ucy_obsmat"
    if not folder.is_dir():
        pytest.skip(f"{folder} not found: the original ETH/UCY annotations are not shared")
    eth = eth_ucy.read_file(folder / "seq_eth_obsmat.txt", dt_s=0.4)
    # The original annotation at 0.4 s per 6 frames: plausible walking speeds, and the
    # same pedestrians as the resampled biwi_eth.txt read at 0.6667 s per row.
    assert eth.source["frame_step"] == "6"
    assert 1.3 < float(eth.source["median_speed_mps"]) < 1.6
    assert len(eth.agent_ids) == 360
    files = [p.name for p in eth_ucy.list_sources(folder)]
    assert files == ["seq_eth_obsmat.txt", "zara02_obsmat.txt"]  # not *_H.txt, *_info.txt
    zara = eth_ucy.read_file(folder / "zara02_obsmat.txt", dt_s=0.4)
    assert len(zara.agent_ids) == 204
    assert 0.8 < float(zara.source["median_speed_mps"]) < 1.4
