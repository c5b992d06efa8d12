"""Logging overhead and bytes per episode, for the MCAP and Rerun sinks.

Per-episode part: for every scenario × planner × seed (default: the five evaluation
scenarios, the five classical planners, seeds 0–3), the script simulates the episode
once and scores it (what the benchmark does without logs), then writes, in the same
process, each kind of log the way the benchmark or ``srfm simulate`` would:

- ``compact``: the benchmark's default MCAP file, plus the shared counterfactual file
  of the (scenario, seed) when the first planner of that seed writes it;
- ``full``: the MCAP file of ``srfm simulate --out``;
- ``rrd``: the Rerun recording (first seed of each cell in a benchmark);
- ``rrd+forces``: the Rerun recording with the SRFM force arrows;
- ``score``: re-scoring the compact file (read, rebuild, metrics).

Each stage is timed with ``time.process_time`` (CPU time of this process: the figure
least disturbed by other jobs on a shared machine) and ``time.perf_counter``; the
report gives the median and mean per episode and the bytes written. It also projects
the MCAP output of a full 100-seed benchmark from the measured means.

Full-benchmark part (``--full-benchmark DIR``): runs ``srfm benchmark`` on the given
planners with 100 seeds twice, with ``--no-logs`` and with the default logs, into
``DIR/no-logs`` and ``DIR/logs``, and reports the wall and CPU time of both and the
bytes of the MCAP and Rerun files actually written.

The same command with ``PYTHONPATH`` pointing at an older checkout measures that
tree's logging ("before" in docs/performance.md).

Usage::

    .venv/bin/python tools/bench/bench_logging.py
    PYTHONPATH=/path/to/old/checkout .venv/bin/python tools/bench/bench_logging.py
    .venv/bin/python tools/bench/bench_logging.py --seeds 2 --planners straight dwa
    .venv/bin/python tools/bench/bench_logging.py --full-benchmark /tmp/bench-logs -j 2
    .venv/bin/python tools/bench/bench_logging.py --planners dwa orca social-force \\
        straight td3-base td3-srfm vo --seeds 4 --full-benchmark /tmp/bench-logs -j 2 \\
        --json docs/results/performance/logging.json

``--json PATH`` also writes every episode's measurements (CPU and wall seconds of each
stage, bytes of each file, the compact file's bytes by channel, the exact positions'
bytes in each encoding) and the run's record (``tools/results/record.py``): the data of
the generated figures of docs/logging.md and docs/performance.md.
"""

from __future__ import annotations

import argparse
import gc
import json
import os
import platform
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from collections import defaultdict
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))
from tools.results.record import run_record, start

EVALUATION = ("footpath", "crosswalk", "cross_footpath", "circle", "concert")
CLASSICAL = ("straight", "dwa", "vo", "orca", "social-force")


def _timed(fn: Any) -> tuple[Any, float, float]:
    """Result, CPU seconds and wall seconds of ``fn()``."""
    cpu, wall = time.process_time(), time.perf_counter()
    out = fn()
    return out, time.process_time() - cpu, time.perf_counter() - wall


def _encodings(pos: Any, out: dict[str, list[float]]) -> None:
    """zstd (level 3, as in MCAP chunks) bytes per value of exact positions: decimal
    JSON text, the .npy file (stored by log schemas 3 and 4, base64 in JSON), a byte
    shuffle (the HDF5/Blosc filter) of the values with time last (reference), and the
    bit planes of the second differences that log schema 5 stores (when the tree
    measured has them)."""
    import base64
    import io

    import numpy as np
    import zstandard

    zc = zstandard.ZstdCompressor(level=3)

    def npy_of(a: Any) -> bytes:
        buf = io.BytesIO()
        np.save(buf, a, allow_pickle=False)
        return buf.getvalue()

    npy = npy_of(pos)
    time_last = np.ascontiguousarray(np.moveaxis(pos, 0, -1))
    ways = {
        "decimal JSON, one message per step": "\n".join(json.dumps(p) for p in pos.tolist()),
        ".npy file": npy,
        ".npy file, base64 (log schemas 3 and 4)": base64.b64encode(npy),
        "byte shuffle, time last (reference)": time_last.view(np.uint8).reshape(-1, 8).T.tobytes(),
    }
    try:
        from srfm.logs._planes import to_planes
    except ImportError:  # a tree from before log schema 5
        pass
    else:
        ways["bit planes of the second differences, .npy, base64 (log schema 5)"] = (
            base64.b64encode(npy_of(to_planes(pos)))
        )
    for name, data in ways.items():
        raw = data.encode() if isinstance(data, str) else data
        out[name].append(len(zc.compress(raw)) / pos.size)
        out[f"bytes: {name}"].append(float(len(zc.compress(raw))))


