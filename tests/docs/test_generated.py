"""Every number in the docs' generated blocks comes from the committed results sets
(docs/results/index.md): the pages match what ``make docs-tables`` writes from the
data, the sets fit their size budget and match their registry, and a packed set gives
back the benchmark's own tables bit for bit. Reads data only; simulates nothing but
one tiny benchmark."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from srfm.benchmark import BenchmarkRequest, draw_params, run_benchmark
from srfm.metrics.tables import benchmark_table, to_markdown
from srfm.models.params import SRFMParams, response_model_name
from tests.benchmark.test_runner import SHORT
from tests.conftest import write_scenario
from tools.results import generate, rl_study, sets


def test_every_generated_block_matches_the_results_sets() -> None:
    stale = generate.stale()
    assert stale == [], "run `make docs-tables`: " + "; ".join(stale)


def test_the_results_sets_fit_their_budget() -> None:
    total = sum(sets.folder_bytes(n) for n in sets.SETS if sets.exists(n))
    assert total <= sets.BUDGET_BYTES, f"{total / 1e6:.1f} MB"


@pytest.mark.parametrize("name", [n for n in sorted(sets.SETS) if sets.exists(n)])
def test_a_committed_set_is_what_its_command_makes(name: str) -> None:
    rset = sets.SETS[name]
    manifest = sets.manifest(name)
    record = manifest["results_set"]
    assert record["name"] == name
    assert record["command"] == rset.command()
    assert record["columns"] == rset.columns
    req = manifest["request"]
    k = (
        sets.read_json(rset.folder / sets.PARAM_DRAWS)["k"]
        if "--param-draws" in rset.options
        else 0
    )
    cells = len(req["scenarios"]) * len(req["planners"]) * len(req["seeds"])
    table = sets.table(name)
    assert table.num_rows == cells
    assert record["episodes"] == cells * (1 + k)
    # one episode per (scenario, planner, seed), every one of the request
    keys = set(zip(*(table[c].to_pylist() for c in ("scenario", "planner", "seed")), strict=True))
    assert len(keys) == cells
    assert {s for s, _, _ in keys} == set(req["scenarios"])
    assert {p for _, p, _ in keys} == set(req["planners"])


def test_generate_puts_back_a_hand_edited_number(tmp_path: Path) -> None:
    page = tmp_path / "page.md"
    block = generate.render("rl-usual-misses", page)
    text = (
        "before\n<!-- generated: rl-usual-misses -->\n\n"
        f"{block}\n\n<!-- end: rl-usual-misses -->\nafter\n"
    )
    assert generate.rewrite(text, page) == (text, [])
    edited = text.replace(" runs (", " runs (1", 1)
    assert edited != text
    assert generate.rewrite(edited, page) == (text, ["rl-usual-misses"])
    with pytest.raises(SystemExit, match="unknown generated block 'nope'"):
        generate.rewrite("<!-- generated: nope -->\nx\n<!-- end: nope -->\n", page)
    with pytest.raises(SystemExit, match="has no"):
        generate.rewrite("<!-- generated: rl-usual-misses -->\nx\n", page)


def test_the_concert_count_is_the_study_tables() -> None:
    text = rl_study.usual_misses()
    cells = rl_study.report_targets()
    concert = [c for (s, _), c in cells.items() if s == "concert"]
    assert sum(c.miss for c in concert) == 12  # the report of 2026-11-27, counted by hand
    assert (
        "(of the 20 runs): `concert`, a standing crowd across the path, missed by 12 runs" in text
    )


def test_a_packed_set_gives_back_the_benchmarks_tables(tmp_path: Path) -> None:
    scenario = write_scenario(tmp_path / "short.toml", SHORT)  # 120 steps: cheap
    request = BenchmarkRequest.create(
        scenarios=[str(scenario)], planners=["straight", "dwa"], seeds=[0, 1, 2]
    )
    out = tmp_path / "run"
    draws = draw_params(request.params, 2, seed=0, source="wide")
    run_benchmark(request, out, jobs=1, figures=False, param_draws=draws)
    rset = sets.ResultsSet("tiny", ("-s", str(scenario)), "all", "a test")
    dest = sets.pack(
        rset,
        out,
        commit="abc1234",
        started="2026-01-01T00:00:00Z",
        finished="2026-01-01T00:01:00Z",
        wall_s=60.0,
        machine="test",
        jobs=1,
        dest=tmp_path / "packed",
    )
    manifest = sets.manifest(dest)
    assert manifest["results_set"]["episodes"] == 6 * 3
    assert manifest["results_set"]["commit"] == "abc1234"
    req = manifest["request"]
    table = benchmark_table(
        sets.episodes(dest),
        scenarios=req["scenarios"],
        planners=req["planners"],
        seeds=req["seeds"],
        reference=req["reference"],
    )
    model = response_model_name(SRFMParams(**manifest["params"]))
    assert to_markdown(table, model=model) == (out / "table.md").read_text(encoding="utf-8")
    # the draws: the benchmark's rankings.json, probabilities and means, bit for bit
    ranked = sets.rank_table_of(dest)
    doc = json.loads((out / "rankings.json").read_text(encoding="utf-8"))
    for s in req["scenarios"]:
        for p in req["planners"]:
            entry = doc["scenarios"][s][p]
            assert list(ranked.probabilities[s][p]) == entry["rank_probabilities"]
            assert list(ranked.means[s][p]) == entry["draw_means"]
    # a folder that is not finished is refused
    (out / "draws" / "draw-001" / "episodes.parquet").unlink()
    with pytest.raises(SystemExit, match="not finished"):
        sets.pack(
            rset,
            out,
            commit="x",
            started="",
            finished="",
            wall_s=0.0,
            machine="",
            jobs=1,
            dest=tmp_path / "again",
        )


def test_the_speed_goal_table_gives_each_goal_its_verdict() -> None:
    def runs(**figures: float) -> list[dict[str, float | None]]:
        return [dict(figures)] * 3

    doc = {
        "date": "2026-12-05 12:00 UTC",
        "commits": {"A": "abc1234"},
        "cores": 2,
        "cpu": "a CPU",
        "command": "python tools/bench/bench_commands.py --json x",
        "rows": {
            "full": {"load_before": "0.1", "load_after": "2.0", "runs": {"A": runs(wall_s=61.0)}},
            "simulate": {"load_before": "0", "load_after": "0", "runs": {"A": runs(wall_s=0.5)}},
            "shared-crowd": {
                "load_before": "0",
                "load_after": "0",
                "runs": {
                    "A": runs(srfm_1000=3.1, jupedsim_1000=1.0, srfm_10000=3.4, jupedsim_10000=1.0)
                },
            },
        },
    }
    lines = generate.performance_goals_table(doc).splitlines()
    verdicts = [
        line.split("|")[5].strip() for line in lines if line.startswith("| `") or "crowd" in line
    ]
    assert verdicts == ["not met", "**met**", "**met**", "not met"]
    del doc["rows"]["full"]  # type: ignore[attr-defined]
    assert "not measured" in generate.performance_goals_table(doc)


def test_the_readme_is_generated_too() -> None:
    readme = sets.ROOT / "README.md"
    assert readme in generate.pages()
    text = readme.read_text(encoding="utf-8")
    assert "<!-- generated: readme-real-people -->" in text
    # the paragraph states the held-out windows and scenes of the response fits' tests
    ade = next(
        r
        for r in json.loads(
            (sets.ROOT / "docs/robot_response/results.json").read_text(encoding="utf-8")
        )["tests"]["ade"]
        if r["model"] == "sidestep" and r["set"] == "pooled"
    )
    assert f"{ade['n_windows']} encounter windows in\n{ade['n_scenes']} scenes" in text or (
        f"{ade['n_windows']} encounter windows in {ade['n_scenes']} scenes" in text
    )
