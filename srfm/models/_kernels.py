"""numba kernels of the Social Robot Force Model.

Plain module-level functions over C-contiguous float64 arrays: no objects, no
allocation inside loops, no I/O, no raising, no random draws. Shapes: ``pos``, ``vel``,
``goal`` (N, 2); ``radius``, ``v0``, ``vmax`` (N,); ``params`` the
:class:`~srfm.models.params.SRFMKernelParams` of :meth:`srfm.SRFMParams.for_kernels`;
``robot`` (5,) = (x, y, radius, vx, vy); ``segments`` (M, 4) = (x1, y1, x2, y2); ``circles``
(K, 3) = (cx, cy, radius). All forces are accelerations (m/s², unit mass).

The force primitives (desired velocity, capped exponential, anisotropy ψ, push of a
disc, closest point of a wall) live in :mod:`srfm.models._primitives`, shared with the
social-force planner; the robot's force, in the form the parameters name, in
:mod:`srfm.models._robot_forces`. Exponents are
capped at ``EXP_ARG_MAX`` (e^60 ≈ 1e26), far beyond any force that changes a step (the
speed cap clips it), so that extreme but valid inputs (tiny B, deep overlap with a
large pillar) give huge finite forces instead of inf and NaN.

Serial and threaded variants share one body over the agents (:func:`_agent_forces`); they
differ only in the loop over the agents (one range, or ``prange``), so their results
are identical. Each variant is its own top-level function (numba's on-disk cache does
not tell apart variants made by a factory from one Python function).

Zero distances use an explicit epsilon: two coincident centres exert no force on each
other (the direction is undefined), an agent at rest with no desired direction has no
heading and is treated isotropically (ψ = 1).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, cast

import numpy as np
from llvmlite import ir
from numba import njit, prange, types
from numba.extending import intrinsic

from srfm.models._arrays import CrowdArrays, ForceContext, ObstacleArrays
from srfm.models._primitives import (
    EPS,
    EXP_ARG_MAX,
    capped_exp,
    closest_on_segment,
    desired_velocity,
    disc_repulsion,
)
from srfm.models._robot_forces import robot_force
from srfm.models.params import SRFMKernelParams

if TYPE_CHECKING:
    from collections.abc import Callable


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
    lo: int, hi: int, crowd: CrowdArrays, context: ForceContext, ped: np.ndarray, total: np.ndarray
) -> tuple[float, float, float, float, float, float, float, float]:
    """The four force components on each agent i in [lo, hi): goal, pedestrians, robot,
    obstacles (x, y each); their sum, the step's force, into ``total[i − lo]``; returns
    the components of agent hi − 1 (zeros when lo = hi).

    ``context.cut`` = (pedestrian cut-off, obstacle cut-off) in m, ``inf`` for none.
    With ``inf`` every other pedestrian pushes, summed in index order (the exact
    kernel); with a finite pedestrian cut-off the pedestrian force is ``ped[i]``, from
    :func:`cell_pair_forces`. Obstacles beyond the obstacle cut-off are skipped.

    A loop over a range of agents rather than one call per agent, so that a crowd step
    binds the arrays once: numba counts a reference for every array an inlined
    function receives or takes out of a tuple, an atomic increment and decrement per
    array and call that its pruning pass cannot remove across this body's branches, and
    called once per agent these cost eight times the forces themselves at N = 1000 with
    the cut-off (docs/performance.md, "Crowd step").
    """
    pos = crowd.pos
    vel = crowd.vel
    goal = crowd.goal
    radius = crowd.radius
    v0 = crowd.v0
    params = context.params
    robot = context.robot
    robot_on = context.robot_on
    cut = context.cut
    segments = context.obstacles.segments
    circles = context.obstacles.circles
    tau = params.tau
    a_p = params.a_ped
    b_p = params.b_ped
    lam_p = params.lambda_ped
    a_o = params.a_obs
    b_o = params.b_obs
    ped_cut = cut[0]
    obs_cut = cut[1]
    gfx = gfy = pfx = pfy = rfx = rfy = ofx = ofy = 0.0
    for i in range(lo, hi):
        px = pos[i, 0]
        py = pos[i, 1]
        vx = vel[i, 0]
        vy = vel[i, 1]
        ri = radius[i]
        dvx, dvy = desired_velocity(px, py, goal[i, 0], goal[i, 1], v0[i])
        hx, hy, has_h = _heading(vx, vy, dvx, dvy)

        gfx = (dvx - vx) / tau
        gfy = (dvy - vy) / tau

        # Pedestrian repulsion, summed over j in index order (deterministic).
        pfx = 0.0
        pfy = 0.0
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

        # Robot repulsion in the parameter set's form (absent in the counterfactual twin,
        # or when the form's strength is 0).
        rfx = 0.0
        rfy = 0.0
        if robot_on:
            rfx, rfy = robot_force(px, py, vx, vy, ri, hx, hy, has_h, robot, params)

        # Obstacle repulsion from the closest point of every wall segment and pillar.
        ofx = 0.0
        ofy = 0.0
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
        total[i - lo, 0] = gfx + pfx + rfx + ofx
        total[i - lo, 1] = gfy + pfy + rfy + ofy
    return gfx, gfy, pfx, pfy, rfx, rfy, ofx, ofy


# Most cells a row list may have per agent (plus a floor): a crowd spread far apart
# gets larger cells instead of a huge, mostly empty grid.
MAX_CELLS_PER_AGENT = 4
MIN_CELLS = 64
# Largest cell sorted by insertion (larger ones, only in a widened grid, by merge sort).
INSERTION_SORT_MAX = 32


@njit(cache=True, inline="always")
def exact_cut() -> tuple[np.ndarray, np.ndarray]:
    """``(cut, ped)`` of the exact kernel (no cut-off, every pair in index order) for
    callers of :func:`_agent_forces` that keep the paper's exact sums."""
    return np.full(2, np.inf), np.zeros((0, 2))


