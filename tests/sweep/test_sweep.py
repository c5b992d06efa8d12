"""``srfm sweep``: the spec, the Parquet dataset, executors and worker counts, resuming
after a kill, a real loopback Dask cluster that loses a worker, and the report."""

from __future__ import annotations

import json
import math
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pyarrow.dataset as ds
import pytest
from click.testing import CliRunner

from srfm.cli import main
from srfm.errors import SweepError
from srfm.sweep import load_spec, run_sweep
from srfm.sweep.report import kendall_tau, load_sweep, write_sweep_report
from tests.benchmark.test_runner import SHORT, SLOW
from tests.conftest import REPO, write_scenario

BIN = Path(sys.executable).parent
WAITER = "tests.benchmark.test_runner:Waiter"  # differs from SLOW (a straight line)
ENV = {**os.environ, "PYTHONPATH": str(REPO)}
HAS_DASK = True
try:
    import distributed  # noqa: F401
except ImportError:  # pragma: no cover - the sweep extra is installed in CI
    HAS_DASK = False
needs_dask = pytest.mark.skipif(
    not HAS_DASK and os.environ.get("CI") != "true", reason="the sweep extra is not installed"
)

SPEC = """
schema_version = 1
name = "tiny"
scenarios = ["short.toml"]
planners = ["{waiter}", "{slow}"]
seeds = "{seeds}"
seeds_per_task = 2

[design]
kind = "grid"
[design.factors]
a_robot = [3.0, 8.0]
b_robot = [0.6, 1.2]
"""


def _spec(folder: Path, seeds: str = "0-3", name: str = "spec.toml") -> Path:
    write_scenario(folder / "short.toml", SHORT)
    path = folder / name
    path.write_text(SPEC.format(waiter=WAITER, slow=SLOW, seeds=seeds), encoding="utf-8")
    return path


def _files(out: Path) -> dict[str, bytes]:
    return {
        str(p.relative_to(out)): p.read_bytes() for p in sorted((out / "data").rglob("*.parquet"))
    }


