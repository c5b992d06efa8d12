"""The interaction cut-off and the cell list against the exact kernel (issue 19); the pair
pass vectorised and the same bits compiled or loaded from the cache (issue 27)."""

from __future__ import annotations

import math
import os
import platform
import re
import subprocess
import sys
from pathlib import Path

import numba
import numpy as np
import pytest

import srfm
from srfm.errors import SimulationError
from srfm.models import _kernels
from srfm.models.forces import (
    CELL_LIST_MIN_AGENTS,
    FORCE_TOLERANCE_MPS2,
    force_components,
    interaction_cutoffs,
    kernel_cutoffs,
)

DT = 1.0 / 15.0
PARAMS = srfm.SRFMParams()
WALLS = srfm.Obstacles.create(
    segments=[[0.0, -1.0, 30.0, -1.0], [0.0, 31.0, 30.0, 31.0]],
    circles=[[10.0, 10.0, 0.5], [20.0, 5.0, 1.0]],
)


def crowd(pos: np.ndarray, seed: int = 0) -> srfm.CrowdState:
    rng = np.random.default_rng(seed)
    n = pos.shape[0]
    return srfm.CrowdState.create(
        pos=pos,
        goal=pos + rng.uniform(-20.0, 20.0, (n, 2)),
        vel=rng.uniform(-0.8, 0.8, (n, 2)),
        v0=1.25,
        radius=rng.uniform(0.2, 0.35, n),
    )


def uniform(n: int, side: float, seed: int = 0) -> srfm.CrowdState:
    return crowd(np.random.default_rng(seed).uniform(0.0, side, (n, 2)), seed)


def assert_within_tolerance(c: srfm.CrowdState, cutoff: float, obstacles: srfm.Obstacles) -> None:
    """Each component of the cut kernel is within the omitted terms' bound of the exact one."""
    exact = force_components(c, PARAMS, obstacles=obstacles, cutoff="exact")
    cut = force_components(c, PARAMS, obstacles=obstacles, cutoff=cutoff)
    r_max = float(c.radius.max()) if c.n else 0.0
    _, d_obs = interaction_cutoffs(PARAMS, r_max)
    n_obs = obstacles.segments.shape[0] + obstacles.circles.shape[0]
    # every omitted term is below the largest term at the cut-off (the tolerance for the
    # cut-off of interaction_cutoffs); the rest differs by rounding only
    term = PARAMS.a_ped * math.exp((2.0 * r_max - cutoff) / PARAMS.b_ped)
    ped_bound = max(c.n - 1, 0) * term + 1e-12
    assert d_obs > 0.0
    np.testing.assert_array_equal(cut.goal, exact.goal)
    np.testing.assert_array_equal(cut.robot, exact.robot)
    assert np.all(np.abs(cut.pedestrians - exact.pedestrians) <= ped_bound)
    assert np.all(np.abs(cut.obstacles - exact.obstacles) <= n_obs * FORCE_TOLERANCE_MPS2)


def test_cutoff_formula_bounds_every_term() -> None:
    d_ped, d_obs = interaction_cutoffs(PARAMS, 0.3)
    assert d_ped == pytest.approx(0.6 + 0.89 * math.log(2.0 / 1e-6))
    assert d_obs == pytest.approx(0.3 + 0.08 * math.log(25.0 / 1e-6))
    # a head-on pair (ψ = 1) at the cut-off feels exactly the tolerance
    pair = crowd(np.array([[0.0, 0.0], [d_ped, 0.0]]))
    pair = srfm.CrowdState.create(pos=pair.pos, goal=[[10.0, 0.0], [-10.0, 0.0]], radius=0.3)
    f = force_components(pair, PARAMS, cutoff="exact").pedestrians
    assert np.abs(f).max() == pytest.approx(FORCE_TOLERANCE_MPS2, rel=1e-9)


@pytest.mark.parametrize("n", [0, 1, 2, 60, 400])
def test_cell_list_agrees_with_exact_on_random_crowds(n: int) -> None:
    c = uniform(n, side=2.0 * math.sqrt(max(n, 1)) + 30.0, seed=n)
    d_ped, _ = interaction_cutoffs(PARAMS, 0.35)
    assert PARAMS.a_ped * math.exp((0.7 - d_ped) / PARAMS.b_ped) == pytest.approx(1e-6)
    assert_within_tolerance(c, d_ped, WALLS)
    assert_within_tolerance(c, 4.0, WALLS)  # a short cut-off: many omitted pairs, bound holds


