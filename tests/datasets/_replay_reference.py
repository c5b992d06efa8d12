"""The replay kernel as it was before issue 39 (part 5) narrowed it to bundles: its 24
arguments, the same loop. Only tests/datasets/test_replay_bundles.py uses it, to check
that the bundled kernel gives the same predictions byte for byte."""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from srfm.models._arrays import CrowdArrays, ForceContext, ObstacleArrays
from srfm.models._kernels import _agent_forces, exact_cut, integrate
from srfm.models.params import SRFMKernelParams


@njit(cache=False)
def replay_windows_24(
    sel: np.ndarray,
    w_agent: np.ndarray,
    w_frame0: np.ndarray,
    w_steps: np.ndarray,
    w_out: np.ndarray,
    w_pos: np.ndarray,
    w_vel: np.ndarray,
    w_goal: np.ndarray,
    w_v0: np.ndarray,
    w_vmax: np.ndarray,
    fr_off: np.ndarray,
    e_agent: np.ndarray,
    e_a: np.ndarray,
    e_b: np.ndarray,
    rb_on: np.ndarray,
    rb_a: np.ndarray,
    rb_b: np.ndarray,
    dt: np.ndarray,
    ped_radius: float,
    robot_radius: float,
    max_substep: float,
    params: SRFMKernelParams,
    use_robot: bool,
    out: np.ndarray,
) -> None:
    """Simulate the windows listed in ``sel``; write positions after each step into ``out``.

    Args:
        sel: (Q,) int64 indices of the windows to simulate.
        w_agent: (W,) global agent index of each window's pedestrian (skipped among the
            neighbours).
        w_frame0: (W,) global frame index of the window start.
        w_steps: (W,) number of observed steps to predict.
        w_out: (W,) row in ``out`` of each window's first predicted step.
        w_pos, w_vel, w_goal: (W, 2) initial position (m), velocity (m/s), goal (m).
        w_v0, w_vmax: (W,) desired speed and speed cap (m/s).
        fr_off: (G + 1,) offsets into the entry arrays of each frame's pedestrians.
        e_agent: (E,) global agent index of each entry.
        e_a, e_b: (E, 2) entry position at its frame and at the next frame (the same
            if the pedestrian is not observed there).
        rb_on: (G,) the robot is observed at this frame.
        rb_a, rb_b: (G, 2) robot position at the frame and at the next frame (the
            robot's velocity over the interval, (rb_b − rb_a) / dt, is what the
            anticipatory robot forms read).
        dt: (G,) time from each frame to the next (s); 0 after a scene's last frame.
        ped_radius, robot_radius: body radii (m).
        max_substep: longest integration step (s); each frame interval is split into
            ceil(dt / max_substep − 1e-6) equal substeps (the tolerance keeps a 15 Hz
            interval rounded to whole nanoseconds at one substep of 1/15 s).
        params: the SRFM parameters (``SRFMParams.for_kernels``), with the robot force in
            its form (``robot_form``).
        use_robot: apply the robot force (SRFM); False ignores the robot (SFM).
        out: (S, 2) predicted positions (m), written for the selected windows only.
    """
    max_nb = 0
    for g in range(fr_off.shape[0] - 1):
        max_nb = max(max_nb, fr_off[g + 1] - fr_off[g])
    n_buf = max_nb + 1
    pos = np.zeros((n_buf, 2))
    vel = np.zeros((n_buf, 2))
    goal = np.zeros((n_buf, 2))
    radius = np.full(n_buf, ped_radius)
    v0 = np.zeros(n_buf)
    vmax = np.zeros(1)
    force = np.zeros((1, 2))
    cut, ped = exact_cut()
    robot = np.zeros(5)  # x, y, radius, vx, vy
    robot[2] = robot_radius
    obstacles = ObstacleArrays(np.zeros((0, 4)), np.zeros((0, 3)), np.zeros((0, 2)), np.zeros(0))
    for q in range(sel.shape[0]):
        w = sel[q]
        me = w_agent[w]
        pos[0, 0] = w_pos[w, 0]
        pos[0, 1] = w_pos[w, 1]
        vel[0, 0] = w_vel[w, 0]
        vel[0, 1] = w_vel[w, 1]
        goal[0, 0] = w_goal[w, 0]
        goal[0, 1] = w_goal[w, 1]
        v0[0] = w_v0[w]
        vmax[0] = w_vmax[w]
        for s in range(w_steps[w]):
            g = w_frame0[w] + s
            n_sub = max(1, math.ceil(dt[g] / max_substep - 1e-6))
            h = dt[g] / n_sub
            robot_on = use_robot and rb_on[g]
            for u in range(n_sub):
                alpha = u / n_sub
                n = 1
                for e in range(fr_off[g], fr_off[g + 1]):
                    if e_agent[e] == me:
                        continue
                    pos[n, 0] = e_a[e, 0] + alpha * (e_b[e, 0] - e_a[e, 0])
                    pos[n, 1] = e_a[e, 1] + alpha * (e_b[e, 1] - e_a[e, 1])
                    n += 1
                if robot_on:
                    robot[0] = rb_a[g, 0] + alpha * (rb_b[g, 0] - rb_a[g, 0])
                    robot[1] = rb_a[g, 1] + alpha * (rb_b[g, 1] - rb_a[g, 1])
                    # the observed robot's velocity over the frame interval
                    robot[3] = (rb_b[g, 0] - rb_a[g, 0]) / dt[g] if dt[g] > 0.0 else 0.0
                    robot[4] = (rb_b[g, 1] - rb_a[g, 1]) / dt[g] if dt[g] > 0.0 else 0.0
                crowd = CrowdArrays(pos[:n], vel[:n], goal[:n], radius[:n], v0[:n], vmax)
                context = ForceContext(params, robot, robot_on, obstacles, cut)
                _agent_forces(0, 1, crowd, context, ped, force)  # (the total into force)
                integrate(pos[:1], vel[:1], force, vmax, h)
            out[w_out[w] + s, 0] = pos[0, 0]
            out[w_out[w] + s, 1] = pos[0, 1]
