"""Prediction windows: the unit of parameter fitting and ADE evaluation.

A window is a stretch of one pedestrian's observed track: from its state at the window
start (sample k), the SRFM predicts the next H samples while every other pedestrian and
the robot move as observed. See ``docs/fitting.md`` for the exact definition.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Final

import attrs
import numpy as np
from numpy.typing import NDArray

from srfm._validate import physical, positive, unit_interval
from srfm.datasets._trajectories import PEDESTRIAN, Trajectories
from srfm.errors import DatasetError, ParameterError

__all__ = ["WindowConfig", "Windows", "build_windows"]

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]

# Helbing & Molnár 1995: a pedestrian's top speed is about 1.3 times its desired speed.
VMAX_FACTOR: Final = 1.3


def _pos(inst: object, attribute: attrs.Attribute[float], value: float) -> None:
    positive(value, attribute.name, ParameterError)


def _duration(inst: object, attribute: attrs.Attribute[float], value: float) -> None:
    physical(value, attribute.name, "duration", ParameterError, strict=True)


def _length(inst: object, attribute: attrs.Attribute[float], value: float) -> None:
    physical(value, attribute.name, "length", ParameterError, strict=True)


def _radius(inst: object, attribute: attrs.Attribute[float], value: float) -> None:
    physical(value, attribute.name, "radius", ParameterError, strict=True)


def _speed(inst: object, attribute: attrs.Attribute[float], value: float) -> None:
    physical(value, attribute.name, "speed", ParameterError, strict=False)


def _quantile(inst: object, attribute: attrs.Attribute[float], value: float) -> None:
    unit_interval(value, attribute.name, ParameterError)


@attrs.frozen(kw_only=True)
class WindowConfig:
    """How tracks are cut into prediction windows, and the bodies' sizes.

    Every length, radius and duration is checked against the physical bounds of
    :mod:`srfm._validate` (radii <= 1e3 m, durations <= 86400 s, ...).

    Attributes:
        horizon_s: prediction horizon (s); H = round(horizon_s / dt) samples per window,
            dt the scene's median frame interval. Default 4.8 s, the usual ETH/UCY
            horizon (12 samples of 0.4 s).
        stride_s: time between the starts of consecutive windows of one track (s),
            rounded to whole samples (at least one). Default 0.4 s: every ETH/UCY
            sample starts a window, as in the usual sliding-window benchmark.
        velocity_span_s: the initial velocity is the mean velocity over this span before
            the window start (rounded to whole samples, at least one).
        speed_span_s: the desired speed v0 of a track is the ``speed_quantile`` of its
            speeds measured over spans of this length (rounded to whole samples).
        speed_quantile: which quantile of those speeds is the desired speed. 0.8: the
            speed a pedestrian walks at when unhindered; the median underestimates it by
            10–15 % on SRFM-simulated tracks (slow-downs for others and near the goal).
        interaction_radius_m: a window is an interaction window when the pedestrian
            comes within this centre distance of the robot at any of its samples
            (the paper: 3 m); otherwise it is a non-interaction window.
        ped_radius_m: pedestrian radius r_i (m), as in the simulator (0.3 m).
        robot_radius_m: robot radius r_r (m), as in the simulator (0.2 m).
        max_substep_s: longest integration step (s); frame intervals are split into
            equal substeps no longer than this (1/15 s, the simulator's step).
        max_gap_factor: an interval longer than this many median frame intervals
            breaks a track (a detection gap).
        min_start_speed_mps: a window starts only where the initial velocity's
            magnitude is at least this (m/s). 0 (default) keeps every window; the
            NavWareSet protocol (``docs/fitting.md``) uses 0.3 m/s to leave out windows
            that start while the pedestrian waits for the experimenter's cue, which no
            force model can time.
    """

    horizon_s: float = attrs.field(default=4.8, validator=_duration)
    stride_s: float = attrs.field(default=0.4, validator=_duration)
    velocity_span_s: float = attrs.field(default=0.4, validator=_duration)
    speed_span_s: float = attrs.field(default=1.0, validator=_duration)
    speed_quantile: float = attrs.field(default=0.8, validator=_quantile)
    interaction_radius_m: float = attrs.field(default=3.0, validator=_length)
    ped_radius_m: float = attrs.field(default=0.3, validator=_radius)
    robot_radius_m: float = attrs.field(default=0.2, validator=_radius)
    max_substep_s: float = attrs.field(default=1.0 / 15.0, validator=_duration)
    max_gap_factor: float = attrs.field(default=1.5, validator=_pos)
    min_start_speed_mps: float = attrs.field(default=0.0, validator=_speed)


@attrs.frozen(kw_only=True, eq=False)
class Windows:
    """Every prediction window of a set of scenes, with the replay data the kernel needs.

    Per window (W): ``agent``, ``track`` (global track id), ``scene`` (index into
    ``scene_names``), ``frame0``, ``steps``, ``out_row`` (first row in the step arrays),
    ``pos``/``vel``/``goal`` (W, 2), ``v0``/``vmax`` (W,), ``min_robot_distance`` (W,; inf
    without a robot) and ``interaction`` (W,). Per predicted step (S): ``observed`` (S, 2)
    and ``step_time`` (S,) seconds since the window start. Per frame (G): ``fr_off``,
    ``rb_on``, ``rb_a``, ``rb_b``, ``dt``; per neighbour entry (E): ``e_agent``, ``e_a``,
    ``e_b`` (see :func:`srfm.fitting._kernels.replay_windows`).
    """

    config: WindowConfig
    scene_names: tuple[str, ...]
    agent: IntArray
    track: IntArray
    scene: IntArray
    frame0: IntArray
    steps: IntArray
    out_row: IntArray
    pos: FloatArray
    vel: FloatArray
    goal: FloatArray
    v0: FloatArray
    vmax: FloatArray
    min_robot_distance: FloatArray
    interaction: NDArray[np.bool_]
    observed: FloatArray
    step_time: FloatArray
    fr_off: IntArray
    e_agent: IntArray
    e_a: FloatArray
    e_b: FloatArray
    rb_on: NDArray[np.bool_]
    rb_a: FloatArray
    rb_b: FloatArray
    dt: FloatArray

    @property
    def n_windows(self) -> int:
        """Number of windows W."""
        return int(self.agent.shape[0])

    def select(self, interaction: bool | None) -> IntArray:
        """Indices of the interaction (True), non-interaction (False) or all (None) windows."""
        if interaction is None:
            return np.arange(self.n_windows, dtype=np.int64)
        return np.flatnonzero(self.interaction == interaction).astype(np.int64)

    def rows(self, sel: IntArray) -> IntArray:
        """Step-array rows of the windows in ``sel``, window by window."""
        if sel.size == 0:
            return np.zeros(0, dtype=np.int64)
        steps = self.steps[sel]
        starts = np.repeat(self.out_row[sel], steps)
        within = np.arange(int(steps.sum())) - np.repeat(np.cumsum(steps) - steps, steps)
        return (starts + within).astype(np.int64)


def _samples(span_s: float, dt: float) -> int:
    return max(1, round(span_s / dt))


def build_windows(scenes: Sequence[Trajectories], config: WindowConfig | None = None) -> Windows:
    """Cut every pedestrian track of ``scenes`` into prediction windows.

    Args:
        scenes: scenes in a world frame (a robot-frame scene is an error: its frame
            moves with the robot, so the model's dynamics do not hold in it).
        config: windowing and body sizes; defaults when omitted.

    Returns:
        The windows and the replay data of every frame.

    Raises:
        DatasetError: a scene in the robot's frame.
    """
    config = config or WindowConfig()
    win: dict[str, list[object]] = {
        k: []
        for k in (
            "agent",
            "track",
            "scene",
            "frame0",
            "steps",
            "pos",
            "vel",
            "goal",
            "v0",
            "mind",
            "obs",
            "tobs",
        )
    }
    fr_counts: list[IntArray] = []
    e_agent: list[IntArray] = []
    e_a: list[FloatArray] = []
    e_b: list[FloatArray] = []
    rb_on: list[NDArray[np.bool_]] = []
    rb_a: list[FloatArray] = []
    rb_b: list[FloatArray] = []
    dts: list[FloatArray] = []
    g_off = 0
    a_off = 0
    for si, scene in enumerate(scenes):
        if scene.frame_of_reference != "world":
            raise DatasetError(
                f"scene {scene.scene!r} is in the robot's moving frame (converted without "
                "odometry); fitting and ADE need world coordinates"
            )
        frames, times = scene.frames()
        n_frames = frames.shape[0]
        t = (times - (times[0] if n_frames else 0)).astype(np.float64) * 1e-9
        fidx = np.searchsorted(frames, scene.frame)
        dt = np.zeros(n_frames)
        if n_frames > 1:
            dt[:-1] = np.diff(t)
        robot = scene.robot_index
        ped = np.array([k == PEDESTRIAN for k in scene.kinds], dtype=bool)
        is_ped = ped[scene.agent] if scene.n_samples else np.zeros(0, dtype=bool)

        # Robot per frame.
        on = np.zeros(n_frames, dtype=bool)
        r_xy = np.zeros((n_frames, 2))
        if robot is not None:
            rmask = scene.agent == robot
            on[fidx[rmask]] = True
            r_xy[fidx[rmask]] = scene.xy[rmask]
        r_next = r_xy.copy()
        if n_frames > 1:
            both = on[:-1] & on[1:]
            r_next[:-1][both] = r_xy[1:][both]
        rb_on.append(on)
        rb_a.append(r_xy)
        rb_b.append(r_next)
        dts.append(dt)

        # Pedestrian entries per frame (samples are sorted by frame, then agent).
        pf = fidx[is_ped]
        pa = scene.agent[is_ped]
        pxy = scene.xy[is_ped]
        fr_counts.append(np.bincount(pf, minlength=n_frames).astype(np.int64))
        # Position of the same pedestrian at the next frame, if observed there.
        by_agent = np.lexsort((pf, pa))
        nxt = pxy.copy()
        sa, sf = pa[by_agent], pf[by_agent]
        follows = (sa[1:] == sa[:-1]) & (sf[1:] == sf[:-1] + 1)
        nxt[by_agent[:-1][follows]] = pxy[by_agent[1:][follows]]
        e_agent.append(pa.astype(np.int64) + a_off)
        e_a.append(pxy)
        e_b.append(nxt)

        # Windows of every pedestrian track.
        if n_frames > 1:
            dt_nom = float(np.median(np.diff(t)))
            horizon = _samples(config.horizon_s, dt_nom)
            stride = _samples(config.stride_s, dt_nom)
            m_v = _samples(config.velocity_span_s, dt_nom)
            m_s = _samples(config.speed_span_s, dt_nom)
            max_gap = config.max_gap_factor * dt_nom
            for a in np.flatnonzero(ped):
                mask = scene.agent == a
                tf = fidx[mask]
                txy = scene.xy[mask]
                tt = t[tf]
                breaks = np.flatnonzero((np.diff(tf) != 1) | (np.diff(tt) > max_gap)) + 1
                seg_bounds = list(
                    zip(
                        np.concatenate([[0], breaks]).tolist(),
                        np.concatenate([breaks, [tf.shape[0]]]).tolist(),
                        strict=True,
                    )
                )
                speed0 = _desired_speed(txy, tt, seg_bounds, m_s, config.speed_quantile)
                goal = txy[-1]
                for lo, hi in seg_bounds:
                    for k in range(lo + m_v, hi - horizon, stride):
                        v_k = (txy[k] - txy[k - m_v]) / (tt[k] - tt[k - m_v])
                        if config.min_start_speed_mps > 0.0 and (
                            math.hypot(v_k[0], v_k[1]) < config.min_start_speed_mps
                        ):
                            continue
                        ks = slice(k + 1, k + horizon + 1)
                        win["agent"].append(int(a) + a_off)
                        win["track"].append(int(a) + a_off)
                        win["scene"].append(si)
                        win["frame0"].append(int(tf[k]) + g_off)
                        win["steps"].append(horizon)
                        win["pos"].append(txy[k])
                        win["vel"].append(v_k)
                        win["goal"].append(goal)
                        win["v0"].append(speed0)
                        win["obs"].append(txy[ks])
                        win["tobs"].append(tt[ks] - tt[k])
                        fr = tf[k : k + horizon + 1]
                        if robot is not None and np.any(on[fr]):
                            d = np.linalg.norm(txy[k : k + horizon + 1] - r_xy[fr], axis=1)
                            win["mind"].append(float(d[on[fr]].min()))
                        else:
                            win["mind"].append(math.inf)
        g_off += n_frames
        a_off += scene.n_agents

    steps = np.array(win["steps"], dtype=np.int64)
    v0 = np.array(win["v0"], dtype=np.float64)
    mind = np.array(win["mind"], dtype=np.float64)
    counts = np.concatenate(fr_counts) if fr_counts else np.zeros(0, dtype=np.int64)
    return Windows(
        config=config,
        scene_names=tuple(s.scene for s in scenes),
        agent=np.array(win["agent"], dtype=np.int64),
        track=np.array(win["track"], dtype=np.int64),
        scene=np.array(win["scene"], dtype=np.int64),
        frame0=np.array(win["frame0"], dtype=np.int64),
        steps=steps,
        out_row=(np.cumsum(steps) - steps).astype(np.int64),
        pos=_rows(win["pos"]),
        vel=_rows(win["vel"]),
        goal=_rows(win["goal"]),
        v0=v0,
        vmax=VMAX_FACTOR * v0,
        min_robot_distance=mind,
        interaction=mind <= config.interaction_radius_m,
        observed=_rows(win["obs"]),
        step_time=np.array(
            [x for block in win["tobs"] for x in np.asarray(block).ravel()], dtype=np.float64
        ),
        fr_off=np.concatenate([[0], np.cumsum(counts)]).astype(np.int64),
        e_agent=np.concatenate(e_agent).astype(np.int64) if e_agent else np.zeros(0, np.int64),
        e_a=_rows(e_a),
        e_b=_rows(e_b),
        rb_on=np.concatenate(rb_on) if rb_on else np.zeros(0, dtype=bool),
        rb_a=_rows(rb_a),
        rb_b=_rows(rb_b),
        dt=np.concatenate(dts) if dts else np.zeros(0),
    )


def _rows(parts: Sequence[object]) -> FloatArray:
    """Stack points or (k, 2) blocks into one C-contiguous (n, 2) float64 array."""
    if not parts:
        return np.zeros((0, 2))
    return np.ascontiguousarray(
        np.concatenate([np.asarray(p, dtype=np.float64).reshape(-1, 2) for p in parts])
    )


def _desired_speed(
    xy: FloatArray, t: FloatArray, segments: list[tuple[int, int]], span: int, quantile: float
) -> float:
    """The ``quantile`` of the speeds (m/s) over ``span``-sample displacements within the
    track's segments (single-sample displacements for segments shorter than that)."""
    speeds: list[FloatArray] = []
    for lo, hi in segments:
        m = span if hi - lo > span else 1
        if hi - lo > m:
            d = np.linalg.norm(xy[lo + m : hi] - xy[lo : hi - m], axis=1)
            speeds.append(d / (t[lo + m : hi] - t[lo : hi - m]))
    if not speeds:
        return 0.0
    return float(np.quantile(np.concatenate(speeds), quantile))
