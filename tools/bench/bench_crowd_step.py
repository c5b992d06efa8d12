"""Crowd step throughput of srfm against PySocialForce and JuPedSim, in agent-steps per second.

For each crowd size N all simulators start from the same state: N pedestrians in a
square of side ``2·sqrt(N)`` m (0.25 pedestrians/m² at every N), one per cell of a
⌈√N⌉ × ⌈√N⌉ lattice (random cells, random jitter that keeps every pair at least
0.7 m apart: JuPedSim refuses overlapping agents), each heading for the point mirrored
through the square's centre, at rest, with no obstacles and no robot:

* srfm, dt = 1/15 s: ``srfm.step_crowd(crowd, 1/15, params, parallel=...)`` with the
  serial kernel, the parallel kernel and the default (``parallel=False``: serial),
  all with the default ``cutoff="auto"`` (exact below ``CELL_LIST_MIN_AGENTS``, cell
  list and interaction cut-off from it on). Forces: goal relaxation, anisotropic
  exponential pedestrian repulsion, obstacle repulsion (no obstacles here), no robot.
* PySocialForce: ``pysocialforce.Simulator(state, groups=None, obstacles=None)`` and
  ``sim.step(1)``, with its default config except: group forces off, step width 1/15 s,
  agent radius 0.3 m, and desired speed = maximum speed = 1.25 m/s. Forces: desired
  (goal) force, the Moussaïd social force over all pairs, obstacle force (no
  obstacles here). PySocialForce takes each pedestrian's desired speed from its
  *initial* speed, so with the shared zero initial velocity nobody would ever move;
  the script sets ``sim.peds.initial_speeds`` to 1.25 m/s after construction.
  O(N²) in numpy memory and time: skipped above ``--max-pysocialforce`` pedestrians.
* JuPedSim (C++), dt = 0.01 s, its own default (its social force model diverges at
  1/15 s): ``jupedsim.SocialForceModel()`` with its default parameters, a square
  walkable area 1 m larger than the crowd's on every side, one direct-steering stage
  whose per-agent ``target`` is the mirrored point, desired speed 1.25 m/s, radius
  0.3 m; ``sim.iterate()`` per step. Agent-steps/s at its own dt (a step of 0.01 s is
  less simulated time than one of 1/15 s).

``--busy`` runs a CPU-bound process (a Python busy loop) beside all measurements,
to see how the kernels fare when the other core is taken. Memory per pedestrian is the
growth of the resident set of a fresh process (warmed up on a small crowd) that builds
a crowd of ``--memory-n`` pedestrians and steps it three times, divided by that N.

Timing: after a warm-up call (JIT compilation, reported separately), steps are run in
chunks timed with ``time.perf_counter`` (or the CPU time, ``--cpu-time``) until each
repeat's share of the time budget is spent; the best repeat is reported.

The same crowd, the same density (``--window-s``): every pedestrian walks to the point
mirrored through the centre, so the crowd converges and its density, and with it the
work per step, grows with the simulated time (at N = 1000 the mean number of others
within srfm's 13.5 m cut-off is 117 at the start, 128 after 2 s, 158 after 5 s, 221
after 10 s and 383 after 50 s). A simulator with a longer step would otherwise be timed
on a denser crowd: in one time budget srfm (dt 1/15 s) covered about 50 simulated
seconds at N = 1000, JuPedSim (dt 0.01 s) about 2. Each simulator is therefore timed
over the same window of simulated time from the start, ``--window-s`` seconds (default
2 s, in which the neighbour count stays within 10 % of the start's at N = 1000; the
state is reset, untimed, whenever a chunk would pass the window's end); ``--window-s 0``
times from the start on without a reset, as before 2026-11-27.

Usage::

    .venv/bin/python tools/bench/bench_crowd_step.py
    .venv/bin/python tools/bench/bench_crowd_step.py --sizes 10 100 1000 --seconds 2
    .venv/bin/python tools/bench/bench_crowd_step.py --sizes 50 100 200 400 --no-pysocialforce
    .venv/bin/python tools/bench/bench_crowd_step.py --busy --no-pysocialforce --no-jupedsim
    .venv/bin/python tools/bench/bench_crowd_step.py --side-by-side --sizes 100 1000 10000 \
        --no-pysocialforce --memory-n 0
    .venv/bin/python tools/bench/bench_crowd_step.py --robot-forms --sizes 10 1000 --cpu-time

``--side-by-side`` adds the side-by-side protocol by which the project's scale target
against JuPedSim is judged: its own start state (N random cells of a lattice of 2 m
cells, ±0.5 m jitter), JuPedSim's walkable square with a margin of the crowd's side,
a fresh start per run (built untimed) after one untimed step, the window of simulated
time (``--window-s``, 2 s by default) timed as a whole, best of
``--side-by-side-repeats`` (3); srfm through ``srfm.step_crowd(crowd, 1/15)``. Few,
short runs: noisier than the main table, which times chunks until a budget is spent.

``--robot-forms`` times srfm's default step (``parallel=False``, ``cutoff="auto"``) with
a robot in the middle of the crowd, walking at 1 m/s, in each form of the robot force
(``SRFMParams(robot_form=...)``, default parameters), the forms in turn within each
repeat, and prints each form's time per step beside the paper's exponential form, and
whether each form stays within 1.3× of it (the target of issues 28 and 40).

``--json PATH`` also writes every rate (agent-steps/s, ``null`` where a simulator was
not run) with the options and the run's record (``tools/results/record.py``): the data
docs/performance.md's crowd-step and robot-form tables are generated from
(``make docs-tables``)::

    .venv/bin/python tools/bench/bench_crowd_step.py --side-by-side --cpu-time \
        --sizes 10 100 1000 10000 --memory-n 0 --json docs/results/performance/crowd.json
"""

