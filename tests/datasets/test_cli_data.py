"""srfm data convert|info, srfm fit and srfm ade through click's CliRunner."""

from __future__ import annotations

import json
import shutil
import tomllib
from pathlib import Path

import pytest
from click.testing import CliRunner

import srfm
from srfm.cli import main
from srfm.datasets import read_mcap, write_mcap
from tests.datasets._synthetic import simulate_scene, write_jrdb


def run(*args: str) -> tuple[int, str]:
    result = CliRunner().invoke(main, list(args))
    return result.exit_code, result.output


@pytest.mark.parametrize("cmd", [["data"], ["data", "convert"], ["data", "info"], ["fit"], ["ade"]])
def test_help(cmd: list[str]) -> None:
    code, out = run(*cmd, "--help")
    assert code == 0
    assert "Usage:" in out


def test_convert_jrdb_world_and_robot_frame(tmp_path: Path) -> None:
    write_jrdb(tmp_path / "jrdb", sequence="seq_a")
    write_jrdb(tmp_path / "jrdb", sequence="seq_b", n_frames=30)
    out = tmp_path / "jrdb.mcap"
    code, text = run(
        "data",
        "convert",
        "jrdb",
        str(tmp_path / "jrdb"),
        str(out),
        "--odometry",
        str(tmp_path / "jrdb" / "odometry"),
    )
    assert code == 0, text
    assert "reading 2 jrdb file(s)" not in text  # no progress bar off a terminal
    assert f"wrote {out}: 2 scene(s)" in text
    scenes = read_mcap(out).scenes
    assert [s.scene for s in scenes] == ["seq_a", "seq_b"]
    assert all(s.frame_of_reference == "world" for s in scenes)
    code, text = run("data", "convert", "jrdb", str(tmp_path / "jrdb"), str(tmp_path / "r.mcap"))
    assert code == 0, text
    assert "robot's moving frame" in text
    code, text = run("fit", str(tmp_path / "r.mcap"), "-o", str(tmp_path / "p.toml"))
    assert code == 2
    assert "robot's moving frame" in text
    assert not (tmp_path / "p.toml").exists()


def test_malformed_input_leaves_no_output(tmp_path: Path) -> None:
    truth = write_jrdb(tmp_path / "jrdb")
    labels = truth["labels"]
    assert isinstance(labels, Path)
    labels.write_text(labels.read_text().replace('"cy": ', '"cy": "oops", "_": ', 1))
    out = tmp_path / "out.mcap"
    code, text = run("data", "convert", "jrdb", str(tmp_path / "jrdb"), str(out))
    assert code == 2
    assert "Error:" in text
    assert ".box.cy: expected a number, got 'oops'" in text
    assert str(labels) in text
    assert not out.exists()
    assert not any(p.name.startswith(".out.mcap") for p in tmp_path.iterdir())


def test_convert_eth_ucy_dt_options(tmp_path: Path) -> None:
    src = tmp_path / "eth"
    src.mkdir()
    rows = "".join(f"{10 * k}\t1\t{1.2 * k}\t0.0\n" for k in range(5))  # 1.2 m per step
    (src / "fast.txt").write_text(rows)
    (src / "slow.txt").write_text(rows)
    out = tmp_path / "eth.mcap"
    code, text = run("data", "convert", "eth-ucy", str(src), str(out))
    assert code == 0, text
    assert "warning:" in text
    assert "3.00 m/s is implausible" in text
    code, text = run(
        "data", "convert", "eth-ucy", str(src), str(out), "--dt", "0.8", "--dt", "slow.txt=1.2"
    )
    assert code == 0, text
    assert "warning" not in text
    fast, slow = read_mcap(out).scenes
    assert fast.t_ns[-1] == 4 * 800_000_000
    assert slow.t_ns[-1] == 4 * 1_200_000_000
    for bad, match in [
        ("x=abc", "--dt expects SECONDS or FILE=SECONDS"),
        ("-1", "--dt must be in (0, 86400] s"),
        ("1e300", "--dt must be in (0, 86400] s"),
        ("other.txt=0.4", "dt given for 'other.txt'"),
    ]:
        code, text = run("data", "convert", "eth-ucy", str(src), str(out), "--dt", bad)
        assert code == 2
        assert match in text
    code, text = run("data", "convert", "navwareset", str(src), str(out), "--dt", "0.4")
    assert code == 2
    assert "--dt applies to eth-ucy only" in text


