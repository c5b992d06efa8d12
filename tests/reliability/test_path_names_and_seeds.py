"""Names that become path components are checked once, at the boundary;
seeds are bounded, and written as plain ASCII decimal digits; a huge --seeds range is
refused at once, without building it."""

from __future__ import annotations

import math
import time
import tracemalloc
from pathlib import Path

import numpy as np
import pytest

import srfm
from srfm._validate import MAX_NAME_LENGTH, MAX_SEED, path_name, planner_name
from srfm.benchmark import BenchmarkRequest, episode_path
from srfm.scenarios import load_scenario
from tests.reliability.conftest import TINY, assert_one_line, cli


class NamedPlanner:
    """A working planner whose name the test sets."""

    detection_range_m = None

    def __init__(self, name: object) -> None:
        self.name = name

    def reset(self, context: object, rng: object) -> None:
        pass

    def act(self, observation: object) -> np.ndarray:
        return np.zeros(2)


@pytest.mark.parametrize(
    ("name", "match"),
    [
        ("tiny\n", "must match"),
        ("x" * 300, "must match"),
        ("Tiny", "must match"),
        ("", "must match"),
        ("../up", "must match"),
    ],
)
def test_bad_scenario_names_are_refused(tmp_path: Path, name: str, match: str) -> None:
    body = TINY.replace('name = "tiny"', f"name = {name!r}".replace("'", '"'))
    body = body.replace('"tiny\n"', '"tiny\\n"')
    path = tmp_path / "s.toml"
    path.write_text(body, encoding="utf-8")
    with pytest.raises(srfm.ScenarioError, match=match):
        load_scenario(path)


@pytest.mark.parametrize(
    "name", ["../../escape", "a/b", "", 42, None, "x" * 300, "a\nb", ".hidden"]
)
def test_a_planner_instance_whose_name_cannot_be_a_folder_is_refused(name: object) -> None:
    with pytest.raises(srfm.PlannerError, match="planner"):
        srfm.run_episode("concert", 0, NamedPlanner(name))  # type: ignore[arg-type]


def test_path_names_and_planner_specs() -> None:
    assert path_name("td3-srfm", "planner name", srfm.PlannerError) == "td3-srfm"
    assert planner_name("my.pkg:Planner", srfm.PlannerError) == "my.pkg:Planner"
    for bad in ("..", ".", "-x", "a b", "a/b", "x" * (MAX_NAME_LENGTH + 1), "tiny\n"):
        with pytest.raises(srfm.PlannerError):
            path_name(bad, "planner name", srfm.PlannerError)
    for bad in (":X", "..:X", "../x:Y", "x:", "a.b:c.d", "1a:X", "a b:X"):
        with pytest.raises(srfm.PlannerError, match="module:attribute"):
            planner_name(bad, srfm.PlannerError)


def test_episode_paths_stay_inside_the_folder(tmp_path: Path) -> None:
    for scenario, planner in (("..", "straight"), ("tiny", "../x"), ("tiny", "")):
        with pytest.raises(srfm.BenchmarkError):
            episode_path(tmp_path, scenario, planner, 0)
    with pytest.raises(srfm.BenchmarkError, match="seed"):
        episode_path(tmp_path, "tiny", "straight", 10**301)


def test_log_paths_stay_inside_the_logs_folder(tmp_path: Path) -> None:
    """The log writers' path functions check the names themselves: a caller of
    srfm.logs cannot write outside OUT/logs or into the counterfactual folder."""
    from srfm.logs import counterfactual_log_path, episode_log_path

    good = episode_log_path(tmp_path, "tiny", "straight", 7, ".mcap")
    assert good == tmp_path / "logs" / "tiny" / "straight" / "seed-000007.mcap"
    for scenario, planner in (
        ("..", "straight"),
        ("tiny", "../x"),
        ("tiny", ""),
        ("tiny", "_counterfactual"),
        ("tiny\n", "straight"),
        ("tiny", 3),
    ):
        with pytest.raises(srfm.LogError):
            episode_log_path(tmp_path, scenario, planner, 0, ".mcap")  # type: ignore[arg-type]
    with pytest.raises(srfm.LogError, match="seed"):
        episode_log_path(tmp_path, "tiny", "straight", -1, ".rrd")
    with pytest.raises(srfm.LogError, match="scenario name"):
        counterfactual_log_path(tmp_path, "../up", 0)


