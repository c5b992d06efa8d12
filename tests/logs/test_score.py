"""`srfm score`: every metric and the benchmark tables from MCAP files alone."""

from __future__ import annotations

import shutil
from pathlib import Path

import attrs
import numpy as np
import pytest
from click.testing import CliRunner

from srfm.benchmark import BenchmarkRequest, episode_path, read_episode, run_benchmark
from srfm.cli import main
from srfm.errors import LogError
from srfm.logs import (
    EpisodeLogger,
    LogOptions,
    load_episode,
    metrics_identical,
    score_logs,
    write_episode_mcap,
    write_score_reports,
)
from tests.conftest import RESULT_TABLES
from tests.logs.conftest import files_state

TABLES = RESULT_TABLES


@pytest.fixture(scope="module")
def bench(
    tmp_path_factory: pytest.TempPathFactory, short_scenario
) -> tuple[Path, BenchmarkRequest]:  # type: ignore[no-untyped-def]
    request = BenchmarkRequest.create(
        scenarios=[short_scenario.source, "concert"],
        planners=["straight", "orca"],
        seeds=[4, 0, 2],
        reference="orca",
    )
    out = tmp_path_factory.mktemp("bench") / "results"
    writer = EpisodeLogger.create(
        LogOptions.benchmark_default(),
        scenarios=request.scenarios,
        planners=request.planners,
        seeds=request.seeds,
        reference=request.reference,
    )
    run_benchmark(request, out, jobs=1, figures=False, writer=writer)
    return out, request


def test_logs_layout(bench) -> None:  # type: ignore[no-untyped-def]
    out, request = bench
    logs = out / "logs"
    for scenario in ("short", "concert"):
        for planner in request.planners:
            folder = logs / scenario / planner
            assert sorted(p.name for p in folder.iterdir()) == [
                "seed-000000.mcap",
                "seed-000002.mcap",
                "seed-000004.mcap",
                "seed-000004.rrd",
            ]  # a recording for the first seed of the request only
        cf = sorted(p.name for p in (logs / scenario / "_counterfactual").iterdir())
        assert cf == ["seed-000000.mcap", "seed-000002.mcap", "seed-000004.mcap"]
    assert not list(logs.rglob(".*.tmp"))


def test_mcap_core_reads_every_benchmark_log(bench, mcap_core) -> None:  # type: ignore[no-untyped-def]
    """Every file a benchmark writes opens in the official @mcap/core reader, with the
    messages per channel its statistics record announces."""
    out, request = bench
    files = sorted((out / "logs").rglob("*.mcap"))
    assert len(files) == 2 * len(request.seeds) * (len(request.planners) + 1)
    for r in mcap_core(files):
        counts = r["counts"]
        assert counts == r["statistics"]["channelMessageCounts"], r["file"]
        if "/_counterfactual/" in r["file"]:
            assert counts == {"/srfm/episode": 1, "/srfm/trajectories": 1}
        else:
            assert counts["/srfm/trajectories"] == 2  # robot, factual
            assert counts["/srfm/metrics"] == counts["/srfm/episode"] == 1
            assert counts["/foxglove/scene"] >= 3


def test_rescored_metrics_equal_the_online_ones_bit_for_bit(bench) -> None:  # type: ignore[no-untyped-def]
    out, _request = bench
    result = score_logs([out])
    assert result.complete
    assert not result.notes
    assert not result.mismatches
    assert result.scenarios == ("short", "concert")
    assert result.planners == ("straight", "orca")
    assert result.seeds == (4, 0, 2)
    assert result.reference == "orca"
    assert len(result.episodes) == 12
    for e in result.episodes:
        m = e.metrics
        online = read_episode(episode_path(out, m.scenario, m.planner, m.seed))
        assert metrics_identical(m, online), e.path
        assert e.online is not None
        assert metrics_identical(e.online, online)