from __future__ import annotations

import argparse
import contextlib
import importlib
import importlib.metadata
import logging
import math
import os
import platform
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

DT_S = 1.0 / 15.0
DENSITY_PER_M2 = 0.25
SPEED_MPS = 1.25
ROBOT_SPEED_MPS = 1.0  # the robot of --robot-forms
ROBOT_FORM_TARGET = 1.3  # a robot form's step at most this times the paper's form's
CHUNK_MIN_S = 2e-3  # steps are timed in chunks of at least this long

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class Bench:
    """One simulator at one crowd size: ``reset()`` restores the start, ``run(k)`` takes k steps."""

    reset: Callable[[], None]
    run: Callable[[int], None]


@dataclass(frozen=True)
class Result:
    """Best throughput (agent-steps/s) and the first call's duration (s)."""

    rate: float
    first_call_s: float


def initial_state(n: int, seed: int) -> tuple[FloatArray, FloatArray]:
    """(pos, goal), each (n, 2) in m: jittered lattice cells, goals mirrored through the centre."""
    side = math.sqrt(n / DENSITY_PER_M2)
    k = math.ceil(math.sqrt(n))
    spacing = side / k
    rng = np.random.default_rng(seed)
    cells = rng.permutation(k * k)[:n]
    centres = np.stack([(cells % k + 0.5) * spacing, (cells // k + 0.5) * spacing], axis=1)
    jitter = spacing / 2.0 - 0.35  # pairs stay >= 0.7 m apart (radius 0.3 m)
    pos = centres + rng.uniform(-jitter, jitter, size=(n, 2))
    return pos, side - pos


JUPEDSIM_DT_S = 0.01


def side_by_side_state(n: int, seed: int = 0) -> tuple[FloatArray, FloatArray, float]:
    """(pos, goal, side) of the side-by-side protocol (``--side-by-side``): N random cells
    of a ⌈√N⌉ × ⌈√N⌉ lattice of 2 m cells (0.25 ped/m²), each pedestrian uniform within
    ±0.5 m of its cell's centre, goals mirrored through the square's centre."""
    rng = np.random.default_rng(seed)
    k = math.ceil(math.sqrt(n))
    side = 2.0 * k
    cells = rng.permutation(k * k)[:n]
    lattice = np.stack([cells % k, cells // k], axis=1) * 2.0 + 1.0
    pos = lattice + rng.uniform(-0.5, 0.5, size=(n, 2))
    return pos, side - pos, side


def jupedsim_bench(
    pos: FloatArray, goal: FloatArray, margin: float = 1.0, side: float | None = None
) -> Bench:
    """JuPedSim's social force model, one direct-steering target per agent, in a square
    walkable area ``margin`` m larger than the crowd's square (of ``side`` m, by default
    the side at DENSITY_PER_M2) on every side."""
    import jupedsim

    side = math.sqrt(pos.shape[0] / DENSITY_PER_M2) if side is None else side
    lo, hi = -margin, side + margin
    area = [(lo, lo), (hi, lo), (hi, hi), (lo, hi)]

    def make() -> Any:
        sim = jupedsim.Simulation(
            model=jupedsim.SocialForceModel(), geometry=area, dt=JUPEDSIM_DT_S
        )
        stage = sim.add_direct_steering_stage()
        journey = sim.add_journey(jupedsim.JourneyDescription([stage]))
        for (x, y), (gx, gy) in zip(pos.tolist(), goal.tolist(), strict=True):
            agent = sim.add_agent(
                jupedsim.SocialForceModelAgentParameters(
                    position=(x, y),
                    journey_id=journey,
                    stage_id=stage,
                    desired_speed=SPEED_MPS,
                    radius=0.3,
                )
            )
            sim.agent(agent).target = (gx, gy)
        return sim

    sim = make()

    def reset() -> None:
        nonlocal sim
        sim = make()

    def run(k: int) -> None:
        for _ in range(k):
            sim.iterate()

    return Bench(reset, run)


_MEMORY_PROBE = """
import sys
sys.path.insert(0, sys.argv[3])
from bench_crowd_step import initial_state, jupedsim_bench, srfm_bench
kind, n = sys.argv[1], int(sys.argv[2])
small = initial_state(16, 0)
(srfm_bench(*small, None) if kind == "srfm" else jupedsim_bench(*small)).run(2)
pos, goal = initial_state(n, 0)
def rss():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * 4096
before = rss()
bench = srfm_bench(pos, goal, None) if kind == "srfm" else jupedsim_bench(pos, goal)
bench.run(3)
print((rss() - before) / n)
"""


def memory_per_pedestrian(kind: str, n: int) -> float:
    """Bytes per pedestrian: resident-set growth of a fresh process (after a warm-up on a
    small crowd) that builds a crowd of n pedestrians and steps it three times."""
    out = subprocess.run(
        [sys.executable, "-c", _MEMORY_PROBE, kind, str(n), str(Path(__file__).parent)],
        capture_output=True,
        text=True,
        check=True,
    )
    return float(out.stdout.strip().splitlines()[-1])


@contextlib.contextmanager
def busy_core(enabled: bool) -> Iterator[None]:
    """A CPU-bound process (a Python busy loop) for the duration, when ``enabled``."""
    if not enabled:
        yield
        return
    proc = subprocess.Popen([sys.executable, "-c", "while True: pass"])
    try:
        time.sleep(0.5)
        yield
    finally:
        proc.kill()
        proc.wait()


def srfm_bench(
    pos: FloatArray,
    goal: FloatArray,
    parallel: bool | None,
    robot_form: str | None = None,
) -> Bench:
    """srfm's public ``step_crowd`` with the given kernel choice (None = default) and
    the default parameters (``params=None``, as a user calls it); with a ``robot_form``,
    a robot in the crowd's centre (radius 0.3 m, walking at 1 m/s along x) that the
    crowd feels in that form of the robot force (default parameters otherwise)."""
    import srfm

    params = None
    robot = None
    if robot_form is not None:
        params = srfm.SRFMParams(robot_form=robot_form)
        centre = (pos.min(axis=0) + pos.max(axis=0)) / 2.0
        robot = srfm.RobotBody(
            x=float(centre[0]), y=float(centre[1]), radius=0.3, vx=ROBOT_SPEED_MPS, vy=0.0
        )
    start = srfm.CrowdState.create(pos=pos, goal=goal, v0=SPEED_MPS)
    crowd = start.copy()

    def reset() -> None:
        nonlocal crowd
        crowd = start.copy()

    def run(k: int) -> None:
        for _ in range(k):
            if parallel is None:
                srfm.step_crowd(crowd, DT_S, params, robot)
            else:
                srfm.step_crowd(crowd, DT_S, params, robot, parallel=parallel)

    return Bench(reset, run)


def robot_form_rates(
    sizes: list[int], seed: int, seconds: float, repeats: int, window: int
) -> list[tuple[int, dict[str, float]]]:
    """Per N, the default crowd step's best throughput with the robot in each form of
    the robot force. The forms are timed in turn within each repeat (round robin), so
    that a change of the machine's load falls on all of them alike."""
    from srfm.models.params import ROBOT_FORMS

    rows = []
    for n in sizes:
        pos, goal = initial_state(n, seed)
        benches = {form: srfm_bench(pos, goal, None, form) for form in ROBOT_FORMS}
        best = dict.fromkeys(ROBOT_FORMS, 0.0)
        for _ in range(repeats):
            for form, bench in benches.items():
                rate = measure(bench, n, seconds / repeats, 1, window).rate
                best[form] = max(best[form], rate)
        rows.append((n, best))
        print(f"  measured the robot forms at N = {n}", file=sys.stderr)
    return rows


def print_robot_form_rows(rows: list[tuple[int, dict[str, float]]]) -> None:
    """The robot-form table: µs per crowd step and the cost relative to the paper's form."""
    forms = list(rows[0][1])
    print("Time per crowd step with a robot, by form of the robot force (µs, lower is better;")
    print("in brackets: the step's time relative to the paper's exponential form):\n")
    print("| N | " + " | ".join(forms) + " |")
    print("|---:|" + "---:|" * len(forms))
    for n, rates in rows:
        base = rates["exponential"]
        cells = [f"{fmt_step_us(rates[f], n)} ({base / rates[f]:.2f}×)" for f in forms]
        print(f"| {n} | " + " | ".join(cells) + " |")
    print()
    for f in forms:
        worst = max(rates["exponential"] / rates[f] for _, rates in rows)
        verdict = "within" if worst <= ROBOT_FORM_TARGET else "OVER"
        print(f"- {f}: at most {worst:.2f}× the paper's form ({verdict} {ROBOT_FORM_TARGET}×)")


@contextlib.contextmanager
def _inside(directory: Path) -> Iterator[None]:
    old = Path.cwd()
    os.chdir(directory)
    try:
        yield
    finally:
        os.chdir(old)


def import_pysocialforce(tmp: Path) -> Any:
    """Import pysocialforce quietly (it logs at DEBUG and opens ./file.log on import)."""
    with _inside(tmp):
        import pysocialforce
    logging.getLogger().setLevel(logging.WARNING)
    logging.getLogger("numba").setLevel(logging.WARNING)
    return pysocialforce


def pysocialforce_config(psf: Any, tmp: Path) -> Path:
    """Write PySocialForce's default config with the changes that match srfm's set-up."""
    import toml

    config = toml.load(Path(psf.__file__).parent / "config" / "default.toml")
    # load_config replaces whole top-level tables, so edit the full default [scene].
    # Simulator reads enable_group from [scene] but PedState reads step_width,
    # agent_radius and max_speed_multiplier from the top level, so set them there too.
    scene = {"step_width": DT_S, "agent_radius": 0.3, "max_speed_multiplier": 1.0}
    config["scene"].update(enable_group=False, **scene)
    config.update(scene)
    path = tmp / "pysocialforce_bench.toml"
    path.write_text(toml.dumps(config))
    return path


def pysocialforce_bench(psf: Any, config: Path, pos: FloatArray, goal: FloatArray) -> Bench:
    """PySocialForce's ``Simulator.step(1)``, desired and maximum speed 1.25 m/s."""
    n = pos.shape[0]
    state = np.hstack([pos, np.zeros((n, 2)), goal])  # rows (x, y, vx, vy, gx, gy)

    def make() -> Any:
        sim = psf.Simulator(state.copy(), groups=None, obstacles=None, config_file=str(config))
        sim.peds.initial_speeds = np.full(n, SPEED_MPS)
        sim.peds.max_speeds = sim.peds.initial_speeds.copy()
        return sim

    sim = make()

    def reset() -> None:
        nonlocal sim
        sim = make()  # also drops the per-step state history the simulator keeps

    def run(k: int) -> None:
        with np.errstate(all="ignore"):
            for _ in range(k):
                sim.step(1)

    return Bench(reset, run)


# The clock of the measurements: wall time, or with --cpu-time this process's CPU time
# (time.process_time, all threads), which a loaded machine's other processes do not
# inflate for a single-threaded simulator.
CLOCK: Callable[[], float] = time.perf_counter


def measure(bench: Bench, n: int, budget_s: float, repeats: int, window_steps: int = 0) -> Result:
    """Best of ``repeats`` throughputs in agent-steps/s, each over ``budget_s / repeats``
    of timed steps. With ``window_steps`` > 0 only the first ``window_steps`` steps from
    the start are timed: the state is reset (untimed) before a chunk would pass them."""
    bench.reset()
    t0 = time.perf_counter()
    bench.run(1)
    first = time.perf_counter() - t0
    limit = window_steps if window_steps > 0 else 1 << 20
    chunk = 1
    bench.reset()
    while True:
        t0 = CLOCK()
        bench.run(chunk)
        if CLOCK() - t0 >= CHUNK_MIN_S or 2 * chunk > limit:
            break
        bench.reset()
        chunk *= 2
    share = budget_s / repeats
    best = 0.0
    for _ in range(repeats):
        bench.reset()
        since_reset = 0
        steps = 0
        elapsed = 0.0
        while elapsed < share:
            if window_steps > 0 and since_reset + chunk > window_steps:
                bench.reset()
                since_reset = 0
            t0 = CLOCK()
            bench.run(chunk)
            elapsed += CLOCK() - t0
            steps += chunk
            since_reset += chunk
        best = max(best, steps * n / elapsed)
    return Result(best, first)


def side_by_side_rate(bench: Bench, n: int, steps: int, repeats: int) -> float:
    """The side-by-side protocol's figure, agent-steps/s: one untimed step from a fresh
    start (compilation), then the best of ``repeats`` runs of ``steps`` steps, each from
    a fresh start (built untimed) and timed as a whole."""
    bench.reset()
    bench.run(1)
    best = 0.0
    for _ in range(repeats):
        bench.reset()
        t0 = CLOCK()
        bench.run(steps)
        best = max(best, n * steps / (CLOCK() - t0))
    return best


def side_by_side_rows(
    sizes: list[int], seed: int, window_s: float, repeats: int
) -> list[tuple[int, float, float]]:
    """Per N, (N, srfm, JuPedSim) agent-steps/s by the side-by-side protocol: its start
    state (:func:`side_by_side_state`), srfm's public ``step_crowd(crowd, 1/15)`` with
    its defaults, JuPedSim in a walkable square whose margin is the crowd's side, both
    over the first ``window_s`` seconds of simulated time."""
    rows = []
    for n in sizes:
        pos, goal, side = side_by_side_state(n, seed)
        ours = side_by_side_rate(
            srfm_bench(pos, goal, None), n, window_steps(window_s, DT_S), repeats
        )
        theirs = side_by_side_rate(
            jupedsim_bench(pos, goal, margin=side, side=side),
            n,
            window_steps(window_s, JUPEDSIM_DT_S),
            repeats,
        )
        rows.append((n, ours, theirs))
        print(f"  measured the side-by-side protocol at N = {n}", file=sys.stderr)
    return rows


def window_steps(window_s: float, dt_s: float) -> int:
    """Steps of ``dt_s`` in the timed window of simulated time (0: no window)."""
    return max(1, round(window_s / dt_s)) if window_s > 0 else 0


class OtherLoad:
    """Share of the machine's CPU time used by *other* processes since construction.

    Timings are only trustworthy when this stays near 0 %: other work on the same
    cores slows the serial kernel and stalls the threaded one.
    """

    def __init__(self) -> None:
        self._t0 = time.perf_counter()
        self._busy0 = self._busy_s()
        self._own0 = self._own_s()

    @staticmethod
    def _busy_s() -> float:
        try:
            fields = Path("/proc/stat").read_text().split("\n", 1)[0].split()[1:9]
        except OSError:
            return math.nan
        ticks = [int(x) for x in fields]  # user nice system idle iowait irq softirq steal
        return (sum(ticks) - ticks[3] - ticks[4]) / os.sysconf("SC_CLK_TCK")

    @staticmethod
    def _own_s() -> float:
        t = os.times()
        return t.user + t.system

    def percent(self) -> float:
        """Other processes' CPU time as a percentage of all cores' wall time."""
        wall = time.perf_counter() - self._t0
        other = self._busy_s() - self._busy0 - (self._own_s() - self._own0)
        return max(0.0, 100.0 * other / (wall * (os.cpu_count() or 1)))


def cpu_model() -> str:
    """The CPU model name from /proc/cpuinfo (or the platform's guess)."""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def _version(dist: str) -> str:
    try:
        return importlib.metadata.version(dist)
    except importlib.metadata.PackageNotFoundError:
        return "not installed"


def machine_info() -> list[str]:
    """Markdown bullet lines describing the machine and the software versions."""
    import numba

    affinity = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else None
    return [
        f"- CPU: {cpu_model()}, {os.cpu_count()} logical cores"
        + (f" ({affinity} usable)" if affinity is not None else ""),
        f"- OS: {platform.platform()}",
        f"- Python {platform.python_version()}, numpy {np.__version__}, numba {numba.__version__}"
        f" ({numba.get_num_threads()} threads), srfm {_version('srfm')} ({srfm_commit()}),"
        f" pysocialforce {_version('pysocialforce')}, jupedsim {_version('jupedsim')}",
        f"- load average (1, 5, 15 min) at start: {load_average()}",
    ]


def srfm_commit(root: Path | None = None) -> str:
    """The git commit of the checkout ``root`` (default: the imported srfm's), '+dirty'
    when its srfm/ has local changes."""
    if root is None:
        import srfm

        root = Path(srfm.__file__).resolve().parent.parent
    try:
        commit = subprocess.run(
            ["git", "-C", str(root), "rev-parse", "--short", "HEAD"],
            capture_output=True,
            text=True,
            check=True,
        ).stdout.strip()
        dirty = subprocess.run(
            ["git", "-C", str(root), "status", "--porcelain", "--", "srfm"],
            capture_output=True,
            text=True,
            check=True,
        ).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"
    return commit + ("+dirty" if dirty else "")


def load_average() -> str:
    """The 1, 5 and 15 minute load averages (other work on the machine skews timings)."""
    return ", ".join(f"{x:.2f}" for x in os.getloadavg())


def fmt_rate(rate: float) -> str:
    """Agent-steps/s with a k/M suffix."""
    if math.isnan(rate):
        return "n/a"
    if rate >= 1e6:
        return f"{rate / 1e6:.2f} M"
    if rate >= 1e3:
        return f"{rate / 1e3:.1f} k"
    return f"{rate:.0f}"


def fmt_step_us(rate: float, n: int) -> str:
    """Microseconds per crowd step."""
    return "n/a" if math.isnan(rate) else f"{n / rate * 1e6:,.1f}"


def parse_args(argv: list[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(
        description=__doc__.split("\n\n")[0] if __doc__ else None,
        formatter_class=argparse.ArgumentDefaultsHelpFormatter,
    )
    parser.add_argument(
        "--sizes", type=int, nargs="+", default=[10, 100, 1000, 10000], help="crowd sizes N"
    )
    parser.add_argument(
        "--seconds", type=float, default=2.0, help="time budget per simulator and size (s)"
    )
    parser.add_argument(
        "--repeats", type=int, default=10, help="repeats per measurement; best kept"
    )
    parser.add_argument("--seed", type=int, default=0, help="seed of the initial states")
    parser.add_argument(
        "--window-s",
        type=float,
        default=2.0,
        help="time every simulator over this window of simulated time from the start, so "
        "all see the same density (0: from the start on, without a reset)",
    )
    parser.add_argument("--no-pysocialforce", action="store_true", help="leave PySocialForce out")
    parser.add_argument("--no-jupedsim", action="store_true", help="leave JuPedSim out")
    parser.add_argument(
        "--max-pysocialforce",
        type=int,
        default=1000,
        help="largest N for PySocialForce (O(N²) memory: ~10 GB at N = 10,000)",
    )
    parser.add_argument(
        "--busy", action="store_true", help="run a CPU-bound process beside the measurements"
    )
    parser.add_argument(
        "--cpu-time",
        action="store_true",
        help="time with this process's CPU time instead of wall time (a loaded machine;"
        " meaningless for the threaded kernel, whose threads' CPU time adds up)",
    )
    parser.add_argument(
        "--memory-n", type=int, default=200_000, help="crowd size of the memory probe (0: skip)"
    )
    parser.add_argument(
        "--robot-forms",
        action="store_true",
        help="time srfm's default step with a robot in each form of the robot force"
        " (srfm.models.params.ROBOT_FORMS) instead of the comparison with other simulators",
    )
    parser.add_argument(
        "--side-by-side",
        action="store_true",
        help="also time srfm and JuPedSim by the side-by-side protocol (its start state,"
        " fresh starts, the window timed as a whole, best of --side-by-side-repeats)",
    )
    parser.add_argument(
        "--side-by-side-repeats",
        type=int,
        default=3,
        help="runs per simulator and size of the side-by-side protocol; best kept",
    )
    parser.add_argument(
        "--cold-cache",
        action="store_true",
        help="use an empty numba cache so srfm's first calls include a full JIT compile",
    )
    parser.add_argument("--json", type=Path, default=None, help="also write the figures here")
    args = parser.parse_args(argv)
    if any(n < 2 for n in args.sizes) or args.seconds <= 0 or args.repeats < 1:
        parser.error("sizes must be >= 2, --seconds > 0 and --repeats >= 1")
    if args.side_by_side and (args.no_jupedsim or args.side_by_side_repeats < 1):
        parser.error("--side-by-side needs JuPedSim and --side-by-side-repeats >= 1")
    if not math.isfinite(args.window_s) or args.window_s < 0:
        parser.error(f"--window-s must be a finite number >= 0, got {args.window_s}")
    return args


def main(argv: list[str] | None = None) -> int:
    global CLOCK
    args = parse_args(argv)
    if args.cpu_time:
        CLOCK = time.process_time
    with tempfile.TemporaryDirectory(prefix="srfm-bench-") as tmp_name:
        tmp = Path(tmp_name)
        if args.cold_cache:
            os.environ["NUMBA_CACHE_DIR"] = str(tmp / "numba-cache")  # before numba loads
        t0 = time.perf_counter()
        importlib.import_module("srfm")
        import_s = time.perf_counter() - t0
        from srfm.models.forces import CELL_LIST_MIN_AGENTS

        sys.path.insert(0, str(Path(__file__).resolve().parents[2]))
        from tools.results import record

        begun = record.start()
        options = {
            "sizes": args.sizes,
            "seconds": args.seconds,
            "repeats": args.repeats,
            "window_s": args.window_s,
            "clock": "cpu" if args.cpu_time else "wall",
            "busy": args.busy,
            "seed": args.seed,
            "dt_s": DT_S,
            "jupedsim_dt_s": JUPEDSIM_DT_S,
            "density_per_m2": DENSITY_PER_M2,
        }

        psf = None if args.no_pysocialforce or args.robot_forms else import_pysocialforce(tmp)
        config = None if psf is None else pysocialforce_config(psf, tmp)
        jps = not args.no_jupedsim

        print("## Crowd step throughput (agent-steps/s, higher is better)\n")
        print(f"- date: {time.strftime('%Y-%m-%d %H:%M', time.gmtime())} UTC")
        print(f"- command: `{' '.join([Path(sys.executable).name, *sys.argv])}`")
        print(
            f"- timed window: the first {args.window_s:g} s of simulated time from the start"
            if args.window_s > 0
            else "- timed window: none (from the start on, without a reset)"
        )
        print(*machine_info(), sep="\n")
        print(
            f"- srfm and PySocialForce dt = {DT_S:.6f} s, JuPedSim dt = {JUPEDSIM_DT_S} s;"
            f" density {DENSITY_PER_M2} ped/m², budget {args.seconds} s per cell, best of"
            f" {args.repeats}, seed {args.seed},"
            f" CELL_LIST_MIN_AGENTS = {CELL_LIST_MIN_AGENTS}, numba cache"
            f" {'cold' if args.cold_cache else 'as found'},"
            f" {'a CPU-bound process busy beside it' if args.busy else 'no extra load'},"
            f" {'CPU time' if args.cpu_time else 'wall time'}\n"
        )

        if args.robot_forms:
            with busy_core(args.busy):
                other = OtherLoad()
                w_ours = window_steps(args.window_s, DT_S)
                form_rows = robot_form_rates(
                    args.sizes, args.seed, args.seconds, args.repeats, w_ours
                )
                other_percent = other.percent()
            print_robot_form_rows(form_rows)
            print(
                f"\n- load average (1, 5, 15 min) at end: {load_average()}; other processes"
                f" used {other_percent:.1f} % of the machine's CPU time during the measurements"
            )
            if args.json is not None:
                record.write_json(
                    args.json,
                    {
                        "options": options,
                        "target": ROBOT_FORM_TARGET,
                        "robot_speed_mps": ROBOT_SPEED_MPS,
                        "other_cpu_percent": other_percent,
                        "robot_forms": [{"n": n, "rates": rates} for n, rates in form_rows],
                    },
                    begun,
                )
            return 0

        with busy_core(args.busy):
            # Warm-up on a small crowd: the first call compiles (or loads from the cache).
            pos, goal = initial_state(16, args.seed)
            other = OtherLoad()
            first: dict[str, float] = {}
            for label, parallel in (("srfm serial", False), ("srfm parallel", True)):
                bench = srfm_bench(pos, goal, parallel)
                first[label] = measure(bench, 16, 1e-3, 1).first_call_s
            if psf is not None and config is not None:
                bench = pysocialforce_bench(psf, config, pos, goal)
                first["pysocialforce"] = measure(bench, 16, 1e-3, 1).first_call_s

            rows: list[tuple[int, str, list[float]]] = []
            for n in args.sizes:
                pos, goal = initial_state(n, args.seed)
                w_ours = window_steps(args.window_s, DT_S)
                rates = [
                    measure(srfm_bench(pos, goal, p), n, args.seconds, args.repeats, w_ours).rate
                    for p in (False, True, None)
                ]
                if psf is not None and config is not None and n <= args.max_pysocialforce:
                    bench = pysocialforce_bench(psf, config, pos, goal)
                    rates.append(measure(bench, n, args.seconds, args.repeats, w_ours).rate)
                else:
                    rates.append(math.nan)
                if jps:
                    w_jps = window_steps(args.window_s, JUPEDSIM_DT_S)
                    bench = jupedsim_bench(pos, goal)
                    rates.append(measure(bench, n, args.seconds, 3, w_jps).rate)
                else:
                    rates.append(math.nan)
                default_kernel = "serial"
                rows.append((n, default_kernel, rates))
                print(f"  measured N = {n}", file=sys.stderr)
            sbs = (
                side_by_side_rows(
                    args.sizes,
                    args.seed,
                    args.window_s or 2.0,
                    args.side_by_side_repeats,
                )
                if args.side_by_side
                else []
            )
            other_percent = other.percent()

        print(
            "| N | srfm serial | srfm parallel | srfm default | pysocialforce | jupedsim"
            " | parallel / serial | default / pysocialforce | default / jupedsim |"
        )
        print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
        for n, kernel, (ser, par, dflt, ref, jp) in rows:
            ratios = [f"{par / ser:,.2f}×"]
            ratios += ["n/a" if math.isnan(x) else f"{dflt / x:,.2f}×" for x in (ref, jp)]
            print(
                f"| {n} | {fmt_rate(ser)} | {fmt_rate(par)} | {fmt_rate(dflt)} ({kernel})"
                f" | {fmt_rate(ref)} | {fmt_rate(jp)} | " + " | ".join(ratios) + " |"
            )

        print("\nTime per crowd step (µs, lower is better):\n")
        print("| N | srfm serial | srfm parallel | srfm default | pysocialforce | jupedsim |")
        print("|---:|---:|---:|---:|---:|---:|")
        for n, _, rates in rows:
            print(f"| {n} | " + " | ".join(fmt_step_us(r, n) for r in rates) + " |")

        if sbs:
            print(
                "\nThe side-by-side protocol (its start state, a fresh start per run, the"
                f" first {args.window_s or 2.0:g} s of simulated time timed as a whole, best of"
                f" {args.side_by_side_repeats}; srfm `step_crowd(crowd, 1/15)` with its"
                " defaults):\n"
            )
            print("| N | srfm | jupedsim | srfm / jupedsim | srfm µs per step |")
            print("|---:|---:|---:|---:|---:|")
            for n, ours, theirs in sbs:
                print(
                    f"| {n} | {fmt_rate(ours)} | {fmt_rate(theirs)} | {ours / theirs:,.2f}×"
                    f" | {fmt_step_us(ours, n)} |"
                )

        print("\nFirst call (s; JIT compile, or a load from numba's on-disk cache):\n")
        print(f"- import srfm: {import_s:.2f}")
        for label, seconds in first.items():
            print(f"- {label}: {seconds:.2f}")
        if args.memory_n > 0:
            print(f"\nMemory per pedestrian (resident-set growth at N = {args.memory_n:,}):\n")
            for kind in ("srfm", *(("jupedsim",) if jps else ())):
                per = memory_per_pedestrian(kind, args.memory_n)
                print(f"- {kind}: {per:,.0f} B")
        print(
            f"\n- load average (1, 5, 15 min) at end: {load_average()}; other processes used"
            f" {other_percent:.1f} % of the machine's CPU time during the measurements"
            + (" (the busy process included)" if args.busy else "")
        )
        if args.json is not None:
            kinds = ("srfm_serial", "srfm_parallel", "srfm_default", "pysocialforce", "jupedsim")
            record.write_json(
                args.json,
                {
                    "options": {
                        **options,
                        "side_by_side_repeats": args.side_by_side_repeats if sbs else 0,
                        "max_pysocialforce": args.max_pysocialforce,
                        "cell_list_min_agents": CELL_LIST_MIN_AGENTS,
                    },
                    "other_cpu_percent": other_percent,
                    "first_call_s": first,
                    "rates": [
                        {
                            "n": n,
                            "default_kernel": kernel,
                            **{
                                k: None if math.isnan(r) else r
                                for k, r in zip(kinds, rates, strict=True)
                            },
                        }
                        for n, kernel, rates in rows
                    ],
                    "side_by_side": [
                        {"n": n, "srfm": ours, "jupedsim": theirs} for n, ours, theirs in sbs
                    ],
                },
                begun,
            )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
