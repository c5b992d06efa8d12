"""tools/rl/study43/report.py: the issue-43 claim test and target tables."""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import numpy as np
import pytest
from scipy import stats

from tools.rl.study43 import report


def _row(seed: int, success: int, frechet: float, collision: int = 0) -> dict[str, str]:
    return {
        "seed": str(seed),
        "robot_success": str(success),
        "robot_collision": str(collision),
        "robot_out_of_bounds": "0",
        "frechet_m": str(frechet),
    }


def test_deviation_is_paired_on_the_seeds_where_both_reach_the_goal() -> None:
    base = [_row(0, 1, 1.0), _row(1, 1, 2.0), _row(2, 0, 9.0), _row(3, 1, 4.0)]
    srfm = [_row(0, 1, 0.5), _row(1, 0, 0.0), _row(2, 1, 0.0), _row(3, 1, 3.0)]
    d, k, n = report.paired_deviation(base, srfm)
    assert (k, n) == (2, 4)
    assert d == pytest.approx(((0.5 - 1.0) + (3.0 - 4.0)) / 2)
    none = report.paired_deviation([_row(0, 0, 1.0)], [_row(0, 1, 1.0)])
    assert math.isnan(none[0])
    assert none[1:] == (0, 1)


def test_paired_statistics_match_scipy() -> None:
    values = [0.1, -0.02, 0.05, 0.07, math.nan]
    got = report.paired(values)
    d = np.array(values[:4])
    assert got.n == 4
    assert got.mean == pytest.approx(d.mean())
    assert got.p == pytest.approx(stats.ttest_1samp(d, 0.0).pvalue)
    half = stats.t.ppf(0.975, 3) * d.std(ddof=1) / 2
    assert (got.lo95, got.hi95) == pytest.approx((d.mean() - half, d.mean() + half))
    assert not got.equivalent(0.03)
    assert report.paired([0.001, -0.001, 0.0005, 0.0]).equivalent(0.03)
    assert math.isnan(report.paired([0.2]).lo95)


def _write(folder: Path, final_shift: float = 0.0) -> None:
    rng = np.random.default_rng(1)
    fields = ["scenario", "planner", "seed", "robot_success", "robot_collision"]
    fields += ["robot_out_of_bounds", "frechet_m"]
    with (folder / "episodes.csv").open("w", newline="") as fh:
        out = csv.DictWriter(fh, fields)
        out.writeheader()
        for scenario in report.REPORT_SCENARIOS:
            for final in (False, True):
                for k2 in ("0", "2"):
                    for train_seed in range(1, 7):
                        base = 0.5 + 0.05 * train_seed
                        for seed in range(10):
                            success = 1
                            if scenario == "crosswalk":  # lowered by 0.2 m
                                dev = base - (0.2 if k2 == "2" and not final else 0.0)
                                dev += rng.normal(0, 0.01)
                            elif scenario == "footpath":  # equal within 1 mm
                                dev = base + rng.normal(0, 0.001)
                            elif scenario == "concert":  # k2 = 2 waits in half the seeds
                                dev = base + rng.normal(0, 0.3)
                                success = 0 if (k2 == "2" and seed % 2 == 0) else 1
                            else:
                                dev = base + rng.normal(0, 0.3)
                            planner = report.planner_name(k2, train_seed, final)
                            out.writerow(
                                {
                                    "scenario": scenario,
                                    "planner": planner,
                                    "seed": seed,
                                    "robot_success": success,
                                    "robot_collision": 0,
                                    "robot_out_of_bounds": 0,
                                    "frechet_m": dev + final_shift,
                                }
                            )


def _rows(lines: list[str]) -> dict[str, str]:
    return {line.split(" | ")[0].strip("| "): line for line in lines if line.startswith("| ")}


def test_the_claim_answers_each_kind_with_k_over_n(tmp_path: Path) -> None:
    _write(tmp_path)
    table = report.load(tmp_path)
    chosen = _rows(report.claim(table, final=False))
    assert "lower with the penalty by 0.2" in chosen["crosswalk"]
    assert "equivalent within ±0.03 m" in chosen["footpath"]
    assert "| 60/60 |" in chosen["footpath"]
    concert = chosen["concert"]
    assert "| 30/60 |" in concert  # deviation only where both reached the goal
    assert "| 60/60 | 30/60 |" in concert  # goals of each arm
    assert "lower with the penalty by 0.500" in concert  # success, co-primary
    assert "| lower |" in concert  # the paper's claim
    assert "no advantage claimed" in chosen["circle"]
    assert "inconclusive" in chosen["down_path"]
    final = _rows(report.claim(table, final=True))
    assert "lower with the penalty" not in final["crosswalk"].split(" | ")[7]


def test_the_claim_needs_both_arms(tmp_path: Path) -> None:
    _write(tmp_path)
    table = {k: v for k, v in report.load(tmp_path).items() if "k2_" not in k[1]}
    assert report.claim(table, final=False) == ["(needs both arms, k2 = 0 and k2 = 2)"]


