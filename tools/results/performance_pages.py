"""The generated blocks of docs/performance.md (all but its speed goals, external
planners, benchmark wall time and logging).

Each block renders a table or a sentence from a JSON record under
``docs/results/performance/`` that a script of ``tools/bench/`` wrote with ``--json``
(the figures, the run's record of ``tools/results/record.py`` and the machine); nothing
is measured here, only formatted, with medians, minima, ranges and ratios of the
recorded figures where said. ``tools/results/generate.py`` registers them (``BLOCKS``).
"""

from __future__ import annotations

import json
import re
import statistics
from collections.abc import Callable
from pathlib import Path
from typing import Any

from tools.results.pages import MissingDataError

ROOT = Path(__file__).resolve().parents[2]
FOLDER = ROOT / "docs" / "results" / "performance"

# file -> the command that writes it (from the repository's root)
COMMANDS: dict[str, str] = {
    "commands.json": "python tools/bench/bench_commands.py --rows help simulate quick-bare "
    "quick cold cold-busy --runs 3 --json docs/results/performance/commands.json",
    "episodes.json": "python tools/bench/bench_episode.py --scenarios footpath crosswalk "
    "cross_footpath circle concert random --json docs/results/performance/episodes.json",
    "crowd.json": "python tools/bench/bench_crowd_step.py --side-by-side "
    "--side-by-side-repeats 5 --cpu-time --sizes 10 100 1000 10000 --memory-n 0 --seconds 1 "
    "--repeats 5 --json docs/results/performance/crowd.json",
    "robot_forms.json": "python tools/bench/bench_crowd_step.py --robot-forms --sizes 10 1000 "
    "--cpu-time --seconds 4 --repeats 8 --memory-n 0 "
    "--json docs/results/performance/robot_forms.json",
    "cutoff.json": "python tools/bench/check_cutoff.py --large-seeds 1 "
    "--json docs/results/performance/cutoff.json",
    "env.json": "python tools/bench/bench_env.py --steps 50000 --repeats 3 "
    "--json docs/results/performance/env.json",
    "train.json": "python tools/bench/bench_train.py --only sb3-paper,sbx-64-tf50,"
    "sbx-64-tf50-ar4 --repeats 2 --json docs/results/performance/train.json",
    # the README's install table (tools/results/readme_pages.py)
    "install.json": "python tools/bench/bench_install.py "
    "--json docs/results/performance/install.json",
}
GOALS = "goals.json"  # the speed goals' record (generate.performance_goals)
RUN_KEYS = ("command", "commit", "started", "finished", "wall_s", "machine")


class RecordError(ValueError):
    """A record of ``docs/results/performance/`` lacks what its script writes."""


def check_record(name: str, doc: dict[str, Any]) -> None:
    """Refuse a record that its command did not write: the run's record
    (``tools/results/record.py``) with the command of ``COMMANDS``, a clean commit, the
    times and the machine.

    Raises:
        RecordError: naming the file and what is wrong.
    """
    run = doc.get("run")
    if not isinstance(run, dict):
        raise RecordError(f"docs/results/performance/{name}: no run record (`run`)")
    missing = [k for k in RUN_KEYS if k not in run]
    if missing:
        raise RecordError(f"docs/results/performance/{name}: the run record lacks {missing}")
    if run["command"] != COMMANDS[name]:
        raise RecordError(
            f"docs/results/performance/{name}: written by `{run['command']}`, "
            f"not by the page's `{COMMANDS[name]}`"
        )
    if not re.fullmatch(r"[0-9a-f]{7,40}", run["commit"]):
        raise RecordError(
            f"docs/results/performance/{name}: commit {run['commit']!r} is not a clean checkout's"
        )
    if not run["started"] <= run["finished"] or not run["wall_s"] > 0:
        raise RecordError(
            f"docs/results/performance/{name}: started {run['started']}, finished "
            f"{run['finished']}, wall {run['wall_s']} s"
        )
    if not {"cpu", "cores", "packages"} <= set(doc.get("machine", {})):
        raise RecordError(f"docs/results/performance/{name}: no machine record (`machine`)")


