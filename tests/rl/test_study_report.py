"""tools/rl/study_report.py: the targets table and the claim's statistics."""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest

from tools.rl import study_report


def test_holm_adjusts_in_order() -> None:
    got = study_report.holm([0.01, 0.04, 0.03, float("nan")])
    assert got[:3] == pytest.approx([0.03, 0.06, 0.06])
    assert np.isnan(got[3])


def _write(folder: Path) -> None:
    rng = np.random.default_rng(0)
    fields = ["scenario", "planner", "seed", "robot_success", "robot_collision"]
    fields += ["robot_out_of_bounds", "frechet_m"]
    with (folder / "episodes.csv").open("w", newline="") as fh:
        out = csv.DictWriter(fh, fields)
        out.writeheader()
        for scenario in study_report.REPORT_SCENARIOS:
            for k2 in ("0", "2"):
                for train_seed in range(1, 7):
                    base = 0.5 + 0.05 * train_seed
                    if scenario == "crosswalk":  # the penalty lowers deviation by 0.2 m
                        dev = base - (0.2 if k2 == "2" else 0.0) + rng.normal(0, 0.01)
                    elif scenario == "footpath":  # equal within 1 mm
                        dev = base + rng.normal(0, 0.001)
                    else:  # noise far beyond the margin
                        dev = base + rng.normal(0, 0.3)
                    for seed in range(4):
                        collided = scenario == "circle" and k2 == "0" and seed == 0
                        out.writerow(
                            {
                                "scenario": scenario,
                                "planner": f"tools.rl.study_planners:k{k2}_seed{train_seed}",
                                "seed": seed,
                                "robot_success": 0 if collided else 1,
                                "robot_collision": 1 if collided else 0,
                                "robot_out_of_bounds": 0,
                                "frechet_m": dev + 0.0 * seed,
                            }
                        )


def test_report_answers_each_kind(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    _write(tmp_path)
    assert study_report.main([str(tmp_path)]) == 0
    text = capsys.readouterr().out
    first, second = text.split("## The claim")

    def rows(part: str) -> dict[str, str]:
        return {line.split(" | ")[0].strip("| "): line for line in part.splitlines() if "|" in line}

    claim = rows(second)
    assert "the penalty lowers deviation by 0.18" in claim["crosswalk"]
    assert "equivalent within ±0.03 m" in claim["footpath"]
    assert "inconclusive: would need about" in claim["concert"]
    # the circle's k2 = 0 policies collide in 1 of 4 episodes: each misses the target
    assert rows(first)["circle"].count("✗") == 6
    assert "(6 cells)" in first


def test_report_reads_several_folders_as_one(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    whole, first, second = (tmp_path / n for n in ("whole", "first", "second"))
    for folder in (whole, first, second):
        folder.mkdir()
    _write(whole)
    with (whole / "episodes.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    for folder, part in ((first, rows[::2]), (second, rows[1::2])):
        with (folder / "episodes.csv").open("w", newline="") as fh:
            out = csv.DictWriter(fh, list(rows[0]))
            out.writeheader()
            out.writerows(part)
    assert study_report.main([str(whole)]) == 0
    one = capsys.readouterr().out
    assert study_report.main([str(first), str(second)]) == 0
    assert capsys.readouterr().out == one
    with pytest.raises(ValueError, match="is in both"):
        study_report.load(first, first)


def test_committed_names_a_missing_part(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(study_report, "STUDY", tmp_path)
    with pytest.raises(SystemExit, match="nope: no seed"):
        study_report.committed("nope")


def test_the_committed_report_is_the_committed_episodes(
    capsys: pytest.CaptureFixture[str],
) -> None:
    """tools/rl/study/report.md and report_ttc.md are study_report.py's output on the
    committed episodes (tools/rl/study_evaluate.py), byte for byte."""
    for part, page in (("report", "report.md"), ("report_ttc", "report_ttc.md")):
        files = sorted((study_report.STUDY / part).glob("seed*.csv.gz"))
        assert len(files) == 10
        assert study_report.main([str(f) for f in files]) == 0
        assert capsys.readouterr().out == (study_report.STUDY / page).read_text(encoding="utf-8")


def test_the_evaluation_runs_each_part_of_a_seed() -> None:
    from tools.rl import study_evaluate

    cmd = study_evaluate.command("report", 3, jobs=2, nice=10)
    assert cmd[:3] == ["nice", "-n", "10"]
    assert cmd[cmd.index("-p") + 1] == (
        "tools.rl.study_planners:k0_seed3,tools.rl.study_planners:k2_seed3"
    )
    assert [cmd[i + 1] for i, a in enumerate(cmd) if a == "-s"] == list(
        study_report.REPORT_SCENARIOS
    )
    assert "--params" not in cmd
    ttc = study_evaluate.command("report_ttc", 3, jobs=1, nice=5)
    assert ttc[-2:] == ["--params", "navwareset2026_ttc"]
    assert [ttc[i + 1] for i, a in enumerate(ttc) if a == "-s"] == list(
        study_report.REPORT_SCENARIOS[:5]
    )
    assert study_evaluate.output("report_ttc", 3).name == "seed3.csv.gz"
    with pytest.raises(SystemExit, match=r"unknown part\(s\) \['x'\]"):
        study_evaluate.main(["--parts", "report,x"])
