"""The measured figures of the logging, external-planner, distributed, reliability,
scenario and convergence pages, from committed run data (``make docs-tables``).

Each block reads one JSON file that a tool wrote with its run record
(``tools/results/record.py``: command, commit, start, end, wall time, machine load):

- ``docs/results/performance/logging.json`` (``tools/bench/bench_logging.py --json``):
  logging.md; performance.md, "Logging" and "Benchmark wall time"; distributed.md;
- ``docs/results/performance/external.json`` (``tools/bench/bench_external_planner.py
  --json``) and ``external_transport.json`` (``tools/bench/bench_external_transport.py
  --json``): performance.md, "External planners"; planners-any-language.md;
- ``docs/results/performance/time_model.json`` (``tools/bench/bench_time_model.py
  --json``): reliability.md;
- ``docs/scenarios/checks.json`` (``tools/scenarios/check_scenarios.py --json``):
  scenarios.md;
- ``docs/convergence/runs.json`` (``tools/analysis/convergence.py run``): metrics.md.

``tools/results/generate.py`` registers :data:`BLOCKS`. Nothing here is measured: the
whole module reads JSON.
"""

from __future__ import annotations

import statistics
from collections import defaultdict
from collections.abc import Callable
from functools import cache
from pathlib import Path
from typing import Any, Final

from tools.results.fitting_pages import DOCS, MissingDataError, prose
from tools.results.sets import read_json

PERFORMANCE: Final = DOCS / "results" / "performance"
LOGGING: Final = PERFORMANCE / "logging.json"
EXTERNAL: Final = PERFORMANCE / "external.json"
TRANSPORT: Final = PERFORMANCE / "external_transport.json"
TIME_MODEL: Final = PERFORMANCE / "time_model.json"
SCENARIO_CHECKS: Final = DOCS / "scenarios" / "checks.json"
CONVERGENCE_RUNS: Final = DOCS / "convergence" / "runs.json"
DATA: Final = {
    LOGGING: "python tools/bench/bench_logging.py --json docs/results/performance/logging.json",
    EXTERNAL: "python tools/bench/bench_external_planner.py "
    "--json docs/results/performance/external.json",
    TRANSPORT: "python tools/bench/bench_external_transport.py "
    "--json docs/results/performance/external_transport.json",
    TIME_MODEL: "python tools/bench/bench_time_model.py "
    "--json docs/results/performance/time_model.json",
    SCENARIO_CHECKS: "python tools/scenarios/check_scenarios.py --json docs/scenarios/checks.json",
    CONVERGENCE_RUNS: "python tools/analysis/convergence.py run results/conv "
    "--csv docs/convergence/frechet.csv --json docs/convergence/runs.json",
}
"""Every data file of this module and the command that writes it."""
SEEDS_PER_TASK: Final = 10
"""A sweep's default episodes per task (``seeds_per_task`` in srfm/sweep/_spec.py)."""
PER_STEP_TARGET_US: Final = 50.0
"""Issue 44's target for the protocol's overhead per control step (median)."""
PER_EPISODE_TARGET_MS: Final = 40.0
"""Issue 44's target for the protocol's overhead per 750-step episode."""
RUN_KEYS: Final = ("command", "commit", "started", "finished", "wall_s", "machine")
"""What every data file's ``run`` record holds (``tools/results/record.py``)."""


@cache
def load(path: Path) -> dict[str, Any]:
    """A committed data file of this module (:data:`DATA`)."""
    if not path.is_file():
        where = path.relative_to(DOCS.parent) if path.is_relative_to(DOCS.parent) else path
        raise MissingDataError(f"`{where}` (`{DATA[path]}`)")
    doc: dict[str, Any] = read_json(path)
    return doc


def when(run: dict[str, Any]) -> str:
    """``2026-12-05 16:20 UTC``, the start of a run."""
    return str(run["started"])[:16].replace("T", " ") + " UTC"


def provenance(run: dict[str, Any], note: str = "") -> str:
    """One italic line: the command, commit, date, wall time and machine of a run."""
    return (
        f"*`{run['command']}`: commit `{run['commit']}`, {when(run)}, "
        f"{run['wall_s']:.0f} s of wall time; {run['machine']}{note}.*"
    )