def channel_bytes(path: Path) -> dict[str, int]:
    """Bytes of an MCAP file by what they hold: each channel's messages (the
    ``/srfm/trajectories`` messages by group) as zstd level 3 compresses them alone, the
    schemas (uncompressed, as the summary repeats them) and ``file``, the file's size."""
    import zstandard
    from mcap.reader import make_reader

    zc = zstandard.ZstdCompressor(level=3)
    data: dict[str, list[bytes]] = defaultdict(list)
    schemas: dict[str, int] = {}
    with path.open("rb") as f:
        reader = make_reader(f)
        for schema, channel, message in reader.iter_messages():
            key = channel.topic
            if key == "/srfm/trajectories":
                key += ":" + str(json.loads(message.data)["group"])
            data[key].append(message.data)
            if schema is not None:
                schemas[schema.name] = len(schema.data)
    out = {key: len(zc.compress(b"".join(parts))) for key, parts in sorted(data.items())}
    out.update({f"schema: {name}": n for name, n in sorted(schemas.items())})
    out["file"] = path.stat().st_size
    return out


def _run_episode() -> Any:
    """``run_episode`` of this tree or of an older one (``PYTHONPATH`` = a checkout from
    before the package layout of issue 11, for before/after measurements)."""
    try:
        from srfm.sim.episode import run_episode
    except ImportError:  # the layout before srfm/sim/
        from srfm.episode import run_episode  # type: ignore[no-redef]
    return run_episode


def _measure_one(
    root: Path, scenario: Any, seed: int, planner: str, first: bool, m: dict[str, Any]
) -> None:
    """Simulate one episode, then time and size every kind of log of it."""
    from srfm.logs import load_episode, write_counterfactual_mcap, write_episode_mcap, write_rrd
    from srfm.metrics import episode_metrics

    run_episode = _run_episode()

    def simulate() -> Any:
        record = run_episode(scenario, seed, planner, parallel=False)
        return record, episode_metrics(record)

    (record, metrics), c, w = _timed(simulate)
    m["cpu"]["simulate + metrics"].append(c)
    m["wall"]["simulate + metrics"].append(w)
    _encodings(record.factual_pos, m["encoding"])
    row: dict[str, Any] = {
        "scenario": scenario.name,
        "planner": planner,
        "seed": seed,
        "steps": int(record.end_step),
        "pedestrians": int(record.factual_pos.shape[1]),
        "position_values": int(record.factual_pos.size),
        "cpu_s": {"simulate + metrics": c},
        "wall_s": {"simulate + metrics": w},
        "bytes": {},
        "encoding_bytes": {
            k[len("bytes: ") :]: v[-1] for k, v in m["encoding"].items() if k.startswith("bytes: ")
        },
    }
    stem = root / f"{scenario.name}-{planner}-{seed}"
    cf = root / f"{scenario.name}-cf-{seed}.mcap"

    def compact() -> int:
        n = 0
        if first:  # the first planner of a seed writes the shared counterfactual file
            n = write_counterfactual_mcap(cf, record, scenario=scenario, fsync=False)
        return n + write_episode_mcap(
            stem.with_suffix(".mcap"),
            record,
            scenario=scenario,
            metrics=metrics,
            profile="compact",
            counterfactual_file=cf.name,
            fsync=False,
        )

    def full() -> int:
        return write_episode_mcap(
            stem.with_suffix(".full.mcap"),
            record,
            scenario=scenario,
            metrics=metrics,
            profile="full",
            fsync=False,
        )

    def rrd(forces: bool) -> int:
        suffix = ".f.rrd" if forces else ".rrd"
        return write_rrd(
            stem.with_suffix(suffix), record, scenario=scenario, metrics=metrics, forces=forces
        )

    def score() -> Any:
        return episode_metrics(load_episode(stem.with_suffix(".mcap")).record)

    stages = {
        "mcap compact": compact,
        "mcap full": full,
        "rrd": lambda: rrd(False),
        "rrd + forces": lambda: rrd(True),
        "score (compact)": score,
    }
    for stage, fn in stages.items():
        out, c, w = _timed(fn)
        m["cpu"][stage].append(c)
        m["wall"][stage].append(w)
        row["cpu_s"][stage] = c
        row["wall_s"][stage] = w
        if isinstance(out, int):
            m["size"][stage].append(out)
            row["bytes"][stage] = out
    m["size"]["compact episode file"].append(stem.with_suffix(".mcap").stat().st_size)
    row["bytes"]["compact episode file"] = stem.with_suffix(".mcap").stat().st_size
    row["compact_channels"] = channel_bytes(stem.with_suffix(".mcap"))
    if first:
        m["size"]["shared counterfactual file"].append(cf.stat().st_size)
        row["bytes"]["shared counterfactual file"] = cf.stat().st_size
    m["episodes"].append(row)
    for p in root.glob(f"{stem.name}*"):
        p.unlink()


