"""The benchmark runner: results folder, resuming, reproducible tables, CLI."""

from __future__ import annotations

import csv
import json
import math
import os
import signal
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from click.testing import CliRunner

from srfm import SRFMParams
from srfm.benchmark import BenchmarkRequest, episode_path, read_episode, run_benchmark
from srfm.cli import main
from srfm.errors import BenchmarkError
from srfm.metrics import episode_metrics
from srfm.scenarios import load_scenario
from tests.conftest import REPO, RESULT_TABLES, write_scenario

TABLES = RESULT_TABLES

SHORT = (REPO / "srfm/scenarios/crosswalk.toml").read_text(encoding="utf-8")
SHORT = SHORT.replace('name = "crosswalk"', 'name = "short"').replace(
    "horizon_steps = 750", "horizon_steps = 120"
)


@pytest.fixture(scope="module")
def short_scenario(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return write_scenario(tmp_path_factory.mktemp("scn") / "short.toml", SHORT)


def _request(scenario: Path, seeds: range, **kwargs: object) -> BenchmarkRequest:
    return BenchmarkRequest.create(
        scenarios=[str(scenario), "concert"],
        planners=["straight", "tests.benchmark.test_runner:Waiter"],
        seeds=list(seeds),
        **kwargs,  # type: ignore[arg-type]
    )


class Waiter:
    """Waits 20 steps, then drives at half speed: a second planner that differs."""

    name = "waiter"
    detection_range_m = 2.0

    def reset(self, context, rng):  # type: ignore[no-untyped-def]
        self.goal = context.robot_goal

    def act(self, observation):  # type: ignore[no-untyped-def]
        import numpy as np

        r = observation.robot
        if observation.step < 20:
            return np.zeros(2)
        heading = np.arctan2(self.goal[1] - r.y, self.goal[0] - r.x)
        err = (heading - r.theta + np.pi) % (2 * np.pi) - np.pi
        return np.array([0.25, 2.0 * err])


class SlowStraight:
    """``straight``, 0.5 ms slower per step, so that a run of the short scenario lasts
    seconds and a signal reliably lands in the middle of it (without the delay all
    200 episodes can finish between two polls of the interrupt test)."""

    def __init__(self) -> None:
        from srfm.planners import make_planner

        self.inner = make_planner("straight")
        self.name = "slow-straight"
        self.detection_range_m = self.inner.detection_range_m

    def reset(self, context, rng):  # type: ignore[no-untyped-def]
        self.inner.reset(context, rng)

    def act(self, observation):  # type: ignore[no-untyped-def]
        time.sleep(0.0005)
        return self.inner.act(observation)


SLOW = "tests.benchmark.test_runner:SlowStraight"


def _tables(out: Path) -> dict[str, bytes]:
    return {name: (out / name).read_bytes() for name in TABLES}


@pytest.fixture(scope="module")
def reference_run(short_scenario: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("ref")
    summary = run_benchmark(_request(short_scenario, range(4)), out, jobs=2)
    assert summary.episodes == summary.simulated == 2 * 2 * 4
    return out


def test_results_folder_layout(reference_run: Path) -> None:
    out = reference_run
    for name in (*TABLES, "manifest.json", "figures/deviation.png", "figures/paths_short.png"):
        assert (out / name).is_file(), name
    assert (out / "figures/paths_concert.png").read_bytes()[:4] == b"\x89PNG"
    rows = list(csv.DictReader((out / "episodes.csv").open()))
    assert len(rows) == 16
    assert {r["planner"] for r in rows} == {"straight", "tests.benchmark.test_runner:Waiter"}
    peds = list(csv.DictReader((out / "pedestrians.csv").open()))
    assert len(peds) == 160
    manifest = json.loads((out / "manifest.json").read_text())
    assert manifest["params"] == SRFMParams().as_dict()
    assert set(manifest["scenarios"]) == {"short", "concert"}
    assert "numpy" in manifest["versions"]
    md = (out / "table.md").read_text()
    assert md.count("| short |") == 2
    assert "Fréchet" in md
    # Issue 41: one noise floor per (scenario, seed), whatever the planners, in the
    # summary beside each scenario; the same numbers as the crowd simulated again.
    floors = sorted(p.relative_to(out).as_posix() for p in (out / "floor").rglob("*.json"))
    assert floors == [
        f"floor/{s}/seed-{k:06d}.json" for s in ("concert", "short") for k in range(4)
    ]
    summary = json.loads((out / "summary.json").read_text())
    floor = summary["attribution"]["scenarios"]["concert"]["floor"]
    from srfm.metrics.attribution import noise_floor
    from srfm.scenarios import load_scenario
    from srfm.sim.floor import nudged_twins

    again = noise_floor(nudged_twins(load_scenario("concert"), 2, SRFMParams()))
    assert floor["values"][2] == float(again.mean())
    assert "Noise floor (no robot, one start moved 1 mm)" in (out / "table_extended.md").read_text()


def test_episode_files_hold_the_metrics_of_the_episode(reference_run: Path) -> None:
    from srfm.sim.episode import run_episode

    expected = episode_metrics(run_episode("concert", 2, "straight"))
    got = read_episode(episode_path(reference_run, "concert", "straight", 2))
    assert (got.scenario, got.planner, got.seed) == ("concert", "straight", 2)
    assert got.values.keys() == expected.values.keys()
    for name, value in expected.values.items():
        assert got.values[name] == value or (math.isnan(value) and math.isnan(got.values[name]))
    for name, arr in expected.pedestrians.items():
        np.testing.assert_array_equal(got.pedestrians[name], arr)


def test_same_request_gives_byte_identical_tables(
    reference_run: Path, short_scenario: Path, tmp_path: Path
) -> None:
    run_benchmark(_request(short_scenario, range(4)), tmp_path, jobs=1)
    assert _tables(tmp_path) == _tables(reference_run)
    assert (tmp_path / "figures/deviation.png").read_bytes() == (
        reference_run / "figures/deviation.png"
    ).read_bytes()


def test_resume_skips_finished_episodes(
    reference_run: Path, short_scenario: Path, tmp_path: Path
) -> None:
    request = _request(short_scenario, range(4))
    run_benchmark(request, tmp_path, jobs=2, figures=False)
    gone = [
        episode_path(tmp_path, "short", "straight", 1),
        episode_path(tmp_path, "concert", "tests.benchmark.test_runner:Waiter", 3),
    ]
    for path in gone:
        path.unlink()
    stale = gone[0].parent / ".seed-000001.json.abc.tmp"
    stale.write_text("half")
    seen: list[int] = []
    summary = run_benchmark(request, tmp_path, jobs=2, figures=False, on_progress=seen.append)
    assert summary.simulated == 2
    assert seen[0] == 14
    assert sum(seen) == 16
    assert not stale.exists()
    assert _tables(tmp_path) == _tables(reference_run)


def test_interrupted_run_resumes_to_the_same_tables(short_scenario: Path, tmp_path: Path) -> None:
    out = tmp_path / "run"
    cmd = [
        sys.executable,
        "-m",
        "srfm.cli",
        "benchmark",
        "-s",
        str(short_scenario),
        "-p",
        SLOW,
        "--seeds",
        "0-199",
        "--out",
        str(out),
        "-j",
        "2",
        "--no-figures",
    ]
    # A shell starts background jobs with SIGINT ignored, and Python keeps it ignored:
    # give the run the default disposition, as a terminal would (a suite started with
    # `make test &` otherwise sees the run ignore the signal and finish with status 0).
    proc = subprocess.Popen(
        cmd,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    episodes = episode_path(out, "short", SLOW, 0).parent
    deadline = time.monotonic() + 300
    while time.monotonic() < deadline and len(list(episodes.glob("seed-*.json"))) < 10:
        time.sleep(0.05)
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 130
    assert "run the same command again to resume" in err
    assert "Traceback" not in err
    done = len(list(episodes.glob("seed-*.json")))
    assert 10 <= done < 200, "the run was not interrupted part way"
    for path in episodes.glob("seed-*.json"):
        json.loads(path.read_text())  # every file that exists is complete
    resumed = run_benchmark(
        BenchmarkRequest.create(scenarios=[str(short_scenario)], planners=[SLOW], seeds=range(200)),
        out,
        jobs=2,
        figures=False,
    )
    assert resumed.simulated == 200 - done
    fresh = tmp_path / "fresh"
    run_benchmark(
        BenchmarkRequest.create(scenarios=[str(short_scenario)], planners=[SLOW], seeds=range(200)),
        fresh,
        jobs=2,
        figures=False,
    )
    assert _tables(out) == _tables(fresh)


def test_folder_of_another_run_is_refused(reference_run: Path, short_scenario: Path) -> None:
    other = _request(short_scenario, range(4), params=SRFMParams(a_robot=1.0))
    with pytest.raises(BenchmarkError, match="other params"):
        run_benchmark(other, reference_run, jobs=1)
    changed = write_scenario(
        short_scenario.parent / "changed.toml",
        SHORT.replace("horizon_steps = 120", "horizon_steps = 90"),
    )
    with pytest.raises(BenchmarkError, match="different scenario 'short'"):
        run_benchmark(_request(changed, range(4)), reference_run, jobs=1)


def test_bad_requests_name_the_bad_value(short_scenario: Path) -> None:
    with pytest.raises(BenchmarkError, match="seeds given twice: 3"):
        BenchmarkRequest.create(scenarios=["concert"], planners=["straight"], seeds=[3, 3])
    with pytest.raises(BenchmarkError, match="reference planner 'vo'"):
        BenchmarkRequest.create(scenarios=["concert"], planners=["straight"], reference="vo")
    with pytest.raises(ValueError, match="unknown planner 'nope'"):
        BenchmarkRequest.create(scenarios=["concert"], planners=["nope"])
    with pytest.raises(ValueError, match="nowhere"):
        BenchmarkRequest.create(scenarios=["nowhere"], planners=["straight"])
    scenario = load_scenario(short_scenario)
    with pytest.raises(BenchmarkError, match="at least one seed"):
        BenchmarkRequest(scenarios=(scenario,), planners=("straight",), seeds=())


def test_cli_quick_run_and_errors(short_scenario: Path, tmp_path: Path) -> None:
    runner = CliRunner()
    out = tmp_path / "cli"
    result = runner.invoke(
        main,
        [
            "benchmark",
            "--quick",
            "-s",
            str(short_scenario),
            "-p",
            "straight",
            "--out",
            str(out),
            "-j",
            "1",
            "--no-figures",
        ],
    )
    assert result.exit_code == 0, result.output
    assert "| short | straight |" in result.output
    assert len(list((out / "episodes/short/straight").glob("*.json"))) == 3
    bad = runner.invoke(main, ["benchmark", "--seeds", "5-2", "--out", str(out)])
    assert bad.exit_code == 2
    assert "'5-2' is not a seed" in bad.output
    unknown = runner.invoke(main, ["benchmark", "-p", "teleport", "--out", str(out)])
    assert unknown.exit_code == 2
    assert "unknown planner 'teleport'" in unknown.output


def test_file_instead_of_folder(tmp_path: Path, short_scenario: Path) -> None:
    target = tmp_path / "file"
    target.write_text("keep me")
    with pytest.raises(BenchmarkError, match="not a folder"):
        run_benchmark(_request(short_scenario, range(1)), target, jobs=1)
    assert target.read_text() == "keep me"
    assert os.path.exists(target)


def test_path_figures_come_from_the_workers_episodes(
    reference_run: Path, short_scenario: Path, tmp_path: Path
) -> None:
    """Workers keep the figure seed's trajectories; drawing from them gives the same
    picture as simulating that seed again (the fallback for folders without them)."""
    import shutil

    from srfm.benchmark import write_reports

    out = tmp_path / "copy"
    shutil.copytree(reference_run, out)
    saved = out / "figures" / "episodes"
    assert sorted(p.name for p in (saved / "concert").iterdir()) == [
        "straight.npz",
        "tests.benchmark.test_runner:Waiter.npz",
    ]
    shutil.rmtree(saved)
    write_reports(out, _request(short_scenario, range(4)))
    for name in ("paths_short.png", "paths_concert.png"):
        assert (out / "figures" / name).read_bytes() == (
            reference_run / "figures" / name
        ).read_bytes()


def test_a_path_figure_is_drawn_once_its_episodes_are_done(
    short_scenario: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """While the episodes run: a scenario's figure right after its last figure episode
    (here one task per scenario and planner, run in order), before the next scenario's
    episodes; the report phase draws none again."""
    from srfm.benchmark import _runner

    drawn: list[tuple[str, int]] = []
    draw = _runner.render_paths_figure

    def spy(out: Path, request: BenchmarkRequest, scenario: Any) -> bytes:
        drawn.append((scenario.name, len(list((out / "episodes").rglob("*.json")))))
        return draw(out, request, scenario)

    monkeypatch.setattr(_runner, "render_paths_figure", spy)
    run_benchmark(_request(short_scenario, range(1)), tmp_path / "run", jobs=1)
    assert drawn == [("short", 2), ("concert", 4)]


_THREADS_SCRIPT = """
import json, multiprocessing
import numba, numpy
from threadpoolctl import threadpool_info
from srfm.benchmark._workers import init_worker

def counts():
    numba.get_num_threads()  # launch numba's threading layer
    return {"numba": numba.get_num_threads(),
            "pools": {p["internal_api"]: p["num_threads"] for p in threadpool_info()}}

parent = counts()
with multiprocessing.get_context("fork").Pool(1, initializer=init_worker) as pool:
    worker = pool.apply(counts)
print(json.dumps({"parent": parent, "worker": worker}))
"""


def test_workers_run_with_one_thread() -> None:
    """The libraries are loaded (two threads each) before the fork; the worker
    initialiser still brings numba and every BLAS/OpenMP pool down to one thread."""
    env = dict(os.environ)
    for var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
        env[var] = "2"
    out = subprocess.run(
        [sys.executable, "-c", _THREADS_SCRIPT],
        env=env,
        cwd=REPO,
        capture_output=True,
        text=True,
        timeout=300,
        check=True,
    ).stdout
    counts = json.loads(out.splitlines()[-1])
    parent, worker = counts["parent"], counts["worker"]
    assert parent["numba"] == 2
    assert parent["pools"], "no BLAS/OpenMP pool found: numpy should bring OpenBLAS"
    assert set(parent["pools"].values()) == {2}
    assert worker["numba"] == 1
    assert worker["pools"].keys() >= parent["pools"].keys()
    assert set(worker["pools"].values()) == {1}


def test_kernels_are_compiled_in_the_parent_before_forking(
    short_scenario: Path, tmp_path: Path
) -> None:
    # issue 19: the parent compiles what the workers will call (only the requested
    # planners), so that forked workers inherit the compiled kernels; nothing is written.
    # A forked helper compiles the planners' kernels while the parent compiles the
    # shared ones; the parent then has the helper's too (loaded from numba's cache)
    from srfm.benchmark._runner import _compile_in_parent, _Task
    from srfm.metrics import _kernels as _metric_kernels
    from srfm.planners import _dwa_kernels, _orca_kernels

    scenario = load_scenario(short_scenario)
    tasks = [
        _Task(
            scenario=scenario,
            episodes=((0, (planner,)),),
            params=SRFMParams(),
            out=str(tmp_path),
            writer=None,
            figure_seed=None,
        )
        for planner in ("dwa", "orca")
    ]
    _compile_in_parent(tasks)
    assert _metric_kernels.frechet_sq_batch.signatures  # the shared kernels
    assert _dwa_kernels.dwa_unicycle.signatures  # the planners
    assert _orca_kernels.orca_command.signatures
    assert list(tmp_path.iterdir()) == []


def test_every_table_names_the_response_model(
    reference_run: Path, short_scenario: Path, tmp_path: Path
) -> None:
    """Issue 40: the legend of table.md (and of the other tables) names the response
    model the table was computed under, the preset's name or "custom parameters"."""
    from srfm.models.params import PRESETS

    names = ("table.md", "outcomes.md", "table_extended.md", "table.tex", "table_extended.tex")
    for name in names:
        text = (reference_run / name).read_text(encoding="utf-8")
        assert "Response model of the pedestrians: agrawal2024." in text, name
    out = tmp_path / "ttc"
    run_benchmark(
        _request(short_scenario, range(2), params=PRESETS["navwareset2026_ttc"]),
        out,
        jobs=1,
        figures=False,
    )
    for name in names:
        text = (out / name).read_text(encoding="utf-8")
        assert "Response model of the pedestrians: navwareset2026_ttc." in text, name
        assert "agrawal2024" not in text, name
    custom = tmp_path / "custom"
    run_benchmark(
        _request(short_scenario, range(2), params=SRFMParams().replace(a_robot=1.0)),
        custom,
        jobs=1,
        figures=False,
    )
    legend = (custom / "table.md").read_text(encoding="utf-8")
    assert "Response model of the pedestrians: custom parameters (exponential robot force)." in (
        legend
    )