def record(name: str) -> dict[str, Any]:
    """A committed record of ``docs/results/performance/``, checked (:func:`check_record`)
    unless it is the speed goals' record, which keeps its own provenance.

    Raises:
        MissingDataError: the file is not committed.
        RecordError: the file is not what its command writes.
    """
    path = FOLDER / name
    if not path.is_file():
        command = COMMANDS.get(name, "tools/bench/bench_commands.py --json")
        raise MissingDataError(f"`docs/results/performance/{name}` (`{command}`)")
    doc: dict[str, Any] = json.loads(path.read_text(encoding="utf-8"))
    if name != GOALS:
        check_record(name, doc)
    return doc


def provenance(name: str) -> str:
    """One line: when, on which commit and machine, at which load, by which command."""
    doc = record(name)
    run, machine = doc["run"], doc["machine"]
    other = doc.get("other_cpu_percent")
    share = (
        f"; other processes {other:.1f} % of the CPU during the measurements"
        if other is not None
        else ""
    )
    return (
        f"*Measured {run['started'][:16].replace('T', ' ')} UTC on commit `{run['commit']}`, "
        f"{machine['cpu']} ({machine['cores']} logical cores; {run['machine'].split(', ', 2)[2]}"
        f"{share}), {run['wall_s']:.0f} s of wall time: `{run['command']}` "
        f"([data](results/performance/{name})).*"
    )


def _goals_provenance() -> str:
    """Where the rows taken from the speed goals' record come from (no emphasis)."""
    doc = record(GOALS)
    return (
        f"Speed goals' record: measured {doc['date']} on commit `{doc['commits']['A']}`, "
        f"`{doc['command']}` ([data](results/performance/{GOALS}))."
    )


def _median(values: list[float]) -> float:
    return float(statistics.median(values))


def _spread(values: list[float], digits: int = 2) -> str:
    return f"{_median(values):.{digits}f} ({min(values):.{digits}f}–{max(values):.{digits}f})"


def _range(values: list[float], digits: int) -> str:
    lo, hi = min(values), max(values)
    if f"{lo:.{digits}f}" == f"{hi:.{digits}f}":
        return f"{lo:.{digits}f}"
    return f"{lo:.{digits}f}–{hi:.{digits}f}"


def _rate(rate: float | None) -> str:
    """Agent-steps/s with a k/M suffix."""
    if rate is None:
        return "–"
    if rate >= 1e6:
        return f"{rate / 1e6:.2f} M"
    if rate >= 1e3:
        return f"{rate / 1e3:.1f} k"
    return f"{rate:.0f}"


# -- Commands ----------------------------------------------------------------------------

# (row of bench_commands.py, label, goal: wall s at most)
COMMAND_GOALS: tuple[tuple[str, str, float], ...] = (
    ("help", "`srfm --help`", 0.3),
    ("simulate", "`srfm simulate --scenario crosswalk --seed 0 --planner dwa`", 1.0),
    ("quick-bare", "`srfm benchmark --quick --no-logs --no-figures`", 4.0),
    ("quick", "`srfm benchmark --quick`", 8.0),
    ("cold", "`srfm benchmark --quick`, empty numba cache", 20.0),
    ("cold-busy", "the same with the other core busy (a Python busy loop beside it)", 40.0),
)
FULL_GOAL_S = 60.0
MCAP_GOAL_KB = 60.0
CROWD_GOAL = 3.0  # srfm / JuPedSim at N = 1000, the shared script


def _verdict(met: bool, by: str) -> str:
    return "**met**" if met else f"not met, by {by}"


def _full_row() -> list[str]:
    """The full benchmark's and its MCAP files' rows, from the speed goals' record."""
    doc = record(GOALS)
    runs = doc["rows"]["full"]["runs"]["A"]
    wall = [r["wall_s"] for r in runs]
    cpu = [r["cpu_s"] for r in runs]
    kb = _median([r["mcap_bytes"] for r in runs]) / 1e3
    over = _median(wall) - FULL_GOAL_S
    return [
        f"| `srfm benchmark` (seeds 0–99, 7 planners, 3,500 episodes, default logs)¹ "
        f"| ≤ {FULL_GOAL_S:g} | {_spread(wall)} | {_median(cpu):.2f} "
        f"| {_verdict(over <= 0, f'{over:.1f} s')} |",
        f"| MCAP per episode of that run (compact, exact positions)¹ | ≤ {MCAP_GOAL_KB:g} kB "
        f"| {kb:.1f} kB | | {_verdict(kb <= MCAP_GOAL_KB, f'{kb - MCAP_GOAL_KB:.0f} kB')} |",
    ]