def _ms(seconds: float) -> str:
    return f"{seconds * 1e3:.1f}"


def _kb(n: float) -> str:
    return f"{n / 1e3:.1f}"


def _mb(n: float) -> str:
    return f"{n / 1e6:.0f}"


def _range(values: list[float], fmt: Callable[[float], str]) -> str:
    lo, hi = fmt(min(values)), fmt(max(values))
    return lo if lo == hi else f"{lo}–{hi}"


# -- logging (tools/bench/bench_logging.py) ---------------------------------------------

STAGES: Final = {
    "simulate + metrics": "simulate and score the episode (no logs)",
    "mcap compact": "write the compact MCAP file (the benchmark's; with the shared "
    "counterfactual file when the episode is the seed's first)",
    "mcap full": "write the full MCAP file (`srfm simulate`)",
    "rrd": "write the Rerun recording",
    "rrd + forces": "write the Rerun recording with force arrows",
    "score (compact)": "read the compact file back and recompute the metrics (`srfm score`)",
}
FILES: Final = {
    "compact episode file": "compact MCAP episode file (the benchmark's)",
    "shared counterfactual file": "shared counterfactual MCAP file (one per scenario and seed)",
    "mcap full": "full MCAP file (`srfm simulate`)",
    "rrd": "Rerun recording",
    "rrd + forces": "Rerun recording with force arrows",
}
CHANNELS: Final = (
    ("the factual pedestrians' exact arrays", ("/srfm/trajectories:factual",)),
    ("the robot's exact arrays", ("/srfm/trajectories:robot",)),
    ("the robot state and command messages (1 Hz)", ("/srfm/robot/state", "/srfm/robot/command")),
    ("the Foxglove scene", ("/foxglove/scene",)),
    ("the metrics", ("/srfm/metrics",)),
    ("the episode and event messages", ("/srfm/episode", "/srfm/events")),
)
"""The compact file's parts, each the zstd-compressed bytes of its channels' messages."""


def _episodes() -> list[dict[str, Any]]:
    rows: list[dict[str, Any]] = load(LOGGING)["episodes"]
    return rows


def _sizes(key: str) -> list[float]:
    return [float(e["bytes"][key]) for e in _episodes() if key in e["bytes"]]


def _cpu(stage: str) -> list[float]:
    return [float(e["cpu_s"][stage]) for e in _episodes()]


def _logging_scope() -> str:
    doc = load(LOGGING)
    n = len(doc["episodes"])
    return (
        f"{n} episodes: the scenarios {', '.join(f'`{s}`' for s in doc['scenarios'])} × "
        f"the planners {', '.join(f'`{p}`' for p in doc['planners'])} × seeds "
        f"{doc['seeds'][0]}–{doc['seeds'][-1]}, one process"
    )


def _full_runs() -> dict[str, dict[str, Any]]:
    return {r["run"]: r for r in load(LOGGING)["full_benchmark"]}


def logging_files_table() -> str:
    """Bytes of every kind of log file, over the measured episodes."""
    lines = [
        "| file | kB, mean | kB, min–max | files |",
        "|---|--:|--:|--:|",
    ]
    for key, label in FILES.items():
        v = _sizes(key)
        lines.append(
            f"| {label} | {_kb(statistics.fmean(v))} | {_kb(min(v))}–{_kb(max(v))} | {len(v)} |"
        )
    return "\n".join(lines)


def logging_cpu_table() -> str:
    """CPU time of every stage per episode, against simulating and scoring it."""
    base = statistics.fmean(_cpu("simulate + metrics"))
    lines = [
        "| per episode | CPU ms, median | CPU ms, mean | mean / simulate and score |",
        "|---|--:|--:|--:|",
    ]
    for stage, label in STAGES.items():
        v = _cpu(stage)
        lines.append(
            f"| {label} | {_ms(statistics.median(v))} | {_ms(statistics.fmean(v))} "
            f"| {statistics.fmean(v) / base:.2f} |"
        )
    return "\n".join(lines)