@pytest.fixture(scope="module")
def spec_file(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return _spec(tmp_path_factory.mktemp("spec"))


@pytest.fixture(scope="module")
def reference(spec_file: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("ref") / "sweep"
    summary = run_sweep(load_spec(spec_file), out, jobs=1)
    assert summary.simulated == summary.episodes == 4 * 2 * 4
    assert summary.partitions == 16
    return out


def test_dataset_one_row_per_episode_with_the_cell(spec_file: Path, reference: Path) -> None:
    table = ds.dataset(reference / "data", format="parquet", partitioning="hive").to_table()
    assert table.num_rows == 32
    rows = table.to_pylist()
    cells = {(r["a_robot"], r["b_robot"]) for r in rows}
    assert cells == {(3.0, 0.6), (3.0, 1.2), (8.0, 0.6), (8.0, 1.2)}
    assert {r["planner"] for r in rows} == {WAITER, SLOW}
    assert all(r["frechet_m"] is not None and r["frechet_m"] >= 0 for r in rows)
    # the robot force matters: a stronger A_r pushes people further (same seeds)
    mean = {a: sum(r["frechet_m"] for r in rows if r["a_robot"] == a) / 16 for a in (3.0, 8.0)}
    assert mean[8.0] > mean[3.0]
    # the second run of the same spec does nothing and changes no byte
    before = _files(reference)
    again = run_sweep(load_spec(spec_file), reference)
    assert again.simulated == 0
    assert _files(reference) == before


@needs_dask
def test_executors_and_worker_counts_give_the_same_bytes(
    spec_file: Path, reference: Path, tmp_path: Path
) -> None:
    """The reference ran in this process (one worker); here a Dask LocalCluster of
    two; the loopback cluster test below compares two workers (then one) with a
    process pool of two."""
    run_sweep(load_spec(spec_file), tmp_path / "dask2", jobs=2, executor="dask")
    expected = _files(reference)
    assert len(expected) == 16
    assert _files(tmp_path / "dask2") == expected


def test_killed_sweep_resumes_to_the_same_bytes(
    spec_file: Path, reference: Path, tmp_path: Path
) -> None:
    """SIGKILL part way (no clean-up at all), the dataset read while the sweep runs,
    then the same command again: only the missing partitions run."""
    out = tmp_path / "run"
    proc = subprocess.Popen(
        [sys.executable, "-m", "srfm.cli", "sweep", str(spec_file), "--out", str(out)],
        env=ENV, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
    )  # fmt: skip
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and len(list(out.rglob("*.parquet"))) < 4:
        time.sleep(0.02)
    # readable while it runs: only whole files are seen, one row per episode
    rows = ds.dataset(out / "data", format="parquet", partitioning="hive").to_table().num_rows
    assert rows >= 8
    assert rows % 2 == 0
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    done = len(list(out.rglob("*.parquet")))
    assert 4 <= done < 16, "the sweep was not killed part way"
    result = CliRunner().invoke(main, ["sweep", str(spec_file), "--out", str(out)])
    assert result.exit_code == 0, result.output
    assert f"simulated {32 - 2 * done} of 32 episodes" in result.output
    assert _files(out) == _files(reference)
    assert not [p for p in out.rglob(".*") if p.name.endswith(".tmp")]


def test_damaged_partition_is_run_again(spec_file: Path, reference: Path, tmp_path: Path) -> None:
    import shutil

    out = tmp_path / "copy"
    shutil.copytree(reference, out)
    victim = sorted((out / "data").rglob("*.parquet"))[5]  # of 16
    victim.write_bytes(victim.read_bytes()[:100])
    summary = run_sweep(load_spec(spec_file), out)
    assert summary.simulated == 2
    assert summary.rewritten == (str(victim.relative_to(out)),)
    assert _files(out) == _files(reference)


def test_a_folder_of_another_sweep_is_refused(spec_file: Path, reference: Path) -> None:
    other = spec_file.parent / "other.toml"
    other.write_text(spec_file.read_text().replace("0-3", "0-4"), encoding="utf-8")
    with pytest.raises(SweepError, match="other seeds"):
        run_sweep(load_spec(other), reference)


@needs_dask
def test_loopback_cluster_survives_a_killed_worker(tmp_path: Path) -> None:
    """A real `dask scheduler` and two `dask worker` processes (no nanny: a killed
    worker stays dead) on 127.0.0.1; the sweep goes through --scheduler; one worker
    is SIGKILLed once the first partitions are written; the sweep completes with the
    bytes of a local run."""
    spec = _spec(tmp_path, seeds="0-5", name="cluster.toml")
    sched_file = tmp_path / "scheduler.json"

    def start(args: list[str], log: str) -> subprocess.Popen[bytes]:
        with (tmp_path / log).open("wb") as fh:
            return subprocess.Popen(
                [str(BIN / "dask"), *args], cwd=REPO, env=ENV, stdout=fh,
                stderr=subprocess.STDOUT, start_new_session=True,
            )  # fmt: skip

    procs = [
        start(["scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
               "--scheduler-file", str(sched_file)], "scheduler.log")
    ]  # fmt: skip
    out = tmp_path / "cluster"
    try:
        deadline = time.monotonic() + 60
        while not sched_file.exists() and time.monotonic() < deadline:
            time.sleep(0.1)
        address = json.loads(sched_file.read_text())["address"]
        assert address.startswith("tcp://127.0.0.1:")
        for k in range(2):
            procs.append(
                start(["worker", address, "--nthreads", "1", "--no-nanny",
                       "--no-dashboard", "--host", "127.0.0.1"], f"worker{k}.log")
            )  # fmt: skip
        run = subprocess.Popen(
            [sys.executable, "-m", "srfm.cli", "sweep", str(spec), "--out", str(out),
             "--scheduler", address],
            cwd=REPO, env=ENV, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
        )  # fmt: skip
        deadline = time.monotonic() + 120
        while time.monotonic() < deadline and len(list(out.rglob("*.parquet"))) < 3:
            time.sleep(0.05)
        os.killpg(procs[1].pid, signal.SIGKILL)
        procs[1].wait()
        at_kill = len(list(out.rglob("*.parquet")))
        assert at_kill < 24, "the sweep ended before the worker was killed"
        stdout, err = run.communicate(timeout=300)
        assert run.returncode == 0, err
        assert "simulated 48 of 48 episodes" in stdout
    finally:
        for proc in procs:
            if proc.poll() is None:
                os.killpg(proc.pid, signal.SIGKILL)
                proc.wait()
    local = tmp_path / "local"
    run_sweep(load_spec(spec), local, jobs=2)
    assert len(_files(local)) == 24
    assert _files(out) == _files(local)


def test_spec_errors_name_the_file_and_key(tmp_path: Path) -> None:
    good = _spec(tmp_path).read_text()
    cases = {
        "unknown factor": (
            good.replace("b_robot = [0.6, 1.2]", "b_rob = [0.6]"),
            "design.factors.b_rob: unknown factor",
        ),
        "bad value": (
            good.replace("[0.6, 1.2]", "[0.6, -1.0]"),
            "design.factors.b_robot: b_robot must be > 0",
        ),
        "bad key": ("planers = []\n" + good, "planers: unknown key"),
        "bad kind": (good.replace('kind = "grid"', 'kind = "latin"'), "design.kind: must be"),
        "bad seeds": (good.replace('"0-3"', '"3-0"'), "seeds: bad range"),
        "fixed crowd": (
            good.replace("b_robot = [0.6, 1.2]", "crowd_size = [5, 10]"),
            "design.factors.crowd_size: the crowd size of a scenario of kind 'fixed'",
        ),
        "unknown planner": (good.replace(f'"{WAITER}"', '"nope"'), "planners: unknown planner"),
        "no design": (good.split("[design]")[0], "design: is required"),
    }
    for what, (text, message) in cases.items():
        path = tmp_path / "bad.toml"
        path.write_text(text, encoding="utf-8")
        with pytest.raises(SweepError) as info:
            load_spec(path)
        assert str(info.value).startswith(f"{path}: "), what
        assert message in str(info.value), (what, str(info.value))
    result = CliRunner().invoke(main, ["sweep", str(path), "--out", str(tmp_path / "o")])
    assert result.exit_code == 2
    assert "design: is required" in result.output
    assert not (tmp_path / "o").exists()


def test_random_design_is_seeded_and_scenario_factors_apply(tmp_path: Path) -> None:
    text = """
schema_version = 1
scenarios = ["random"]
planners = ["straight"]
seeds = [0, 1]
[design]
kind = "random"
samples = 5
seed = 7
[design.factors]
a_robot = { low = 0.0, high = 16.0 }
crowd_size = [4, 12]
ped_speed_mps = [1.0, 1.6]
"""
    path = tmp_path / "random.toml"
    path.write_text(text, encoding="utf-8")
    a, b = load_spec(path), load_spec(path)
    assert [c.values for c in a.cells] == [c.values for c in b.cells]
    assert len(a.cells) == 5
    assert all(0.0 <= c.as_dict()["a_robot"] < 16.0 for c in a.cells)
    path.write_text(text.replace("seed = 7", "seed = 8"), encoding="utf-8")
    assert [c.values for c in load_spec(path).cells] != [c.values for c in a.cells]
    from srfm.sweep._run import all_tasks

    task = all_tasks(a)[0]
    values = task.cell.as_dict()
    assert task.scenario.n_pedestrians == values["crowd_size"]
    assert task.scenario.ped_desired_speed_mps == values["ped_speed_mps"]
    assert task.params.a_robot == values["a_robot"]


def test_kendall_tau() -> None:
    assert kendall_tau([1, 2, 3, 4], [10, 20, 30, 40]) == pytest.approx(1.0)
    assert kendall_tau([1, 2, 3, 4], [40, 30, 20, 10]) == pytest.approx(-1.0)
    assert kendall_tau([1, 2, 3, 4], [2, 1, 3, 4]) == pytest.approx(2 / 3)
    assert math.isnan(kendall_tau([0, 0, 0], [1, 2, 3]))  # all tied: no ranking


def test_report(reference: Path) -> None:
    files = write_sweep_report(reference)
    names = sorted(p.name for p in files)
    assert names == sorted(
        ["a_robot.png", "a_robot_by_scenario.png", "b_robot.png", "b_robot_by_scenario.png",
         "report.md", "rankings.csv"]
    )  # fmt: skip
    for path in files:
        assert path.stat().st_size > 0
    data = load_sweep(reference)
    assert data.episodes == data.expected == 32
    # nearest the base (A_r 7.93, B_r 0.99): A_r 8 and B_r 1.2
    ref = data.reference_cell()
    assert data.cells[ref] == {"a_robot": 8.0, "b_robot": 1.2}
    text = (reference / "report" / "report.md").read_text()
    assert "32 of 32 episodes (complete)" in text
    assert f"Reference cell: `{ref}`" in text
    head = text.split("### Head to head")[1]
    total = int(head.split("Over the ")[1].split(" ")[0])
    assert total == 4  # 4 cells × 1 scenario: the two planners differ in each
    row = next(line for line in head.splitlines() if line.startswith(f"| {WAITER} vs {SLOW} |"))
    assert sum(int(x) for x in row.strip("|").split("|")[1:]) == total
    rankings = (reference / "report" / "rankings.csv").read_text().splitlines()
    assert len(rankings) == 1 + 2 * 4 * 2  # (scenario + all) × cells × planners
    with pytest.raises(SweepError, match="unknown metric 'nope'"):
        write_sweep_report(reference, metric="nope")
    with pytest.raises(SweepError, match="not a sweep folder"):
        write_sweep_report(reference / "data")