def test_info_text_and_json(tmp_path: Path) -> None:
    path = tmp_path / "s.mcap"
    scenes = [simulate_scene(srfm.SRFMParams(), 1, name="synthetic_a", robot=True)]
    write_mcap(path, scenes, dataset="synthetic")
    code, text = run("data", "info", str(path))
    assert code == 0, text
    assert "synthetic dataset, 1 scene(s), schema srfm.datasets.AgentFrame.v1" in text
    assert "synthetic_a" in text
    assert "world" in text
    assert "yes" in text
    code, text = run("data", "info", str(path), "--json")
    assert code == 0
    info = json.loads(text)
    (scene,) = info["scenes"]
    assert scene["pedestrians"] == 10
    assert scene["robot"] is True
    assert scene["median_dt_s"] == pytest.approx(1 / 15, abs=1e-9)
    code, text = run("data", "info", str(tmp_path / "missing.mcap"))
    assert code == 2
    assert "file not found" in text


def test_fit_then_ade_then_simulate(tmp_path: Path) -> None:
    true = srfm.SRFMParams(a_ped=2.0, b_ped=0.5, lambda_ped=0.4, tau=0.6, a_robot=6.0, b_robot=0.8)
    data = tmp_path / "synthetic.mcap"
    scenes = [simulate_scene(true, 3, name="peds")]
    scenes.append(simulate_scene(true, 4, name="robot", robot=True))
    write_mcap(data, scenes, dataset="synthetic")
    params = tmp_path / "fitted.toml"
    code, text = run("fit", str(data), "-o", str(params), "--stride", "2.4", "--max-nfev", "30")
    assert code == 0, text
    assert f"wrote {params}" in text
    assert "pedestrian" in text
    assert "robot" in text
    fitted = srfm.load_params(params)
    assert fitted != srfm.SRFMParams()
    meta = tomllib.loads(params.read_text())["meta"]
    assert meta["pedestrian_windows"] > 0
    assert meta["robot_windows"] > 0
    assert meta["horizon_s"] == 4.8
    assert meta["stride_s"] == 2.4
    assert meta["robot_ade_m"] > 0
    code, text = run("ade", str(data), "--params", str(params), "--stride", "2.4", "--json")
    assert code == 0, text
    rows = json.loads(text)["rows"]
    assert [r["model"] for r in rows][-1] == "SRFM"
    assert all(r["ade_m"] > 0 for r in rows)
    code, text = run("ade", str(data), "--stride", "2.4")
    assert code == 0, text
    assert "paper ADE (JRDB)" in text
    assert "0.59 m" in text
    code, text = run("simulate", "--scenario", "crosswalk", "--params", str(params))
    assert code == 0, text
    # One stage only; a stage without windows is an error when it is all there is.
    code, text = run(
        "fit",
        str(data),
        "-o",
        str(tmp_path / "r.toml"),
        "--stage",
        "robot",
        "--stride",
        "2.4",
        "--max-nfev",
        "5",
        "--json",
    )
    assert code == 0, text
    (stage,) = json.loads(text)["stages"]
    assert stage["stage"] == "robot"
    write_mcap(tmp_path / "peds.mcap", scenes[:1], dataset="synthetic")
    code, text = run(
        "fit", str(tmp_path / "peds.mcap"), "-o", str(tmp_path / "x.toml"), "--stage", "robot"
    )
    assert code == 2
    assert "nothing to fit" in text
    assert "no interaction windows" in text
    code, text = run("fit", str(data), "-o", str(tmp_path / "x.toml"), "--horizon", "-1")
    assert code == 2
    assert "horizon_s must be in (0, 86400] s" in text
    code, text = run("ade", str(data), "--horizon", "60")
    assert code == 2
    assert "no prediction windows" in text