def per_episode(scenarios: list[str], planners: list[str], seeds: list[int]) -> dict[str, Any]:
    """Time every stage and record every file size; returns the raw measurements."""
    from srfm.logs import load_episode, write_episode_mcap, write_rrd
    from srfm.metrics import episode_metrics
    from srfm.scenarios import load_scenario

    run_episode = _run_episode()

    m: dict[str, Any] = {k: defaultdict(list) for k in ("cpu", "wall", "size", "encoding")}
    m["episodes"] = []
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        warm = load_scenario("concert")  # compile and load everything once, untimed
        for planner in planners:  # (policies load their networks on the first episode)
            rec = run_episode(warm, 0, planner, parallel=False)
        write_episode_mcap(root / "w.mcap", rec, scenario=warm, metrics=episode_metrics(rec))
        load_episode(root / "w.mcap")
        write_rrd(root / "w.rrd", rec, scenario=warm, forces=True)
        gc.collect()  # not inside the first timed stage
        for name in scenarios:
            scenario = load_scenario(name)
            for seed in seeds:
                for i, planner in enumerate(planners):
                    _measure_one(root, scenario, seed, planner, i == 0, m)
    return m


def _ms(values: list[float]) -> str:
    return f"{statistics.median(values) * 1e3:.1f} | {statistics.fmean(values) * 1e3:.1f}"


def report(m: dict[str, Any], n_planners: list[int], n_scenarios: int, seeds: int) -> str:
    """Markdown tables of the per-episode measurements and the projection."""
    cpu, wall, size = m["cpu"], m["wall"], m["size"]
    base = statistics.fmean(cpu["simulate + metrics"])
    lines = [
        "| stage | CPU ms, median | CPU ms, mean | CPU ms, max | wall ms, median | "
        "wall ms, mean | mean CPU / simulation |",
        "|---|--:|--:|--:|--:|--:|--:|",
    ]
    for stage in cpu:
        ratio = statistics.fmean(cpu[stage]) / base
        worst = max(cpu[stage]) * 1e3
        lines.append(
            f"| {stage} | {_ms(cpu[stage])} | {worst:.1f} | {_ms(wall[stage])} | {ratio:.2f}× |"
        )
    lines += ["", "| file | kB mean | kB min | kB max | files |", "|---|--:|--:|--:|--:|"]
    rename = {
        "compact episode file": "MCAP compact, episode file",
        "shared counterfactual file": "MCAP compact, shared counterfactual file",
        "mcap full": "MCAP full (srfm simulate)",
        "rrd": "Rerun .rrd",
        "rrd + forces": "Rerun .rrd with force arrows",
    }
    for key, label in rename.items():
        v = size[key]
        lines.append(
            f"| {label} | {statistics.fmean(v) / 1e3:.1f} | {min(v) / 1e3:.1f} | "
            f"{max(v) / 1e3:.1f} | {len(v)} |"
        )
    lines += ["", "| exact factual positions, zstd level 3 | bytes per value, mean |", "|---|--:|"]
    for name, values in m["encoding"].items():
        if name.startswith("bytes: "):
            continue
        lines.append(f"| {name} | {statistics.fmean(values):.2f} |")
    ep = statistics.fmean(size["compact episode file"])
    cf = statistics.fmean(size["shared counterfactual file"])
    lines += [
        "",
        f"Projected MCAP output of a {seeds}-seed benchmark over {n_scenarios} scenarios "
        "(compact episode files + one shared counterfactual file per scenario and seed):",
        "",
    ]
    for p in n_planners:
        total = n_scenarios * seeds * (p * ep + cf)
        lines.append(
            f"- {p} planners: {total / 1e6:.0f} MB ({(ep + cf / p) / 1e3:.1f} kB per episode)"
        )
    return "\n".join(lines)


def _folder_bytes(root: Path, suffix: str) -> tuple[int, int]:
    files = [p for p in root.rglob(f"*{suffix}") if p.is_file()]
    return len(files), sum(p.stat().st_size for p in files)


