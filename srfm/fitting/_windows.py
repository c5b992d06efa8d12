"""Prediction windows: the unit of parameter fitting and ADE evaluation.

A window is a stretch of one pedestrian's observed track: from its state at the window
start (sample k), the SRFM predicts the next H samples while every other pedestrian and
the robot move as observed. See ``docs/fitting.md`` for the exact definition.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Final, Literal, NamedTuple, get_args

import attrs
import numpy as np
from numpy.typing import NDArray

from srfm._text import plain
from srfm._validate import physical, positive, unit_interval
from srfm.datasets._trajectories import PEDESTRIAN, Trajectories
from srfm.errors import DatasetError, ParameterError

if TYPE_CHECKING:
    from srfm.fitting._kernels import ReplayBodies, ReplayScenes, ReplayWindows

__all__ = ["ALIGNS", "GOALS", "Align", "Goal", "WindowConfig", "Windows", "build_windows"]

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]

# Helbing & Molnár 1995: a pedestrian's top speed is about 1.3 times its desired speed.
VMAX_FACTOR: Final = 1.3

# Where windows start: every ``stride`` along a track, or once per encounter with the
# robot, ``lead`` before the closest approach.
Align = Literal["stride", "encounter"]
ALIGNS: Final[tuple[str, ...]] = get_args(Align)
# The goal of a window's pedestrian: the track's last position, or a point straight
# ahead along the initial velocity (nothing after the window start).
Goal = Literal["track_end", "heading"]
GOALS: Final[tuple[str, ...]] = get_args(Goal)


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


def _one_of(choices: tuple[str, ...]) -> Callable[[object, attrs.Attribute[str], str], None]:
    def check(inst: object, attribute: attrs.Attribute[str], value: str) -> None:
        if not isinstance(value, str) or value not in choices:
            raise ParameterError(
                f"{attribute.name} must be one of {', '.join(choices)}; got {plain(value)}"
            )

    return check


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
            speed a pedestrian walks at when unhindered; the median underestimates it
            wherever people slow down for others and near the goal (docs/fitting.md).
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
        align: where windows start. ``"stride"`` (default): every ``stride_s`` along
            each track segment. ``"encounter"``: one window per track segment whose
            closest centre distance to the robot (over the segment's samples with the
            robot observed) is at most ``interaction_radius_m``, starting ``lead_s``
            before that closest approach (the sample nearest to it), so that the
            avoidance happens inside the window; none when the segment has too few
            samples before or after (velocity span, horizon) or the start is slower
            than ``min_start_speed_mps``. ``stride_s`` is then not used.
        lead_s: for ``align="encounter"``: time from the window start to the closest
            approach (s); shorter than ``horizon_s``. Default 3 s
            (``docs/real_encounters.md``: people begin to steer away about 2.5–3.5 s
            before the closest approach).
        goal: the pedestrian's goal. ``"track_end"`` (default): the last observed
            position of the track (the same for every window of the track).
            ``"heading"``: the point ``goal_distance_m`` straight ahead of the window
            start along the initial velocity, the constant-velocity extrapolation of
            the pre-window heading; it uses nothing observed after the window start, so
            an avoidance inside the window cannot leak into it (the start position
            itself when the initial velocity is zero).
        goal_distance_m: for ``goal="heading"``: distance of the goal (m). Default
            10 m, beyond what a pedestrian walks in a window (4.8 s at 1.3 m/s is
            6.2 m), so the goal force does not slow the pedestrian down (it does
            within v0 · 1 s of the goal).
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
    align: str = attrs.field(default="stride", validator=_one_of(ALIGNS))
    lead_s: float = attrs.field(default=3.0, validator=_duration)
    goal: str = attrs.field(default="track_end", validator=_one_of(GOALS))
    goal_distance_m: float = attrs.field(default=10.0, validator=_length)

    def __attrs_post_init__(self) -> None:
        if self.align == "encounter" and self.lead_s >= self.horizon_s:
            raise ParameterError(
                f"lead_s ({self.lead_s:g} s) must be shorter than horizon_s "
                f"({self.horizon_s:g} s): the closest approach must lie inside the window"
            )


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

    def replay_bundles(self) -> tuple[ReplayWindows, ReplayScenes, ReplayBodies]:
        """The windows as the replay kernel takes them (the arrays themselves, no copy)."""
        from srfm.fitting._kernels import ReplayBodies, ReplayScenes, ReplayWindows

        return (
            ReplayWindows(
                self.agent,
                self.frame0,
                self.steps,
                self.out_row,
                self.pos,
                self.vel,
                self.goal,
                self.v0,
                self.vmax,
            ),
            ReplayScenes(
                self.fr_off,
                self.e_agent,
                self.e_a,
                self.e_b,
                self.rb_on,
                self.rb_a,
                self.rb_b,
                self.dt,
            ),
            ReplayBodies(
                float(self.config.ped_radius_m),
                float(self.config.robot_radius_m),
                float(self.config.max_substep_s),
            ),
        )

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


class _Window(NamedTuple):
    """One prediction window (global agent and frame indices; fields as in :class:`Windows`)."""

    agent: int
    scene: int
    frame0: int
    steps: int
    pos: FloatArray
    vel: FloatArray
    goal: FloatArray
    v0: float
    min_robot_distance: float
    observed: FloatArray
    step_time: FloatArray


class _SceneReplay(NamedTuple):
    """The replay data of one scene: per frame (F) and per pedestrian entry (E)."""

    fr_count: IntArray
    e_agent: IntArray
    e_a: FloatArray
    e_b: FloatArray
    rb_on: NDArray[np.bool_]
    rb_a: FloatArray
    rb_b: FloatArray
    dt: FloatArray


class _Clock(NamedTuple):
    """A scene's time base: the frame of every sample and the time of every frame."""

    fidx: IntArray  # (M,) index into the scene's frames of each sample
    t: FloatArray  # (F,) seconds since the first frame
    dt: FloatArray  # (F,) seconds to the next frame, 0 at the last