def _channel_means() -> tuple[list[tuple[str, float]], float, float, float]:
    """The compact file's parts (mean bytes), the schemas' bytes, Foxglove's
    descriptor's bytes, and the mean file size."""
    rows = [e["compact_channels"] for e in _episodes()]
    parts = [
        (label, statistics.fmean(sum(r.get(k, 0) for k in keys) for r in rows))
        for label, keys in CHANNELS
    ]
    schemas = statistics.fmean(
        sum(v for k, v in r.items() if k.startswith("schema: ")) for r in rows
    )
    scene = statistics.fmean(r.get("schema: foxglove.SceneUpdate", 0) for r in rows)
    return parts, schemas, scene, statistics.fmean(r["file"] for r in rows)


def logging_breakdown() -> str:
    """What the compact episode file's bytes hold."""
    parts, schemas, scene, size = _channel_means()
    lines = [
        "| of a compact episode file | kB, mean |",
        "|---|--:|",
        *(f"| {label} | {_kb(b)} |" for label, b in parts),
        f"| the schemas (uncompressed; Foxglove's `SceneUpdate` descriptor {_kb(scene)}) "
        f"| {_kb(schemas)} |",
        f"| chunk, index and statistics records, and what the channels share in a chunk "
        f"(the rest) | {_kb(size - schemas - sum(b for _, b in parts))} |",
        f"| **the file** | **{_kb(size)}** |",
    ]
    return "\n".join(lines)


def _encoding_rows() -> list[tuple[str, float, float]]:
    """Each encoding of the exact factual positions: bytes per value and mean kB."""
    by: dict[str, list[tuple[float, int]]] = defaultdict(list)
    for e in _episodes():
        for name, b in e["encoding_bytes"].items():
            by[name].append((float(b), int(e["position_values"])))
    return [
        (
            name,
            statistics.fmean(b / n for b, n in v),
            statistics.fmean(b for b, _ in v),
        )
        for name, v in by.items()
    ]


def logging_encodings() -> str:
    """The exact positions in each encoding tried, zstd level 3 as in the MCAP chunks."""
    doc = load(LOGGING)
    lines = [
        provenance(doc["run"]),
        "",
        f"The factual positions of {len(doc['episodes'])} episodes, each encoding "
        "compressed with zstd level 3 (as the MCAP chunks are):",
        "",
        "| exact factual positions | bytes per value, mean | kB per episode, mean |",
        "|---|--:|--:|",
    ]
    for name, per_value, total in _encoding_rows():
        bold = "**" if "log schema 5" in name else ""
        lines.append(f"| {bold}{name}{bold} | {per_value:.2f} | {_kb(total)} |")
    return "\n".join(lines)


def logging_size_cost() -> str:
    """docs/logging.md, "Size and cost": every figure from ``logging.json``."""
    doc = load(LOGGING)
    full = _full_runs()
    logs, none = full["default logs"], full["no logs"]
    episode_mcap = logs["mcap_bytes"] - logs["counterfactual_bytes"]
    episodes = logs["mcap_files"] - logs["counterfactual_files"]
    compact = _sizes("compact episode file")
    parts, _, _, _ = _channel_means()
    factual = parts[0][1]
    lines = [
        provenance(doc["run"], ", with every other job of the machine paused"),
        "",
        f"Per episode, over {_logging_scope()}: a compact episode file is "
        f"{_kb(statistics.fmean(compact))} kB on average, of which the factual "
        f"positions are {_kb(factual)} kB (exact float64: what is left after the "
        "lossless transforms tried, [above](#exact-arrays)):",
        "",
        logging_files_table(),
        "",
        logging_cpu_table(),
        "",
        logging_breakdown(),
        "",
        "(Each part is its channel's messages compressed alone with zstd level 3; the "
        "summary repeats the schemas uncompressed, and the indexed readers, Foxglove's "
        "included, take them from there.)",
        "",
        prose(
            f"The whole default benchmark, `{logs['command']}` (seeds 0–99, "
            f"{episodes:,} episodes), wrote {_mb(episode_mcap)} MB of episode MCAP files, "
            f"{_mb(logs['counterfactual_bytes'])} MB of shared counterfactual files "
            f"({logs['counterfactual_files']} files) and {_mb(logs['rrd_bytes'])} MB of "
            f"recordings ({logs['rrd_files']} files); it took {logs['wall_s']:.1f} s of wall "
            f"time and {logs['cpu_s']:.0f} CPU-s, against {none['wall_s']:.1f} s and "
            f"{none['cpu_s']:.0f} CPU-s with `--no-logs` (load {none['load_before']:.1f} "
            f"before). `--no-logs` turns it all off."
        ),
    ]
    return "\n".join(lines)