def full_benchmark(out: Path, planners: list[str], jobs: int) -> tuple[str, list[dict[str, Any]]]:
    """Run the 100-seed benchmark without and with logs; report time and bytes (as a
    Markdown table and as one dict per run)."""
    srfm = str(Path(sys.executable).with_name("srfm"))
    rows = []
    data = []
    for label, extra in (("no logs", ["--no-logs"]), ("default logs", [])):
        folder = out / label.replace(" ", "-")
        cmd = [
            srfm,
            "benchmark",
            "-p",
            ",".join(planners),
            "--out",
            str(folder),
            "--no-figures",
            "-j",
            str(jobs),
            *extra,
        ]
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        load_before = os.getloadavg()[0]
        start_t = time.perf_counter()
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
        wall = time.perf_counter() - start_t
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
        logs = folder / "logs"
        n_mcap, b_mcap = _folder_bytes(logs, ".mcap") if logs.exists() else (0, 0)
        n_rrd, b_rrd = _folder_bytes(logs, ".rrd") if logs.exists() else (0, 0)
        cf = logs.rglob("_counterfactual/*.mcap") if logs.exists() else iter(())
        cf_files = [p for p in cf if p.is_file()]
        rows.append(
            f"| {label} | {wall:.1f} | {cpu:.1f} | {n_mcap} | {b_mcap / 1e6:.1f} | "
            f"{n_rrd} | {b_rrd / 1e6:.1f} |"
        )
        data.append(
            {
                "run": label,
                "command": " ".join(["srfm", *cmd[1:]]).replace(str(folder), f"DIR/{folder.name}"),
                "wall_s": round(wall, 2),
                "cpu_s": round(cpu, 2),
                "load_before": round(load_before, 2),
                "load_after": round(os.getloadavg()[0], 2),
                "mcap_files": n_mcap,
                "mcap_bytes": b_mcap,
                "counterfactual_files": len(cf_files),
                "counterfactual_bytes": sum(p.stat().st_size for p in cf_files),
                "rrd_files": n_rrd,
                "rrd_bytes": b_rrd,
            }
        )
    head = [
        f"`srfm benchmark -p {','.join(planners)} --no-figures -j {jobs}` (100 seeds, "
        "5 scenarios):",
        "",
        "| run | wall s | CPU s (all workers) | .mcap files | MCAP MB | .rrd files | Rerun MB |",
        "|---|--:|--:|--:|--:|--:|--:|",
    ]
    return "\n".join(head + rows), data


def main() -> None:
    """Command-line entry point."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scenarios", nargs="+", default=list(EVALUATION))
    parser.add_argument("--planners", nargs="+", default=list(CLASSICAL))
    parser.add_argument("--seeds", type=int, default=4, help="seeds 0 .. N-1 per cell")
    parser.add_argument("--project-planners", type=int, nargs="+", default=[5, 7])
    parser.add_argument("--full-benchmark", type=Path, default=None, metavar="DIR")
    parser.add_argument("-j", "--jobs", type=int, default=2)
    parser.add_argument("--json", type=Path, default=None, help="also write every episode here")
    args = parser.parse_args()
    started, t0, load0 = start()
    os.environ.setdefault("NUMBA_NUM_THREADS", "1")
    import srfm.logs

    print(
        f"python {platform.python_version()}, {platform.machine()}, {os.cpu_count()} CPUs, "
        f"load average {os.getloadavg()[0]:.1f}; srfm from {Path(srfm.logs.__file__).parents[2]}"
    )
    m = per_episode(args.scenarios, args.planners, list(range(args.seeds)))
    episodes = len(m["cpu"]["simulate + metrics"])
    print(
        f"\n{episodes} episodes ({len(args.scenarios)} scenarios × {len(args.planners)} "
        f"planners × {args.seeds} seeds), one process:\n"
    )
    print(report(m, args.project_planners, len(args.scenarios), 100))
    benchmark_runs: list[dict[str, Any]] = []
    if args.full_benchmark is not None:
        print()
        text, benchmark_runs = full_benchmark(args.full_benchmark, args.planners, args.jobs)
        print(text)
    print(f"\nload average at the end {os.getloadavg()[0]:.1f}")
    if args.json is not None:
        doc = {
            "scenarios": args.scenarios,
            "planners": args.planners,
            "seeds": list(range(args.seeds)),
            "episodes": m["episodes"],
            "full_benchmark": benchmark_runs,
            "run": run_record(started, t0, load0),
        }
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(doc, indent=1) + "\n", encoding="utf-8")
        print(f"-> {args.json}")


if __name__ == "__main__":
    main()
