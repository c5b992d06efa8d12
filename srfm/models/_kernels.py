"""numba kernels of the Social Robot Force Model.

Plain module-level functions over C-contiguous float64 arrays: no objects, no
allocation inside loops, no I/O, no raising, no random draws. Shapes: ``pos``, ``vel``,
``goal`` (N, 2); ``radius``, ``v0``, ``vmax`` (N,); ``params`` the
:class:`~srfm.models.params.SRFMKernelParams` of :meth:`srfm.SRFMParams.for_kernels`;
``robot`` (3,) = (x, y, radius); ``segments`` (M, 4) = (x1, y1, x2, y2); ``circles``
(K, 3) = (cx, cy, radius). All forces are accelerations (m/s², unit mass).

The force primitives (desired velocity, capped exponential, anisotropy ψ, push of a
disc, closest point of a wall) live in :mod:`srfm.models._primitives`, shared with the
social-force planner. Exponents are
capped at ``EXP_ARG_MAX`` (e^60 ≈ 1e26), far beyond any force that changes a step (the
speed cap clips it), so that extreme but valid inputs (tiny B, deep overlap with a
large pillar) give huge finite forces instead of inf and NaN.

Serial and threaded variants share one per-agent body (:func:`_agent_total`); they
differ only in the loop over the agents (``range`` or ``prange``), so their results
are identical. Each variant is its own top-level function (numba's on-disk cache does
not tell apart variants made by a factory from one Python function).

Zero distances use an explicit epsilon: two coincident centres exert no force on each
other (the direction is undefined), an agent at rest with no desired direction has no
heading and is treated isotropically (ψ = 1).
"""

from __future__ import annotations

import math

import numpy as np
from llvmlite import ir
from numba import njit, prange, types
from numba.extending import intrinsic

from srfm.models._primitives import (
    EPS,
    EXP_ARG_MAX,
    FALSE,
    TRUE,
    capped_exp,
    closest_on_segment,
    desired_velocity,
    disc_repulsion,
)
from srfm.models.params import SRFMKernelParams


@njit(cache=True, inline="always")
def _heading(vx: float, vy: float, dvx: float, dvy: float) -> tuple[float, float, bool]:
    """Unit heading: the velocity direction, else the desired direction, else none."""
    speed = math.sqrt(vx * vx + vy * vy)
    if speed > EPS:
        return vx / speed, vy / speed, True
    dspeed = math.sqrt(dvx * dvx + dvy * dvy)
    if dspeed > EPS:
        return dvx / dspeed, dvy / dspeed, True
    return 0.0, 0.0, False


