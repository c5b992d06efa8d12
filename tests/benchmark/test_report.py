"""The results folder's new files: extended tables, Parquet copies, report.html (also in
a real headless Chromium), ``srfm report``, and the refusal of old results folders."""

from __future__ import annotations

import csv
import html.parser
import json
import math
import os
import re
import shutil
from pathlib import Path

import pytest
from click.testing import CliRunner

from srfm.benchmark import BenchmarkRequest, run_benchmark
from srfm.cli import main
from srfm.errors import BenchmarkError
from srfm.metrics import EPISODE_METRICS, PEDESTRIAN_METRICS
from tests.benchmark.test_runner import SHORT
from tests.conftest import write_scenario

CHROMIUM = Path("/usr/bin/chromium")
CHROMIUM_ARGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-component-update",
    "--no-first-run",
    "--disable-sync",
]


@pytest.fixture(scope="module")
def results(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A small benchmark with logs (an MCAP file per episode, .rrd for the first seed)
    and two parameter draws, run through the CLI as a user would."""
    scenario = write_scenario(tmp_path_factory.mktemp("scn") / "short.toml", SHORT)
    out = tmp_path_factory.mktemp("results") / "out"
    result = CliRunner().invoke(
        main,
        [
            "benchmark",
            "-s",
            f"{scenario},concert",
            "-p",
            "straight,tests.benchmark.test_runner:Waiter",
            "--seeds",
            "0-2",
            "--out",
            str(out),
            "-j",
            "1",
            "--param-draws",
            "2",
            "--reference",
            "straight",
        ],
    )
    assert result.exit_code == 0, result.output
    return out


def test_new_files_are_written(results: Path) -> None:
    for name in (
        "report.html",
        "table_extended.md",
        "table_extended.tex",
        "episodes.parquet",
        "pedestrians.parquet",
        "figures/social_work.png",
    ):
        assert (results / name).is_file(), name
    extended = (results / "table_extended.md").read_text(encoding="utf-8")
    for m in EPISODE_METRICS:
        assert f"| `{m.name}`" in extended
    table = (results / "table.md").read_text(encoding="utf-8")
    assert "Time: robot run (s)" in table
    assert "n ≥ 3" in table


def _same(a: str, b: object) -> bool:
    if a == "":
        return b is None
    if isinstance(b, float):
        return math.isclose(float(a), b, rel_tol=0, abs_tol=0) or repr(b) == a
    return str(b) == a


def test_parquet_copies_hold_the_csv_rows(results: Path) -> None:
    import pyarrow.parquet as pq

    for name, metrics in (("episodes", EPISODE_METRICS), ("pedestrians", PEDESTRIAN_METRICS)):
        rows = list(csv.DictReader((results / f"{name}.csv").open(encoding="utf-8")))
        table = pq.read_table(results / f"{name}.parquet").to_pylist()
        assert len(rows) == len(table) > 0
        assert list(rows[0]) == list(table[0])
        for row, record in zip(rows, table, strict=True):
            for key, text in row.items():
                assert _same(text, record[key]), (name, key, text, record[key])
        assert str(pq.read_schema(results / f"{name}.parquet").field("seed").type) == "int64"
        assert {m.name for m in metrics} <= set(table[0])


def test_srfm_report_rebuilds_the_same_page(results: Path, tmp_path: Path) -> None:
    copy = tmp_path / "copy"
    shutil.copytree(results, copy)
    (copy / "report.html").unlink()
    result = CliRunner().invoke(main, ["report", str(copy)])
    assert result.exit_code == 0, result.output
    assert (copy / "report.html").read_bytes() == (results / "report.html").read_bytes()


def test_old_results_folders_are_refused_with_a_clear_error(results: Path, tmp_path: Path) -> None:
    old = tmp_path / "old"
    shutil.copytree(results, old)
    manifest = json.loads((old / "manifest.json").read_text(encoding="utf-8"))
    manifest["schema"] = "srfm.benchmark_manifest/1"
    (old / "manifest.json").write_text(json.dumps(manifest), encoding="utf-8")
    result = CliRunner().invoke(main, ["report", str(old)])
    assert result.exit_code == 2
    assert "manifest schema 'srfm.benchmark_manifest/1'" in result.output
    assert "new --out folder" in result.output
    request = BenchmarkRequest.create(scenarios=["concert"], planners=["straight"], seeds=[0])
    with pytest.raises(BenchmarkError, match=r"older or newer srfm .* new --out folder"):
        run_benchmark(request, old, jobs=1)
    summary = json.loads((results / "summary.json").read_text(encoding="utf-8"))
    summary["schema"] = "srfm.summary/1"
    stale = tmp_path / "stale"
    shutil.copytree(results, stale)
    (stale / "summary.json").write_text(json.dumps(summary), encoding="utf-8")
    result = CliRunner().invoke(main, ["report", str(stale)])
    assert result.exit_code == 2
    assert "summary schema 'srfm.summary/1'" in result.output


class _Targets(html.parser.HTMLParser):
    """Every href and src, and every id, of a page."""

    def __init__(self) -> None:
        super().__init__()
        self.refs: list[str] = []
        self.ids: set[str] = set()

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        for key, value in attrs:
            if key in ("href", "src") and value is not None:
                self.refs.append(value)
            if key == "id" and value is not None:
                self.ids.add(value)


def _missing_targets(folder: Path, refs: list[str], ids: set[str]) -> list[str]:
    """The references of the page that lead nowhere: anchors without their element,
    files that do not exist in the folder, and anything outside it."""
    problems = []
    for ref in refs:
        if ref.startswith("#"):
            if ref[1:] not in ids:
                problems.append(f"anchor {ref}")
        elif "://" in ref or ref.startswith("/") or ".." in ref.split("/"):
            problems.append(f"not a relative path inside the folder: {ref}")
        elif not (folder / ref).is_file():
            problems.append(f"missing file {ref}")
    return problems


def test_every_link_and_image_of_the_page_exists(results: Path, tmp_path: Path) -> None:
    page = _Targets()
    page.feed((results / "report.html").read_text(encoding="utf-8"))
    assert _missing_targets(results, page.refs, page.ids) == []
    mcaps = sorted(
        p.relative_to(results).as_posix()
        for p in (results / "logs").rglob("*.mcap")
        if p.parent.name != "_counterfactual"
    )
    rrds = sorted(p.relative_to(results).as_posix() for p in (results / "logs").rglob("*.rrd"))
    assert len(mcaps) == 12  # 2 scenarios x 2 planners x 3 seeds
    assert len(rrds) == 4  # the first seed of each cell
    assert set(mcaps) | set(rrds) <= set(page.refs)  # every episode's logs are linked
    for name in ("figures/deviation.png", "figures/paths_concert.png", "table.tex"):
        assert name in page.refs
    # The check sees a missing target.
    broken = tmp_path / "broken"
    shutil.copytree(results, broken)
    (broken / "figures/deviation.png").unlink()
    (broken / mcaps[0]).unlink()
    problems = _missing_targets(broken, page.refs, page.ids)
    assert problems == [f"missing file {mcaps[0]}", "missing file figures/deviation.png"] or set(
        problems
    ) == {f"missing file {mcaps[0]}", "missing file figures/deviation.png"}


def test_the_page_names_the_run(results: Path) -> None:
    text = (results / "report.html").read_text(encoding="utf-8")
    manifest = json.loads((results / "manifest.json").read_text(encoding="utf-8"))
    assert manifest["command"].startswith("srfm ")
    assert manifest["request"]["seeds"] == [0, 1, 2]
    for needle in (
        "0–2 (3 seeds)",
        "a_robot",
        "intimate_m",
        "numba",
        "test_runner:Waiter reached its goal",
    ):
        assert needle in text.replace("<b>", "").replace("</b>", ""), needle
    assert "<script" not in text  # nothing to run: opens offline as it is


# The page in a real browser ------------------------------------------------------------


def _browser_or_skip() -> None:
    """Chromium from Debian and the playwright package, or a skip; in CI (CI=true) their
    absence is a failure: .ci/run installs chromium."""
    reasons = []
    if not CHROMIUM.is_file():
        reasons.append(f"{CHROMIUM} is missing (apt-get install chromium)")
    try:
        import playwright.sync_api  # noqa: F401
    except ImportError:
        reasons.append("the playwright package is missing (pip install -e '.[dev]')")
    if reasons:
        message = "no browser for the results page test: " + "; ".join(reasons)
        if os.environ.get("CI") == "true":
            pytest.fail(message)
        pytest.skip(message)


def _load_in_chromium(page_path: Path) -> dict[str, object]:
    """Open the page from disk in headless Chromium: console messages, page errors,
    failed requests, the images' load state, every href and every id."""
    from playwright.sync_api import sync_playwright

    console: list[str] = []
    failed: list[str] = []
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=str(CHROMIUM), args=CHROMIUM_ARGS)
        try:
            page = browser.new_page(viewport={"width": 1400, "height": 900})
            page.on("console", lambda m: console.append(f"{m.type}: {m.text}"))
            page.on("pageerror", lambda e: console.append(f"pageerror: {e}"))
            page.on("requestfailed", lambda r: failed.append(r.url))
            page.goto(page_path.resolve().as_uri(), wait_until="load")
            images = page.evaluate(
                "Array.from(document.images).map(i => "
                "[i.getAttribute('src'), i.complete, i.naturalWidth])"
            )
            hrefs = page.evaluate(
                "Array.from(document.querySelectorAll('a[href]')).map(a => a.getAttribute('href'))"
            )
            ids = page.evaluate("Array.from(document.querySelectorAll('[id]')).map(e => e.id)")
            title = page.title()
            # What a reader sees of the issue-29 parts: the first table's headers, its
            # cells conditioned on success, its outcome shares, the rank tables.
            headers = page.evaluate(
                "Array.from(document.querySelector('#table + p + div table')"
                ".querySelectorAll('thead th')).map(t => t.innerText.trim())"
            )
            conditioned = page.evaluate(
                "Array.from(document.querySelector('#table + p + div table')"
                ".querySelectorAll('td.cond')).filter(t => t.offsetWidth > 0)"
                ".map(t => t.innerText.trim())"
            )
            shares = page.evaluate(
                "Array.from(document.querySelector('#table + p + div table')"
                ".querySelectorAll('td.shares')).map(t => t.innerText.trim())"
            )
            legend = page.evaluate("document.querySelector('#table + p + div + p').innerText")
            ranks = page.evaluate(
                "Array.from(document.querySelectorAll('table.ranks tbody tr')).filter("
                "r => r.offsetHeight > 0).map(r => Array.from(r.querySelectorAll('td.prob'))"
                ".map(t => parseFloat(t.innerText)))"
            )
            # the reference points: each row's normalised score, the headroom table
            scores = page.evaluate(
                "Array.from(document.querySelector('#table + p + div table')"
                ".querySelectorAll('td.score')).filter(t => t.offsetWidth > 0)"
                ".map(t => t.innerText.trim())"
            )
            references = page.evaluate(
                "Array.from(document.querySelectorAll('table.references tbody tr')).filter("
                "r => r.offsetHeight > 0).map(r => Array.from(r.querySelectorAll('td'))"
                ".map(t => t.innerText.trim()))"
            )
            # issue 41: the noise floor, the direct / knock-on split, the suite statistics
            floor = page.evaluate(
                "Array.from(document.querySelectorAll('table.floor tbody tr')).filter("
                "r => r.offsetHeight > 0).map(r => Array.from(r.querySelectorAll('td'))"
                ".map(t => t.innerText.trim()))"
            )
            split = page.evaluate(
                "Array.from(document.querySelectorAll('table.split td.split')).filter("
                "t => t.offsetWidth > 0).map(t => t.innerText.trim())"
            )
            iqm = page.evaluate(
                "Array.from(document.querySelectorAll('table.iqm tbody tr')).filter("
                "r => r.offsetHeight > 0).map(r => Array.from(r.querySelectorAll('td'))"
                ".map(t => t.innerText.trim()))"
            )
            poi = page.evaluate(
                "Array.from(document.querySelectorAll('table.poi tbody tr')).filter("
                "r => r.offsetHeight > 0).map(r => Array.from(r.querySelectorAll('td'))"
                ".map(t => t.innerText.trim()))"
            )
        finally:
            browser.close()
    return {
        "console": console,
        "failed": failed,
        "images": images,
        "hrefs": hrefs,
        "ids": set(ids),
        "title": title,
        "headers": headers,
        "conditioned": conditioned,
        "shares": shares,
        "legend": legend,
        "ranks": ranks,
        "scores": scores,
        "references": references,
        "floor": floor,
        "split": split,
        "iqm": iqm,
        "poi": poi,
    }