@njit(cache=True)
def build_rows(pos: np.ndarray, row_height: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A row list of the positions ``pos``: horizontal bands at least ``row_height``
    tall, each sorted by x.

    Returns ``(order, starts, grid)``: ``grid`` (3,) = (y0, height, ny), the lowest y,
    the row height and the number of rows; ``starts`` (ny + 1,) the start of each row's
    run in ``order``; ``order`` (N,) the agent indices, row by row and within a row by
    x, ties in index order. A counting sort puts the agents into square cells of the
    row height, row-major, in index order within a cell; sorting each cell by x (stable)
    then sorts each row. With ``row_height = inf`` (no cut-off), a height <= 0 or no
    agents all are empty placeholders.
    """
    n = pos.shape[0]
    if n == 0 or not 0.0 < row_height < np.inf:
        return np.zeros(0, dtype=np.int64), np.zeros(1, dtype=np.int64), np.zeros(3)
    x0 = pos[0, 0]
    y0 = pos[0, 1]
    x1 = x0
    y1 = y0
    for i in range(1, n):
        x0 = min(x0, pos[i, 0])
        x1 = max(x1, pos[i, 0])
        y0 = min(y0, pos[i, 1])
        y1 = max(y1, pos[i, 1])
    size = row_height
    max_cells = max(MAX_CELLS_PER_AGENT * n, MIN_CELLS)
    # widen the cells until the grid has at most max_cells cells
    while (np.floor((x1 - x0) / size) + 1.0) * (np.floor((y1 - y0) / size) + 1.0) > max_cells:
        size *= 2.0  # (in float64: no integer overflow for a tiny cut-off)
    nx = math.floor((x1 - x0) / size) + 1
    ny = math.floor((y1 - y0) / size) + 1
    n_cells = nx * ny
    cell = np.empty(n, dtype=np.int64)
    counts = np.zeros(n_cells + 1, dtype=np.int64)
    for i in range(n):
        cx = min(max(math.floor((pos[i, 0] - x0) / size), 0), nx - 1)
        cy = min(max(math.floor((pos[i, 1] - y0) / size), 0), ny - 1)
        cell[i] = cy * nx + cx
        counts[cell[i] + 1] += 1
    for c in range(n_cells):
        counts[c + 1] += counts[c]
    fill = counts[:n_cells].copy()
    order = np.empty(n, dtype=np.int64)
    for i in range(n):
        order[fill[cell[i]]] = i
        fill[cell[i]] += 1
    for c in range(n_cells):
        _sort_by_x(order, counts[c], counts[c + 1], pos)
    starts = np.empty(ny + 1, dtype=np.int64)
    for r in range(ny + 1):
        starts[r] = counts[r * nx]
    return order, starts, np.array([y0, size, float(ny)])


@njit(cache=True, inline="always")
def _sort_by_x(order: np.ndarray, a: int, b: int, pos: np.ndarray) -> None:
    """Sort ``order[a:b]`` by the agents' x, stable (ties keep their order): by insertion
    for up to INSERTION_SORT_MAX agents, else by merge sort."""
    if b - a <= INSERTION_SORT_MAX:
        for k in range(a + 1, b):
            i = order[k]
            x = pos[i, 0]
            j = k
            while j > a and pos[order[j - 1], 0] > x:
                order[j] = order[j - 1]
                j -= 1
            order[j] = i
        return
    # bottom-up merge sort (np.argsort(kind="mergesort") gives the same order but took
    # 1.7 s of numba's compile time of build_rows)
    m = b - a
    src = order[a:b].copy()
    key = np.empty(m)
    for k in range(m):
        key[k] = pos[src[k], 0]
    dst = np.empty(m, dtype=np.int64)
    dkey = np.empty(m)
    width = 1
    while width < m:
        for lo in range(0, m, 2 * width):
            mid = min(lo + width, m)
            hi = min(lo + 2 * width, m)
            i = lo
            j = mid
            for k in range(lo, hi):
                if j >= hi or (i < mid and key[i] <= key[j]):  # a tie: the earlier first
                    dst[k] = src[i]
                    dkey[k] = key[i]
                    i += 1
                else:
                    dst[k] = src[j]
                    dkey[k] = key[j]
                    j += 1
        src, dst = dst, src
        key, dkey = dkey, key
        width *= 2
    for k in range(m):
        order[a + k] = src[k]


# Rows per cut-off: the rows are cut-off / ROW_SPLIT tall. Thinner rows follow the
# cut-off circle more closely (fewer candidate pairs beyond it) at the price of more,
# shorter runs per pedestrian (3 was the fastest of 2, 3, 4 and 6 at N = 1000 and 10,000).
ROW_SPLIT = 3

# The pair pass (_pair_block, _pair_start, fast_exp4, _pair_end) is written for LLVM's loop
# vectoriser, and its bits are fixed by this source alone. What to keep when changing it:
#
# * The lanes. One iteration of the loop over q takes one candidate q of a run against
#   the PAIR_BLOCK pedestrians of a block: four independent pair terms. The vectoriser
#   puts consecutive q side by side in a vector register (4 per AVX2 instruction, 8 with
#   AVX-512): a vector lane is one candidate, and each lane carries the block's four
#   chains. A run is walked in whole multiples of RUN_STEP candidates, so that no scalar
#   remainder loop runs with AVX2; dat, acc_x and acc_y have LANE_PAD padding columns after the n
#   agents (x = 1e30, far from everyone; r, h and c zero). A candidate past the run's
#   end, not after the pedestrian in pair-once order, beyond the cut-off or closer than
#   EPS gets the weight 0 by a select, never a branch. A block short of PAIR_BLOCK
#   pedestrians is filled with the first padding column, n.
# * No fastmath flags. Each rounding is written out: a product is fused with an addition
#   exactly where _fma says so (LLVM's llvm.fma, one rounding, one instruction on a CPU
#   with FMA), and each pedestrian's force is summed lane by lane: lane j of ``lanes``
#   takes the candidates q ≡ j (mod LANE_PAD) in increasing q, then the LANE_PAD lanes
#   are added in a fixed tree (_lane_total, the same sums whichever lane a run ends
#   on). Nothing is left to LLVM to choose: the bits
#   do not depend on the vector width, on which iterations run as vector or as scalar
#   code, nor on the caller. numba re-optimises a copy of _pair_block inside every
#   caller's module and a process runs the copy it loaded first; with the flags
#   ``reassoc`` and ``contract`` (before 2026-11-27) LLVM re-chose the order of the sums
#   and the fused products in each copy, so that results depended on the on-disk cache,
#   on the order of the calls and on how the caller passed its arrays
#   (docs/performance.md, "Determinism of the cut-off's pair pass").
# * Memory the vectoriser can check. LLVM vectorises the loop only if it can prove at
#   run time, with a bounded number of checks, that the arrays written (acc_x, acc_y,
#   lanes) do not overlap those read, and if every index is a plain count from 0. So the
#   force accumulators are two 1-D arrays (two rows of one array, written at a distance
#   known only at run time, make LLVM check every access pair apart and give up); the
#   eight lane rows sit in one flat array at the compile-time distance LANE_ROW, each
#   lane's running sum stored LANE_PAD further on (a dependence at a constant distance,
#   safe for up to LANE_PAD lanes per vector); and every array is sliced at the run's
#   start, so that q counts from 0 (no negative-index wraparound).
# * The tests that guard it, in tests/models/test_cutoff.py: the cut kernel against the
#   exact one (within the omitted terms' bound, or up to rounding when nothing is
#   omitted, also for runs longer than a lane segment), fast_exp against math.exp, the
#   pair loop still vectorised (test_pair_loop_is_vectorised), and a cut-off episode
#   byte for byte the same compiled and loaded from the cache
#   (test_cutoff_episode_is_identical_compiled_and_cached).
#
# The lanes a pedestrian's force is summed in (the vector width of AVX-512 in float64).
LANE_PAD = 8
# The pair loop runs over whole multiples of RUN_STEP candidates (AVX2's vector width in
# float64; with AVX-512 a run may end with up to 4 scalar iterations, the same bits): a
# short run costs one vector iteration, and no more than 3 padding candidates (with
# LANE_PAD, 8 % fewer pair terms at N = 1000 on the protocol's crowd).
RUN_STEP = 4
# Pedestrians of a row that share one window per row in the pair loop (_pair_block):
# four independent chains per vector lane, and a quarter of the runs.
PAIR_BLOCK = 4
# The lane rows' stride in the flat ``lanes`` array (a constant, see above), and the
# candidates a lane row holds at a time: a longer run is walked in segments of
# LANE_SEGMENT, each segment's lane sums carried to the front of the rows.
LANE_ROW = 512
LANE_SEGMENT = LANE_ROW - LANE_PAD


@intrinsic
def _float_bits_ir(typingctx, x):  # type: ignore[no-untyped-def]
    """The IEEE 754 bits of a float64 as an int64 (a bit cast, no conversion)."""
    sig = types.int64(types.float64)

    def codegen(context, builder, signature, args):  # type: ignore[no-untyped-def]
        return builder.bitcast(args[0], ir.IntType(64))

    return sig, codegen


@intrinsic
def _bits_float_ir(typingctx, i):  # type: ignore[no-untyped-def]
    """The float64 whose IEEE 754 bits are the int64 ``i`` (a bit cast, no conversion)."""
    sig = types.float64(types.int64)

    def codegen(context, builder, signature, args):  # type: ignore[no-untyped-def]
        return builder.bitcast(args[0], ir.DoubleType())

    return sig, codegen


@intrinsic
def _fma_ir(typingctx, a, b, c):  # type: ignore[no-untyped-def]
    """a·b + c with one rounding (LLVM's llvm.fma: the same bits in any context; one
    instruction on a CPU with FMA, a correctly rounded libm call on one without)."""
    sig = types.float64(types.float64, types.float64, types.float64)

    def codegen(context, builder, signature, args):  # type: ignore[no-untyped-def]
        fn = builder.module.declare_intrinsic("llvm.fma", [ir.DoubleType()] * 3)
        return builder.call(fn, args)

    return sig, codegen


# the intrinsics as the kernels call them (the same objects, typed for the type checker)
_float_bits = cast("Callable[[float], int]", _float_bits_ir)
_bits_float = cast("Callable[[int], float]", _bits_float_ir)
_fma = cast("Callable[[float, float, float], float]", _fma_ir)

_LOG2E = 1.4426950408889634
_LN2_HI = 0.693147180369123816490  # ln 2 split in two (Cody and Waite): n·_LN2_HI is exact
_LN2_LO = 1.90821492927058770002e-10
_ROUND_SHIFT = 6755399441055744.0  # 1.5·2^52: an integer added to it lands in the low bits


# the Taylor coefficients of e^t after the leading 1 / 12!, from t^11 down to t^0
_EXP_TAYLOR = (
    1.0 / 39916800.0,
    1.0 / 3628800.0,
    1.0 / 362880.0,
    1.0 / 40320.0,
    1.0 / 5040.0,
    1.0 / 720.0,
    1.0 / 120.0,
    1.0 / 24.0,
    1.0 / 6.0,
    0.5,
    1.0,
    1.0,
)


@njit(cache=True)
def _exp_reduce(arg: float) -> tuple[float, float]:
    """``(nf, t)`` of :func:`fast_exp4`'s argument reduction: arg, clipped, = nf ln 2 + t."""
    x = min(max(arg, -EXP_ARG_MAX), EXP_ARG_MAX)
    nf = np.floor(_fma(x, _LOG2E, 0.5))  # a float: no float-to-int conversion per lane
    t = _fma(-nf, _LN2_LO, _fma(-nf, _LN2_HI, x))
    return nf, t


@njit(cache=True)
def _exp_scale(nf: float) -> float:
    """2^nf for an integral float ``nf`` in the exponent's range, written into the bits."""
    # nf + 1.5·2^52 is exact and holds nf in its low bits: n without a float-to-int64
    # conversion (AVX2 has none)
    n = _float_bits(nf + _ROUND_SHIFT) - _float_bits(_ROUND_SHIFT)
    return _bits_float((n + 1023) << 52)


# inlined by numba: LLVM does not inline a function this long into the pair loop by
# itself, and the loop does not vectorise around a call
@njit(cache=True, inline="always")
def fast_exp4(a0: float, a1: float, a2: float, a3: float) -> tuple[float, float, float, float]:
    """exp of four arguments, each clipped to [−EXP_ARG_MAX, EXP_ARG_MAX], branch-free so
    that the pair loop vectorises (numba's math.exp is a libm call per element).

    arg = n ln 2 + t with n = round(arg / ln 2) and |t| <= ln 2 / 2; e^t from its Taylor
    polynomial of degree 12 (truncation below 2e-17 relative) in Horner form with fused
    multiply-adds, 2^n written straight into the exponent bits. Within 2.3e-16 relative
    of math.exp over [−60, 60]. No fastmath (see the pair pass's comment above
    LANE_PAD): reassociation would fold the two-part ln 2 into one product.

    Four at a time, step by step side by side, each the same operations as alone
    (:func:`fast_exp`): the Horner chain is 12 dependent fused multiply-adds, and a
    pair-loop iteration is longer than the CPU's reordering window, so written one after
    the other the four chains ran mostly one at a time (the pair pass 25 % slower).
    """
    n0, t0 = _exp_reduce(a0)
    n1, t1 = _exp_reduce(a1)
    n2, t2 = _exp_reduce(a2)
    n3, t3 = _exp_reduce(a3)
    p0 = p1 = p2 = p3 = 1.0 / 479001600.0
    for c in _EXP_TAYLOR:  # (a constant trip count: LLVM unrolls it)
        p0 = _fma(p0, t0, c)
        p1 = _fma(p1, t1, c)
        p2 = _fma(p2, t2, c)
        p3 = _fma(p3, t3, c)
    return p0 * _exp_scale(n0), p1 * _exp_scale(n1), p2 * _exp_scale(n2), p3 * _exp_scale(n3)


@njit(cache=True)
def fast_exp(arg: float) -> float:
    """exp(arg) of :func:`fast_exp4` for one argument (the same bits)."""
    return fast_exp4(arg, arg, arg, arg)[0]


@njit(cache=True, inline="always")
def _pair_start(
    xk: float, yk: float, rk: float, xq: float, yq: float, rq: float, inv_b: float
) -> tuple[float, float, float, float, float]:
    """``(dx, dy, d2, inv_d, arg)`` of one pair (k, q), up to the exponential: (dx, dy)
    from q to k, d2 its squared length, inv_d = 1 / d (d at least EPS) and the exponent
    arg = (r_k + r_q − d) / B, the radii already over B (see :func:`_pair_end`)."""
    dx = xk - xq
    dy = yk - yq
    d2 = _fma(dx, dx, dy * dy)
    d = math.sqrt(max(d2, EPS * EPS))
    return dx, dy, d2, 1.0 / d, _fma(-d, inv_b, rk + rq)


@njit(cache=True, inline="always")
def _pair_end(
    e: float,
    dx: float,
    dy: float,
    d2: float,
    inv_d: float,
    hxk: float,
    hyk: float,
    ck: float,
    hxq: float,
    hyq: float,
    cq: float,
    live: bool,
    cut2: float,
) -> tuple[float, float]:
    """``(mk, mq)`` of one pair (k, q) from :func:`_pair_start`'s values and e = exp(arg):
    the forces on k and on q are mk (dx, dy) and −mq (dx, dy); mk = mq = 0 unless
    ``live`` and the pair is closer than the cut-off (``cut2`` its square) and not closer
    than EPS. Branch-free (a select), so that the loop around it vectorises; the columns
    are those of :func:`cell_pair_forces` (radii over B, A in c and h'): m = A exp((r_k +
    r_q − d) / B) ψ / d, each with its own ψ."""
    eps2 = EPS * EPS
    # e / d: the unit vector from q to k is (dx, dy) / d
    s = e * inv_d if live & (d2 < cut2) & (d2 >= eps2) else 0.0
    mk = s * _fma(_fma(hxk, dx, hyk * dy), inv_d, ck)
    mq = s * _fma(-_fma(hxq, dx, hyq * dy), inv_d, cq)
    return mk, mq


@njit(cache=True, inline="always")
def _lane_total(lanes: np.ndarray, at: int) -> float:
    """The sum of the LANE_PAD lanes ``lanes[at : at + LANE_PAD]``, in a fixed tree: the
    lanes 4 apart, then those sums 2 apart, then the two halves. Whatever ``at`` (lane j
    of the pair loop sits at the position ≡ j mod LANE_PAD), these are the same pairs of
    lanes, so the same sums (each addition commutes)."""
    total: float = ((lanes[at] + lanes[at + 4]) + (lanes[at + 2] + lanes[at + 6])) + (
        (lanes[at + 1] + lanes[at + 5]) + (lanes[at + 3] + lanes[at + 7])
    )
    return total


@njit(cache=True)
def _pair_block(
    k: np.ndarray,
    lo: int,
    hi: int,
    dat: np.ndarray,
    cut2: float,
    inv_b: float,
    acc_x: np.ndarray,
    acc_y: np.ndarray,
    lanes: np.ndarray,
) -> None:
    """The pairs (k[j], q) for the PAIR_BLOCK agents ``k`` and q in [lo, hi) with q > k[j]
    of the row-ordered agents ``dat`` (columns x, y, r / B, hx', hy', c: A ψ = c ±
    (hx', hy')·u, see :func:`cell_pair_forces`), each share added into ``acc_x`` and
    ``acc_y``; ``lanes`` (2 PAIR_BLOCK LANE_ROW,) is scratch.

    The loop runs over q, a whole number of RUN_STEP candidates past ``lo``, the force on
    each k[j] summed lane by lane (the comment above LANE_PAD says what the lanes are,
    why the sums are written out and what keeps the loop vectorised): without a scalar
    remainder and with the PAIR_BLOCK agents' independent chains in every lane it
    vectorises well even for the short runs of the row windows.
    """
    k0 = k[0]
    k1 = k[1]
    k2 = k[2]
    k3 = k[3]
    x0, y0, r0, hx0, hy0, c0 = (
        dat[0, k0],
        dat[1, k0],
        dat[2, k0],
        dat[3, k0],
        dat[4, k0],
        dat[5, k0],
    )
    x1, y1, r1, hx1, hy1, c1 = (
        dat[0, k1],
        dat[1, k1],
        dat[2, k1],
        dat[3, k1],
        dat[4, k1],
        dat[5, k1],
    )
    x2, y2, r2, hx2, hy2, c2 = (
        dat[0, k2],
        dat[1, k2],
        dat[2, k2],
        dat[3, k2],
        dat[4, k2],
        dat[5, k2],
    )
    x3, y3, r3, hx3, hy3, c3 = (
        dat[0, k3],
        dat[1, k3],
        dat[2, k3],
        dat[3, k3],
        dat[4, k3],
        dat[5, k3],
    )
    # lane row r (x and y of k[0], then of k[1], ...) at lanes[r * LANE_ROW:]; the lane
    # sums of the candidates before q at [q, q + LANE_PAD), starting from zero
    for r in range(2 * PAIR_BLOCK):
        for j in range(LANE_PAD):
            lanes[r * LANE_ROW + j] = 0.0
    m = hi - lo
    end = (m + RUN_STEP - 1) & -RUN_STEP
    at = 0  # where the lane sums of the candidates so far are
    for s in range(0, end, LANE_SEGMENT):
        if at > 0:  # a further segment: its lane sums start from the last one's
            for r in range(2 * PAIR_BLOCK):
                for j in range(LANE_PAD):
                    lanes[r * LANE_ROW + j] = lanes[r * LANE_ROW + at + j]
        at = min(LANE_SEGMENT, end - s)
        # the segment's slices, indexed from 0: a loop index known to be >= 0 lets LLVM
        # drop numba's negative-index wraparound and vectorise the loop
        start = lo + s
        xs = dat[0, start:]
        ys = dat[1, start:]
        rs = dat[2, start:]
        hxs = dat[3, start:]
        hys = dat[4, start:]
        cs = dat[5, start:]
        ax = acc_x[start:]
        ay = acc_y[start:]
        # q (from start) must be before hi and past k[j]: q > k[j] − start
        left = hi - start
        m0 = k0 - start
        m1 = k1 - start
        m2 = k2 - start
        m3 = k3 - start
        for q in range(at):
            xq = xs[q]
            yq = ys[q]
            rq = rs[q]
            hxq = hxs[q]
            hyq = hys[q]
            cq = cs[q]
            inside = q < left
            # the four pairs side by side up to and through the exponentials (see fast_exp4)
            dx0, dy0, d20, id0, g0 = _pair_start(x0, y0, r0, xq, yq, rq, inv_b)
            dx1, dy1, d21, id1, g1 = _pair_start(x1, y1, r1, xq, yq, rq, inv_b)
            dx2, dy2, d22, id2, g2 = _pair_start(x2, y2, r2, xq, yq, rq, inv_b)
            dx3, dy3, d23, id3, g3 = _pair_start(x3, y3, r3, xq, yq, rq, inv_b)
            e0, e1, e2, e3 = fast_exp4(g0, g1, g2, g3)
            live0 = inside & (q > m0)
            live1 = inside & (q > m1)
            live2 = inside & (q > m2)
            live3 = inside & (q > m3)
            mk0, mq0 = _pair_end(e0, dx0, dy0, d20, id0, hx0, hy0, c0, hxq, hyq, cq, live0, cut2)
            mk1, mq1 = _pair_end(e1, dx1, dy1, d21, id1, hx1, hy1, c1, hxq, hyq, cq, live1, cut2)
            mk2, mq2 = _pair_end(e2, dx2, dy2, d22, id2, hx2, hy2, c2, hxq, hyq, cq, live2, cut2)
            mk3, mq3 = _pair_end(e3, dx3, dy3, d23, id3, hx3, hy3, c3, hxq, hyq, cq, live3, cut2)
            p = q + LANE_PAD
            lanes[p] = _fma(mk0, dx0, lanes[q])
            lanes[LANE_ROW + p] = _fma(mk0, dy0, lanes[LANE_ROW + q])
            lanes[2 * LANE_ROW + p] = _fma(mk1, dx1, lanes[2 * LANE_ROW + q])
            lanes[3 * LANE_ROW + p] = _fma(mk1, dy1, lanes[3 * LANE_ROW + q])
            lanes[4 * LANE_ROW + p] = _fma(mk2, dx2, lanes[4 * LANE_ROW + q])
            lanes[5 * LANE_ROW + p] = _fma(mk2, dy2, lanes[5 * LANE_ROW + q])
            lanes[6 * LANE_ROW + p] = _fma(mk3, dx3, lanes[6 * LANE_ROW + q])
            lanes[7 * LANE_ROW + p] = _fma(mk3, dy3, lanes[7 * LANE_ROW + q])
            ax[q] -= _fma(mq3, dx3, _fma(mq2, dx2, _fma(mq1, dx1, mq0 * dx0)))
            ay[q] -= _fma(mq3, dy3, _fma(mq2, dy2, _fma(mq1, dy1, mq0 * dy0)))
    acc_x[k0] += _lane_total(lanes, at)
    acc_y[k0] += _lane_total(lanes, LANE_ROW + at)
    acc_x[k1] += _lane_total(lanes, 2 * LANE_ROW + at)
    acc_y[k1] += _lane_total(lanes, 3 * LANE_ROW + at)
    acc_x[k2] += _lane_total(lanes, 4 * LANE_ROW + at)
    acc_y[k2] += _lane_total(lanes, 5 * LANE_ROW + at)
    acc_x[k3] += _lane_total(lanes, 6 * LANE_ROW + at)
    acc_y[k3] += _lane_total(lanes, 7 * LANE_ROW + at)


@njit(cache=True)
def window_setup(cutoff: float, grid: np.ndarray, scale: float) -> tuple[float, np.ndarray]:
    """``(reach, chord)`` of the row windows for a pedestrian ``cutoff`` on the rows of
    ``grid`` (:func:`build_rows`), coordinates up to ``scale`` in magnitude.

    ``reach`` is the cut-off plus a margin for rounding (1e-9 of the cut-off and of the
    coordinates' magnitude): windows may hold a few pairs beyond the cut-off, which the
    pair pass leaves out, but never miss a pair within it. ``chord[o]`` (o = 1, 2, …) is
    the half-width in x of the window in the o-th row above a pedestrian's own: two
    agents o rows apart are at least (o − 1) row heights apart in y, so a neighbour's x
    lies within sqrt(reach² − ((o − 1) h)²) of the pedestrian's. ``chord[0]`` holds the
    margin.
    """
    margin = 1e-9 * (cutoff + scale)
    reach = cutoff + margin
    height = grid[1]
    n_up = math.floor(reach / height) + 1  # rows o with (o − 1) h < reach
    chord = np.zeros(n_up + 1)
    chord[0] = margin  # (the own row has no chord)
    for o in range(1, n_up + 1):
        dy = max((o - 1) * height - margin, 0.0)
        chord[o] = math.sqrt(max(reach * reach - dy * dy, 0.0)) + margin
    return reach, chord


@njit(cache=True, inline="always")
def _row_windows(
    first: int,
    last: int,
    row: int,
    xs: np.ndarray,
    ys: np.ndarray,
    starts: np.ndarray,
    grid: np.ndarray,
    reach: float,
    chord: np.ndarray,
    lo: np.ndarray,
    hi: np.ndarray,
    run: np.ndarray,
) -> int:
    """The runs of row-ordered agents that may lie within the cut-off of the agents
    ``first`` to ``last`` (consecutive in row ``row``) and come after them in the
    pair-once order, written into ``run`` (2, ·) as ``[run[0, o], run[1, o])`` for o
    below the returned count: o = 0 the agents after ``first`` in its own row up to
    those whose x is within ``reach`` of ``last``'s, o >= 1 the agents of row
    ``row + o`` whose x is within the cut-off circle's chord of the block's x range
    (from ``first``'s x to ``last``'s) at the row's distance from the block's highest
    agent.

    ``lo`` and ``hi`` are the bounds for ``chord[o]``, the widest chord of any agent of
    the row; they carry over from the previous block of the row (reset them with
    :func:`_reset_windows` at each row's start): x grows along a row, so each only moves
    forward. Each run narrows them to this block's own chord.
    """
    x_first = xs[first]
    x_last = xs[last]
    y_high = ys[first]  # the block's agent closest to the rows above
    for k in range(first + 1, last + 1):
        y_high = max(y_high, ys[k])
    end = starts[row + 1]
    h0 = max(hi[0], last + 1)
    while h0 < end and xs[h0] < x_last + reach:
        h0 += 1
    hi[0] = h0
    run[0, 0] = first + 1
    run[1, 0] = h0
    ny = starts.shape[0] - 1
    margin = chord[0]
    count = 1
    for o in range(1, chord.shape[0]):
        r = row + o
        dy = grid[0] + r * grid[1] - y_high - margin  # at most the distance to row r
        if r >= ny or dy >= reach:
            break  # this row (and every one above it) starts beyond the cut-off
        end = starts[r + 1]
        ch = chord[o]
        a = lo[o]
        while a < end and xs[a] <= x_first - ch:
            a += 1
        b = max(hi[o], a)
        while b < end and xs[b] < x_last + ch:
            b += 1
        lo[o] = a
        hi[o] = b
        ch = min(math.sqrt(max(reach * reach - max(dy, 0.0) ** 2, 0.0)) + margin, ch)
        while a < b and xs[a] <= x_first - ch:
            a += 1
        while b > a and xs[b - 1] >= x_last + ch:
            b -= 1
        run[0, o] = a
        run[1, o] = b
        count += 1
    return count


@njit(cache=True, inline="always")
def _reset_windows(row: int, starts: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> None:
    """Point every window bound at the start of its row, before the first agent of ``row``."""
    ny = starts.shape[0] - 1
    for o in range(lo.shape[0]):
        s = starts[min(row + o, ny)]
        lo[o] = s
        hi[o] = s


@njit(cache=True)
def window_pairs(pos: np.ndarray, cutoff: float) -> np.ndarray:
    """Every pair (i, j) of agents closer than ``cutoff`` that the row windows of
    :func:`cell_pair_forces` find, as (P, 2) agent indices (for tests: it must be every
    pair closer than the cut-off, each once)."""
    n = pos.shape[0]
    order, starts, grid = build_rows(pos, cutoff / ROW_SPLIT)
    if n == 0:
        return np.zeros((0, 2), dtype=np.int64)
    xs = np.empty(n)
    ys = np.empty(n)
    for k in range(n):
        xs[k] = pos[order[k], 0]
        ys[k] = pos[order[k], 1]
    reach, chord = window_setup(cutoff, grid, _magnitude(pos))
    lo = np.zeros(chord.shape[0], dtype=np.int64)
    hi = np.zeros(chord.shape[0], dtype=np.int64)
    run = np.zeros((2, chord.shape[0]), dtype=np.int64)
    cut2 = cutoff * cutoff
    out = []
    for row in range(starts.shape[0] - 1):
        _reset_windows(row, starts, lo, hi)
        for first in range(starts[row], starts[row + 1], PAIR_BLOCK):
            last = min(first + PAIR_BLOCK, starts[row + 1]) - 1
            for o in range(
                _row_windows(first, last, row, xs, ys, starts, grid, reach, chord, lo, hi, run)
            ):
                for k in range(first, last + 1):
                    for q in range(max(run[0, o], k + 1), run[1, o]):
                        dx = xs[k] - xs[q]
                        dy = ys[k] - ys[q]
                        if dx * dx + dy * dy < cut2:
                            out.append((order[k], order[q]))
    pairs = np.empty((len(out), 2), dtype=np.int64)
    for p in range(len(out)):
        pairs[p, 0] = out[p][0]
        pairs[p, 1] = out[p][1]
    return pairs


@njit(cache=True, inline="always")
def _magnitude(pos: np.ndarray) -> float:
    """The largest coordinate magnitude in ``pos``."""
    m = 0.0
    for i in range(pos.shape[0]):
        m = max(m, abs(pos[i, 0]), abs(pos[i, 1]))
    return m


@njit(cache=True)
def cell_pair_forces(crowd: CrowdArrays, params: SRFMKernelParams, cutoff: float) -> np.ndarray:
    """The pedestrian repulsion on every agent (N, 2), over the pairs closer than
    ``cutoff``, found with a row list (:func:`build_rows`, rows cutoff / ROW_SPLIT
    tall, each sorted by x); empty (0, 2) without a cut-off (``inf``) or with A_p = 0.

    Each pair is visited once, row by row and along each row in x order: the agents
    after the pedestrian in its own row whose x is within the cut-off, then in each row
    above the agents whose x is within the cut-off circle's chord at that row's distance
    (:func:`_row_windows`: contiguous runs, so the pair loop vectorises). The
    exponential A exp((r_i + r_j − d) / B) (:func:`fast_exp`) is shared, each agent gets
    its own ψ, written as ψ = (λ + w) − w e·u with w = (1 − λ)/2 (ψ = 1 without a
    heading), the terms of :func:`disc_repulsion`. Sums follow that visiting order (a
    pedestrian's share of one run lane by lane, :func:`_pair_block`), every rounding
    written out, so the result is the same bits in any process, whatever compiled it,
    and equals the exact kernel's up to rounding (a few units in the last place).
    """
    pos = crowd.pos
    vel = crowd.vel
    goal = crowd.goal
    radius = crowd.radius
    v0 = crowd.v0
    n = pos.shape[0]
    a_p = params.a_ped
    if n == 0 or a_p == 0.0 or not 0.0 < cutoff < np.inf:
        return np.zeros((0, 2))
    lam = params.lambda_ped
    w = (1.0 - lam) * 0.5
    order, starts, grid = build_rows(pos, cutoff / ROW_SPLIT)
    # 1/B capped: finite even for a subnormal B, so that r / B and d / B stay finite or
    # clip to the exponential's range instead of making inf − inf
    inv_b = min(1.0 / params.b_ped, 1e300)
    # per agent in row order: x, y, r / B, then (hx', hy', c) with A ψ_k = c + (hx', hy')·u
    # for u the unit vector from the source to k
    dat = np.empty((6, n + LANE_PAD))
    dat[:, n:] = 0.0
    dat[0, n:] = 1e30  # padding, far from everyone
    for k in range(n):
        i = order[k]
        dvx, dvy = desired_velocity(pos[i, 0], pos[i, 1], goal[i, 0], goal[i, 1], v0[i])
        hx, hy, has_h = _heading(vel[i, 0], vel[i, 1], dvx, dvy)
        dat[0, k] = pos[i, 0]
        dat[1, k] = pos[i, 1]
        dat[2, k] = radius[i] * inv_b
        if has_h:
            dat[3, k] = -a_p * w * hx
            dat[4, k] = -a_p * w * hy
            dat[5, k] = a_p * (lam + w)
        else:
            dat[3, k] = 0.0
            dat[4, k] = 0.0
            dat[5, k] = a_p
    # the forces in row order, two arrays (not one (2, n) array: see above LANE_PAD)
    acc_x = np.zeros(n + LANE_PAD)
    acc_y = np.zeros(n + LANE_PAD)
    cut2 = cutoff * cutoff
    reach, chord = window_setup(cutoff, grid, _magnitude(pos))
    lo = np.zeros(chord.shape[0], dtype=np.int64)
    hi = np.zeros(chord.shape[0], dtype=np.int64)
    run = np.zeros((2, chord.shape[0]), dtype=np.int64)
    xs = dat[0]
    ys = dat[1]
    block = np.empty(PAIR_BLOCK, dtype=np.int64)
    lanes = np.empty(2 * PAIR_BLOCK * LANE_ROW)
    for row in range(starts.shape[0] - 1):
        _reset_windows(row, starts, lo, hi)
        for first in range(starts[row], starts[row + 1], PAIR_BLOCK):
            last = min(first + PAIR_BLOCK, starts[row + 1]) - 1
            for j in range(PAIR_BLOCK):
                # a block short of PAIR_BLOCK agents is filled with the first padding
                # column, far from everyone
                block[j] = first + j if first + j <= last else n
            for o in range(
                _row_windows(first, last, row, xs, ys, starts, grid, reach, chord, lo, hi, run)
            ):
                _pair_block(block, run[0, o], run[1, o], dat, cut2, inv_b, acc_x, acc_y, lanes)
    out = np.empty((n, 2))
    for k in range(n):
        i = order[k]
        out[i, 0] = acc_x[k]
        out[i, 1] = acc_y[k]
    return out


@njit(cache=True)
def force_components_kernel(crowd: CrowdArrays, context: ForceContext, out: np.ndarray) -> None:
    """Write the components into ``out`` (4, N, 2): goal, pedestrians, robot, obstacles."""
    ped = cell_pair_forces(crowd, context.params, context.cut[0])
    total = np.empty((1, 2))
    for i in range(crowd.pos.shape[0]):
        g0, g1, p0, p1, r0, r1, o0, o1 = _agent_forces(i, i + 1, crowd, context, ped, total)
        out[0, i, 0] = g0
        out[0, i, 1] = g1
        out[1, i, 0] = p0
        out[1, i, 1] = p1
        out[2, i, 0] = r0
        out[2, i, 1] = r1
        out[3, i, 0] = o0
        out[3, i, 1] = o1


@njit(cache=True, inline="always")
def euler_velocity(
    vx: float, vy: float, fx: float, fy: float, vmax: float, dt: float
) -> tuple[float, float]:
    """The semi-implicit Euler velocity: v + F dt, its length capped at ``vmax``.

    The one definition of the step's velocity update: :func:`integrate` (every crowd
    step) and the environment's one-step counterfactual deviation
    (:func:`srfm.rl._kernels.one_step_deviation`) both call it, so they agree bit for bit.
    """
    ux = vx + fx * dt
    uy = vy + fy * dt
    speed = math.sqrt(ux * ux + uy * uy)
    if speed > vmax:
        scale = vmax / speed
        ux *= scale
        uy *= scale
    return ux, uy


@njit(cache=True)
def integrate(
    pos: np.ndarray, vel: np.ndarray, force: np.ndarray, vmax: np.ndarray, dt: float
) -> None:
    """Semi-implicit Euler in place: v ← v + F dt, |v| capped at vmax, x ← x + v dt."""
    for i in range(pos.shape[0]):
        vx, vy = euler_velocity(vel[i, 0], vel[i, 1], force[i, 0], force[i, 1], vmax[i], dt)
        vel[i, 0] = vx
        vel[i, 1] = vy
        pos[i, 0] += vx * dt
        pos[i, 1] += vy * dt


# The three crowd steps, ``step_*(crowd, context, dt, force_buf)``: the total force on
# every agent from one snapshot into ``force_buf`` (N, 2), then :func:`integrate`, in
# place on ``crowd``. They differ only in the pedestrian pairs (a cut-off's row list,
# or every pair) and in the loop over the agents (``range``, or ``prange`` over
# threads); each is its own top-level function so that numba's on-disk cache tells
# them apart and a run compiles only the one it uses.


@njit(cache=True)
def step_serial(
    crowd: CrowdArrays, context: ForceContext, dt: float, force_buf: np.ndarray
) -> None:
    """One crowd step; with a finite pedestrian cut-off (``context.cut[0]``) the row list
    of the snapshot (:func:`build_rows`) sums only the pairs closer than it."""
    ped = cell_pair_forces(crowd, context.params, context.cut[0])
    _agent_forces(0, crowd.pos.shape[0], crowd, context, ped, force_buf)
    integrate(crowd.pos, crowd.vel, force_buf, crowd.vmax, dt)


# Compiled apart, not inline="always" (the same holds for robot_force and robot_event):
# numba inlines at the level of its own IR, so every copy is typed and lowered again.
# The episode's step (srfm.sim._kernels._advance) calls this step twice (both twins),
# and inlined, each copy carried the robot force's four forms: a first run's crowd,
# robot and metric kernels took 34.5 CPU-s to compile with it, 13.9 without. As compiled
# callees, which LLVM may still inline, an episode runs 0-3 % slower (docs/performance.md,
# "First run with an empty numba cache").
@njit(cache=True)
def step_exact(crowd: CrowdArrays, context: ForceContext, dt: float, force_buf: np.ndarray) -> None:
    """One crowd step with every pedestrian pair, in index order (the exact kernel),
    whatever ``context.cut[0]``; obstacles cut at ``context.cut[1]``.

    A kernel of its own so that runs without a cut-off (every built-in scenario but the
    large ones) never compile the cell list: a first run compiles seconds less.
    """
    c = context
    exact = ForceContext(c.params, c.robot, c.robot_on, c.obstacles, np.array([np.inf, c.cut[1]]))
    ped = np.zeros((0, 2))
    _agent_forces(0, crowd.pos.shape[0], crowd, exact, ped, force_buf)
    integrate(crowd.pos, crowd.vel, force_buf, crowd.vmax, dt)


@njit(cache=True, parallel=True)
def step_parallel(
    crowd: CrowdArrays, context: ForceContext, dt: float, force_buf: np.ndarray
) -> None:
    """As :func:`step_serial` with the agents of the force pass split over threads (for
    large crowds); bit-identical results.

    numba's threaded loop takes a tuple from outside only when it is an argument or
    made by its class's call in view of the loop, so the loop gets the arrays one by
    one (and the parameters made again) and bundles them inside, which costs nothing.
    """
    ped = cell_pair_forces(crowd, context.params, context.cut[0])
    pos = crowd.pos
    vel = crowd.vel
    goal = crowd.goal
    radius = crowd.radius
    v0 = crowd.v0
    params = SRFMKernelParams(*context.params)
    robot = context.robot
    robot_on = context.robot_on
    segments = context.obstacles.segments
    circles = context.obstacles.circles
    cut = context.cut
    for i in prange(pos.shape[0]):
        each = CrowdArrays(pos, vel, goal, radius, v0, v0)  # vmax is not read here
        walls = ObstacleArrays(segments, circles, circles, v0)  # nor the pillars' split
        felt = ForceContext(params, robot, robot_on, walls, cut)
        _agent_forces(i, i + 1, each, felt, ped, force_buf[i:])
    integrate(pos, vel, force_buf, crowd.vmax, dt)


@njit(cache=True, inline="always")
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