def test_everyone_in_one_cell_matches_exact_up_to_rounding() -> None:
    c = uniform(80, side=1.5, seed=3)  # all within one 13.5 m cell: no pair is omitted
    exact = force_components(c, PARAMS, cutoff="exact").pedestrians
    cut = force_components(c, PARAMS, cutoff=13.5).pedestrians
    np.testing.assert_allclose(cut, exact, rtol=1e-12, atol=1e-12)


def test_agents_on_cell_borders() -> None:
    # a lattice with spacing = cut-off / 2: agents on the cell borders, pairs exactly at
    # and just inside the cut-off distance
    cut = 2.0
    g = np.arange(0.0, 10.01, cut / 2.0)
    pos = np.array([[x, y] for x in g for y in g])
    pos[1::7] += 1e-12  # a few just off the borders
    assert_within_tolerance(crowd(pos, seed=1), cut, srfm.Obstacles())
    # and the pair exactly at the cut-off is left out, a pair just inside is not
    c = srfm.CrowdState.create(
        pos=[[0.0, 0.0], [cut, 0.0], [0.0, cut - 1e-9]], goal=[[5.0, 5.0]] * 3
    )
    f = force_components(c, PARAMS, cutoff=cut).pedestrians
    e = force_components(c, PARAMS, cutoff="exact").pedestrians
    assert f[1, 0] == 0.0  # agent 1 only has agent 0, at d = cut
    assert e[1, 0] != 0.0
    assert f[2, 1] != 0.0


def test_spread_out_crowd_widens_the_cells() -> None:
    # two groups 1e6 m apart: the grid would need ~1e11 cells of the cut-off's width
    a = np.random.default_rng(0).uniform(0.0, 5.0, (30, 2))
    c = crowd(np.vstack([a, a + 1e6]), seed=2)
    assert_within_tolerance(c, 13.5, srfm.Obstacles())
    order, starts, grid = _kernels.build_rows(c.pos, 13.5)
    assert grid[2] <= max(_kernels.MAX_CELLS_PER_AGENT * c.n, _kernels.MIN_CELLS)
    assert sorted(order) == list(range(c.n))
    assert starts[0] == 0
    assert starts[-1] == c.n
    assert np.all(np.diff(starts) >= 0)


def brute_force_pairs(pos: np.ndarray, cutoff: float) -> set[tuple[int, int]]:
    """Every pair (i < j) of agents closer than ``cutoff``, from all N² distances."""
    d = pos[:, None, :] - pos[None, :, :]
    i, j = np.nonzero(np.triu((d**2).sum(axis=-1) < cutoff * cutoff, 1))
    return set(zip(i.tolist(), j.tolist(), strict=True))


def assert_windows_find_every_pair_once(pos: np.ndarray, cutoff: float) -> None:
    pairs = _kernels.window_pairs(pos, cutoff)
    found = [(min(i, j), max(i, j)) for i, j in pairs.tolist()]
    assert len(set(found)) == len(found)  # none twice
    assert set(found) == brute_force_pairs(pos, cutoff)


@pytest.mark.parametrize("n", [0, 1, 2, 3, 5, 33, 300, 1500])
@pytest.mark.parametrize("side", [0.5, 7.0, 40.0])
def test_row_windows_find_the_pairs_of_a_brute_force_search(n: int, side: float) -> None:
    rng = np.random.default_rng(n + int(side))
    pos = rng.uniform(0.0, side, (n, 2))
    for cutoff in (13.5, 2.0, 0.3):
        assert_windows_find_every_pair_once(pos, cutoff)