def test_convert_real_data(real_data: Path, tmp_path: Path) -> None:
    out = tmp_path / "nav.mcap"
    code, text = run("data", "convert", "navwareset", str(real_data / "navwareset"), str(out))
    assert code == 0, text
    assert "12 scene(s)" in text
    code, text = run("data", "info", str(out))
    assert code == 0
    assert text.count("yes") == 12
    src = tmp_path / "eth"
    shutil.copytree(real_data / "eth_ucy", src)
    code, text = run(
        "data",
        "convert",
        "eth-ucy",
        str(src),
        str(tmp_path / "eth.mcap"),
        "--dt",
        "biwi_eth.txt=0.6667",
    )
    assert code == 0, text
    assert "warning" not in text
    assert len(read_mcap(tmp_path / "eth.mcap").scenes) == 5


def test_fit_robot_stage_with_lambda_robot_and_walking_starts(tmp_path: Path) -> None:
    true = srfm.SRFMParams(tau=0.6, a_robot=4.0, b_robot=0.6, lambda_robot=0.4)
    data = tmp_path / "robot.mcap"
    write_mcap(
        data, [simulate_scene(true, 5, name="r", robot=True, n_per_side=2)], dataset="synthetic"
    )
    out = tmp_path / "fitted.toml"
    args = ("fit", str(data), "-o", str(out), "--stage", "robot", "--stride", "2.4")
    code, text = run(*args, "--max-nfev", "20", "--fit-lambda-robot", "--min-start-speed", "0.5")
    assert code == 0, text
    assert "lambda_robot" in text
    fitted = srfm.load_params(out)
    assert fitted.lambda_robot != srfm.SRFMParams().lambda_robot  # fitted, not kept
    meta = tomllib.loads(out.read_text())["meta"]
    assert meta["min_start_speed_mps"] == 0.5
    assert meta["fit_lambda_robot"] is True
    # Without the flag λ_r keeps the start value.
    code, text = run(*args, "--max-nfev", "5")
    assert code == 0, text
    assert srfm.load_params(out).lambda_robot == srfm.SRFMParams().lambda_robot
    code, text = run(*args, "--min-start-speed", "-1")
    assert code != 0
    assert "min_start_speed_mps" in text


def test_fit_and_ade_on_encounter_windows_reproduce_the_python_protocol(
    real_data: Path, tmp_path: Path
) -> None:
    """--align/--lead/--goal/--goal-distance build the windows of issue 28's part 4 on
    the real NavWareSet excerpt: srfm fit gives what fit_params gives on the same
    windows, records the options in [meta], and srfm ade evaluates on them."""
    from srfm.datasets.navwareset import read_navwareset
    from srfm.fitting import WindowConfig, build_windows, fit_params

    data = tmp_path / "nav.mcap"
    code, text = run("data", "convert", "navwareset", str(real_data / "navwareset"), str(data))
    assert code == 0, text
    out = tmp_path / "robot.toml"
    options = ("--align", "encounter", "--lead", "2.5", "--goal", "heading")
    options += ("--goal-distance", "8", "--min-start-speed", "0.3")
    code, text = run(
        "fit", str(data), "-o", str(out), "--stage", "robot", "--max-nfev", "15", *options
    )
    assert code == 0, text
    config = WindowConfig(
        align="encounter", lead_s=2.5, goal="heading", goal_distance_m=8.0, min_start_speed_mps=0.3
    )
    windows = build_windows(read_navwareset(real_data / "navwareset"), config)
    assert 0 < windows.n_windows <= 12  # at most one window per recording
    expected = fit_params(windows, stages=("robot",), max_nfev=15).params
    fitted = srfm.load_params(out)
    assert fitted.a_robot == pytest.approx(expected.a_robot, rel=1e-6)
    assert fitted.b_robot == pytest.approx(expected.b_robot, rel=1e-6)
    meta = tomllib.loads(out.read_text())["meta"]
    assert (meta["align"], meta["lead_s"], meta["goal"], meta["goal_distance_m"]) == (
        "encounter",
        2.5,
        "heading",
        8.0,
    )
    assert meta["robot_windows"] == windows.n_windows
    code, text = run("ade", str(data), "--params", str(out), "--json", *options)
    assert code == 0, text
    rows = {(r["model"], r["tracks"]): r for r in json.loads(text)["rows"]}
    assert rows[("SRFM", "interaction")]["windows"] == windows.n_windows
    assert rows[("SFM", "non-interaction")]["windows"] == 0  # every window is an encounter
    # A lead as long as the horizon is refused, naming the option.
    code, text = run("ade", str(data), "--align", "encounter", "--lead", "4.8")
    assert code == 2
    assert "lead_s (4.8 s) must be shorter than horizon_s" in text
    code, text = run("ade", str(data), "--align", "sideways")
    assert code == 2
    assert "sideways" in text


