"""Parameter draws and the rank probabilities over them (issue 29, part 4)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from srfm.benchmark import (
    SENSITIVITY_RANGES,
    WIDE_RANGES,
    BenchmarkRequest,
    draw_params,
    rank_probabilities,
    rank_table,
    run_benchmark,
)
from srfm.errors import BenchmarkError, ParameterError
from srfm.models.params import SRFMParams
from tests.benchmark.test_runner import SHORT
from tests.conftest import write_scenario


def test_sensitivity_draws_are_deterministic_and_inside_the_ranges() -> None:
    base = SRFMParams()
    a = draw_params(base, 20, seed=3)
    b = draw_params(base, 20, seed=3)
    c = draw_params(base, 20, seed=4)
    assert a.params == b.params  # same seed, bit-identical values
    assert a.params != c.params
    assert a.document() == b.document()
    for p in a.params:
        for name, (low, high) in SENSITIVITY_RANGES.items():
            assert low <= getattr(p, name) <= high
        # Every other parameter is the base's.
        assert p.replace(a_robot=base.a_robot, b_robot=base.b_robot) == base
    assert len({p.a_robot for p in a.params}) == 20
    # Fewer draws with the same seed are the first ones of more.
    assert draw_params(base, 5, seed=3).params == a.params[:5]
    assert "U(3.965, 15.86)" in a.description


def test_wide_draws_cover_the_real_data_fit_log_uniformly() -> None:
    base = SRFMParams()
    draws = draw_params(base, 400, seed=1, source="wide")
    assert draws.params == draw_params(base, 400, seed=1, source="wide").params
    assert draws.source == "wide"
    assert draws.file_sha256 is None
    assert draws.params[:7] == draw_params(base, 7, seed=1, source="wide").params
    a = np.array([p.a_robot for p in draws.params])
    b = np.array([p.b_robot for p in draws.params])
    for name, x in (("a_robot", a), ("b_robot", b)):
        low, high = WIDE_RANGES[name]
        assert low <= x.min()
        assert x.max() <= high
        # Uniform in the logarithm: about half the draws below the geometric midpoint.
        assert abs(np.mean(x < np.sqrt(low * high)) - 0.5) < 0.1
    # The real-data fit (A_r = 0.55 m/s², B_r = 0.23 m) lies inside the ranges.
    assert WIDE_RANGES["a_robot"][0] < 0.55 < WIDE_RANGES["a_robot"][1]
    assert WIDE_RANGES["b_robot"][0] < 0.23 < WIDE_RANGES["b_robot"][1]
    assert np.any(a < 1.0)
    assert np.any(b < 0.3)
    assert all(p.replace(a_robot=base.a_robot, b_robot=base.b_robot) == base for p in draws.params)
    assert "log-U(0.25, 15.86)" in draws.description


def test_draws_from_a_file_of_parameter_sets(tmp_path: Path) -> None:
    path = tmp_path / "boot.csv"
    rows = [(1.0 + k, 0.5 + 0.1 * k) for k in range(6)]
    path.write_text("a_robot,b_robot\n" + "".join(f"{a},{b}\n" for a, b in rows), encoding="utf-8")
    base = SRFMParams()
    draws = draw_params(base, 4, seed=1, source=path)
    assert draws.params == draw_params(base, 4, seed=1, source=path).params
    chosen = [(p.a_robot, p.b_robot) for p in draws.params]
    assert len(set(chosen)) == 4  # without replacement
    assert set(chosen) <= set(rows)
    assert all(p.tau == base.tau for p in draws.params)
    assert draws.file_sha256 is not None
    assert "4 of the 6 parameter sets of boot.csv" in draws.description
    every = draw_params(base, 6, seed=1, source=path)
    assert sorted((p.a_robot, p.b_robot) for p in every.params) == rows
    with pytest.raises(ParameterError, match="6 parameter sets, fewer than the 7 draws"):
        draw_params(base, 7, source=path)
    bad = tmp_path / "bad.csv"
    bad.write_text("a_robot,speed\n1,2\n", encoding="utf-8")
    with pytest.raises(ParameterError, match=r"header must name SRFM parameters.*\['speed'\]"):
        draw_params(base, 1, source=bad)
    bad.write_text("a_robot,b_robot\n1,0.5\n2,-1\n", encoding="utf-8")
    with pytest.raises(ParameterError, match=r"bad\.csv, line 3"):
        draw_params(base, 1, source=bad)
    with pytest.raises(ParameterError, match=r"number of parameter draws .* got 0"):
        draw_params(base, 0)
    with pytest.raises(ParameterError, match=r"seed of the parameter draws .* got -1"):
        draw_params(base, 1, seed=-1)


def test_rank_probabilities_share_ties_and_sum_to_one() -> None:
    means = [
        [0.1, 0.2, 0.3],  # a, b, c
        [0.2, 0.1, 0.3],  # b, a, c
        [0.1, 0.1, 0.3],  # a and b tied first
        [0.3, 0.2, 0.1],  # c, b, a
    ]
    probs = rank_probabilities(means)
    expected = (
        np.array(
            [
                [1 + 0 + 0.5 + 0, 0 + 1 + 0.5 + 0, 0 + 0 + 0 + 1],
                [0 + 1 + 0.5 + 0, 1 + 0 + 0.5 + 1, 0],
                [0 + 0 + 0 + 1, 0, 1 + 1 + 1 + 0],
            ]
        )
        / 4
    )
    np.testing.assert_allclose(probs, expected, rtol=0, atol=1e-15)
    np.testing.assert_allclose(probs.sum(axis=0), 1.0, rtol=0, atol=1e-15)
    np.testing.assert_allclose(probs.sum(axis=1), 1.0, rtol=0, atol=1e-15)
    # An undefined mean ranks last.
    assert rank_probabilities([[np.nan, 1.0]]).tolist() == [[0.0, 1.0], [1.0, 0.0]]
    table = rank_table(
        [{"s": {"a": m[0], "b": m[1], "c": m[2]}} for m in means],
        scenarios=["s"],
        planners=["a", "b", "c"],
        n_seeds=10,
        description="test",
    )
    assert table.probabilities["s"]["c"] == pytest.approx((0.25, 0.0, 0.75))
    # Wilson's interval over the 4 draws around each probability (c first in 1 of 4).
    low_p, high_p = table.probability_interval("s", "c", 1)
    assert low_p < 0.25 < high_p
    assert (low_p, high_p) == pytest.approx((0.04558726, 0.6993582), abs=1e-7)
    assert table.probability_interval("s", "c", 2)[0] == 0.0
    low, mid, high = table.interval("s", "a")
    assert (low, mid, high) == pytest.approx(
        tuple(np.percentile([0.1, 0.2, 0.1, 0.3], [2.5, 50, 97.5]))
    )


def test_a_benchmark_under_parameter_draws(tmp_path: Path) -> None:
    scenario = write_scenario(tmp_path / "short.toml", SHORT)  # 120 steps: cheap
    request = BenchmarkRequest.create(
        scenarios=[str(scenario)],
        planners=["straight", "tests.benchmark.test_runner:Waiter"],
        seeds=[0, 1],
    )
    draws = draw_params(request.params, 2, seed=5)
    out = tmp_path / "run"
    summary = run_benchmark(request, out, jobs=1, figures=False, param_draws=draws)
    assert (summary.episodes, summary.simulated, summary.draws) == (12, 12, 2)
    doc = json.loads((out / "rankings.json").read_text(encoding="utf-8"))
    assert doc["n_draws"] == 2
    for entry in doc["scenarios"]["short"].values():
        assert sum(entry["rank_probabilities"]) == pytest.approx(1.0)
        assert len(entry["draw_means"]) == 2
    for k, params in enumerate(draws.params):
        manifest = json.loads(
            (out / "draws" / f"draw-{k:03d}" / "manifest.json").read_text(encoding="utf-8")
        )
        assert manifest["params"] == params.as_dict()
    assert "rankings.md" in summary.files
    assert "Rankings under the model" in (out / "report.html").read_text(encoding="utf-8")
    # The same request again: nothing to run, the same bytes.
    before = (out / "rankings.json").read_bytes()
    again = run_benchmark(request, out, jobs=1, figures=False, param_draws=draws)
    assert again.simulated == 0
    assert (out / "rankings.json").read_bytes() == before
    # Other draws in the same folder are refused before anything is written.
    files = {p: p.read_bytes() for p in out.rglob("*") if p.is_file()}
    with pytest.raises(BenchmarkError, match=r"other parameter draws \(seed differs\)"):
        run_benchmark(
            request, out, jobs=1, figures=False, param_draws=draw_params(request.params, 2)
        )
    assert {p: p.read_bytes() for p in out.rglob("*") if p.is_file()} == files