def test_row_windows_on_borders_ties_and_spread_crowds() -> None:
    cut = 2.0
    # a lattice with spacing = row height: agents on row and cell borders, many pairs
    # exactly at the cut-off, many equal x (ties in the sort) and y
    g = np.arange(0.0, 10.01, cut / _kernels.ROW_SPLIT)
    lattice = np.array([[x, y] for x in g for y in g])
    assert_windows_find_every_pair_once(lattice, cut)
    nudged = lattice.copy()
    nudged[1::7] += 1e-12
    nudged[2::5] -= 1e-12
    assert_windows_find_every_pair_once(nudged, cut)
    # all on one point, all on one vertical or horizontal line
    assert_windows_find_every_pair_once(np.zeros((40, 2)), cut)
    line = np.stack([np.zeros(60), np.linspace(0.0, 20.0, 60)], axis=1)
    assert_windows_find_every_pair_once(line, cut)
    assert_windows_find_every_pair_once(line[:, ::-1].copy(), cut)
    # clumps far apart (widened cells, merge-sorted cells) and negative coordinates
    rng = np.random.default_rng(5)
    clump = rng.uniform(-3.0, 3.0, (120, 2))
    assert_windows_find_every_pair_once(np.vstack([clump, clump + 1e5, clump - 1e3]), cut)
    # rows that are empty between occupied ones
    bands = np.vstack(
        [rng.uniform(0.0, 30.0, (50, 2)) * [1.0, 0.05] + [0.0, 12.0 * k] for k in range(4)]
    )
    assert_windows_find_every_pair_once(bands, 13.5)


def test_rows_are_sorted_by_x_with_ties_in_index_order() -> None:
    rng = np.random.default_rng(9)
    pos = np.round(rng.uniform(0.0, 20.0, (500, 2)), 0)  # many equal x within a row
    pos = np.vstack([pos, rng.uniform(0.0, 1.0, (100, 2))])  # a crowded cell (merge sort)
    order, starts, grid = _kernels.build_rows(pos, 3.0)
    for r in range(int(grid[2])):
        run = order[starts[r] : starts[r + 1]]
        rows = np.clip(np.floor((pos[run, 1] - grid[0]) / grid[1]), 0, grid[2] - 1)
        assert np.all(rows == r)
        keys = list(zip(pos[run, 0].tolist(), run.tolist(), strict=True))
        assert keys == sorted(keys)


def test_cell_list_steps_are_deterministic_and_threading_independent() -> None:
    start = uniform(300, side=35.0, seed=7)
    runs = []
    for parallel in (False, True, False):
        c = start.copy()
        for _ in range(5):
            srfm.step_crowd(c, DT, PARAMS, obstacles=WALLS, parallel=parallel, cutoff=6.0)
        runs.append(c)
    for c in runs[1:]:
        np.testing.assert_array_equal(c.pos, runs[0].pos)
        np.testing.assert_array_equal(c.vel, runs[0].vel)


def test_auto_is_exact_below_the_threshold_and_cut_from_it() -> None:
    small = uniform(CELL_LIST_MIN_AGENTS - 1, side=60.0, seed=4)
    assert np.all(np.isinf(kernel_cutoffs("auto", PARAMS, small.radius)))
    a = small.copy()
    b = small.copy()
    srfm.step_crowd(a, DT, PARAMS, obstacles=WALLS)
    srfm.step_crowd(b, DT, PARAMS, obstacles=WALLS, cutoff="exact")
    np.testing.assert_array_equal(a.pos, b.pos)  # bit for bit
    large = uniform(CELL_LIST_MIN_AGENTS, side=60.0, seed=4)
    cut = kernel_cutoffs("auto", PARAMS, large.radius)
    assert cut.tolist() == list(interaction_cutoffs(PARAMS, float(large.radius.max())))


@pytest.mark.parametrize("bad", [0.0, -1.0, math.inf, math.nan, "fast", True, None])
def test_bad_cutoff_is_named(bad: object) -> None:
    c = uniform(3, side=5.0)
    with pytest.raises(SimulationError, match="cutoff"):
        srfm.step_crowd(c, DT, cutoff=bad)  # type: ignore[arg-type]
    with pytest.raises(SimulationError, match="tolerance"):
        interaction_cutoffs(PARAMS, 0.3, tolerance=0.0)


def test_builtin_scenarios_below_the_threshold_keep_the_exact_kernel() -> None:
    from srfm.scenarios import BUILTIN_SCENARIOS, load_scenario

    for name in BUILTIN_SCENARIOS:
        n = load_scenario(name).n_pedestrians
        assert n < CELL_LIST_MIN_AGENTS, name
        assert np.all(np.isinf(kernel_cutoffs("auto", PARAMS, np.full(n, 0.3))))


