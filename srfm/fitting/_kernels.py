"""numba kernel that replays observed scenes around one simulated pedestrian per window.

For every prediction window the kernel simulates one pedestrian with the SRFM from its
observed state at the window start, while its neighbours and the robot move exactly as
observed (linearly interpolated between observed frames). It reuses the model's own
force function (:func:`srfm.models._kernels._agent_forces`) and integrator, so a fitted
parameter set means the same thing in the simulator.

Not cached on disk: numba's cache is keyed on this file only, so a change of the force
kernels in ``srfm/models/_kernels.py`` (or of the primitives in
``srfm/models/_primitives.py``) would silently keep stale physics here. The
kernel compiles in a few seconds once per process.

Shapes: W windows, S = Σ steps of all windows, G frames of all scenes, E neighbour
entries (one per pedestrian per frame). The kernel takes its data in three bundles, as
the crowd kernels do: :class:`ReplayWindows` (per window), :class:`ReplayScenes` (per
frame and neighbour entry) and :class:`ReplayBodies` (radii and the substep);
:meth:`srfm.fitting.Windows.replay_bundles` builds them.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from srfm.models._arrays import CrowdArrays, ForceContext, ObstacleArrays
from srfm.models._kernels import _agent_forces, exact_cut, integrate
from srfm.models.params import SRFMKernelParams


class ReplayWindows(NamedTuple):
    """The windows to replay, per window (W).

    Attributes:
        agent: (W,) int64 global agent index of each window's pedestrian (skipped among
            the neighbours).
        frame0: (W,) int64 global frame index of the window start.
        steps: (W,) int64 number of observed steps to predict.
        out_row: (W,) int64 row in ``out`` of each window's first predicted step.
        pos, vel, goal: (W, 2) initial position (m), velocity (m/s), goal (m).
        v0, vmax: (W,) desired speed and speed cap (m/s).
    """

    agent: np.ndarray
    frame0: np.ndarray
    steps: np.ndarray
    out_row: np.ndarray
    pos: np.ndarray
    vel: np.ndarray
    goal: np.ndarray
    v0: np.ndarray
    vmax: np.ndarray


class ReplayScenes(NamedTuple):
    """What the replayed pedestrian meets, per frame (G) and neighbour entry (E).

    Attributes:
        fr_off: (G + 1,) int64 offsets into the entry arrays of each frame's pedestrians.
        e_agent: (E,) int64 global agent index of each entry.
        e_a, e_b: (E, 2) entry position at its frame and at the next frame (the same
            if the pedestrian is not observed there).
        rb_on: (G,) bool, the robot is observed at this frame.
        rb_a, rb_b: (G, 2) robot position at the frame and at the next frame (the
            robot's velocity over the interval, (rb_b − rb_a) / dt, is what the
            anticipatory robot forms read).
        dt: (G,) time from each frame to the next (s); 0 after a scene's last frame.
    """

    fr_off: np.ndarray
    e_agent: np.ndarray
    e_a: np.ndarray
    e_b: np.ndarray
    rb_on: np.ndarray
    rb_a: np.ndarray
    rb_b: np.ndarray
    dt: np.ndarray


class ReplayBodies(NamedTuple):
    """Body radii and the integration step of the replay.

    Attributes:
        ped_radius, robot_radius: body radii (m).
        max_substep: longest integration step (s); each frame interval is split into
            ceil(dt / max_substep − 1e-6) equal substeps (the tolerance keeps a 15 Hz
            interval rounded to whole nanoseconds at one substep of 1/15 s).
    """

    ped_radius: float
    robot_radius: float
    max_substep: float


@njit(cache=False)
def replay_windows(
    sel: np.ndarray,
    windows: ReplayWindows,
    scenes: ReplayScenes,
    bodies: ReplayBodies,
    params: SRFMKernelParams,
    use_robot: bool,
    out: np.ndarray,
) -> None:
    """Simulate the windows listed in ``sel``; write positions after each step into ``out``.

    Args:
        sel: (Q,) int64 indices of the windows to simulate.
        windows: the windows (:class:`ReplayWindows`).
        scenes: their neighbours and robot (:class:`ReplayScenes`).
        bodies: radii and substep (:class:`ReplayBodies`).
        params: the SRFM parameters (``SRFMParams.for_kernels``), with the robot force in
            its form (``robot_form``).
        use_robot: apply the robot force (SRFM); False ignores the robot (SFM).
        out: (S, 2) predicted positions (m), written for the selected windows only.
    """
    fr_off = scenes.fr_off
    e_agent = scenes.e_agent
    e_a = scenes.e_a
    e_b = scenes.e_b
    rb_on = scenes.rb_on
    rb_a = scenes.rb_a
    rb_b = scenes.rb_b
    dt = scenes.dt
    max_substep = bodies.max_substep
    max_nb = 0
    for g in range(fr_off.shape[0] - 1):
        max_nb = max(max_nb, fr_off[g + 1] - fr_off[g])
    n_buf = max_nb + 1
    pos = np.zeros((n_buf, 2))
    vel = np.zeros((n_buf, 2))
    goal = np.zeros((n_buf, 2))
    radius = np.full(n_buf, bodies.ped_radius)
    v0 = np.zeros(n_buf)
    vmax = np.zeros(1)
    force = np.zeros((1, 2))
    cut, ped = exact_cut()
    robot = np.zeros(5)  # x, y, radius, vx, vy
    robot[2] = bodies.robot_radius
    obstacles = ObstacleArrays(np.zeros((0, 4)), np.zeros((0, 3)), np.zeros((0, 2)), np.zeros(0))
    for q in range(sel.shape[0]):
        w = sel[q]
        me = windows.agent[w]
        pos[0, 0] = windows.pos[w, 0]
        pos[0, 1] = windows.pos[w, 1]
        vel[0, 0] = windows.vel[w, 0]
        vel[0, 1] = windows.vel[w, 1]
        goal[0, 0] = windows.goal[w, 0]
        goal[0, 1] = windows.goal[w, 1]
        v0[0] = windows.v0[w]
        vmax[0] = windows.vmax[w]
        for s in range(windows.steps[w]):
            g = windows.frame0[w] + s
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
            out[windows.out_row[w] + s, 0] = pos[0, 0]
            out[windows.out_row[w] + s, 1] = pos[0, 1]