def _crowd_row() -> str:
    doc = record(GOALS)
    runs = doc["rows"]["shared-crowd"]["runs"]["A"]
    ratios = [r["srfm_1000"] / r["jupedsim_1000"] for r in runs]
    met = _median(ratios) >= CROWD_GOAL
    return (
        f"| crowd step at N = 1,000 against JuPedSim's social force model (the shared "
        f"script)¹ | ≥ {CROWD_GOAL:g}× | {_spread(ratios)}× | | "
        f"{_verdict(met, f'{CROWD_GOAL - _median(ratios):.2f}×')} |"
    )


def commands_table() -> str:
    """What a user waits for: every command's wall and CPU time against its goal."""
    doc = record("commands.json")
    lines = [
        provenance("commands.json"),
        "",
        "Median (min–max) of the runs after one untimed run (the cold rows: a new, empty "
        "numba cache every run); CPU s: the command and all its workers, median.",
        "",
        "| command | goal (wall s) | wall s | CPU s | verdict |",
        "|---|---|---:|---:|---|",
    ]
    for row, label, goal in COMMAND_GOALS:
        entry = doc["rows"].get(row)
        if entry is None:
            lines.append(f"| {label} | ≤ {goal:g} | not measured | | – |")
            continue
        runs = entry["runs"]["A"]
        wall = [r["wall_s"] for r in runs]
        cpu = [r["cpu_s"] for r in runs]
        over = _median(wall) - goal
        lines.append(
            f"| {label} | ≤ {goal:g} | {_spread(wall)} | {_median(cpu):.2f} "
            f"| {_verdict(over <= 0, f'{over:.2f} s')} |"
        )
    lines += [*_full_row(), _crowd_row(), "", f"¹ *{_goals_provenance()}*"]
    loads = "; ".join(
        f"{row} {doc['rows'][row]['load_before']} → {doc['rows'][row]['load_after']}"
        for row, _, _ in COMMAND_GOALS
        if row in doc["rows"]
    )
    lines += ["", f"Load average (1/5/15 min) before → after each row: {loads}."]
    return "\n".join(lines)


# -- Machine -----------------------------------------------------------------------------


def machine() -> str:
    """The machine and software of the records (each record keeps its own)."""
    doc = record("commands.json")
    m = doc["machine"]
    packages = ", ".join(f"{k} {v}" for k, v in m["packages"].items() if v != "not installed")
    others = sorted(
        {
            record(name)["machine"]["cpu"]
            for name in COMMANDS
            if (FOLDER / name).is_file() and record(name)["machine"] != m
        }
    )
    same = (
        "Every record of this page was taken on it."
        if not others
        else "Records on other machines: " + ", ".join(others) + " (each says so)."
    )
    return (
        f"{m['cpu']}, {m['cores']} logical cores, {m['memory_gib']:g} GiB of memory; "
        f"{m['os']}; Python {m['python']}; {packages} (as recorded in "
        f"`docs/results/performance/commands.json`). {same}"
    )


# -- Full episodes -----------------------------------------------------------------------


def _episode_rows(doc: dict[str, Any], planner: str) -> dict[str, dict[str, Any]]:
    return {r["scenario"]: r for r in doc["planners"][planner]}