def test_fast_exp_matches_math_exp() -> None:
    xs = np.concatenate([np.linspace(-60.0, 60.0, 20001), [-0.0, 1e-300, -1e-300, 0.3466]])
    # within 1e-15 (2.3e-16 measured): a compiler folding the two-part ln 2 of the
    # argument reduction into one product (reassociation) would give 2.2e-15
    for x in xs:
        assert _kernels.fast_exp(float(x)) == pytest.approx(math.exp(x), rel=1e-15, abs=0.0)
    # clipped at ±EXP_ARG_MAX like capped_exp, never inf or 0
    assert _kernels.fast_exp(1e300) == pytest.approx(math.exp(60.0), rel=1e-15)
    assert _kernels.fast_exp(-1e300) == pytest.approx(math.exp(-60.0), rel=1e-15)


def test_fast_exp4_gives_each_argument_the_bits_of_fast_exp() -> None:
    # the pair loop takes four exponentials side by side: each is the one alone, whatever
    # its neighbours (clipped ones, tiny ones, huge ones)
    rng = np.random.default_rng(7)
    args = np.concatenate([rng.uniform(-70.0, 70.0, 400), [-1e300, 1e300, -0.0, 1e-300]])
    for a in args.reshape(-1, 4):
        four = _kernels.fast_exp4(*(float(x) for x in a))
        alone = [_kernels.fast_exp(float(x)) for x in a]
        assert np.array_equal(np.array(four).view(np.int64), np.array(alone).view(np.int64))
        for x, y in zip(four, a, strict=True):
            assert x == pytest.approx(math.exp(min(max(y, -60.0), 60.0)), rel=1e-15)


@pytest.mark.parametrize("b_ped", [1e-320, 1e-300, 1e-3])
def test_tiny_range_gives_finite_forces_in_the_cell_list(b_ped: float) -> None:
    # overlapping agents and a (subnormal) tiny B: capped exponents, never inf or NaN
    c = uniform(40, side=10.0, seed=12)
    params = srfm.SRFMParams(b_ped=b_ped)
    cut = force_components(c, params, cutoff=13.5).pedestrians
    exact = force_components(c, params, cutoff="exact").pedestrians
    assert np.all(np.isfinite(cut))
    np.testing.assert_allclose(cut, exact, rtol=1e-12, atol=1e-12)


def test_coincident_and_stacked_agents_get_no_pair_force() -> None:
    # three agents on one point and one 1 m away: the coincident pairs push nothing
    # (direction undefined), as in the exact kernel
    pos = np.array([[5.0, 5.0], [5.0, 5.0], [5.0, 5.0], [6.0, 5.0]])
    c = crowd(pos, seed=5)
    exact = force_components(c, PARAMS, cutoff="exact").pedestrians
    cut = force_components(c, PARAMS, cutoff=13.5).pedestrians
    assert np.all(np.isfinite(cut))
    np.testing.assert_allclose(cut, exact, rtol=1e-13, atol=1e-15)


def test_agents_without_heading_are_isotropic_in_the_cell_list() -> None:
    # agents at rest on their goal have no heading (ψ = 1); mixed with walking ones
    rng = np.random.default_rng(11)
    pos = rng.uniform(0.0, 40.0, (120, 2))
    goal = pos + rng.uniform(-10.0, 10.0, (120, 2))
    vel = rng.uniform(-1.0, 1.0, (120, 2))
    goal[::3] = pos[::3]
    vel[::3] = 0.0
    c = srfm.CrowdState.create(pos=pos, goal=goal, vel=vel, v0=1.25, radius=0.3)
    d_ped, _ = interaction_cutoffs(PARAMS, 0.3)
    assert_within_tolerance(c, d_ped, srfm.Obstacles())
    assert_within_tolerance(c, 40.0 * math.sqrt(2.0) + 1.0, srfm.Obstacles())  # none left out
    everyone = force_components(c, PARAMS, cutoff=60.0).pedestrians
    exact = force_components(c, PARAMS, cutoff="exact").pedestrians
    np.testing.assert_allclose(everyone, exact, rtol=1e-12, atol=1e-13)


