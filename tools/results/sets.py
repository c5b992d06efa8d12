"""The results sets behind the documentation's numbers (docs/results/index.md).

A results set is one benchmark run, committed as data in ``docs/results/<name>/``:

- ``episodes.parquet``: one row per episode, the benchmark's own ``episodes.parquet``
  (scenario, planner, seed, outcome, end_step and every per-episode metric; NaN as
  null), or, for a set that keeps only what its tables read (``columns="frechet"``),
  the identity, outcome, end step and Fréchet deviation. A set with parameter draws
  adds the column ``draw`` (null: the run's own parameters, k: ``draws/draw-k``).
- ``manifest.json``: the benchmark's manifest (package versions, SRFM parameters,
  metric thresholds, the SHA-256 of every scenario, the request, the command line) and
  ``results_set``: the source commit, the command, when it ran, its wall time, the
  machine, and the SHA-256 of the two TD3 policies' weights.
- ``param_draws.json``: a set with parameter draws, the benchmark's own file.

``SETS`` names every set with the benchmark options that make it; ``tools/results/run.py
NAME`` runs it (resumably) and packs it here; ``tools/results/generate.py`` (``make
docs-tables``) writes every generated block of the docs from these folders alone.
Episodes are read back bit for bit (Parquet keeps float64), so the tables the library
computes from a set are those the benchmark printed (tested).
"""

from __future__ import annotations

import functools
import hashlib
import json
import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow as pa
import pyarrow.compute as pc
import pyarrow.parquet as pq

from srfm.benchmark import RankTable, rank_table
from srfm.metrics.episode import EPISODE_METRICS, EpisodeMetrics
from srfm.metrics.stats import summarize
from srfm.scenarios.suites import SUITES

ROOT = Path(__file__).resolve().parents[2]
SETS_DIR = ROOT / "docs" / "results"
EPISODES = "episodes.parquet"
MANIFEST = "manifest.json"
PARAM_DRAWS = "param_draws.json"
BUDGET_BYTES = 30_000_000
"""The size budget of all results sets together (30 MB): the sets keep one row per
episode and, where their tables need no more, only the Fréchet deviation."""
IDENTITY = ("scenario", "planner", "seed", "outcome", "end_step")
ALL9 = "straight,oracle,stay,dwa,orca,social-force,vo,td3-base,td3-srfm"
FIXED_OPTIONS = ("--no-logs", "--no-figures")


@dataclass(frozen=True)
class ResultsSet:
    """One results set: the ``srfm benchmark`` options that make it and what it keeps.

    Attributes:
        name: the folder name under ``docs/results/``.
        options: the benchmark's options (without ``--out``, ``-j``, on which no
            episode depends, and :data:`FIXED_OPTIONS`, which every set uses).
        columns: ``"all"`` (every per-episode metric) or ``"frechet"`` (the Fréchet
            deviation only).
        purpose: what the docs use it for.
    """

    name: str
    options: tuple[str, ...]
    columns: str
    purpose: str

    def command(self) -> str:
        """The command line that makes the set (from the repository's root; ``-j N``
        for N workers gives the same episodes)."""
        out = f"results/{self.name}"
        return " ".join(["srfm benchmark", *self.options, *FIXED_OPTIONS, "--out", out])

    @property
    def folder(self) -> Path:
        """Where the set is committed."""
        return SETS_DIR / self.name


def _set(name: str, options: str, columns: str, purpose: str) -> ResultsSet:
    return ResultsSet(name, tuple(options.split()), columns, purpose)