def logging_profiles() -> str:
    """The two profiles' sizes, for docs/logging.md's "Profiles"."""
    full = statistics.fmean(_sizes("mcap full"))
    compact = statistics.fmean(_sizes("compact episode file"))
    cf = statistics.fmean(_sizes("shared counterfactual file"))
    rrd = _sizes("rrd")
    ratios = [e["bytes"]["rrd"] / e["bytes"]["compact episode file"] for e in _episodes()]
    return prose(
        f"Measured sizes ([Size and cost](#size-and-cost)): a full file {full / 1e6:.2f} MB "
        f"an episode; a compact one {_kb(compact)} kB an episode plus {_kb(cf)} kB per "
        f"scenario and seed; a Rerun recording {statistics.fmean(rrd) / 1e6:.2f} MB, "
        f"{_range(ratios, lambda x: f'{x:.1f}')} times the episode's compact file, which "
        "is why a benchmark records only the first seed of each cell."
    )


def performance_logging() -> str:
    """docs/performance.md, "Logging": the cost of the logs in one table."""
    doc = load(LOGGING)
    full = _full_runs()
    logs, none = full["default logs"], full["no logs"]
    compact = _sizes("compact episode file")
    cf = _sizes("shared counterfactual file")
    write = _cpu("mcap compact")
    base = _cpu("simulate + metrics")
    lines = [
        provenance(doc["run"], ", with every other job of the machine paused"),
        "",
        "| what | figure |",
        "|---|--:|",
        "| compact MCAP episode file, CPU ms to write (median) | "
        f"{_ms(statistics.median(write))} |",
        f"| the same, mean / simulating and scoring the episode | "
        f"{statistics.fmean(write) / statistics.fmean(base):.2f} |",
        f"| Rerun recording, CPU ms to write (median) | {_ms(statistics.median(_cpu('rrd')))} |",
        f"| `srfm score` of one compact file, CPU ms (median) | "
        f"{_ms(statistics.median(_cpu('score (compact)')))} |",
        f"| compact episode file, kB (mean, {len(compact)} files) | "
        f"{_kb(statistics.fmean(compact))} |",
        f"| shared counterfactual file, kB (mean, {len(cf)} files) | {_kb(statistics.fmean(cf))} |",
        f"| default benchmark, CPU-s with logs / without | {logs['cpu_s']:.0f} / "
        f"{none['cpu_s']:.0f} |",
        "",
        f"Over {_logging_scope()}; every figure, the byte breakdown and the encodings "
        "tried are in [logging.md](logging.md#size-and-cost).",
    ]
    return "\n".join(lines)


def benchmark_wall_time() -> str:
    """docs/performance.md, "Benchmark wall time", from the logging run's benchmarks."""
    doc = load(LOGGING)
    full = _full_runs()
    logs, none = full["default logs"], full["no logs"]
    return prose(
        f"The full benchmark (`srfm benchmark`, seeds 0–99, every planner: "
        f"{logs['mcap_files'] - logs['counterfactual_files']:,} episodes) took "
        f"**{logs['wall_s']:.1f} s** with the default logs ({logs['cpu_s']:.0f} CPU-s) and "
        f"{none['wall_s']:.1f} s without (`--no-logs`, {none['cpu_s']:.0f} CPU-s) on the "
        f"two cores, every other job paused, 1-minute load {none['load_before']:.1f} "
        f"before; measured {when(doc['run'])} on commit `{doc['run']['commit']}` by "
        f"`{doc['run']['command']}`. Earlier figures (before issue 31, the paper's "
        "2,000-episode Table 3 setting, the reference code's hour): the "
        "[notebook](history/performance.md#benchmark-wall-time)."
    )