def episodes_table() -> str:
    doc = record("episodes.json")
    straight, stay = _episode_rows(doc, "straight"), _episode_rows(doc, "stay")
    lines = [
        provenance("episodes.json"),
        "",
        f"Seeds 0–{doc['seeds'] - 1} of each scenario after one untimed episode; wall time in ms.",
        "",
        "| scenario | `straight`: robot active steps (median) | median (ms) | min (ms) "
        "| `stay` (active all steps): median (ms) | min (ms) |",
        "|---|---:|---:|---:|---:|---:|",
    ]
    for name, r in straight.items():
        s = stay[name]
        lines.append(
            f"| {name} | {r['active_steps_median']:g} | {1e3 * _median(r['times_s']):.1f} "
            f"| {1e3 * min(r['times_s']):.1f} | {1e3 * _median(s['times_s']):.1f} "
            f"| {1e3 * min(s['times_s']):.1f} |"
        )
    per_step = [_median(s["times_s"]) / s["horizon_steps"] * 1e6 for s in stay.values()]
    horizon = {s["horizon_steps"] for s in stay.values()}
    lines += [
        "",
        f"With `stay` a step costs {_range(per_step, 0)} µs (median episode over its "
        f"{'/'.join(map(str, sorted(horizon)))} steps); the first episode in the process "
        f"(numba's cache {doc['numba_cache']}) took {doc['first_episode_s']:.2f} s.",
    ]
    return "\n".join(lines)


def _episode_summary() -> str:
    doc = record("episodes.json")
    straight = doc["planners"]["straight"]
    stay = doc["planners"]["stay"]
    med = [1e3 * _median(r["times_s"]) for r in straight]
    mins = [1e3 * min(r["times_s"]) for r in straight]
    stay_med = [1e3 * _median(r["times_s"]) for r in stay]
    return (
        f"{_range(med, 1)} ms (median over {doc['seeds']} seeds; minima {_range(mins, 1)} ms); "
        f"{_range(stay_med, 1)} ms with the robot active for the whole horizon"
    )


# -- Crowd step --------------------------------------------------------------------------


def _shared_ratios() -> dict[int, list[float]]:
    runs = record(GOALS)["rows"]["shared-crowd"]["runs"]["A"]
    return {
        n: [r[f"srfm_{n}"] / r[f"jupedsim_{n}"] for r in runs]
        for n in (1000, 10000)
        if f"srfm_{n}" in runs[0]
    }