@pytest.mark.parametrize("seed", [2**32, 10**301, -1])
def test_seeds_are_bounded(seed: int) -> None:
    with pytest.raises(srfm.ScenarioError, match=f"at most {MAX_SEED}"):
        srfm.run_episode("concert", seed)
    res = cli("simulate", "--scenario", "concert", "--seed", str(seed))
    assert res.exit_code == 2


def test_a_huge_seed_range_is_refused_at_once(tmp_path: Path) -> None:
    """Each refusal comes before the range is expanded (it was: gigabytes), checked by
    the memory it allocates rather than by this machine's speed."""
    tracemalloc.start()
    try:
        for spec in ("0-99999999", "0-99999,100000-100001", "0-" + "9" * 301):
            res = cli("benchmark", "--seeds", spec, "--out", str(tmp_path / "x"))
            assert res.exit_code == 2
            assert "--seeds" in res.output
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 256 * 2**20, peak  # 10^8 seeds as a list: 3.6 GB
    assert not (tmp_path / "x").exists()


def _duplicate_check_s(n: int) -> float:
    """CPU seconds (the fastest of three) to refuse ``n`` seeds whose last is repeated."""
    seeds = [*range(n - 1), n - 2]
    best = math.inf
    for _ in range(3):
        start = time.process_time()
        with pytest.raises(srfm.BenchmarkError, match=f"seeds given twice: {n - 2}"):
            BenchmarkRequest.create(scenarios=["concert"], planners=["straight"], seeds=seeds)
        best = min(best, time.process_time() - start)
    return best


def test_the_duplicate_check_is_linear(tmp_path: Path) -> None:
    """Ten times the seeds cost about ten times the time (a quadratic check: a hundred
    times; 10^10 comparisons, hours, at 100,000 seeds): a ratio of two times measured
    on the same machine, which no machine's speed changes."""
    small, large = _duplicate_check_s(10_000), _duplicate_check_s(100_000)
    assert large < 40 * max(small, 1e-4), (small, large)
    with pytest.raises(srfm.BenchmarkError, match="at most 100000"):
        BenchmarkRequest.create(scenarios=["concert"], planners=["straight"], seeds=range(100_001))


def test_a_benchmark_planner_named_to_escape_is_refused(tmp_path: Path) -> None:
    scenario = load_scenario("concert")
    with pytest.raises(srfm.BenchmarkError, match=r"module:attribute|letters"):
        BenchmarkRequest(scenarios=(scenario,), planners=("../../x",), seeds=(0,))
    res = cli("benchmark", "-p", "../x:Y", "--seeds", "0", "--out", str(tmp_path / "o"))
    assert res.exit_code == 2
    assert "module:attribute" in res.output
    assert not (tmp_path / "o").exists()


# Python's int() takes each of these (issue 33: `--seed 1_000` ran seed 1000 and
# `--seed ٣`, an Arabic-Indic digit, seed 3); a seed is plain ASCII decimal digits.
NOT_PLAIN = ["1_000", "٣", "１", "+3", "0x10", "3.0", "1e3", "²"]


@pytest.mark.parametrize("text", NOT_PLAIN)
def test_seeds_are_plain_ascii_digits_on_the_command_line(tmp_path: Path, text: str) -> None:
    taken = tmp_path / "a-file"  # not a run folder: train would refuse it next
    taken.write_text("x")
    for args in (
        ["simulate", "--scenario", "concert", "--seed", text],
        ["train", "--seed", text, "--run-dir", str(taken)],
    ):
        assert_one_line(cli(*args), "Invalid value for '--seed'", f"{text!r} is not a seed")
    out = str(tmp_path / "out")
    for option in ("--seeds", "--rrd-seeds"):
        res = cli("benchmark", "-s", "concert", "-p", "straight", option, text, "--out", out)
        assert_one_line(res, f"Invalid value for {option}")
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("text", [t for t in NOT_PLAIN if "," not in t and "-" not in t])
def test_seeds_are_plain_ascii_digits_in_a_sweep_spec(tmp_path: Path, text: str) -> None:
    spec = tmp_path / "spec.toml"
    spec.write_text(
        f'schema_version = 1\nscenarios = ["concert"]\nplanners = ["straight"]\n'
        f"seeds = {text!r}\n"
        '[design]\nkind = "grid"\n[design.factors]\na_robot = [1.0]\n',
        encoding="utf-8",
    )
    res = cli("sweep", str(spec), "--out", str(tmp_path / "out"))
    assert_one_line(res, f"{spec}: seeds: {text.strip()!r} is not a seed or a range like 0-29")