def distributed_task_work() -> str:
    """docs/distributed.md: the work in one sweep task, from the logging run's episodes."""
    doc = load(LOGGING)
    cells: dict[tuple[str, str], list[float]] = defaultdict(list)
    for e in _episodes():
        cells[(e["scenario"], e["planner"])].append(float(e["cpu_s"]["simulate + metrics"]))
    per_task = [statistics.fmean(v) * SEEDS_PER_TASK for v in cells.values()]
    return prose(
        f"One task is `seeds_per_task` episodes (default {SEEDS_PER_TASK}) of one cell, "
        f"scenario and planner: about {min(per_task):.1f}–{max(per_task):.1f} s of CPU "
        f"time per task on the paper's scenarios ({SEEDS_PER_TASK} × the mean episode of "
        f"each of the {len(cells)} scenario × planner cells of `tools/bench/"
        f"bench_logging.py`, {when(doc['run'])}, [logging.md](logging.md#size-and-cost)), "
        "large enough that the scheduler's overhead (Dask's documentation puts it near a "
        "millisecond a task) stays small, small enough that a lost worker costs little. "
        "Start workers with **one thread each** (`--nthreads 1`) and as many workers per "
        "machine as it has cores (`--nworkers`): the simulation kernels are single-threaded "
        "inside a task."
    )


# -- external planners (tools/bench/bench_external_*.py) --------------------------------

TRANSPORTS: Final = {
    "json-unix": "JSON lines (`json`; nlohmann-json3-dev), Unix socket",
    "msgpack-unix": "**MessagePack (`msgpack`; libmsgpack-cxx-dev), length-prefixed, Unix socket**",
    "msgpack-tcp": "the same over TCP loopback",
    "msgpack-zmq": "MessagePack over ZeroMQ REQ/REP, `ipc://` (`pyzmq`; libzmq3-dev, cppzmq-dev)",
}


def external_transport() -> str:
    """The wire formats and transports, timed round trip by round trip."""
    doc = load(TRANSPORT)
    lines = [
        provenance(doc["run"], ", with every other job of the machine paused"),
        "",
        f"{doc['repeats']} × {doc['steps']:,} round trips per candidate:",
        "",
        "| candidate | median (µs) | 90th percentile (µs) |",
        "|---|---:|---:|",
    ]
    for name, row in doc["candidates"].items():
        lines.append(
            f"| {TRANSPORTS.get(name, name)} | {row['median_us']:.1f} | {row['p90_us']:.1f} |"
        )
    ranked = sorted(doc["candidates"], key=lambda n: doc["candidates"][n]["median_us"])
    lines += ["", f"Ranked by the median: {', '.join(f'`{n}`' for n in ranked)}."]
    unix = doc["candidates"].get("msgpack-unix")
    if unix is not None and EXTERNAL.is_file():
        cpp = load(EXTERNAL)["per_step_us"]["cpp"]["median"]
        if unix["median_us"] > 2 * cpp:
            lines += [
                "",
                prose(
                    f"These round trips took longer ({unix['median_us']:.1f} µs for "
                    "MessagePack over a Unix socket) than the same exchange inside the "
                    f"overhead measurement below ({cpp:.1f} µs a C++ client call), and "
                    "longer than on the busy machine of the first runs "
                    "([history](history/external-planners.md)): with every other job "
                    "paused, each message waits for an idle core to wake, the likely "
                    "cause (not checked further)."
                ),
            ]
    return "\n".join(lines)


def _overhead_us(doc: dict[str, Any]) -> float:
    step = doc["per_step_us"]
    return float(step["cpp"]["median"] - step["builtin"]["median"])