def crowd_table() -> str:
    doc = record("crowd.json")
    opts = doc["options"]
    sbs = {r["n"]: r for r in doc["side_by_side"]}
    shared = _shared_ratios()
    lines = [
        provenance("crowd.json"),
        "",
        f"Agent-steps per {'CPU-' if opts['clock'] == 'cpu' else ''}second, best of "
        f"{opts['repeats']} over {opts['seconds']:g} s per simulator and size, the first "
        f"{opts['window_s']:g} s of simulated time; side-by-side rows best of "
        f"{opts['side_by_side_repeats']}; the shared script's column (wall time) is the "
        "median (min–max) ratio of the speed goals' record.",
        "",
        "| N | srfm serial | srfm default | JuPedSim | default / JuPedSim | side-by-side rows "
        "| shared script | srfm µs per step | JuPedSim µs per 0.01 s step |",
        "|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for r in doc["rates"]:
        n = r["n"]
        jps = r["jupedsim"]
        side = sbs.get(n)
        lines.append(
            f"| {n} | {_rate(r['srfm_serial'])} | {_rate(r['srfm_default'])} "
            f"({r['default_kernel']}) | {_rate(jps)} "
            f"| {r['srfm_default'] / jps:.2f}× | "
            + (f"{side['srfm'] / side['jupedsim']:.2f}×" if side else "–")
            + " | "
            + (f"{_spread(shared[n])}×" if n in shared else "–")
            + f" | {n / r['srfm_default'] * 1e6:,.1f} | {n / jps * 1e6:,.1f} |"
        )
    lines += ["", f"*{_goals_provenance()}*", "", pysocialforce_sentence()]
    return "\n".join(lines)


def pysocialforce_sentence() -> str:
    doc = record("crowd.json")
    rows = [r for r in doc["rates"] if r["pysocialforce"] is not None]
    if not rows:
        return "PySocialForce was not run (`--no-pysocialforce`)."
    ns = ", ".join(f"{r['n']:,}" for r in rows)
    ours = ", ".join(_rate(r["srfm_default"]) for r in rows)
    theirs = ", ".join(_rate(r["pysocialforce"]) for r in rows)
    ratios = ", ".join(f"{r['srfm_default'] / r['pysocialforce']:,.1f}×" for r in rows)
    return (
        f"PySocialForce (O(N²) memory, run up to N = {doc['options']['max_pysocialforce']:,}) "
        f"in the same run: srfm {ours} against {theirs} agent-steps per "
        f"{'CPU-' if doc['options']['clock'] == 'cpu' else ''}second at N = {ns}: "
        f"**{ratios}**."
    )


# -- Robot forms -------------------------------------------------------------------------


def robot_forms_table() -> str:
    doc = record("robot_forms.json")
    rows = doc["robot_forms"]
    forms = sorted(rows[0]["rates"], key=lambda f: (f != "exponential", f))
    opts = doc["options"]
    lines = [
        provenance("robot_forms.json"),
        "",
        f"µs per crowd step (in brackets: relative to the paper's exponential form), the "
        f"forms timed in turn within each of {opts['repeats']} repeats, best kept, "
        f"{'CPU' if opts['clock'] == 'cpu' else 'wall'} time:",
        "",
        "| N | "
        + " | ".join(f"{f}{' (the paper’s)' if f == 'exponential' else ''}" for f in forms)
        + " |",
        "|---:|" + "---:|" * len(forms),
    ]
    worst: dict[str, float] = {}
    for row in rows:
        n, rates = row["n"], row["rates"]
        base = rates["exponential"]
        cells = []
        for f in forms:
            ratio = base / rates[f]
            worst[f] = max(worst.get(f, 0.0), ratio)
            cells.append(f"{n / rates[f] * 1e6:,.1f} µs ({ratio:.2f}×)")
        lines.append(f"| {n} | " + " | ".join(cells) + " |")
    over = [f for f, w in worst.items() if w > doc["target"]]
    lo, hi = min(worst.values()), max(worst.values())
    lines += [
        "",
        (
            f"Every form is within the target of {doc['target']:g}× the paper's form "
            if not over
            else f"Over the target of {doc['target']:g}× the paper's form: "
            + ", ".join(over)
            + "; "
        )
        + f"(each form's slowest ratio: {lo:.2f}–{hi:.2f}×).",
    ]
    return "\n".join(lines)


def _robot_forms_summary() -> str:
    doc = record("robot_forms.json")
    ratios = [
        row["rates"]["exponential"] / r
        for row in doc["robot_forms"]
        for f, r in row["rates"].items()
        if f != "exponential"
    ]
    ns = " and ".join(str(row["n"]) for row in doc["robot_forms"])
    return f"{_range(ratios, 2)}× the paper's form at N = {ns}"


# -- Cut-off -----------------------------------------------------------------------------


def cutoff_distances() -> str:
    doc = record("cutoff.json")
    return (
        f"with `agrawal2024` and r = {doc['radius_m']:g} m, **d_ped = {doc['d_ped_m']:.2f} m**, "
        f"**d_obs = {doc['d_obs_m']:.2f} m** (tol = {doc['tolerance_mps2']:g} m/s²)."
    )


def cutoff_table() -> str:
    doc = record("cutoff.json")
    rows = doc["rows"]
    lines = [
        provenance("cutoff.json"),
        "",
        "| scenario | N | walls + pillars | seeds | cut-off (m) | largest force difference (m/s²) "
        "| largest position difference (m) |",
        "|---|---:|---:|---:|---:|---:|---:|",
    ]
    for r in rows:
        lines.append(
            f"| {r['scenario']} | {r['pedestrians']} | {r['obstacles']} | {r['seeds']} "
            f"| {r['cutoff_m']:.2f} "
            f"| {_sci(r['force_difference_mps2'])} | {_sci(r['position_difference_m'])} |"
        )
    worst = max(rows, key=lambda r: r["force_difference_mps2"])
    over = [
        r["scenario"]
        for r in rows
        if r["force_difference_mps2"]
        > (r["pedestrians"] - 1 + r["obstacles"]) * doc["tolerance_mps2"]
    ]
    bound = (
        "within that bound in every scenario"
        if not over
        else "above that bound in " + ", ".join(over)
    )
    lines += [
        "",
        "The force column is the cut-off's own error in one step: each term it leaves out "
        "is below tol, so it is at most tol times the other pedestrians and obstacles "
        f"(N − 1 + walls + pillars), and it is {bound}; **at most "
        f"{_sci(worst['force_difference_mps2'])} m/s²** ({worst['scenario']}).",
    ]
    return "\n".join(lines)


def _sci(x: float) -> str:
    return "0" if x == 0 else f"{x:.2e}"


# -- Environment and training ------------------------------------------------------------

ENV_SHOWN = (
    "SocialNavEnv, full twin",
    "SocialNavEnv, no full twin (training)",
    "gym.make (default wrappers), full twin",
)
SAMPLE = "SocialNavEnv + action_space.sample() per step"


def env_table() -> str:
    doc = record("env.json")
    lines = [
        provenance("env.json"),
        "",
        f"One environment, random actions drawn up front, resets inside the timed loop, "
        f"{doc['repeats']} blocks of {doc['steps']:,} steps after an untimed one:",
        "",
        "| scenario | configuration | best (steps/s) | median (steps/s) | µs per step (best) |",
        "|---|---|---:|---:|---:|",
    ]
    sampled = []
    for r in doc["rows"]:
        rates = r["steps_per_s"]
        if r["configuration"] == SAMPLE:
            sampled.append(f"{max(rates):,.0f} (`{r['scenario']}`)")
        if r["configuration"] not in ENV_SHOWN:
            continue
        lines.append(
            f"| {r['scenario']} | {r['configuration']} | {max(rates):,.0f} "
            f"| {_median(rates):,.0f} | {1e6 / max(rates):.1f} |"
        )
    if sampled:
        lines += [
            "",
            "*no full twin*: `EnvConfig(counterfactual_twin=False)`, the training set-up. "
            "Drawing actions with gymnasium's `Box.sample` inside the loop: "
            + " and ".join(sampled)
            + " steps/s (best block).",
        ]
    return "\n".join(lines)


def _env_best(scenario: str) -> float:
    rows = record("env.json")["rows"]
    return max(
        float(max(r["steps_per_s"]))
        for r in rows
        if r["scenario"] == scenario and r["configuration"] == ENV_SHOWN[0]
    )


TRAIN_STEPS = 2_000_000


def train_table() -> str:
    doc = record("train.json")
    configs = doc["configurations"]
    ref = next((c["steps_per_s"] for c in configs if c["name"] == "sb3-paper"), None)
    lines = [
        provenance("train.json"),
        "",
        f"`random` scenario, {doc['warmup']:,} random-action steps, then {doc['learn']:,} "
        f"learning steps (the first {doc['settle']:,} untimed); best of {doc['repeats']} "
        "rounds (every round's rate in brackets). A step of a configuration with action "
        "repeat k is one action of k simulation steps.",
        "",
        "| configuration | backend | net | grad. steps / env steps | action repeat "
        "| steps/s (rounds) | × paper SB3 | 2M steps | 2M simulation steps |",
        "|---|---|---|---|---:|---:|---:|---:|---:|",
    ]
    for c in configs:
        rate = c["steps_per_s"]
        k = doc["action_repeat"][c["name"]]
        rounds = ", ".join(f"{x:.0f}" for x in c["rounds_steps_per_s"])
        lines.append(
            f"| `{c['name']}` | {c['backend']} | {c['net_arch']} "
            f"| {c['gradient_steps']} / {c['train_freq'] * c['n_envs']} | {k} "
            f"| {rate:.0f} ({rounds}) | {rate / ref:.2f} | {TRAIN_STEPS / rate / 3600:.2f} h "
            f"| {TRAIN_STEPS / (rate * k) / 3600:.2f} h |"
            if ref
            else f"| `{c['name']}` | {c['backend']} | {c['net_arch']} "
            f"| {c['gradient_steps']} / {c['train_freq'] * c['n_envs']} | {k} "
            f"| {rate:.0f} ({rounds}) | – | {TRAIN_STEPS / rate / 3600:.2f} h "
            f"| {TRAIN_STEPS / (rate * k) / 3600:.2f} h |"
        )
    return "\n".join(lines)


SHIPPED_TRAINING = "sbx-64-tf50-ar4"


def _train_summary() -> str:
    doc = record("train.json")
    c = next(c for c in doc["configurations"] if c["name"] == SHIPPED_TRAINING)
    k = doc["action_repeat"][SHIPPED_TRAINING]
    rate = c["steps_per_s"]
    return (
        f"{rate:,.0f} actions/s ({rate * k:,.0f} simulation steps/s); {TRAIN_STEPS:,} "
        f"simulation steps in {TRAIN_STEPS / (rate * k) / 3600:.2f} h"
    )


# -- In short ----------------------------------------------------------------------------


def in_short() -> str:
    """The page's summary table, every figure from the records below it."""
    commands = record("commands.json")["rows"]

    def wall(row: str) -> str:
        return f"{_median([r['wall_s'] for r in commands[row]['runs']['A']]):.2f} s"

    full = record(GOALS)["rows"]["full"]["runs"]["A"]
    shared = _shared_ratios()
    crowd = record("crowd.json")
    psf = [r for r in crowd["rates"] if r["pysocialforce"] is not None]
    big = max(crowd["rates"], key=lambda r: r["n"])
    lines = [
        "| what | current figure | section |",
        "|---|---|---|",
        "| one twin episode of a paper scenario (10 pedestrians, two crowds, 750 steps) | "
        + _episode_summary()
        + " | [Full episodes](#full-episodes) |",
        "| crowd step against JuPedSim's social force model (srfm / JuPedSim) | the shared "
        "script: "
        + ", ".join(f"{_spread(v)}× at N = {n:,}" for n, v in shared.items())
        + "; `bench_crowd_step.py`: "
        + ", ".join(
            f"{r['srfm_default'] / r['jupedsim']:.2f}× at N = {r['n']:,}" for r in crowd["rates"]
        )
        + f"; {_rate(big['srfm_default'])} agent-steps per "
        f"{'CPU-' if crowd['options']['clock'] == 'cpu' else ''}second at N = {big['n']:,}; "
        "PySocialForce: "
        + ", ".join(
            f"{r['srfm_default'] / r['pysocialforce']:,.1f}× at N = {r['n']:,}" for r in psf
        )
        + " | [Crowd step](#crowd-step-srfm-pysocialforce-and-jupedsim) |",
        f"| what a user waits for (wall time, median) | `srfm --help` {wall('help')}, "
        f"`srfm simulate` {wall('simulate')}, `srfm benchmark --quick` {wall('quick')} "
        f"({wall('quick-bare')} without logs and figures), its first run with an empty numba "
        f"cache {wall('cold')} | [Commands](#commands-what-a-user-waits-for) |",
        f"| the full benchmark (3,500 episodes, default logs) | "
        f"{_median([r['wall_s'] for r in full]):.1f} s "
        f"({_median([r['cpu_s'] for r in full]):.0f} CPU-s), "
        f"{_median([r['mcap_bytes'] for r in full]) / 1e3:.1f} kB of MCAP an episode "
        "| [Speed goals](#speed-goals) |",
        f"| gymnasium environment, one process | {_env_best('random'):,.0f} steps/s "
        f"(`random`), {_env_best('crosswalk'):,.0f} (`crosswalk`) "
        "| [Environment](#gymnasium-environment-throughput) |",
        f"| training with the shipped recipe | {_train_summary()} "
        "| [Training](#training-throughput) |",
        "| an external planner (C++ or Python over the protocol) | its overhead per control "
        "step and per episode | [External planners](#external-planners) |",
        f"| crowd step with the robot force's other forms | {_robot_forms_summary()} "
        "| [Robot force's forms](#the-robot-forces-forms) |",
        "",
        "Each figure's date, commit, load and command are under its section's table.",
    ]
    return "\n".join(lines)


BLOCKS: dict[str, Callable[[], str]] = {
    "performance-in-short": in_short,
    "performance-commands": commands_table,
    "performance-machine": machine,
    "performance-episodes": episodes_table,
    "performance-crowd": crowd_table,
    "performance-robot-forms": robot_forms_table,
    "performance-cutoff-distances": cutoff_distances,
    "performance-cutoff": cutoff_table,
    "performance-env": env_table,
    "performance-train": train_table,
}
