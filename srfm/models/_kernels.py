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
from numba import njit, prange

from srfm.models._primitives import (
    EPS,
    anisotropy,
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
    ``cutoff``, found with a cell list (:func:`build_cells`); empty (0, 2) without a
    cut-off (``inf``) or with A_p = 0.

    Each pair is visited once, cell by cell in row-major order (its own cell, then the
    right neighbour and the three cells above: every neighbouring pair of cells once):
    the exponential A exp((r_i + r_j − d) / B) is shared, each agent gets its own ψ
    (:func:`disc_repulsion`'s terms, as a pair). Sums follow that visiting order, so the
    result is deterministic but not bit for bit the exact kernel's index-order sum.
    """
    n = pos.shape[0]
    a_p = params.a_ped
    if n == 0 or a_p == 0.0 or not 0.0 < cutoff < np.inf:
        return np.zeros((0, 2))
    b_p = params.b_ped
    lam = params.lambda_ped
    cells, grid, xyr = build_cells(pos, radius, cutoff)
    nx = int(grid[3])
    ny = int(grid[4])
    n_cells = nx * ny
    # headings in cell order: (hx, hy, 1 if the agent has a heading else 0)
    head = np.empty((n, 3))
    for k in range(n):
        i = cells[n_cells + 1 + k]
        dvx, dvy = desired_velocity(pos[i, 0], pos[i, 1], goal[i, 0], goal[i, 1], v0[i])
        hx, hy, has_h = _heading(vel[i, 0], vel[i, 1], dvx, dvy)
        head[k, 0] = hx
        head[k, 1] = hy
        head[k, 2] = 1.0 if has_h else 0.0
    acc = np.zeros((n, 2))
    cut2 = cutoff * cutoff
    for cy in range(ny):
        for cx in range(nx):
            c = cy * nx + cx
            # the runs after cell c: the rest of c and its right neighbour (contiguous),
            # then the row above from cx - 1 to cx + 1
            r0_end = cells[c + 2] if cx + 1 < nx else cells[c + 1]
            r1_start = 0
            r1_end = 0
            if cy + 1 < ny:
                r1_start = cells[(cy + 1) * nx + max(cx - 1, 0)]
                r1_end = cells[(cy + 1) * nx + min(cx + 1, nx - 1) + 1]
            for k in range(cells[c], cells[c + 1]):
                for run in range(2):
                    lo = k + 1 if run == 0 else r1_start
                    hi = r0_end if run == 0 else r1_end
                    for q in range(lo, hi):
                        dx = xyr[k, 0] - xyr[q, 0]
                        dy = xyr[k, 1] - xyr[q, 1]
                        d2 = dx * dx + dy * dy
                        if d2 >= cut2:
                            continue
                        d = math.sqrt(d2)
                        if d < EPS:
                            continue
                        e = a_p * capped_exp((xyr[k, 2] + xyr[q, 2] - d) / b_p)
                        ux = dx / d  # unit vector from q to k
                        uy = dy / d
                        psi_k = anisotropy(head[k, 0], head[k, 1], head[k, 2] > 0.0, -ux, -uy, lam)
                        psi_q = anisotropy(head[q, 0], head[q, 1], head[q, 2] > 0.0, ux, uy, lam)
                        mk = e * psi_k
                        mq = e * psi_q
                        acc[k, 0] += mk * ux
                        acc[k, 1] += mk * uy
                        acc[q, 0] -= mq * ux
                        acc[q, 1] -= mq * uy
    out = np.empty((n, 2))
    for k in range(n):
        i = cells[n_cells + 1 + k]
        out[i, 0] = acc[k, 0]
        out[i, 1] = acc[k, 1]
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
        True,
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
        False,
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
        True,
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
        False,
        segments,
        circles,
        dt,
        force_buf,
        cut,
    )
    return _twin_arrivals(
        f_pos, f_goal, c_pos, c_goal, goal_radius, f_arrived, c_arrived, f_new, c_new
    )
