"""One benchmark under several response models, and which orderings of planners hold
under all of them (issue 40, part 4)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from srfm.benchmark._models import (
    MODELS_JSON,
    ResponseModels,
    _verdict,
    kendall_tau_b,
    model_folder,
)
from srfm.cli import main
from srfm.errors import BenchmarkError
from srfm.models.params import SRFMParams, response_model_name
from tests.benchmark.test_report import _browser_or_skip
from tests.benchmark.test_runner import SHORT
from tests.conftest import write_scenario

MODELS = "agrawal2024,ferrer2013,navwareset2026_ttc"
PLANNERS = "straight,stay,tests.benchmark.test_runner:Waiter"


def _run(scenario: Path, out: Path, *extra: str, models: str = MODELS) -> str:
    result = CliRunner().invoke(
        main,
        ["benchmark", "-s", str(scenario), "-p", PLANNERS, "--seeds", "0-5", "--out", str(out),
         "-j", "1", "--no-figures", "--no-logs", "--params", models, *extra],
    )  # fmt: skip
    assert result.exit_code == 0, result.output
    return result.output


@pytest.fixture(scope="module")
def scenario(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return write_scenario(tmp_path_factory.mktemp("scn") / "short.toml", SHORT)


@pytest.fixture(scope="module")
def results(scenario: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("models") / "out"
    output = _run(scenario, out)
    assert "under 3 response models" in output
    return out


def test_kendall_tau_b_is_scipys_on_rankings_with_ties() -> None:
    from scipy.stats import kendalltau

    rng = np.random.default_rng(7)
    x = rng.integers(0, 4, size=(300, 6)).astype(np.float64)  # many ties
    y = rng.integers(0, 4, size=(300, 6)).astype(np.float64)
    ours = kendall_tau_b(x, y)
    for row in range(x.shape[0]):
        theirs = kendalltau(x[row], y[row]).statistic
        if np.isnan(theirs):
            assert np.isnan(ours[row])
        else:
            assert ours[row] == pytest.approx(theirs, abs=1e-12)
    assert kendall_tau_b(np.array([[1.0, 2, 3]]), np.array([[3.0, 2, 1]]))[0] == -1.0
    assert np.isnan(kendall_tau_b(np.array([[1.0, 1, 1]]), np.array([[3.0, 2, 1]]))[0])
    assert np.isnan(kendall_tau_b(np.array([[1.0, np.nan, 1]]), np.array([[3.0, 2, 1]]))[0])


def test_the_verdict_rule() -> None:
    assert _verdict([0.1, 0.2, 0.05], [0.01, 0.001, 0.04]) == "holds"
    assert _verdict([-0.1, -0.2], [0.01, 0.001]) == "holds"
    assert _verdict([0.1, -0.2, 0.05], [0.01, 0.001, 0.5]) == "flips"
    assert _verdict([0.1, 0.2, 0.05], [0.01, 0.001, 0.2]) == "unresolved"
    assert _verdict([0.1, 0.2], [0.01, float("nan")]) == "unresolved"
    assert _verdict([0.1, -0.2], [0.3, 0.4]) == "unresolved"


def test_every_model_runs_into_its_folder_and_the_reports_hold_the_verdicts(
    results: Path,
) -> None:
    models = json.loads((results / MODELS_JSON).read_text())
    assert [m["name"] for m in models["models"]] == MODELS.split(",")
    for name in MODELS.split(",")[1:]:
        folder = model_folder(results, name)
        summary = json.loads((folder / "summary.json").read_text())
        assert summary["request"]["params"] == SRFMParams.preset(name).as_dict()
        assert len(list((folder / "episodes").rglob("seed-*.json"))) == 3 * 6
    summary = json.loads((results / "summary.json").read_text())
    robust = summary["robustness"]
    assert robust == json.loads((results / "robustness.json").read_text())
    assert robust["models"] == MODELS.split(",")
    pairs = robust["pairs"]["short"]
    assert len(pairs) == 3  # three planners
    for pair in pairs:
        assert len(pair["difference_m"]) == 3
        assert pair["verdict"] in ("holds", "flips", "unresolved")
    assert sum(robust["counts"]["short"].values()) == 3
    taus = [t for t in robust["kendall_tau"] if t["scenario"] == "short"]
    assert len(taus) == 3  # every two of three models
    for t in taus:
        low, high = t["interval"]
        assert low is None or -1.0 <= low <= high <= 1.0
    # the differences are the planners' own episodes under each model
    own = {
        (r["planner"], int(r["seed"])): float(r["frechet_m"])
        for r in _rows(results / "episodes.csv")
    }
    straight = np.array([own["straight", s] for s in range(6)])
    stay = np.array([own["stay", s] for s in range(6)])
    first = next(p for p in pairs if {p["a"], p["b"]} == {"straight", "stay"})
    sign = 1.0 if first["a"] == "straight" else -1.0
    assert first["difference_m"][0] == pytest.approx(sign * float(np.mean(straight - stay)))
    markdown = (results / "robustness.md").read_text()
    assert "| short |" in markdown
    assert "Kendall" in markdown
    page = (results / "report.html").read_text()
    assert 'id="robustness"' in page
    assert "Response model of the pedestrians: agrawal2024." in page


def _rows(path: Path) -> list[dict[str, str]]:
    import csv

    with path.open(encoding="utf-8") as f:
        return list(csv.DictReader(f))


def test_a_second_run_resumes_and_gives_the_same_bytes(results: Path, scenario: Path) -> None:
    before = (results / "robustness.json").read_bytes()
    output = _run(scenario, results)
    assert "simulated 0 of 54 episodes" in output
    assert (results / "robustness.json").read_bytes() == before


def test_the_same_request_in_another_process_order_gives_the_same_bytes(
    results: Path, scenario: Path, tmp_path: Path
) -> None:
    out = tmp_path / "two"
    _run(scenario, out, "-j", "2")
    assert (out / "robustness.json").read_bytes() == (results / "robustness.json").read_bytes()


def test_other_models_in_the_same_folder_are_refused(results: Path, scenario: Path) -> None:
    result = CliRunner().invoke(
        main,
        ["benchmark", "-s", str(scenario), "-p", PLANNERS, "--seeds", "0-5", "--out",
         str(results), "-j", "1", "--no-figures", "--no-logs", "--params",
         "agrawal2024,ferrer2013"],
    )  # fmt: skip
    assert result.exit_code == 2
    assert "holds a run under other response models" in result.output


@pytest.mark.parametrize(
    ("spec", "message"),
    [
        ("agrawal2024,agrawal2024", "response model 'agrawal2024' is given twice"),
        ("agrawal2024,nosuch", "unknown parameter preset 'nosuch'"),
        ("agrawal2024,", "an empty name in 'agrawal2024,'"),
    ],
)
def test_bad_model_lists_are_one_clear_error(
    spec: str, message: str, scenario: Path, tmp_path: Path
) -> None:
    out = tmp_path / "out"
    result = CliRunner().invoke(
        main, ["benchmark", "-s", str(scenario), "--seeds", "0", "--out", str(out),
               "--params", spec],
    )  # fmt: skip
    assert result.exit_code == 2, result.output
    assert message in result.output
    assert len(result.output.strip().splitlines()) == 1, result.output
    assert not out.exists()


def test_a_parameter_file_is_a_model_named_by_its_stem(scenario: Path, tmp_path: Path) -> None:
    from srfm.models.params import save_params

    path = tmp_path / "strong.toml"
    save_params(SRFMParams(a_robot=15.0), path)
    out = tmp_path / "out"
    result = CliRunner().invoke(
        main,
        ["benchmark", "-s", str(scenario), "-p", "straight,stay", "--seeds", "0-1", "--out",
         str(out), "-j", "1", "--no-figures", "--no-logs", "--params", f"agrawal2024,{path}"],
    )  # fmt: skip
    assert result.exit_code == 0, result.output
    assert (out / "models" / "strong" / "summary.json").is_file()
    assert response_model_name(SRFMParams(a_robot=15.0)) == (
        "custom parameters (exponential robot force)"
    )
    assert response_model_name(SRFMParams.preset("ferrer2013")) == "ferrer2013"


def test_the_models_must_differ_in_name_only_once() -> None:
    with pytest.raises(BenchmarkError, match="at least two"):
        ResponseModels(names=("a",), params=(SRFMParams(),))


def test_the_robustness_section_shows_in_chromium(results: Path) -> None:
    _browser_or_skip()
    from playwright.sync_api import sync_playwright

    from tests.benchmark.test_report import CHROMIUM, CHROMIUM_ARGS

    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=str(CHROMIUM), args=CHROMIUM_ARGS)
        try:
            page = browser.new_page()
            errors: list[str] = []
            page.on("pageerror", lambda e: errors.append(str(e)))
            page.goto((results / "report.html").resolve().as_uri(), wait_until="load")
            counts = page.evaluate(
                "Array.from(document.querySelectorAll('table.robustness tbody tr'))"
                ".map(r => Array.from(r.querySelectorAll('td')).map(t => t.innerText.trim()))"
            )
            taus = page.evaluate(
                "Array.from(document.querySelectorAll('table.taus tbody tr')).length"
            )
            visible = page.evaluate(
                "document.querySelector('#robustness').getBoundingClientRect().height > 0"
            )
        finally:
            browser.close()
    assert not errors, errors
    assert visible
    assert len(counts) == 1
    assert counts[0][0] == "short"
    assert sum(int(c) for c in counts[0][1:]) == 3
    assert taus == 6  # 3 pairs of models × (short + suite)
