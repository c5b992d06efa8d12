"""The large-crowd scenarios and the benchmark suites (issue 19)."""

from __future__ import annotations

import attrs
import numpy as np
import pytest
from click.testing import CliRunner

import srfm
from srfm.cli import main
from srfm.metrics.episode import episode_metrics
from srfm.models.forces import CELL_LIST_MIN_AGENTS, kernel_cutoffs
from srfm.scenarios import BUILTIN_SCENARIOS, EVALUATION_SCENARIOS, LARGE_SCENARIOS, load_scenario
from srfm.scenarios.suites import DEFAULT_SUITE, SUITES


def test_suites_name_builtin_scenarios() -> None:
    assert SUITES["paper"] == EVALUATION_SCENARIOS
    assert SUITES["large"] == LARGE_SCENARIOS
    assert DEFAULT_SUITE in SUITES
    for names in SUITES.values():
        for name in names:
            assert load_scenario(name).name == name
    assert not set(LARGE_SCENARIOS) & set(BUILTIN_SCENARIOS)


@pytest.mark.parametrize("name", LARGE_SCENARIOS)
def test_large_scenario_runs_a_short_episode(name: str) -> None:
    scenario = load_scenario(name)
    assert 200 <= scenario.n_pedestrians <= 1000
    short = attrs.evolve(scenario, horizon_steps=15)
    setup = srfm.episode_setup(short, 0)
    # the cell list and the cut-off are in use at this size
    assert scenario.n_pedestrians >= CELL_LIST_MIN_AGENTS
    assert np.all(np.isfinite(kernel_cutoffs("auto", srfm.SRFMParams(), setup.crowd.radius)))
    first = srfm.run_episode(short, 0, "straight")
    again = srfm.run_episode(short, 0, "straight")
    np.testing.assert_array_equal(first.factual_pos, again.factual_pos)
    np.testing.assert_array_equal(first.counterfactual_pos, again.counterfactual_pos)
    assert first.factual_pos.shape == (16, scenario.n_pedestrians, 2)
    assert np.all(np.isfinite(first.factual_pos))
    metrics = episode_metrics(first)
    assert metrics.scenario == name


def test_suite_option_errors_name_the_problem() -> None:
    runner = CliRunner()
    result = runner.invoke(main, ["benchmark", "--suite", "huge", "--out", "x"])
    assert result.exit_code != 0
    assert "huge" in result.output
    result = runner.invoke(
        main, ["benchmark", "--suite", "large", "--scenario", "footpath", "--out", "x"]
    )
    assert result.exit_code != 0
    assert "not both" in result.output