class _Track(NamedTuple):
    """One pedestrian's samples in a scene, in time order."""

    agent: int  # global agent index (over all scenes)
    scene: int  # index of the scene
    frame_offset: int  # global index of the scene's first frame
    frames: IntArray  # (L,) index into the scene's frames
    xy: FloatArray  # (L, 2) positions (m)
    t: FloatArray  # (L,) seconds since the scene's first frame


class _Cadence(NamedTuple):
    """The window spans of :class:`WindowConfig` in samples of one scene."""

    horizon: int
    stride: int
    velocity_span: int
    speed_span: int
    max_gap_s: float
    lead: int


def build_windows(scenes: Sequence[Trajectories], config: WindowConfig | None = None) -> Windows:
    """Cut every pedestrian track of ``scenes`` into prediction windows.

    Scene by scene: the time base, the robot and the pedestrians per frame (the replay
    data), then the windows of every pedestrian track; frame and agent indices are
    offset to be global over ``scenes``.

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
    windows: list[_Window] = []
    replays: list[_SceneReplay] = []
    g_off = 0
    a_off = 0
    for si, scene in enumerate(scenes):
        _check_world_frame(scene)
        clock = _clock(scene)
        replay = _scene_replay(scene, clock, a_off)
        replays.append(replay)
        windows.extend(_scene_windows(scene, si, clock, replay, config, g_off, a_off))
        g_off += clock.t.shape[0]
        a_off += scene.n_agents
    return _assemble(config, scenes, windows, replays)


def _check_world_frame(scene: Trajectories) -> None:
    if scene.frame_of_reference != "world":
        raise DatasetError(
            f"scene {scene.scene!r} is in the robot's moving frame (converted without "
            "odometry); fitting and ADE need world coordinates"
        )


def _clock(scene: Trajectories) -> _Clock:
    frames, times = scene.frames()
    n_frames = frames.shape[0]
    t = (times - (times[0] if n_frames else 0)).astype(np.float64) * 1e-9
    dt = np.zeros(n_frames)
    if n_frames > 1:
        dt[:-1] = np.diff(t)
    return _Clock(fidx=np.searchsorted(frames, scene.frame), t=t, dt=dt)


def _pedestrians(scene: Trajectories) -> NDArray[np.bool_]:
    """(A,) True for the scene's pedestrians."""
    return np.array([k == PEDESTRIAN for k in scene.kinds], dtype=bool)