@njit(cache=True, inline="always")
def _agent_forces(
    i: int,
    pos: np.ndarray,
    vel: np.ndarray,
    goal: np.ndarray,
    radius: np.ndarray,
    v0: np.ndarray,
    params: SRFMKernelParams,
    robot: np.ndarray,
    robot_on: bool,
    segments: np.ndarray,
    circles: np.ndarray,
    cut: np.ndarray,
    ped: np.ndarray,
) -> tuple[float, float, float, float, float, float, float, float]:
    """The four force components on agent i: goal, pedestrians, robot, obstacles (x, y each).

    ``cut`` = (pedestrian cut-off, obstacle cut-off) in m, ``inf`` for none. With
    ``inf`` every other pedestrian pushes, summed in index order (the exact kernel);
    with a finite pedestrian cut-off the pedestrian force is ``ped[i]``, from
    :func:`cell_pair_forces`. Obstacles beyond the obstacle cut-off are skipped.
    """
    px = pos[i, 0]
    py = pos[i, 1]
    vx = vel[i, 0]
    vy = vel[i, 1]
    ri = radius[i]
    dvx, dvy = desired_velocity(px, py, goal[i, 0], goal[i, 1], v0[i])
    hx, hy, has_h = _heading(vx, vy, dvx, dvy)

    tau = params.tau
    gfx = (dvx - vx) / tau
    gfy = (dvy - vy) / tau

    # Pedestrian repulsion, summed over j in index order (deterministic).
    a_p = params.a_ped
    b_p = params.b_ped
    lam_p = params.lambda_ped
    pfx = 0.0
    pfy = 0.0
    ped_cut = cut[0]
    if a_p != 0.0 and ped_cut == np.inf:
        for j in range(pos.shape[0]):
            if j == i:
                continue
            fx, fy = disc_repulsion(
                px, py, pos[j, 0], pos[j, 1], ri + radius[j], a_p, b_p, hx, hy, has_h, lam_p
            )
            pfx += fx
            pfy += fy
    elif a_p != 0.0:
        # With a cut-off the pedestrian forces were summed pair by pair beforehand
        # (cell_pair_forces).
        pfx = ped[i, 0]
        pfy = ped[i, 1]

    # Robot repulsion (absent in the counterfactual twin, or when A_r = 0).
    rfx = 0.0
    rfy = 0.0
    a_r = params.a_robot
    if robot_on and a_r != 0.0:
        b_r = params.b_robot
        lam_r = params.lambda_robot
        rfx, rfy = disc_repulsion(
            px, py, robot[0], robot[1], ri + robot[2], a_r, b_r, hx, hy, has_h, lam_r
        )

    # Obstacle repulsion from the closest point of every wall segment and pillar.
    ofx = 0.0
    ofy = 0.0
    a_o = params.a_obs
    b_o = params.b_obs
    obs_cut = cut[1]
    if a_o != 0.0:
        for k in range(segments.shape[0]):
            cx, cy = closest_on_segment(
                px, py, segments[k, 0], segments[k, 1], segments[k, 2], segments[k, 3]
            )
            dx = px - cx
            dy = py - cy
            d = math.sqrt(dx * dx + dy * dy)
            if d < EPS or d >= obs_cut:
                continue
            mag = a_o * capped_exp((ri - d) / b_o)
            ofx += mag * dx / d
            ofy += mag * dy / d
        for k in range(circles.shape[0]):
            dx = px - circles[k, 0]
            dy = py - circles[k, 1]
            dc = math.sqrt(dx * dx + dy * dy)
            if dc < EPS:
                continue
            d = dc - circles[k, 2]  # distance to the pillar's surface
            if d >= obs_cut:
                continue
            mag = a_o * capped_exp((ri - d) / b_o)
            ofx += mag * dx / dc
            ofy += mag * dy / dc
    return gfx, gfy, pfx, pfy, rfx, rfy, ofx, ofy


# Most cells a cell list may have per agent (plus a floor): a crowd spread far apart gets
# wider cells instead of a huge, mostly empty grid.
MAX_CELLS_PER_AGENT = 4
MIN_CELLS = 64


@njit(cache=True, inline="always")
def exact_cut() -> tuple[np.ndarray, np.ndarray]:
    """``(cut, ped)`` of the exact kernel (no cut-off, every pair in index order) for
    callers of :func:`_agent_forces` that keep the paper's exact sums."""
    return np.full(2, np.inf), np.zeros((0, 2))


