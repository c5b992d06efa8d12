"""numba kernels of the social metrics: time to collision, near misses, the robot force
each pedestrian feels, and pedestrians brought to a stop.

Plain module-level functions over C-contiguous float64 arrays (docs/design.md): no
objects, no allocation inside the loops, no raising. Shapes: ``pos`` (T + 1, N, 2)
pedestrian positions, ``robot_xy`` (T + 1, 2), ``radius`` (N,). Velocities are the
displacement of the step that ended at a sample divided by dt (0 at sample 0): what
the positions say, so that a log without velocities (compact MCAP) gives the same
numbers bit for bit. ``enter`` (N,) int64 is the sample at which each pedestrian
appears (:meth:`srfm.sim.record.EpisodeRecord.enter_steps`): the samples before it
count for nothing.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from srfm.models._primitives import EPS
from srfm.models._robot_forces import robot_force, robot_strength
from srfm.models.params import SRFMKernelParams

__all__ = ["force_exposure", "min_time_to_collision", "near_miss_entries", "stopped_samples"]


@njit(cache=True)
def _step_velocity(pos: np.ndarray, k: int, i: int, dt: float) -> tuple[float, float]:
    """Velocity of agent i at sample k: (x_k − x_(k−1)) / dt; (0, 0) at k = 0."""
    if k == 0:
        return 0.0, 0.0
    return (pos[k, i, 0] - pos[k - 1, i, 0]) / dt, (pos[k, i, 1] - pos[k - 1, i, 1]) / dt


@njit(cache=True)
def min_time_to_collision(
    pos: np.ndarray,
    radius: np.ndarray,
    robot_xy: np.ndarray,
    robot_radius: float,
    end: int,
    dt: float,
    enter: np.ndarray,
    out: np.ndarray,
) -> None:
    """Smallest constant-velocity time to collision of each pedestrian with the robot.

    At every sample k = 0..end, with relative position p = x_i − x_r and relative
    velocity w = v_i − v_r (step velocities), the time t ≥ 0 at which |p + w t| = R =
    r_i + r_r first holds: 0 when already |p| ≤ R; none when the two do not approach
    (p·w ≥ 0) or the line misses the disc. ``out[i]`` gets the smallest over the
    samples, inf when there is none.
    """
    n = pos.shape[1]
    for i in range(n):
        out[i] = np.inf
    for k in range(end + 1):
        rvx = 0.0
        rvy = 0.0
        if k > 0:
            rvx = (robot_xy[k, 0] - robot_xy[k - 1, 0]) / dt
            rvy = (robot_xy[k, 1] - robot_xy[k - 1, 1]) / dt
        for i in range(n):
            if k < enter[i]:
                continue
            px = pos[k, i, 0] - robot_xy[k, 0]
            py = pos[k, i, 1] - robot_xy[k, 1]
            vx, vy = _step_velocity(pos, k, i, dt)
            wx = vx - rvx
            wy = vy - rvy
            r = radius[i] + robot_radius
            c = px * px + py * py - r * r
            if c <= 0.0:
                out[i] = 0.0
                continue
            b = px * wx + py * wy  # half of the usual b
            a = wx * wx + wy * wy
            if b >= 0.0 or a < EPS:
                continue
            disc = b * b - a * c
            if disc < 0.0:
                continue
            t = (-b - math.sqrt(disc)) / a
            if t < out[i]:
                out[i] = t


@njit(cache=True)
def near_miss_entries(
    pos: np.ndarray,
    radius: np.ndarray,
    robot_xy: np.ndarray,
    robot_radius: float,
    end: int,
    threshold: float,
    enter: np.ndarray,
    out: np.ndarray,
) -> None:
    """Times each pedestrian's clearance to the robot goes below ``threshold``.

    Clearance = centre distance − r_i − r_r. An entry is a sample k in 0..end with
    clearance < threshold where sample k − 1 had clearance ≥ threshold (or k = 0).
    ``out[i]`` (float) gets the count.
    """
    n = pos.shape[1]
    for i in range(n):
        out[i] = 0.0
        inside = False
        for k in range(enter[i], end + 1):
            dx = pos[k, i, 0] - robot_xy[k, 0]
            dy = pos[k, i, 1] - robot_xy[k, 1]
            clearance = math.sqrt(dx * dx + dy * dy) - radius[i] - robot_radius
            now = clearance < threshold
            if now and not inside:
                out[i] += 1.0
            inside = now


@njit(cache=True)
def force_exposure(
    pos: np.ndarray,
    goal: np.ndarray,
    radius: np.ndarray,
    robot_xy: np.ndarray,
    robot_radius: float,
    robot_moving: np.ndarray,
    params: SRFMKernelParams,
    dt: float,
    enter: np.ndarray,
    magnitude: np.ndarray,
    work: np.ndarray,
) -> None:
    """The magnitude of the SRFM robot term on each factual pedestrian at every step.

    For every sample k = 0..T − 1 (the state a step starts from) and pedestrian i:
    |f_robot|, the model's own robot force in the parameter set's form
    (:func:`srfm.models._robot_forces.robot_force`; the paper's A_r exp((r_i + r_r − d)
    / B_r) ψ(φ; λ_r) by default), with the pedestrian's velocity its step velocity, the
    heading the direction of that velocity, else of the goal, else none (ψ = 1), and
    the robot's velocity its step velocity while ``robot_moving[k]`` (the robot's
    episode goes on at k), else 0 (it stands where its episode ended); into
    ``magnitude[k, i]`` ((T, N)). ``work[i]`` gets Σ_k |f_k| |x_(k+1) − x_k|, the force
    integrated along the pedestrian's path (m²/s², J per kg). Before its entry sample a
    pedestrian gets 0.
    """
    steps = pos.shape[0] - 1
    n = pos.shape[1]
    body = np.zeros(5)
    body[2] = robot_radius
    on = robot_strength(params) != 0.0
    for i in range(n):
        work[i] = 0.0
    for k in range(steps):
        body[0] = robot_xy[k, 0]
        body[1] = robot_xy[k, 1]
        body[3] = 0.0
        body[4] = 0.0
        if k > 0 and robot_moving[k]:
            body[3] = (robot_xy[k, 0] - robot_xy[k - 1, 0]) / dt
            body[4] = (robot_xy[k, 1] - robot_xy[k - 1, 1]) / dt
        for i in range(n):
            px = pos[k, i, 0]
            py = pos[k, i, 1]
            mag = 0.0
            if on and k >= enter[i]:
                vx, vy = _step_velocity(pos, k, i, dt)
                speed = math.sqrt(vx * vx + vy * vy)
                has_h = True
                if speed > EPS:
                    hx = vx / speed
                    hy = vy / speed
                else:
                    hx = goal[k, i, 0] - px
                    hy = goal[k, i, 1] - py
                    gd = math.sqrt(hx * hx + hy * hy)
                    if gd > EPS:
                        hx /= gd
                        hy /= gd
                    else:
                        has_h = False
                fx, fy = robot_force(px, py, vx, vy, radius[i], hx, hy, has_h, body, params)
                mag = math.sqrt(fx * fx + fy * fy)
            magnitude[k, i] = mag
            dx = pos[k + 1, i, 0] - px
            dy = pos[k + 1, i, 1] - py
            work[i] += mag * math.sqrt(dx * dx + dy * dy)


@njit(cache=True)
def stopped_samples(
    factual: np.ndarray,
    counterfactual: np.ndarray,
    until: np.ndarray,
    dt: float,
    speed: float,
    out: np.ndarray,
) -> None:
    """Samples at which a pedestrian stood while its counterfactual twin walked.

    ``out[i]`` (float) counts the samples k = 1..until[i] − 1 (``until`` (N,) int64, the
    sample of the pedestrian's first arrival at its goal, or T + 1 if none) at which
    the factual step speed is below ``speed`` and the counterfactual twin's is not.
    """
    n = factual.shape[1]
    for i in range(n):
        count = 0.0
        for k in range(1, until[i]):
            fx, fy = _step_velocity(factual, k, i, dt)
            cx, cy = _step_velocity(counterfactual, k, i, dt)
            if math.sqrt(fx * fx + fy * fy) < speed and math.sqrt(cx * cx + cy * cy) >= speed:
                count += 1.0
        out[i] = count