def test_the_page_loads_cleanly_in_chromium(results: Path, tmp_path: Path) -> None:
    _browser_or_skip()
    seen = _load_in_chromium(results / "report.html")
    assert seen["console"] == []
    assert seen["failed"] == []
    assert seen["title"] == "srfm benchmark results"
    images = seen["images"]
    assert isinstance(images, list)
    assert len(images) == 5  # deviation, social work, profiles, two path figures
    assert "figures/profiles.png" in [src for src, _, _ in images]
    for src, complete, width in images:
        assert complete, src
        assert width > 0, src
    hrefs = seen["hrefs"]
    ids = seen["ids"]
    assert isinstance(hrefs, list)
    assert isinstance(ids, set)
    assert _missing_targets(results, [str(h) for h in hrefs], ids) == []
    # Issue 29: the success-conditioned columns with their n, the outcome shares, the
    # corrected marks' legend and the rank probabilities are on the page, visible.
    headers = seen["headers"]
    assert isinstance(headers, list)
    assert "Fréchet dist. | success (m) ↓" in headers
    assert "Min. robot dist. | success (m) ↑" in headers
    assert headers[-1] == "Outcomes"
    conditioned = seen["conditioned"]
    assert isinstance(conditioned, list)
    assert len(conditioned) == 2 * 2 * 3  # scenarios x planners x conditioned columns
    assert all(re.search(r"\(n=[0-3]\)$", text) for text in conditioned), conditioned
    shares = seen["shares"]
    assert isinstance(shares, list)
    assert len(shares) == 4
    assert all("% goal" in text for text in shares), shares
    assert "Holm's step-down correction" in str(seen["legend"])
    ranks = seen["ranks"]
    assert isinstance(ranks, list)
    assert ranks
    assert len(ranks) == 2 * 2  # a row per planner in each scenario's rank table
    for row in ranks:
        assert len(row) == 2
        assert sum(row) == pytest.approx(1.0, abs=0.011)  # two decimals shown
    _check_issue_41(results, seen)
    # The same check on a folder with a figure gone: the browser reports it.
    broken = tmp_path / "broken"
    shutil.copytree(results, broken)
    (broken / "figures/social_work.png").unlink()
    seen = _load_in_chromium(broken / "report.html")
    failed = seen["failed"]
    assert isinstance(failed, list)
    assert any(url.endswith("figures/social_work.png") for url in failed)
    images = seen["images"]
    assert isinstance(images, list)
    assert [src for src, _, width in images if width == 0] == ["figures/social_work.png"]