SETS: dict[str, ResultsSet] = {
    s.name: s
    for s in (
        _set(
            "paper",
            "--suite paper -p dwa,orca,social-force,straight,td3-base,td3-srfm,vo,stay,oracle "
            "--seeds 0-99",
            "all",
            "the paper's Table 3 beside srfm's, the paper suite's reference points, the "
            "agrawal2024 side of the preset comparison",
        ),
        _set(
            "paper_ttc",
            "--suite paper --params navwareset2026_ttc --seeds 0-99",
            "all",
            "the navwareset2026_ttc side of the preset comparison (paper suite)",
        ),
        _set(
            "paper_nws2025",
            "--suite paper --params navwareset2025 --seeds 0-99",
            "frechet",
            "the navwareset2025 side of the orderings under every response model (paper suite)",
        ),
        _set(
            "paper_nws2025_issue15",
            "--suite paper --params docs/fitting_navwareset2025_issue15.toml --seeds 0-99",
            "frechet",
            "the paper's benchmark with navwareset2025 as issue 15 fitted it (docs/fitting.md)",
        ),
        _set(
            "francis_nws2025",
            "--suite francis --params navwareset2025 --seeds 0-99",
            "frechet",
            "the navwareset2025 side of the orderings under every response model (Francis suite)",
        ),
        _set(
            "flows",
            "--suite flows --seeds 0-99",
            "all",
            "the flows suite's table",
        ),
        _set(
            "draws",
            "--suite paper --seeds 0-39 --param-draws 50 --param-draws-from wide "
            "--param-draws-seed 0",
            "frechet",
            "rank probabilities under parameter draws",
        ),
        _set(
            "francis",
            f"--suite francis -p {ALL9} --reference straight --seeds 0-99",
            "all",
            "the Francis suite's tables and reference points; the discriminative suite's "
            "table (its Francis scenarios)",
        ),
        _set(
            "navwareset",
            f"--suite navwareset -p {ALL9} --reference straight --seeds 0-99",
            "all",
            "the NavWareSet suite's reference points; the discriminative suite's table (its "
            "NavWareSet scenarios)",
        ),
        _set(
            "francis_ttc",
            "--suite francis --params navwareset2026_ttc --seeds 0-99",
            "all",
            "the navwareset2026_ttc side of the preset comparison (Francis suite)",
        ),
        _set(
            "selection",
            " ".join(f"-s {name}" for name in SUITES["all"] if name != "corridor_flow")
            + f" -p {ALL9} --reference straight --seeds 1000-1099",
            "all",
            "the selection of the discriminative suite (seeds 1000-1099): every candidate "
            "but corridor_flow, where the oracle costs tens of seconds an episode",
        ),
        _set(
            "selection_flow",
            "-s corridor_flow -p straight,stay,dwa,orca,social-force,vo,td3-base,td3-srfm "
            "--reference straight --seeds 1000-1099",
            "all",
            "corridor_flow on the selection seeds without the oracle: condition (d) of the "
            "selection rule, which does not involve the oracle",
        ),
    )
}


def _policies() -> dict[str, str]:
    """SHA-256 of the shipped TD3 policies' weights (what `td3-base`/`td3-srfm` ran)."""
    out = {}
    for planner, stem in (("td3-base", "td3_base"), ("td3-srfm", "td3_srfm")):
        doc = json.loads((ROOT / "srfm" / "policies" / f"{stem}.json").read_text("utf-8"))
        out[planner] = str(doc["weights_sha256"])
    return out


def _keep(table: pa.Table, columns: str) -> pa.Table:
    if columns == "all":
        return table
    if columns == "frechet":
        return table.select([*IDENTITY, "frechet_m"])
    raise ValueError(f"unknown column set {columns!r} (all, frechet)")


def _episodes_of_run(out: Path, columns: str) -> pa.Table:
    """The run's episodes (and every draw's, with the column ``draw``)."""
    base = _keep(pq.read_table(out / EPISODES), columns)
    draws = sorted((out / "draws").glob("draw-*")) if (out / "draws").is_dir() else []
    if not draws:
        return base
    parts = [base.append_column("draw", pa.nulls(base.num_rows, pa.int64()))]
    for folder in draws:
        if not (folder / EPISODES).is_file():
            raise SystemExit(f"{folder}: no {EPISODES}: the run is not finished")
        k = int(folder.name.split("-")[1])
        part = _keep(pq.read_table(folder / EPISODES), columns)
        parts.append(part.append_column("draw", pa.array([k] * part.num_rows, pa.int64())))
    return pa.concat_tables(parts)


def pack(
    rset: ResultsSet,
    out: Path,
    *,
    commit: str,
    started: str,
    finished: str,
    wall_s: float,
    machine: str,
    jobs: int,
    dest: Path | None = None,
) -> Path:
    """Write the set's committed folder from a finished benchmark folder ``out``.

    Raises:
        SystemExit: the run is not finished (its episodes.parquet, or a draw's, missing
            or short of the request).
    """
    dest = rset.folder if dest is None else dest
    manifest = json.loads((out / MANIFEST).read_text(encoding="utf-8"))
    request = manifest["request"]
    expected = len(request["scenarios"]) * len(request["planners"]) * len(request["seeds"])
    if not (out / EPISODES).is_file():
        raise SystemExit(f"{out}: no {EPISODES}: the run is not finished")
    table = _episodes_of_run(out, rset.columns)
    n_draws = 0
    if (out / PARAM_DRAWS).is_file():
        n_draws = int(json.loads((out / PARAM_DRAWS).read_text(encoding="utf-8"))["k"])
    if table.num_rows != expected * (1 + n_draws):
        raise SystemExit(
            f"{out}: {table.num_rows} episodes, expected {expected * (1 + n_draws)}: "
            "the run is not finished"
        )
    dest.mkdir(parents=True, exist_ok=True)
    pq.write_table(table, dest / EPISODES, compression="zstd", compression_level=19)
    manifest["results_set"] = {
        "name": rset.name,
        "commit": commit,
        "command": rset.command(),
        "columns": rset.columns,
        "episodes": table.num_rows,
        "started": started,
        "finished": finished,
        "wall_s": round(wall_s),
        "jobs": jobs,
        "machine": machine,
        "policies_weights_sha256": _policies(),
    }
    (dest / MANIFEST).write_text(json.dumps(manifest, indent=1) + "\n", encoding="utf-8")
    if n_draws:
        (dest / PARAM_DRAWS).write_bytes((out / PARAM_DRAWS).read_bytes())
    return dest