@njit(cache=True)
def build_cells(
    pos: np.ndarray, radius: np.ndarray, cell_size: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A cell list of the positions ``pos`` for cells at least ``cell_size`` wide.

    Returns ``(cells, grid, xyr)``: ``grid`` (5,) = (x0, y0, size, nx, ny), the lower
    left corner, the cell width and the number of cells along x and y; ``cells``
    (nx·ny + 1 + N,) int64, first the start of each cell's run in row-major order
    (counting sort, agents in index order within a cell), then the agent indices of
    every run; ``xyr`` (N, 3) the agents' (x, y, radius) in that order. With
    ``cell_size = inf`` (no cut-off), a size <= 0 or no agents both are empty
    placeholders.
    """
    n = pos.shape[0]
    if n == 0 or not 0.0 < cell_size < np.inf:
        return np.zeros(0, dtype=np.int64), np.zeros(5), np.zeros((0, 3))
    x0 = pos[0, 0]
    y0 = pos[0, 1]
    x1 = x0
    y1 = y0
    for i in range(1, n):
        x0 = min(x0, pos[i, 0])
        x1 = max(x1, pos[i, 0])
        y0 = min(y0, pos[i, 1])
        y1 = max(y1, pos[i, 1])
    size = cell_size
    max_cells = max(MAX_CELLS_PER_AGENT * n, MIN_CELLS)
    # widen the cells until the grid has at most max_cells cells
    while (np.floor((x1 - x0) / size) + 1.0) * (np.floor((y1 - y0) / size) + 1.0) > max_cells:
        size *= 2.0  # (in float64: no integer overflow for a tiny cut-off)
    nx = math.floor((x1 - x0) / size) + 1
    ny = math.floor((y1 - y0) / size) + 1
    grid = np.array([x0, y0, size, float(nx), float(ny)])
    n_cells = nx * ny
    cells = np.zeros(n_cells + 1 + n, dtype=np.int64)
    for i in range(n):
        cx, cy = _cell_of(pos[i, 0], pos[i, 1], grid)
        cells[cy * nx + cx + 1] += 1
    for c in range(n_cells):
        cells[c + 1] += cells[c]
    fill = cells[:n_cells].copy()
    xyr = np.empty((n, 3))
    for i in range(n):
        cx, cy = _cell_of(pos[i, 0], pos[i, 1], grid)
        c = cy * nx + cx
        k = fill[c]
        cells[n_cells + 1 + k] = i
        xyr[k, 0] = pos[i, 0]
        xyr[k, 1] = pos[i, 1]
        xyr[k, 2] = radius[i]
        fill[c] = k + 1
    return cells, grid, xyr


@njit(cache=True, inline="always")
def _cell_of(x: float, y: float, grid: np.ndarray) -> tuple[int, int]:
    """The (column, row) of the cell of (x, y), clipped to the grid."""
    nx = int(grid[3])
    ny = int(grid[4])
    cx = min(max(math.floor((x - grid[0]) / grid[2]), 0), nx - 1)
    cy = min(max(math.floor((y - grid[1]) / grid[2]), 0), ny - 1)
    return cx, cy


# Cells per cut-off: the cells are cut-off / CELL_SPLIT wide, and a pedestrian's
# neighbours lie within CELL_SPLIT cells of its own. Narrower cells test fewer pairs
# beyond the cut-off (the stencil covers (2·CELL_SPLIT + 1)² / CELL_SPLIT² cut-off
# squares instead of 9) at the price of shorter runs.
CELL_SPLIT = 2
# Flags of the pair pass only (never of the exact kernel): reassociation and contraction
# let LLVM vectorise the inner loop (a reduction, fused multiply-adds). The pass stays
# deterministic (same input, same machine, same bits); it is not bit for bit the
# index-order sum of the exact kernel anyway.
PAIR_FASTMATH = {"reassoc", "contract", "nsz"}


@intrinsic
def _float_bits(typingctx, x):  # type: ignore[no-untyped-def]
    """The IEEE 754 bits of a float64 as an int64 (a bit cast, no conversion)."""
    sig = types.int64(types.float64)

    def codegen(context, builder, signature, args):  # type: ignore[no-untyped-def]
        return builder.bitcast(args[0], ir.IntType(64))

    return sig, codegen


@intrinsic
def _bits_float(typingctx, i):  # type: ignore[no-untyped-def]
    """The float64 whose IEEE 754 bits are the int64 ``i`` (a bit cast, no conversion)."""
    sig = types.float64(types.int64)

    def codegen(context, builder, signature, args):  # type: ignore[no-untyped-def]
        return builder.bitcast(args[0], ir.DoubleType())

    return sig, codegen


_LOG2E = 1.4426950408889634
_LN2_HI = 0.693147180369123816490  # ln 2 split in two (Cody and Waite): n·_LN2_HI is exact
_LN2_LO = 1.90821492927058770002e-10
_ROUND_SHIFT = 6755399441055744.0  # 1.5·2^52: an integer added to it lands in the low bits


@njit(cache=True, fastmath=PAIR_FASTMATH)
def fast_exp(arg: float) -> float:
    """exp(arg), arg clipped to [−EXP_ARG_MAX, EXP_ARG_MAX], branch-free so that the pair
    loop vectorises (numba's math.exp is a libm call per element).

    arg = n ln 2 + t with n = round(arg / ln 2) and |t| <= ln 2 / 2; e^t from its Taylor
    polynomial of degree 12 (truncation below 2e-17 relative), 2^n written straight into
    the exponent bits. Agrees with math.exp to a few units in the last place. Compiled
    with the pair loop's fastmath flags, set here explicitly: numba lets a callee without
    flags of its own inherit its caller's, so that otherwise its bits would depend on
    who compiled it first. n comes from ``floor``, not from the add-and-subtract
    rounding trick, which reassociation would fold away.
    """
    x = min(max(arg, -EXP_ARG_MAX), EXP_ARG_MAX)
    nf = math.floor(x * _LOG2E + 0.5)
    t = (x - nf * _LN2_HI) - nf * _LN2_LO
    p = 1.0 / 479001600.0
    p = p * t + 1.0 / 39916800.0
    p = p * t + 1.0 / 3628800.0
    p = p * t + 1.0 / 362880.0
    p = p * t + 1.0 / 40320.0
    p = p * t + 1.0 / 5040.0
    p = p * t + 1.0 / 720.0
    p = p * t + 1.0 / 120.0
    p = p * t + 1.0 / 24.0
    p = p * t + 1.0 / 6.0
    p = p * t + 0.5
    p = p * t + 1.0
    p = p * t + 1.0
    # nf + 1.5·2^52 is exact and holds nf in its low bits: n without a float-to-int64
    # conversion (AVX2 has none)
    n: int = _float_bits(nf + _ROUND_SHIFT) - _float_bits(_ROUND_SHIFT)  # type: ignore[call-arg]
    scale: float = _bits_float((n + 1023) << 52)
    return p * scale


@njit(cache=True, fastmath=PAIR_FASTMATH)
def _pair_run(
    k: int,
    lo: int,
    hi: int,
    dat: np.ndarray,
    cut2: float,
    inv_b: float,
    a_p: float,
    acc: np.ndarray,
) -> tuple[float, float]:
    """The pairs (k, q) for q in [lo, hi) of the cell-ordered agents ``dat`` (columns x,
    y, r, hx', hy', c: ψ = c ± (hx', hy')·u, see :func:`cell_pair_forces`): q's share
    goes into ``acc[q]``, k's share is returned. Pairs at or beyond the cut-off (``cut2``
    its square) or closer than EPS get no force; branch-free, so it vectorises.
    """
    xk = dat[0, k]
    yk = dat[1, k]
    rk = dat[2, k]
    hxk = dat[3, k]
    hyk = dat[4, k]
    ck = dat[5, k]
    # row slices of the run, indexed from 0: a loop index known to be >= 0 lets LLVM
    # drop numba's negative-index wraparound and vectorise the loop
    xs = dat[0, lo:hi]
    ys = dat[1, lo:hi]
    rs = dat[2, lo:hi]
    hxs = dat[3, lo:hi]
    hys = dat[4, lo:hi]
    cs = dat[5, lo:hi]
    ax = acc[0, lo:hi]
    ay = acc[1, lo:hi]
    eps2 = EPS * EPS
    fx = 0.0
    fy = 0.0
    for q in range(hi - lo):
        dx = xk - xs[q]
        dy = yk - ys[q]
        d2 = dx * dx + dy * dy
        d = math.sqrt(max(d2, eps2))
        inv_d = 1.0 / d
        ux = dx * inv_d  # unit vector from q to k
        uy = dy * inv_d
        e = a_p * fast_exp((rk + rs[q] - d) * inv_b)
        e = e if (d2 < cut2) & (d2 >= eps2) else 0.0
        mk = e * (ck + (hxk * ux + hyk * uy))
        mq = e * (cs[q] - (hxs[q] * ux + hys[q] * uy))
        fx += mk * ux
        fy += mk * uy
        ax[q] -= mq * ux
        ay[q] -= mq * uy
    return fx, fy


@njit(cache=True)
def cell_pair_forces(
    pos: np.ndarray,
    vel: np.ndarray,
    goal: np.ndarray,
    radius: np.ndarray,
    v0: np.ndarray,
    params: SRFMKernelParams,
    cutoff: float,
) -> np.ndarray:
    """The pedestrian repulsion on every agent (N, 2), over the pairs closer than
    ``cutoff``, found with a cell list (:func:`build_cells`, cells cutoff / CELL_SPLIT
    wide); empty (0, 2) without a cut-off (``inf``) or with A_p = 0.

    Each pair is visited once, cell by cell in row-major order: the rest of the agent's
    own cell and the CELL_SPLIT cells to its right (one contiguous run of the cell
    order), then CELL_SPLIT rows above, each from CELL_SPLIT cells left to CELL_SPLIT
    cells right (one run per row). The exponential A exp((r_i + r_j − d) / B)
    (:func:`fast_exp`) is shared, each agent gets its own ψ, written as
    ψ = (λ + w) − w e·u with w = (1 − λ)/2 (ψ = 1 without a heading), the terms of
    :func:`disc_repulsion`. Sums follow that visiting order, so the result is
    deterministic and equals the exact kernel's up to rounding (a few units in the last place).
    """
    n = pos.shape[0]
    a_p = params.a_ped
    if n == 0 or a_p == 0.0 or not 0.0 < cutoff < np.inf:
        return np.zeros((0, 2))
    lam = params.lambda_ped
    w = (1.0 - lam) * 0.5
    cells, grid, xyr = build_cells(pos, radius, cutoff / CELL_SPLIT)
    nx = int(grid[3])
    ny = int(grid[4])
    n_cells = nx * ny
    # per agent in cell order: x, y, r, then (hx', hy', c) with ψ_k = c + (hx', hy')·u for
    # u the unit vector from the source to k
    dat = np.empty((6, n))
    for k in range(n):
        i = cells[n_cells + 1 + k]
        dvx, dvy = desired_velocity(pos[i, 0], pos[i, 1], goal[i, 0], goal[i, 1], v0[i])
        hx, hy, has_h = _heading(vel[i, 0], vel[i, 1], dvx, dvy)
        dat[0, k] = xyr[k, 0]
        dat[1, k] = xyr[k, 1]
        dat[2, k] = xyr[k, 2]
        if has_h:
            dat[3, k] = -w * hx
            dat[4, k] = -w * hy
            dat[5, k] = lam + w
        else:
            dat[3, k] = 0.0
            dat[4, k] = 0.0
            dat[5, k] = 1.0
    acc = np.zeros((2, n))
    cut2 = cutoff * cutoff
    inv_b = 1.0 / params.b_ped
    reach = CELL_SPLIT
    for cy in range(ny):
        for cx in range(nx):
            c = cy * nx + cx
            own_end = cells[cy * nx + min(cx + reach, nx - 1) + 1]
            left = max(cx - reach, 0)
            right = min(cx + reach, nx - 1)
            for k in range(cells[c], cells[c + 1]):
                fx, fy = _pair_run(k, k + 1, own_end, dat, cut2, inv_b, a_p, acc)
                for ry in range(cy + 1, min(cy + reach, ny - 1) + 1):
                    gx, gy = _pair_run(
                        k,
                        cells[ry * nx + left],
                        cells[ry * nx + right + 1],
                        dat,
                        cut2,
                        inv_b,
                        a_p,
                        acc,
                    )
                    fx += gx
                    fy += gy
                acc[0, k] += fx
                acc[1, k] += fy
    out = np.empty((n, 2))
    for k in range(n):
        i = cells[n_cells + 1 + k]
        out[i, 0] = acc[0, k]
        out[i, 1] = acc[1, k]
    return out


@njit(cache=True)
def force_components_kernel(
    pos: np.ndarray,
    vel: np.ndarray,
    goal: np.ndarray,
    radius: np.ndarray,
    v0: np.ndarray,
    params: SRFMKernelParams,
    robot: np.ndarray,
    robot_on: bool,
    segments: np.ndarray,
    circles: np.ndarray,
    cut: np.ndarray,
    out: np.ndarray,
) -> None:
    """Write the components into ``out`` (4, N, 2): goal, pedestrians, robot, obstacles;
    ``cut`` as in :func:`step_serial`."""
    ped = cell_pair_forces(pos, vel, goal, radius, v0, params, cut[0])
    for i in range(pos.shape[0]):
        g0, g1, p0, p1, r0, r1, o0, o1 = _agent_forces(
            i,
            pos,
            vel,
            goal,
            radius,
            v0,
            params,
            robot,
            robot_on,
            segments,
            circles,
            cut,
            ped,
        )
        out[0, i, 0] = g0
        out[0, i, 1] = g1
        out[1, i, 0] = p0
        out[1, i, 1] = p1
        out[2, i, 0] = r0
        out[2, i, 1] = r1
        out[3, i, 0] = o0
        out[3, i, 1] = o1


@njit(cache=True, inline="always")
def _agent_total(
    i: int,
    pos: np.ndarray,
    vel: np.ndarray,
    goal: np.ndarray,
    radius: np.ndarray,
    v0: np.ndarray,
    params: SRFMKernelParams,
    robot: np.ndarray,
    robot_on: bool,
    segments: np.ndarray,
    circles: np.ndarray,
    cut: np.ndarray,
    ped: np.ndarray,
    out: np.ndarray,
) -> None:
    """Total force F_i on agent i into ``out[i]``: goal + pedestrians + robot + obstacles."""
    g0, g1, p0, p1, r0, r1, o0, o1 = _agent_forces(
        i,
        pos,
        vel,
        goal,
        radius,
        v0,
        params,
        robot,
        robot_on,
        segments,
        circles,
        cut,
        ped,
    )
    out[i, 0] = g0 + p0 + r0 + o0
    out[i, 1] = g1 + p1 + r1 + o1


@njit(cache=True)
def integrate(
    pos: np.ndarray, vel: np.ndarray, force: np.ndarray, vmax: np.ndarray, dt: float
) -> None:
    """Semi-implicit Euler in place: v ← v + F dt, |v| capped at vmax, x ← x + v dt."""
    for i in range(pos.shape[0]):
        vx = vel[i, 0] + force[i, 0] * dt
        vy = vel[i, 1] + force[i, 1] * dt
        speed = math.sqrt(vx * vx + vy * vy)
        if speed > vmax[i]:
            scale = vmax[i] / speed
            vx *= scale
            vy *= scale
        vel[i, 0] = vx
        vel[i, 1] = vy
        pos[i, 0] += vx * dt
        pos[i, 1] += vy * dt


@njit(cache=True)
def step_serial(
    pos: np.ndarray,
    vel: np.ndarray,
    goal: np.ndarray,
    radius: np.ndarray,
    v0: np.ndarray,
    vmax: np.ndarray,
    params: SRFMKernelParams,
    robot: np.ndarray,
    robot_on: bool,
    segments: np.ndarray,
    circles: np.ndarray,
    dt: float,
    force_buf: np.ndarray,
    cut: np.ndarray,
) -> None:
    """One crowd step in place: the total force on every agent from one snapshot into
    ``force_buf`` (N, 2), one agent after another, then :func:`integrate`.

    ``cut`` (2,) = (pedestrian cut-off, obstacle cut-off) in m: ``inf`` for none (the
    exact kernel: every pair, in index order); a finite pedestrian cut-off builds a
    cell list of the snapshot (:func:`build_cells`) and sums only the pairs closer than it.
    """
    ped = cell_pair_forces(pos, vel, goal, radius, v0, params, cut[0])
    for i in range(pos.shape[0]):
        _agent_total(
            i,
            pos,
            vel,
            goal,
            radius,
            v0,
            params,
            robot,
            robot_on,
            segments,
            circles,
            cut,
            ped,
            force_buf,
        )
    integrate(pos, vel, force_buf, vmax, dt)


@njit(cache=True)
def step_exact(
    pos: np.ndarray,
    vel: np.ndarray,
    goal: np.ndarray,
    radius: np.ndarray,
    v0: np.ndarray,
    vmax: np.ndarray,
    params: SRFMKernelParams,
    robot: np.ndarray,
    robot_on: bool,
    segments: np.ndarray,
    circles: np.ndarray,
    dt: float,
    force_buf: np.ndarray,
    cut: np.ndarray,
) -> None:
    """:func:`step_serial` with every pedestrian pair, in index order (the exact kernel),
    whatever ``cut[0]``; obstacles cut at ``cut[1]`` as there.

    A kernel of its own so that runs without a cut-off (every built-in scenario but the
    large ones) never compile the cell list: a first run compiles seconds less.
    """
    ped = np.zeros((0, 2))
    cut = np.array([np.inf, cut[1]])
    for i in range(pos.shape[0]):
        _agent_total(
            i,
            pos,
            vel,
            goal,
            radius,
            v0,
            params,
            robot,
            robot_on,
            segments,
            circles,
            cut,
            ped,
            force_buf,
        )
    integrate(pos, vel, force_buf, vmax, dt)


@njit(cache=True, parallel=True)
def step_parallel(
    pos: np.ndarray,
    vel: np.ndarray,
    goal: np.ndarray,
    radius: np.ndarray,
    v0: np.ndarray,
    vmax: np.ndarray,
    params: SRFMKernelParams,
    robot: np.ndarray,
    robot_on: bool,
    segments: np.ndarray,
    circles: np.ndarray,
    dt: float,
    force_buf: np.ndarray,
    cut: np.ndarray,
) -> None:
    """As :func:`step_serial` with the agents of the force pass split over threads (for
    large crowds); bit-identical results."""
    ped = cell_pair_forces(pos, vel, goal, radius, v0, params, cut[0])
    for i in prange(pos.shape[0]):
        _agent_total(
            i,
            pos,
            vel,
            goal,
            radius,
            v0,
            params,
            robot,
            robot_on,
            segments,
            circles,
            cut,
            ped,
            force_buf,
        )
    integrate(pos, vel, force_buf, vmax, dt)


@njit(cache=True)
def mark_arrivals(
    pos: np.ndarray, goal: np.ndarray, goal_radius: float, arrived: np.ndarray, new: np.ndarray
) -> int:
    """Flag in ``new`` the agents within ``goal_radius`` of their goal that have not
    ``arrived`` yet; return how many. ``arrived`` is left unchanged."""
    r2 = goal_radius * goal_radius
    count = 0
    for i in range(pos.shape[0]):
        dx = pos[i, 0] - goal[i, 0]
        dy = pos[i, 1] - goal[i, 1]
        hit = dx * dx + dy * dy < r2 and not arrived[i]
        new[i] = hit
        if hit:
            count += 1
    return count


@njit(cache=True)
def nearest_clearance(pos: np.ndarray, radius: np.ndarray, x: float, y: float) -> tuple[float, int]:
    """Smallest (centre distance − agent radius) from (x, y) to an agent, and its index.

    Returns (inf, -1) for an empty crowd.
    """
    best = np.inf
    idx = -1
    for i in range(pos.shape[0]):
        dx = pos[i, 0] - x
        dy = pos[i, 1] - y
        c = math.sqrt(dx * dx + dy * dy) - radius[i]
        if c < best:
            best = c
            idx = i
    return best, idx


@njit(cache=True)
def within_range(pos: np.ndarray, x: float, y: float, max_range: float, out: np.ndarray) -> int:
    """Write into ``out`` the indices of agents closer than ``max_range`` to (x, y);
    return the count."""
    r2 = max_range * max_range
    k = 0
    for i in range(pos.shape[0]):
        dx = pos[i, 0] - x
        dy = pos[i, 1] - y
        if dx * dx + dy * dy < r2:
            out[k] = i
            k += 1
    return k


@njit(cache=True)
def segment_distance(segments: np.ndarray, x: float, y: float) -> float:
    """Smallest distance from (x, y) to any segment (x1, y1, x2, y2); inf when none."""
    best = np.inf
    for k in range(segments.shape[0]):
        cx, cy = closest_on_segment(
            x, y, segments[k, 0], segments[k, 1], segments[k, 2], segments[k, 3]
        )
        dx = x - cx
        dy = y - cy
        best = min(best, math.sqrt(dx * dx + dy * dy))
    return best


@njit(cache=True, inline="always")
def _twin_arrivals(
    f_pos: np.ndarray,
    f_goal: np.ndarray,
    c_pos: np.ndarray,
    c_goal: np.ndarray,
    goal_radius: float,
    f_arrived: np.ndarray,
    c_arrived: np.ndarray,
    f_new: np.ndarray,
    c_new: np.ndarray,
) -> int:
    """New arrivals of the factual and the counterfactual crowd, flagged in ``f_new`` and
    ``c_new`` (see :func:`mark_arrivals`); return how many in total."""
    count = mark_arrivals(f_pos, f_goal, goal_radius, f_arrived, f_new)
    return count + mark_arrivals(c_pos, c_goal, goal_radius, c_arrived, c_new)


@njit(cache=True)
def twin_step_serial(
    f_pos: np.ndarray,
    f_vel: np.ndarray,
    f_goal: np.ndarray,
    c_pos: np.ndarray,
    c_vel: np.ndarray,
    c_goal: np.ndarray,
    radius: np.ndarray,
    v0: np.ndarray,
    vmax: np.ndarray,
    params: SRFMKernelParams,
    robot: np.ndarray,
    segments: np.ndarray,
    circles: np.ndarray,
    dt: float,
    force_buf: np.ndarray,
    goal_radius: float,
    f_arrived: np.ndarray,
    c_arrived: np.ndarray,
    f_new: np.ndarray,
    c_new: np.ndarray,
    cut: np.ndarray,
) -> int:
    """Step the factual (robot on) and counterfactual (robot off) crowds, then flag
    new arrivals of each twin (see :func:`mark_arrivals`); return how many in total."""
    step_serial(
        f_pos,
        f_vel,
        f_goal,
        radius,
        v0,
        vmax,
        params,
        robot,
        TRUE,
        segments,
        circles,
        dt,
        force_buf,
        cut,
    )
    step_serial(
        c_pos,
        c_vel,
        c_goal,
        radius,
        v0,
        vmax,
        params,
        robot,
        FALSE,
        segments,
        circles,
        dt,
        force_buf,
        cut,
    )
    return _twin_arrivals(
        f_pos, f_goal, c_pos, c_goal, goal_radius, f_arrived, c_arrived, f_new, c_new
    )


@njit(cache=True)
def twin_step_exact(
    f_pos: np.ndarray,
    f_vel: np.ndarray,
    f_goal: np.ndarray,
    c_pos: np.ndarray,
    c_vel: np.ndarray,
    c_goal: np.ndarray,
    radius: np.ndarray,
    v0: np.ndarray,
    vmax: np.ndarray,
    params: SRFMKernelParams,
    robot: np.ndarray,
    segments: np.ndarray,
    circles: np.ndarray,
    dt: float,
    force_buf: np.ndarray,
    goal_radius: float,
    f_arrived: np.ndarray,
    c_arrived: np.ndarray,
    f_new: np.ndarray,
    c_new: np.ndarray,
    cut: np.ndarray,
) -> int:
    """As :func:`twin_step_serial` with :func:`step_exact` (no cell list compiled)."""
    step_exact(
        f_pos,
        f_vel,
        f_goal,
        radius,
        v0,
        vmax,
        params,
        robot,
        TRUE,
        segments,
        circles,
        dt,
        force_buf,
        cut,
    )
    step_exact(
        c_pos,
        c_vel,
        c_goal,
        radius,
        v0,
        vmax,
        params,
        robot,
        FALSE,
        segments,
        circles,
        dt,
        force_buf,
        cut,
    )
    return _twin_arrivals(
        f_pos, f_goal, c_pos, c_goal, goal_radius, f_arrived, c_arrived, f_new, c_new
    )


@njit(cache=True)
def twin_step_parallel(
    f_pos: np.ndarray,
    f_vel: np.ndarray,
    f_goal: np.ndarray,
    c_pos: np.ndarray,
    c_vel: np.ndarray,
    c_goal: np.ndarray,
    radius: np.ndarray,
    v0: np.ndarray,
    vmax: np.ndarray,
    params: SRFMKernelParams,
    robot: np.ndarray,
    segments: np.ndarray,
    circles: np.ndarray,
    dt: float,
    force_buf: np.ndarray,
    goal_radius: float,
    f_arrived: np.ndarray,
    c_arrived: np.ndarray,
    f_new: np.ndarray,
    c_new: np.ndarray,
    cut: np.ndarray,
) -> int:
    """As :func:`twin_step_serial` with the threaded force pass (identical results)."""
    step_parallel(
        f_pos,
        f_vel,
        f_goal,
        radius,
        v0,
        vmax,
        params,
        robot,
        TRUE,
        segments,
        circles,
        dt,
        force_buf,
        cut,
    )
    step_parallel(
        c_pos,
        c_vel,
        c_goal,
        radius,
        v0,
        vmax,
        params,
        robot,
        FALSE,
        segments,
        circles,
        dt,
        force_buf,
        cut,
    )
    return _twin_arrivals(
        f_pos, f_goal, c_pos, c_goal, goal_radius, f_arrived, c_arrived, f_new, c_new
    )