def _scene_replay(scene: Trajectories, clock: _Clock, a_off: int) -> _SceneReplay:
    """The robot per frame (on, position, position at the next frame when on at both)
    and the pedestrian entries per frame (position, and at the next frame when the
    pedestrian is observed there, else the same position)."""
    n_frames = clock.t.shape[0]
    fidx = clock.fidx
    robot = scene.robot_index
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

    # Samples are sorted by frame, then agent.
    is_ped = _pedestrians(scene)[scene.agent] if scene.n_samples else np.zeros(0, dtype=bool)
    pf = fidx[is_ped]
    pa = scene.agent[is_ped]
    pxy = scene.xy[is_ped]
    by_agent = np.lexsort((pf, pa))
    nxt = pxy.copy()
    sa, sf = pa[by_agent], pf[by_agent]
    follows = (sa[1:] == sa[:-1]) & (sf[1:] == sf[:-1] + 1)
    nxt[by_agent[:-1][follows]] = pxy[by_agent[1:][follows]]
    return _SceneReplay(
        fr_count=np.bincount(pf, minlength=n_frames).astype(np.int64),
        e_agent=pa.astype(np.int64) + a_off,
        e_a=pxy,
        e_b=nxt,
        rb_on=on,
        rb_a=r_xy,
        rb_b=r_next,
        dt=clock.dt,
    )


def _scene_windows(
    scene: Trajectories,
    si: int,
    clock: _Clock,
    replay: _SceneReplay,
    config: WindowConfig,
    g_off: int,
    a_off: int,
) -> list[_Window]:
    """The windows of every pedestrian track of one scene (none with fewer than two
    frames), spans in samples of the scene's median frame interval."""
    if clock.t.shape[0] <= 1:
        return []
    dt_nom = float(np.median(np.diff(clock.t)))
    cadence = _Cadence(
        horizon=_samples(config.horizon_s, dt_nom),
        stride=_samples(config.stride_s, dt_nom),
        velocity_span=_samples(config.velocity_span_s, dt_nom),
        speed_span=_samples(config.speed_span_s, dt_nom),
        max_gap_s=config.max_gap_factor * dt_nom,
        lead=round(config.lead_s / dt_nom),
    )
    windows: list[_Window] = []
    for a in np.flatnonzero(_pedestrians(scene)):
        mask = scene.agent == a
        frames = clock.fidx[mask]
        track = _Track(
            agent=int(a) + a_off,
            scene=si,
            frame_offset=g_off,
            frames=frames,
            xy=scene.xy[mask],
            t=clock.t[frames],
        )
        windows.extend(_track_windows(track, replay, cadence, config))
    return windows


def _track_segments(tf: IntArray, tt: FloatArray, max_gap_s: float) -> list[tuple[int, int]]:
    """[lo, hi) sample ranges of a track between breaks: a missing frame or an interval
    longer than ``max_gap_s``."""
    breaks = np.flatnonzero((np.diff(tf) != 1) | (np.diff(tt) > max_gap_s)) + 1
    return list(
        zip(
            np.concatenate([[0], breaks]).tolist(),
            np.concatenate([breaks, [tf.shape[0]]]).tolist(),
            strict=True,
        )
    )


def _track_windows(
    track: _Track, replay: _SceneReplay, cadence: _Cadence, config: WindowConfig
) -> list[_Window]:
    """The windows of one track: in each segment, at the starts :func:`_starts` gives,
    with the velocity span before the start and the horizon after it inside the
    segment, and a start speed of at least ``config.min_start_speed_mps``."""
    tf, txy, tt = track.frames, track.xy, track.t
    segments = _track_segments(tf, tt, cadence.max_gap_s)
    speed0 = _desired_speed(txy, tt, segments, cadence.speed_span, config.speed_quantile)
    horizon = cadence.horizon
    m_v = cadence.velocity_span
    min_speed = config.min_start_speed_mps
    windows: list[_Window] = []
    for lo, hi in segments:
        for k in _starts(track, replay, cadence, config, lo, hi):
            v_k = (txy[k] - txy[k - m_v]) / (tt[k] - tt[k - m_v])
            if min_speed > 0.0 and math.hypot(v_k[0], v_k[1]) < min_speed:
                continue
            ks = slice(k + 1, k + horizon + 1)
            span = slice(k, k + horizon + 1)
            windows.append(
                _Window(
                    agent=track.agent,
                    scene=track.scene,
                    frame0=int(tf[k]) + track.frame_offset,
                    steps=horizon,
                    pos=txy[k],
                    vel=v_k,
                    goal=_goal(txy, k, v_k, config),
                    v0=speed0,
                    min_robot_distance=_min_robot_distance(txy[span], tf[span], replay),
                    observed=txy[ks],
                    step_time=tt[ks] - tt[k],
                )
            )
    return windows