def _check_issue_41(results: Path, seen: dict[str, object]) -> None:
    """The noise floor per scenario, the direct / knock-on split of every cell, the IQM
    of every planner and the probabilities of improvement are on the page, visible, as
    summary.json holds them."""
    summary = json.loads((results / "summary.json").read_text(encoding="utf-8"))
    attribution = summary["attribution"]["scenarios"]
    suite = summary["suite"]
    planners = summary["request"]["planners"]
    floor = seen["floor"]
    assert isinstance(floor, list)
    assert [row[0] for row in floor] == list(attribution)  # every scenario has its floor
    for row in floor:
        f = attribution[row[0]]["floor"]
        assert row[1] == f"{f['mean']:.4f}"
        assert f["mean"] > 0.0
        assert len(f["values"]) == 3  # one per seed, not per planner
        assert row[4] == f["verdict"]
    split = seen["split"]
    assert isinstance(split, list)
    assert len(split) == len(attribution) * len(planners)
    cells = [attribution[s]["split"][p] for s in attribution for p in planners]
    for text, cell in zip(split, cells, strict=True):
        assert text.startswith(f"{cell['frechet_direct_m']['mean']:.3f} / ")
        assert f"({cell['pedestrians_felt']['mean']:.1f} felt)" in text
    iqm = seen["iqm"]
    assert isinstance(iqm, list)
    assert [row[0] for row in iqm] == planners
    for row in iqm:
        x = suite["deviation_iqm"][row[0]]
        assert row[1] == f"{x['estimate']:.3f} [{x['low']:.3f}, {x['high']:.3f}]"
    poi = seen["poi"]
    assert isinstance(poi, list)
    assert len(poi) == len(planners)
    a, b = planners
    x = suite["improvement"][a][b]
    assert poi[0][1:] == ["–", f"{x['estimate']:.2f} [{x['low']:.2f}, {x['high']:.2f}]"]
    assert suite["improvement"][b][a]["estimate"] == pytest.approx(1.0 - x["estimate"])
    floor_files = sorted((results / "floor").rglob("seed-*.json"))
    assert len(floor_files) == 2 * 3  # per (scenario, seed), whatever the planners