def test_fit_robot_force_form_on_real_encounters(real_data: Path, tmp_path: Path) -> None:
    """srfm fit --robot-force FORM fits that form's own parameters (FORM_FIT_FIELDS) on
    the real NavWareSet excerpt, as fit_params does, and writes a file that runs."""
    from srfm.datasets.navwareset import read_navwareset
    from srfm.fitting import WindowConfig, build_windows, fit_params

    data = tmp_path / "nav.mcap"
    code, text = run("data", "convert", "navwareset", str(real_data / "navwareset"), str(data))
    assert code == 0, text
    out = tmp_path / "ttc.toml"
    options = ("--align", "encounter", "--goal", "heading", "--min-start-speed", "0.3")
    code, text = run(
        "fit", str(data), "-o", str(out), "--stage", "robot", "--robot-force", "ttc",
        "--max-nfev", "10", *options,
    )  # fmt: skip
    assert code == 0, text
    fitted = srfm.load_params(out)
    assert fitted.robot_form == "ttc"
    default = srfm.SRFMParams()
    assert fitted.ttc_k != default.ttc_k  # fitted, not kept
    assert (fitted.a_robot, fitted.b_robot) == (default.a_robot, default.b_robot)
    windows = build_windows(
        read_navwareset(real_data / "navwareset"),
        WindowConfig(align="encounter", goal="heading", min_start_speed_mps=0.3),
    )
    expected = fit_params(
        windows,
        start=default.replace(robot_form="ttc"),
        stages=("robot",),
        fields={"robot": ("ttc_k", "ttc_tau0")},
        max_nfev=10,
    ).params
    assert fitted.ttc_k == pytest.approx(expected.ttc_k, rel=1e-6)
    assert fitted.ttc_tau0 == pytest.approx(expected.ttc_tau0, rel=1e-6)
    meta = tomllib.loads(out.read_text())["meta"]
    assert meta["robot_force"] == "ttc"
    code, text = run("ade", str(data), "--params", str(out), *options)
    assert code == 0, text
    assert "SRFM" in text
    # The form's λ_r does not exist for ttc.
    code, text = run(
        "fit", str(data), "-o", str(out), "--stage", "robot", "--robot-force", "ttc",
        "--fit-lambda-robot",
    )  # fmt: skip
    assert code == 2
    assert "the ttc robot force has no λ_r" in text
    code, text = run("fit", str(data), "-o", str(out), "--robot-force", "spring")
    assert code == 2
    assert "spring" in text


def test_fit_the_sidestep_form_on_real_encounters(real_data: Path, tmp_path: Path) -> None:
    """srfm fit --robot-force sidestep fits A, d_on, T and γ (issue 40)."""
    data = tmp_path / "nav.mcap"
    code, text = run("data", "convert", "navwareset", str(real_data / "navwareset"), str(data))
    assert code == 0, text
    out = tmp_path / "sidestep.toml"
    code, text = run(
        "fit", str(data), "-o", str(out), "--stage", "robot", "--robot-force", "sidestep",
        "--max-nfev", "5", "--align", "encounter", "--goal", "heading",
        "--min-start-speed", "0.3",
    )  # fmt: skip
    assert code == 0, text
    fitted = srfm.load_params(out)
    assert fitted.robot_form == "sidestep"
    default = srfm.SRFMParams()
    fields = ("ss_a", "ss_miss", "ss_horizon", "ss_speed_gain")
    assert any(getattr(fitted, f) != getattr(default, f) for f in fields)
    assert fitted.robot_force_cap == default.robot_force_cap  # not a field of srfm fit