def test_target_tables_and_the_shipping_rule(tmp_path: Path) -> None:
    _write(tmp_path)
    table = report.load(tmp_path)
    missed = _rows(report.missed_table(table))
    assert missed["k2 = 2, chosen"].split(" | ")[1:] == ["1"] * 5 + ["1 |"]
    assert missed["k2 = 0, final"].split(" | ")[1:] == ["0"] * 5 + ["0 |"]
    validation = tmp_path / "validation"
    validation.mkdir()
    for name, success, collisions in (
        ("k0-seed1", 0.99, 0.0),
        ("k0-seed2", 1.0, 0.01),
        ("k0-seed3", 1.0, 0.0),
        ("k0-seed4", 1.0, 0.0),
        ("k2-seed5", 0.98, 0.0),
        ("k2-seed6", 0.98, 0.0),
    ):
        best = {"checkpoint": "step_000300000.zip", "success_rate": success,
                "collision_rate": collisions}  # fmt: skip
        (validation / f"{name}.json").write_text(json.dumps({"best": best}))
    assert report.validation_choice(validation, "0") == (3, 1.0, 0.0)
    assert report.validation_choice(validation, "2") == (5, 0.98, 0.0)
    shipped = report.ship_table(table, validation)
    assert "k0-seed3" in shipped[0]
    assert "k2-seed5" in shipped[0]
    rows = _rows(shipped)
    assert rows["concert"].endswith("| 1.00 / 0.00 / 0.00 | 0.50 / 0.00 / 0.00 ✗ |")
    assert "| held out |" in rows["blind_corner"]


def test_the_planners_module_names_chosen_and_final_policies() -> None:
    from tools.rl.study43 import planners

    assert callable(planners.k0_seed3)
    assert callable(planners.k2_seed10_final)
    with pytest.raises(AttributeError, match="k3_seedx"):
        _ = planners.k3_seedx


def test_validation_check_reads_the_issue_30_report_and_scene_outcomes(tmp_path: Path) -> None:
    """The cells missed per issue-30 run, as docs/rl.md's table lists them."""
    from tools.rl.study43 import validation_check

    missed = validation_check.missed_cells()
    assert len(missed) == 20
    expected = {"k0-seed1": 0, "k0-seed2": 5, "k0-seed4": 2, "k0-seed10": 6}
    expected |= {"k2-seed4": 0, "k2-seed6": 1, "k2-seed10": 9}
    assert {run: missed[run] for run in expected} == expected
    with (tmp_path / "episodes.csv").open("w", newline="") as fh:
        out = csv.DictWriter(fh, ["planner", "robot_success", "robot_collision"])
        out.writeheader()
        for success, collision in ((1, 0), (0, 1), (0, 0)):
            out.writerow(
                {"planner": "tools.rl.study_planners:k2_seed3", "robot_success": success,
                 "robot_collision": collision}
            )  # fmt: skip
        out.writerow({"planner": "dwa", "robot_success": 1, "robot_collision": 0})
    assert validation_check.scene_outcomes(tmp_path) == {"k2-seed3": (1, 1, 3)}


def test_the_committed_columns_give_the_same_tables(tmp_path: Path) -> None:
    from tools.rl.study43 import evaluate

    _write(tmp_path)
    packed = tmp_path / "seed1.csv.gz"
    evaluate.write_columns(tmp_path / "episodes.csv", packed)
    first = packed.read_bytes()
    evaluate.write_columns(tmp_path / "episodes.csv", packed)
    assert packed.read_bytes() == first  # the same episodes give the same bytes
    from_folder, from_file = report.load(tmp_path), report.load(packed)
    assert report.claim(from_file, final=False) == report.claim(from_folder, final=False)
    assert report.missed_table(from_file) == report.missed_table(from_folder)
    with pytest.raises(ValueError, match="in both"):
        report.load(packed, tmp_path)
    assert evaluate.planners(3) == [
        "tools.rl.study43.planners:k0_seed3",
        "tools.rl.study43.planners:k2_seed3",
        "tools.rl.study43.planners:k0_seed3_final",
        "tools.rl.study43.planners:k2_seed3_final",
    ]
    names = [report.planner_name(k, 3, final) for final in (False, True) for k in ("0", "2")]
    assert names == evaluate.planners(3)


def test_shipped_scenes_runs_the_six_scenes_with_the_shipped_pair(tmp_path: Path) -> None:
    from tools.rl.study43 import shipped_scenes

    cmd = shipped_scenes.command(tmp_path / "out")
    scenes = [cmd[i + 1] for i, a in enumerate(cmd) if a == "-s"]
    assert len(scenes) == 6
    assert all(s.startswith("tools/rl/study43/validation_scenes/val_") for s in scenes)
    assert cmd[cmd.index("-p") + 1] == "td3-srfm,td3-base"
    assert cmd[cmd.index("--seeds") + 1] == "20000-20009"