def test_rescored_tables_are_byte_identical(bench, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    out, _ = bench
    files = write_score_reports(tmp_path / "re", score_logs([out / "logs"]))
    assert sorted(files) == sorted(TABLES)
    for name in TABLES:
        assert (tmp_path / "re" / name).read_bytes() == (out / name).read_bytes(), name


def test_cli_score_prints_the_table_and_writes_reports(bench, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    out, _ = bench
    res = CliRunner().invoke(main, ["score", str(out), "--out", str(tmp_path / "re")])
    assert res.exit_code == 0, res.output
    assert res.stdout == (out / "table.md").read_text(encoding="utf-8")
    assert "all 12 logged episodes recomputed bit for bit" in res.stderr
    assert (tmp_path / "re" / "table.tex").read_bytes() == (out / "table.tex").read_bytes()
    # The benchmark's own folder is never overwritten, and that is checked first.
    before = files_state(out)
    res = CliRunner().invoke(main, ["score", str(out / "logs"), "--out", str(out)])
    assert res.exit_code == 2
    assert "is a benchmark results folder" in res.output
    assert files_state(out) == before


@pytest.mark.parametrize("damage", ["truncate", "foreign", "flip"])
def test_a_bad_file_names_itself_and_touches_nothing(bench, tmp_path: Path, damage: str) -> None:  # type: ignore[no-untyped-def]
    out, _ = bench
    logs = tmp_path / "logs"
    shutil.copytree(out / "logs", logs)
    bad = logs / "concert" / "orca" / "seed-000002.mcap"
    data = bad.read_bytes()
    if damage == "truncate":
        bad.write_bytes(data[: len(data) // 3])
    elif damage == "foreign":
        bad.write_bytes(b"\x89MCAP0\r\n" + b"\x00" * 64)
    else:
        flipped = bytearray(data)
        flipped[len(data) // 2] ^= 0xFF
        bad.write_bytes(bytes(flipped))
    reports = tmp_path / "reports"
    reports.mkdir()
    (reports / "table.md").write_text("an earlier table\n", encoding="utf-8")
    before_reports, before_logs = files_state(reports), files_state(logs)
    res = CliRunner().invoke(main, ["score", str(logs), "--out", str(reports)])
    assert res.exit_code == 2
    assert str(bad) in res.output
    assert "Traceback" not in res.output
    assert files_state(reports) == before_reports
    assert files_state(logs) == before_logs


def test_a_missing_shared_counterfactual_is_named(bench, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    out, _ = bench
    logs = tmp_path / "logs"
    shutil.copytree(out / "logs", logs)
    (logs / "short" / "_counterfactual" / "seed-000000.mcap").unlink()
    with pytest.raises(LogError, match=r"seed-000000\.mcap: its counterfactual file .* missing"):
        score_logs([logs])


def test_partial_logs_give_tables_over_the_common_seeds(bench, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    out, _ = bench
    logs = tmp_path / "logs"
    shutil.copytree(out / "logs", logs)
    (logs / "concert" / "straight" / "seed-000000.mcap").unlink()
    result = score_logs([logs])
    assert not result.complete
    assert result.seeds == (4, 2)
    assert any("left out of the tables" in n for n in result.notes)
    one = score_logs([logs / "short" / "orca" / "seed-000004.mcap"])
    assert (one.scenarios, one.planners, one.seeds, one.reference) == (
        ("short",),
        ("orca",),
        (4,),
        "orca",
    )
    assert not one.complete


def test_duplicates_and_mixed_parameters_are_refused(bench, tmp_path: Path, episode) -> None:  # type: ignore[no-untyped-def]
    out, _ = bench
    logs = tmp_path / "logs"
    shutil.copytree(out / "logs", logs)
    (logs / "concert" / "copy").mkdir()
    shutil.copy(logs / "concert" / "orca" / "seed-000000.mcap", logs / "concert" / "copy")
    with pytest.raises(LogError, match=r"seed-000000\.mcap: the same episode .* as .*copy/"):
        score_logs([logs])
    shutil.rmtree(logs / "concert" / "copy")
    scenario, record, metrics = episode("concert", 7, "straight")
    other = attrs.evolve(record, params=record.params.replace(a_robot=1.0))
    write_episode_mcap(tmp_path / "other.mcap", other, scenario=scenario, metrics=metrics)
    with pytest.raises(LogError, match="other SRFM parameters"):
        score_logs([logs, tmp_path / "other.mcap"])


def test_changed_logged_metrics_are_reported(tmp_path: Path, episode) -> None:  # type: ignore[no-untyped-def]
    scenario, record, metrics = episode("concert", 1, "straight")
    values = dict(metrics.values)
    values["frechet_m"] = float(np.nextafter(values["frechet_m"], np.inf))  # one ulp
    forged = attrs.evolve(metrics, values=values)
    write_episode_mcap(tmp_path / "ep.mcap", record, scenario=scenario, metrics=forged)
    assert load_episode(tmp_path / "ep.mcap").online_metrics is not None
    res = CliRunner().invoke(main, ["score", str(tmp_path / "ep.mcap")])
    assert res.exit_code == 1
    assert "MISMATCH" in res.stderr
    assert "ep.mcap" in res.stderr


def test_score_usage_errors(tmp_path: Path) -> None:
    res = CliRunner().invoke(main, ["score", str(tmp_path / "nope")])
    assert res.exit_code == 2
    assert "no such file or folder" in res.output
    (tmp_path / "empty").mkdir()
    res = CliRunner().invoke(main, ["score", str(tmp_path / "empty")])
    assert res.exit_code == 2
    assert "no .mcap files" in res.output