def _folder(name: str | Path) -> Path:
    """A set's folder: the committed one of a name, or the folder itself."""
    return name if isinstance(name, Path) else SETS[name].folder


def manifest(name: str | Path) -> dict[str, Any]:
    """A committed set's manifest."""
    doc: dict[str, Any] = json.loads((_folder(name) / MANIFEST).read_text(encoding="utf-8"))
    return doc


def read_json(path: Path) -> Any:
    """A committed JSON file."""
    return json.loads(path.read_text(encoding="utf-8"))


def exists(name: str) -> bool:
    """Whether the set is committed."""
    return (SETS[name].folder / EPISODES).is_file()


@functools.cache
def _read(folder: Path) -> pa.Table:
    return pq.read_table(folder / EPISODES)


def table(name: str | Path, *, draw: int | None = None) -> pa.Table:
    """A set's episodes (of the run's own parameters, or of draw ``draw``)."""
    t = _read(_folder(name))
    if "draw" in t.column_names:
        mask = pc.is_null(t["draw"]) if draw is None else pc.equal(t["draw"], draw)
        t = t.filter(mask).drop_columns(["draw"])
    elif draw is not None:
        raise ValueError(f"results set {name!r} has no parameter draws")
    return t


def episodes(name: str | Path, *, draw: int | None = None) -> list[EpisodeMetrics]:
    """A committed set's episodes as the library's :class:`EpisodeMetrics` (the metrics
    the set keeps; no per-pedestrian values), bit for bit as the benchmark scored them."""
    t = table(name, draw=draw)
    names = [m.name for m in EPISODE_METRICS if m.name in t.column_names]
    cols = {c: t[c].to_pylist() for c in [*IDENTITY, *names]}
    out = []
    for i in range(t.num_rows):
        values = {n: math.nan if cols[n][i] is None else float(cols[n][i]) for n in names}
        out.append(
            EpisodeMetrics(
                scenario=str(cols["scenario"][i]),
                planner=str(cols["planner"][i]),
                seed=int(cols["seed"][i]),
                outcome=str(cols["outcome"][i]),
                end_step=int(cols["end_step"][i]),
                values=values,
                pedestrians={},
            )
        )
    return out


def frechet(
    name: str | Path, *, draw: int | None = None
) -> dict[tuple[str, str], dict[int, tuple[float, str]]]:
    """Per (scenario, planner), per seed: the Fréchet deviation (NaN: undefined) and the
    outcome."""
    t = table(name, draw=draw)
    out: dict[tuple[str, str], dict[int, tuple[float, str]]] = {}
    for s, p, seed, outcome, value in zip(
        *(t[c].to_pylist() for c in ("scenario", "planner", "seed", "outcome", "frechet_m")),
        strict=True,
    ):
        out.setdefault((s, p), {})[int(seed)] = (
            math.nan if value is None else float(value),
            str(outcome),
        )
    return out


def frechet_array(
    cells: dict[tuple[str, str], dict[int, tuple[float, str]]],
    scenario: str,
    planner: str,
    seeds: Sequence[int],
) -> np.ndarray:
    """The Fréchet deviations of one cell in the order of ``seeds``."""
    cell = cells[scenario, planner]
    return np.array([cell[s][0] for s in seeds], dtype=np.float64)


def rank_table_of(name: str | Path) -> RankTable:
    """The rank probabilities of a set with parameter draws, as the benchmark computes
    them (``rankings.json``): per draw, each planner's mean deviation over the seeds."""
    req = manifest(name)["request"]
    draws = read_json(_folder(name) / PARAM_DRAWS)
    means = []
    for k in range(int(draws["k"])):
        cells = frechet(name, draw=k)
        means.append(
            {
                s: {
                    p: summarize(frechet_array(cells, s, p, req["seeds"])).mean
                    for p in req["planners"]
                }
                for s in req["scenarios"]
            }
        )
    return rank_table(
        means,
        scenarios=req["scenarios"],
        planners=req["planners"],
        n_seeds=len(req["seeds"]),
        description=str(draws["description"]),
    )


def folder_bytes(name: str) -> int:
    """The size of a committed set's files."""
    return sum(p.stat().st_size for p in SETS[name].folder.iterdir() if p.is_file())


def file_sha256(path: Path) -> str:
    """SHA-256 of a file."""
    return hashlib.sha256(path.read_bytes()).hexdigest()