def external_overhead() -> str:
    """The protocol's cost per step and per 750-step episode, and whole episodes."""
    doc = load(EXTERNAL)
    step, block = doc["per_step_us"], doc["per_episode_ms"]
    overhead = _overhead_us(doc)
    n = doc["episode_steps"]
    lines = [
        provenance(doc["run"], ", with every other job of the machine paused"),
        "",
        f"{doc['episodes']} episodes ({len(doc['scenarios'])} paper scenarios × seeds "
        f"0–{doc['seeds'] - 1}), {doc['observations']:,} observations, {doc['passes']} passes:",
        "",
        "| per control step | median (µs) | 90th percentile (µs) |",
        "|---|---:|---:|",
        f"| built-in `straight`, `act()` | {step['builtin']['median']:.1f} "
        f"| {step['builtin']['p90']:.1f} |",
        f"| C++ client's straight over the protocol | {step['cpp']['median']:.1f} "
        f"| {step['cpp']['p90']:.1f} |",
        f"| **overhead** (difference of the medians) | **{overhead:.1f}** | |",
        f"| Python client's straight over the protocol | {step['python']['median']:.1f} "
        f"| {step['python']['p90']:.1f} |",
        "",
        f"| per {n}-step episode ({block['blocks']} blocks) | median (ms) | max (ms) |",
        "|---|---:|---:|",
        f"| built-in `straight` | {block['builtin']['median']:.1f} "
        f"| {block['builtin']['max']:.1f} |",
        f"| C++ client over the protocol | {block['cpp']['median']:.1f} "
        f"| {block['cpp']['max']:.1f} |",
        f"| **overhead** | **{block['overhead']['median']:.1f}** "
        f"| {block['overhead']['max']:.1f} |",
        "",
        "| whole episode, `srfm.run_episode`, seed 0 (median of the passes) | built-in (ms) "
        "| external (ms) | planner steps |",
        "|---|---:|---:|---:|",
        *(
            f"| {w['scenario']} | {w['builtin_ms']:.1f} | {w['external_ms']:.1f} "
            f"| {w['planner_steps']} |"
            for w in doc["whole_episodes_ms"]
        ),
        "",
        prose(
            f"Issue 44's targets: at most {PER_STEP_TARGET_US:.0f} µs overhead per step "
            f"(median): {overhead:.1f} µs, "
            + ("met" if overhead <= PER_STEP_TARGET_US else "**not met**")
            + f" (the Python client {step['python']['median']:.1f} µs a call); at most "
            f"{PER_EPISODE_TARGET_MS:.0f} ms per {n}-step episode: "
            f"{block['overhead']['median']:.1f} ms median, "
            + ("met" if block["overhead"]["median"] <= PER_EPISODE_TARGET_MS else "**not met**")
            + f", {block['overhead']['max']:.1f} ms for the slowest block, "
            + ("met." if block["overhead"]["max"] <= PER_EPISODE_TARGET_MS else "**not met**.")
        ),
    ]
    return "\n".join(lines)


def external_cost() -> str:
    """docs/planners-any-language.md: the protocol's cost in one sentence."""
    doc = load(EXTERNAL)
    return prose(
        f"The protocol costs {_overhead_us(doc):.1f} µs per control step (median, the C++ "
        f"client against the built-in planner; {doc['per_step_us']['python']['median']:.1f} µs "
        f"a call with the Python client), measured {when(doc['run'])} with every other job "
        "of the machine paused ([performance.md](performance.md#external-planners))."
    )


# -- the run-size time model (tools/bench/bench_time_model.py) --------------------------

TERMS: Final = {
    "S": "per sample",
    "S·N": "per pedestrian and sample",
    "S·N·K": "per neighbour, pedestrian and sample",
    "S·N·M": "per wall or pillar, pedestrian and sample",
    "N·S": "metrics, per pedestrian and sample",
    "N·S²": "metrics, per pedestrian and sample squared",
}


def _time_unit(seconds: float) -> str:
    if seconds >= 1e-7:
        return f"{seconds * 1e6:.2g} µs"
    return f"{seconds * 1e9:.2g} ns"