@pytest.fixture(scope="module")
def walled_results(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Two Francis scenarios (walls) with the reference planners, two seeds: one where
    the oracle has room (a 3 m corridor) and one where it has none."""
    out = tmp_path_factory.mktemp("walled") / "out"
    result = CliRunner().invoke(
        main,
        [
            "benchmark",
            "-s",
            "pedestrian_overtaking,parallel_traffic",
            "-p",
            "straight,oracle",
            "--seeds",
            "0-1",
            "--out",
            str(out),
            "-j",
            "1",
            "--no-logs",
            "--no-figures",
            "--reference",
            "straight",
        ],
    )
    assert result.exit_code == 0, result.output
    return out


def test_the_page_shows_the_reference_points_in_chromium(walled_results: Path) -> None:
    """Issue 29: with straight and oracle in the run (here walled scenarios of the
    Francis suite), the page shows every row's normalised score and each scenario's
    headroom, standard error, seeds needed and whether it discriminates, as summary.json
    holds them."""
    _browser_or_skip()
    seen = _load_in_chromium(walled_results / "report.html")
    assert seen["console"] == []
    assert seen["failed"] == []
    headers = seen["headers"]
    assert isinstance(headers, list)
    assert headers[-2:] == ["Norm. score ↑", "Outcomes"]
    summary = json.loads((walled_results / "summary.json").read_text(encoding="utf-8"))
    refs = summary["table"]["references"]
    scores = seen["scores"]
    assert isinstance(scores, list)
    expected = []
    for scenario in ("pedestrian_overtaking", "parallel_traffic"):
        for planner in ("straight", "oracle"):
            score = refs[scenario]["scores"][planner]
            k = f"(k={score['n']}/{refs[scenario]['n_seeds']})"
            if score["estimate"] is None:
                expected.append(f"undefined {k}")
            else:
                interval = f"{score['estimate']:.2f} [{score['low']:.2f}, {score['high']:.2f}]"
                expected.append(f"{interval} {k}")
    assert scores == expected
    assert scores[1] == "1.00 [1.00, 1.00] (k=2/2)"  # the oracle is the end of the ruler
    references = seen["references"]
    assert isinstance(references, list)
    assert [row[0] for row in references] == ["pedestrian_overtaking", "parallel_traffic"]
    room, none = references
    headroom = refs["pedestrian_overtaking"]["headroom"]
    assert room[1].startswith(f"{headroom['estimate']:.3f} [")
    assert headroom["estimate"] > 1.0  # the corridor: the oracle lets the pedestrian pass
    assert room[-1] == "yes"
    assert none[-1] == "does not discriminate"
    assert refs["parallel_traffic"]["discriminates"] is False


def test_outcome_shares_never_round_to_all_or_nothing() -> None:
    from srfm.metrics.tables import share_text

    assert [share_text(k, 500) for k in (500, 499, 481, 1, 0)] == [
        "100 %",
        "99.8 %",
        "96 %",
        "0.2 %",
        "0 %",
    ]
    assert (share_text(99_999, 100_000), share_text(1, 100_000), share_text(0, 0)) == (
        "> 99.9 %",
        "< 0.1 %",
        "–",
    )
