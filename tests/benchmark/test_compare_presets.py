"""tools/analysis/compare_presets.py: two folders' mean deviations, ranks and Kendall's τ,
restricted to the planners both folders hold with ``--planners``."""

from __future__ import annotations

from pathlib import Path

import pytest

from tools.analysis import compare_presets


def _folder(path: Path, rows: list[tuple[str, str, float]]) -> Path:
    path.mkdir()
    lines = ["scenario,planner,seed,frechet_m"]
    lines += [f"{s},{p},{i},{v}" for i, (s, p, v) in enumerate(rows)]
    (path / "episodes.csv").write_text("\n".join(lines) + "\n")
    return path


def test_planners_option_compares_the_common_planners(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    a = _folder(
        tmp_path / "a",
        [("s", "dwa", 1.0), ("s", "dwa", 2.0), ("s", "vo", 3.0), ("s", "oracle", 0.5)],
    )
    b = _folder(tmp_path / "b", [("s", "dwa", 0.4), ("s", "vo", 0.2)])
    with pytest.raises(SystemExit, match="different scenarios or planners"):
        compare_presets.main([str(a), str(b)])
    compare_presets.main([str(a), str(b), "--planners", "dwa,vo", "--labels", "A", "B"])
    out = capsys.readouterr().out
    assert "A: 3 episodes; B: 2 episodes" in out
    assert "oracle" not in out
    # dwa: mean 1.5 under A (rank 1), 0.4 under B (rank 2); the order flips: τ = -1
    assert "| s | 1.50 / 0.40 (1 / 2) | 3.00 / 0.20 (2 / 1) | -1.00 | 0.13 |" in out


def test_planners_option_names_a_missing_planner(tmp_path: Path) -> None:
    a = _folder(tmp_path / "a", [("s", "dwa", 1.0)])
    with pytest.raises(SystemExit, match=r"no episodes of planner\(s\) vo"):
        compare_presets.main([str(a), str(a), "--planners", "dwa,vo"])