def _measured(name: str) -> tuple[float, list[float]]:
    """A scenario's estimate and its measured CPU seconds (every planner and seed)."""
    rows = [r for r in load(TIME_MODEL)["episodes"] if r["scenario"] == name]
    if not rows:
        raise MissingDataError(f"episodes of `{name}` in `{TIME_MODEL.name}`")
    return float(rows[0]["estimate_s"]), [r["simulation_s"] + r["metrics_s"] for r in rows]


def _seconds(x: float) -> str:
    return f"{x * 1e3:.0f} ms" if x < 1 else f"{x:.1f} s"


def _seconds_range(values: list[float]) -> str:
    """``9–13 ms`` or ``0.48–0.71 s``: one unit for both ends."""
    if max(values) < 1:
        return _range([v * 1e3 for v in values], lambda x: f"{x:.0f}") + " ms"
    return _range(values, lambda x: f"{x:.2f}") + " s"


def time_model_check() -> str:
    """docs/reliability.md: the model's estimates against measured episodes, and a refit."""
    doc = load(TIME_MODEL)
    rows = doc["episodes"]
    ratios = [(r["simulation_s"] + r["metrics_s"]) / r["estimate_s"] for r in rows]
    scenarios = sorted({r["scenario"] for r in rows})
    cw_est, cw = _measured("crosswalk")
    cc_est, cc = _measured("concert_crowd")
    within = max(max(ratios), 1 / min(ratios))
    lines = [
        prose(
            f"Measured against the shipped model ({len(rows)} episodes: {len(scenarios)} "
            f"built-in scenarios and large crowds × {len(doc['planners'])} planners × "
            f"{len(doc['seeds'])} seeds, one process, serial kernels): measured / estimated "
            f"CPU time {min(ratios):.2f}–{max(ratios):.2f}, so within a factor of "
            f"{within:.1f} (crosswalk: {_seconds(cw_est)} estimated, "
            f"{_seconds_range(cw)} measured; concert_crowd, 400 pedestrians: "
            f"{_seconds(cc_est)} estimated, {_seconds_range(cc)} measured over the "
            "planners)."
        ),
        "",
        provenance(doc["run"], ", with every other job of the machine paused"),
        "",
        "| term | shipped | refit on this run |",
        "|---|--:|--:|",
        *(
            f"| {term} ({label}) | {_time_unit(doc['shipped'][term])} "
            f"| {_time_unit(doc['refit'][term])} |"
            for term, label in TERMS.items()
        ),
        "",
        prose(
            "The refit is non-negative least squares in relative terms (simulation on the "
            "first four terms, metrics on the last two); the shipped coefficients are "
            "those of `srfm/sim/budget.py`, fitted when the model was written (issue 33; "
            "that fit's data was not committed)."
        ),
        "",
        *held_memory_lines(doc),
    ]
    return "\n".join(lines)


def held_memory_lines(doc: dict[str, Any]) -> list[str]:
    """What a benchmark's report phase holds per episode, measured and as shipped."""
    memory = doc["held_memory"]
    fit, shipped = memory["fit"], memory["shipped"]
    return [
        "| held by the report phase, per episode | pedestrians | episodes | bytes |",
        "|---|--:|--:|--:|",
        *(
            f"| `{r['scenario']}` | {r['pedestrians']} | {r['episodes']} "
            f"| {r['bytes_per_episode']:,} |"
            for r in memory["scenarios"]
        ),
        "",
        prose(
            "Each scenario's episodes written and read back as a benchmark does "
            "(`write_episode`, `read_episode`), the bytes the read metrics hold after "
            "garbage collection (`tracemalloc`). Fitted as a + b · N: "
            f"{fit['per_episode']:,.0f} bytes per episode and {fit['per_pedestrian']:,.0f} "
            "per pedestrian and episode; the model ships "
            f"{shipped['per_episode']:,.0f} and {shipped['per_pedestrian']:,.0f} "
            "(`srfm/benchmark/_runner.py`)."
        ),
    ]