def _starts(
    track: _Track, replay: _SceneReplay, cadence: _Cadence, config: WindowConfig, lo: int, hi: int
) -> range | list[int]:
    """Window starts (sample indices) in the segment [lo, hi): every ``stride`` samples
    with room for the velocity span and the horizon, or (``align="encounter"``) the one
    ``lead`` samples before the segment's closest approach to the robot when that is
    within the interaction radius and the window fits."""
    first, stop = lo + cadence.velocity_span, hi - cadence.horizon
    if config.align == "stride":
        return range(first, stop, cadence.stride)
    fr = track.frames[lo:hi]
    on = replay.rb_on[fr]
    if not np.any(on):
        return []
    d = np.linalg.norm(track.xy[lo:hi] - replay.rb_a[fr], axis=1)
    d[~on] = np.inf
    k_pass = lo + int(np.argmin(d))
    k = k_pass - cadence.lead
    if d[k_pass - lo] > config.interaction_radius_m or not first <= k < stop:
        return []
    return [k]


def _goal(txy: FloatArray, k: int, v_k: FloatArray, config: WindowConfig) -> FloatArray:
    """The goal of a window starting at sample k (``config.goal``)."""
    if config.goal == "track_end":
        goal: FloatArray = txy[-1]
        return goal
    speed = math.hypot(v_k[0], v_k[1])
    goal = txy[k] + v_k * (config.goal_distance_m / speed) if speed > 0.0 else txy[k].copy()
    return goal


def _min_robot_distance(xy: FloatArray, fr: IntArray, replay: _SceneReplay) -> float:
    """The closest centre distance (m) of the positions ``xy`` at frames ``fr`` to the
    robot at the frames it is on; inf when it is on at none (or there is no robot)."""
    on = replay.rb_on[fr]
    if not np.any(on):
        return math.inf
    d = np.linalg.norm(xy - replay.rb_a[fr], axis=1)
    return float(d[on].min())


def _assemble(
    config: WindowConfig,
    scenes: Sequence[Trajectories],
    windows: list[_Window],
    replays: list[_SceneReplay],
) -> Windows:
    """The :class:`Windows` of the windows and the replay data of every scene, in order."""
    steps = np.array([w.steps for w in windows], dtype=np.int64)
    v0 = np.array([w.v0 for w in windows], dtype=np.float64)
    mind = np.array([w.min_robot_distance for w in windows], dtype=np.float64)
    counts = (
        np.concatenate([r.fr_count for r in replays]) if replays else np.zeros(0, dtype=np.int64)
    )
    agent = np.array([w.agent for w in windows], dtype=np.int64)
    return Windows(
        config=config,
        scene_names=tuple(s.scene for s in scenes),
        agent=agent,
        track=agent.copy(),
        scene=np.array([w.scene for w in windows], dtype=np.int64),
        frame0=np.array([w.frame0 for w in windows], dtype=np.int64),
        steps=steps,
        out_row=(np.cumsum(steps) - steps).astype(np.int64),
        pos=_rows([w.pos for w in windows]),
        vel=_rows([w.vel for w in windows]),
        goal=_rows([w.goal for w in windows]),
        v0=v0,
        vmax=VMAX_FACTOR * v0,
        min_robot_distance=mind,
        interaction=mind <= config.interaction_radius_m,
        observed=_rows([w.observed for w in windows]),
        step_time=np.concatenate([w.step_time for w in windows]) if windows else np.zeros(0),
        fr_off=np.concatenate([[0], np.cumsum(counts)]).astype(np.int64),
        e_agent=(
            np.concatenate([r.e_agent for r in replays]).astype(np.int64)
            if replays
            else np.zeros(0, np.int64)
        ),
        e_a=_rows([r.e_a for r in replays]),
        e_b=_rows([r.e_b for r in replays]),
        rb_on=np.concatenate([r.rb_on for r in replays]) if replays else np.zeros(0, dtype=bool),
        rb_a=_rows([r.rb_a for r in replays]),
        rb_b=_rows([r.rb_b for r in replays]),
        dt=np.concatenate([r.dt for r in replays]) if replays else np.zeros(0),
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