def test_runs_longer_than_a_lane_segment_match_exact() -> None:
    # 1200 agents in one row (a strip 4 m tall, rows of 4.5 m), all within the cut-off of
    # each other: runs of up to 1199 candidates, walked in segments of LANE_SEGMENT
    rng = np.random.default_rng(6)
    pos = np.stack([rng.uniform(0.0, 12.0, 1200), rng.uniform(0.0, 4.0, 1200)], axis=1)
    c = crowd(pos, seed=6)
    _, starts, _ = _kernels.build_rows(c.pos, 13.5 / _kernels.ROW_SPLIT)
    assert starts.tolist() == [0, c.n]
    assert c.n > 2 * _kernels.LANE_SEGMENT
    exact = force_components(c, PARAMS, cutoff="exact").pedestrians
    cut = force_components(c, PARAMS, cutoff=13.5).pedestrians
    np.testing.assert_allclose(cut, exact, rtol=1e-12, atol=1e-14 * np.abs(exact).max())


@pytest.mark.skipif(platform.machine().lower() not in ("x86_64", "amd64"), reason="x86-64 only")
def test_pair_loop_is_vectorised() -> None:
    # a fresh compile (numba does not show the code of a cached one): the optimised IR of
    # the pair loop has vector square roots, <4 x double> with AVX2, <8 x ...> with
    # AVX-512; a change that stops LLVM vectorising it (see the comment above LANE_PAD)
    # costs about three times the time
    pair_block = numba.njit(_kernels._pair_block.py_func)
    m = 21
    dat = np.zeros((6, m + _kernels.LANE_PAD))
    dat[0, m:] = 1e30
    acc_x = np.zeros(m + _kernels.LANE_PAD)
    acc_y = np.zeros(m + _kernels.LANE_PAD)
    lanes = np.empty(2 * _kernels.PAIR_BLOCK * _kernels.LANE_ROW)
    pair_block(np.arange(4), 0, m, dat, 4.0, 1.0, acc_x, acc_y, lanes)
    (llvm_ir,) = pair_block.inspect_llvm().values()
    assert re.search(r"@llvm\.sqrt\.v\d+f64\(", llvm_ir)


_CUTOFF_CROWD = """\
schema_version = 1
name = "cutoff_crowd"
description = "48 pedestrians with random goals: more than the cell list's threshold."
kind = "random"

[simulation]
dt_s = 0.06666666666666667
horizon_steps = 20

[world]
x_min = 0.0
x_max = 20.0
y_min = 0.0
y_max = 20.0

[robot]
kinematics = "unicycle"
radius_m = 0.2
max_speed_mps = 0.5
max_angular_speed_radps = 3.141592653589793

[pedestrians]
radius_m = 0.3
desired_speed_mps = 1.25
max_speed_mps = 1.25
goal_radius_m = 0.5

[random]
count = 48
"""

_EPISODE_DIGEST = """\
import sys
import srfm
from tests.conftest import record_digest
print(record_digest(srfm.run_episode(sys.argv[1], 0, "straight")))
"""


def test_cutoff_episode_is_identical_compiled_and_cached(tmp_path: Path) -> None:
    # The same episode in two processes sharing an empty numba cache: the first compiles
    # every kernel, the second loads them. Before 2026-11-27 the pair pass's fastmath
    # flags let LLVM sum in a different order in each compiled copy of it, and the two
    # records differed in their last bits.
    from tests.conftest import REPO, write_scenario

    scenario = write_scenario(tmp_path / "cutoff_crowd.toml", _CUTOFF_CROWD)
    spec = srfm.load_scenario(scenario).random
    assert spec is not None
    assert spec.count >= CELL_LIST_MIN_AGENTS  # the cell list's path
    cache = tmp_path / "numba"
    paths = [str(Path(srfm.__file__).resolve().parents[1]), str(REPO)]
    env = {
        **os.environ,
        "NUMBA_CACHE_DIR": str(cache),
        "PYTHONPATH": os.pathsep.join([*paths, os.environ.get("PYTHONPATH", "")]),
    }

    def digest() -> str:
        out = subprocess.run(
            [sys.executable, "-c", _EPISODE_DIGEST, str(scenario)],
            capture_output=True,
            text=True,
            env=env,
            timeout=600,
            check=False,
        )
        assert out.returncode == 0, out.stderr
        return out.stdout.strip()

    compiled = digest()
    files = {p: p.stat().st_mtime_ns for p in cache.rglob("*") if p.is_file()}
    assert any(p.name.startswith("_kernels.cell_pair_forces") for p in files)
    cached = digest()
    # the second process loaded everything (it wrote nothing) and got the same bytes
    assert {p: p.stat().st_mtime_ns for p in cache.rglob("*") if p.is_file()} == files
    assert cached == compiled