def time_model_estimate() -> str:
    """The estimate line ``srfm benchmark`` prints, as the model gives it."""
    doc = load(TIME_MODEL)
    e = doc["estimates_on_2_workers"]
    return prose(
        f"A run that goes ahead and is estimated at 5 minutes or more, or 1 GiB or more, or "
        f"beyond a limit (by `--force`), prints its estimate first (`srfm benchmark --suite "
        f"large` on two cores: `estimate: {e['large']}`; the paper's full benchmark, "
        f"{e['paper'].split(':')[0]} in about {float(e['paper_wall_s']):.0f} s on two "
        "workers, prints none)."
    )


# -- scenarios.md, metrics.md ------------------------------------------------------------


def scenario_checks_cost() -> str:
    """docs/scenarios.md: what the 20-seed checks of the library cost."""
    doc = load(SCENARIO_CHECKS)
    run = doc["run"]
    return prose(
        f"The run below took {doc['cpu_s']:.0f} CPU-s for all {len(doc['scenarios'])} "
        f"scenarios ({run['wall_s']:.0f} s of wall time, {when(run)}, commit "
        f"`{run['commit']}`, every other job of the machine paused)."
    )


def convergence_wall_times() -> str:
    """docs/metrics.md: what the finer crowd step costs, from the convergence runs."""
    doc = load(CONVERGENCE_RUNS)
    runs = {r["crowd_substeps"]: r for r in doc["runs"]}
    walls = ", ".join(f"{r['wall_s']:.0f} s" for r in runs.values())
    cpus = ", ".join(f"{r['cpu_s']:.0f}" for r in runs.values())
    loads = [r["load_before"][0] for r in runs.values()] + [
        r["load_after"][0] for r in runs.values()
    ]
    return prose(
        "**The fix** for a study that ranks planners by centimetres is the finer crowd "
        "step: `srfm benchmark --crowd-substeps 4`. The three runs above, at dt, dt/2 and "
        f"dt/4, took {cpus} CPU-s (all processes of each run): dt/4 costs "
        f"{runs[4]['cpu_s'] / runs[1]['cpu_s']:.2f}× the CPU time of dt, since the crowd "
        "step is a small part of an episode beside the planners and the metrics. Their "
        f"wall times, {walls}, were measured under load and say little: they ran under "
        "`nice -n 10` beside other jobs on the two cores (1-minute load "
        f"{min(loads):.1f}–{max(loads):.1f}) and were paused while other jobs were timed "
        f"({when(doc['run'])}, commit `{doc['run']['commit']}`). The paper's step stays "
        "the default for reproduction."
    )


PAGES: Final = {
    LOGGING: "logging.md, performance.md, distributed.md",
    EXTERNAL: "performance.md, planners-any-language.md",
    TRANSPORT: "performance.md",
    TIME_MODEL: "reliability.md",
    SCENARIO_CHECKS: "scenarios.md",
    CONVERGENCE_RUNS: "metrics.md",
}
"""The pages each data file's figures are on."""


def data_index() -> str:
    """docs/results/index.md: every data file of this module, its size, run and pages."""
    lines = [
        "| data | size (kB) | measured (UTC) | commit | wall time | pages | command |",
        "|---|--:|---|---|--:|---|---|",
    ]
    for path in DATA:
        run = load(path)["run"]
        lines.append(
            f"| `{path.relative_to(DOCS.parent)}` | {path.stat().st_size / 1e3:.0f} "
            f"| {when(run)[:-4]} | `{run['commit']}` | {run['wall_s']:.0f} s "
            f"| {PAGES[path]} | `{run['command']}` |"
        )
    return "\n".join(lines)


BLOCKS: dict[str, Callable[[], str]] = {
    "io-data-index": data_index,
    "logging-size-cost": logging_size_cost,
    "logging-encodings": logging_encodings,
    "logging-profiles": logging_profiles,
    "performance-logging": performance_logging,
    "performance-benchmark-wall": benchmark_wall_time,
    "distributed-task-work": distributed_task_work,
    "external-transport": external_transport,
    "external-overhead": external_overhead,
    "external-cost": external_cost,
    "time-model-check": time_model_check,
    "time-model-estimate": time_model_estimate,
    "scenario-checks-cost": scenario_checks_cost,
    "convergence-wall-times": convergence_wall_times,
}
