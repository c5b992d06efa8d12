"""The canonical trajectory representation every dataset adapter produces.

One :class:`Trajectories` holds one *scene*: every observed sample of every agent
(pedestrians and at most one robot) in one 2-D frame of reference, as a struct of
arrays sorted by time. A dataset is a list of scenes (one per source file or sequence);
scenes never share a frame of reference or a clock.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any, Final, Literal

import attrs
import numpy as np
from numpy.typing import NDArray

from srfm._text import plain
from srfm._validate import BOUNDS
from srfm.errors import DatasetError, DatasetWarning

__all__ = [
    "AGENT_KINDS",
    "FRAMES_OF_REFERENCE",
    "PEDESTRIAN",
    "ROBOT",
    "DatasetWarning",
    "Trajectories",
]

PEDESTRIAN: Final = "pedestrian"
ROBOT: Final = "robot"
AGENT_KINDS: Final = (PEDESTRIAN, ROBOT)
AgentKind = Literal["pedestrian", "robot"]

# "world": a fixed frame (odometry, a surveyed scene). "robot": the robot's own moving
# frame (x forward, y left), used when a robot-mounted dataset comes without odometry.
FRAMES_OF_REFERENCE: Final = ("world", "robot")
# Headings beyond one turn either way are not angles in radians (degrees, most likely).
MAX_YAW_RAD: Final = 2.0 * math.pi


def _read_only(arr: NDArray[Any]) -> NDArray[Any]:
    arr.setflags(write=False)
    return arr


@attrs.frozen(kw_only=True, eq=False)
class Trajectories:
    """Every sample of every agent of one scene, sorted by (frame, agent).

    Use :meth:`from_samples` to build one from unsorted samples; the constructor checks
    every invariant and raises :class:`srfm.DatasetError` naming the scene.

    Attributes:
        scene: the scene's name, unique within a dataset file (e.g. the source file's stem).
        agent_ids: (A,) agent ids, unique within the scene (e.g. ``"pedestrian:12"``).
        kinds: (A,) ``"pedestrian"`` or ``"robot"`` per agent; at most one robot.
        agent: (M,) int64 index into ``agent_ids`` of each sample.
        frame: (M,) int64 source frame number of each sample (JRDB frame, ETH/UCY frame
            id, NavWareSet row); strictly increasing in time.
        t_ns: (M,) int64 timestamp of each sample (ns), >= 0; all samples of one frame
            share it.
        xy: (M, 2) float64 position (m) in the scene's frame of reference.
        frame_of_reference: ``"world"`` or ``"robot"`` (robot-centred, moving).
        source: provenance, string to string (dataset, file, dt, ...).
        yaw: (M,) float64 heading (rad, counter-clockwise from +x) of each sample, NaN
            where the source gives none; None when no sample has one (NavWareSet gives
            the robot's). Finite values lie in [-2π, 2π].
    """

    scene: str
    agent_ids: tuple[str, ...]
    kinds: tuple[AgentKind, ...]
    agent: NDArray[np.int64]
    frame: NDArray[np.int64]
    t_ns: NDArray[np.int64]
    xy: NDArray[np.float64]
    frame_of_reference: str = "world"
    source: Mapping[str, str] = attrs.field(factory=dict)
    yaw: NDArray[np.float64] | None = None

    def __attrs_post_init__(self) -> None:
        where = f"scene {self.scene!r}"
        if not isinstance(self.scene, str) or not self.scene:
            raise DatasetError(f"scene name must be a non-empty string, got {plain(self.scene)}")
        if self.frame_of_reference not in FRAMES_OF_REFERENCE:
            raise DatasetError(
                f"{where}: frame_of_reference must be one of {FRAMES_OF_REFERENCE}, "
                f"got {plain(self.frame_of_reference)}"
            )
        ids = tuple(self.agent_ids)
        kinds = tuple(self.kinds)
        if len(ids) != len(kinds):
            raise DatasetError(f"{where}: {len(ids)} agent ids but {len(kinds)} kinds")
        for aid in ids:
            if not isinstance(aid, str) or not aid:
                raise DatasetError(
                    f"{where}: agent ids must be non-empty strings, got {plain(aid)}"
                )
        if len(set(ids)) != len(ids):
            dup = next(a for a in ids if ids.count(a) > 1)
            raise DatasetError(f"{where}: duplicate agent id {dup!r}")
        for aid, kind in zip(ids, kinds, strict=True):
            if kind not in AGENT_KINDS:
                raise DatasetError(
                    f"{where}: agent {aid!r} has kind {kind!r}; expected one of {AGENT_KINDS}"
                )
        if kinds.count(ROBOT) > 1:
            raise DatasetError(f"{where}: at most one robot per scene, got {kinds.count(ROBOT)}")
        source = dict(self.source)
        for key, value in source.items():
            if not isinstance(key, str) or not isinstance(value, str):
                raise DatasetError(
                    f"{where}: source metadata must map str to str, got {plain(key)}"
                )

        agent = _int_array(self.agent, "agent", where)
        frame = _int_array(self.frame, "frame", where)
        t_ns = _int_array(self.t_ns, "t_ns", where)
        try:
            xy = np.array(self.xy, dtype=np.float64, order="C")
        except (TypeError, ValueError):
            raise DatasetError(f"{where}: xy must be a numeric (M, 2) array") from None
        m = agent.shape[0]
        if frame.shape != (m,) or t_ns.shape != (m,) or xy.shape != (m, 2):
            raise DatasetError(
                f"{where}: sample arrays disagree in shape: agent {agent.shape}, frame "
                f"{frame.shape}, t_ns {t_ns.shape}, xy {xy.shape}"
            )
        if m and (agent.min() < 0 or agent.max() >= len(ids)):
            raise DatasetError(f"{where}: agent index out of range [0, {len(ids)})")
        if not np.all(np.isfinite(xy)):
            k = int(np.argwhere(~np.isfinite(xy))[0, 0])
            raise DatasetError(
                f"{where}: non-finite position {xy[k].tolist()} of agent {ids[agent[k]]!r} "
                f"at frame {int(frame[k])}"
            )
        lo, hi, unit = BOUNDS["coordinate"]
        outside = (xy < lo) | (xy > hi)
        if np.any(outside):
            k = int(np.argwhere(outside)[0, 0])
            raise DatasetError(
                f"{where}: position {xy[k].tolist()} of agent {ids[agent[k]]!r} at frame "
                f"{int(frame[k])} is outside [{lo:g}, {hi:g}] {unit} (the physical bound)"
            )
        if m and t_ns.min() < 0:
            k = int(np.argmin(t_ns))
            raise DatasetError(f"{where}: negative timestamp {int(t_ns[k])} ns at frame {frame[k]}")
        if m > 1:
            df = np.diff(frame)
            da = np.diff(agent)
            order_bad = (df < 0) | ((df == 0) & (da <= 0))
            if np.any(order_bad):
                k = int(np.argmax(order_bad)) + 1
                if df[k - 1] == 0 and da[k - 1] == 0:
                    raise DatasetError(
                        f"{where}: agent {ids[agent[k]]!r} appears twice in frame {int(frame[k])}"
                    )
                raise DatasetError(
                    f"{where}: samples not sorted by (frame, agent) at sample {k}; "
                    "use Trajectories.from_samples"
                )
            dt = np.diff(t_ns)
            same = df == 0
            if np.any(same & (dt != 0)):
                k = int(np.argmax(same & (dt != 0))) + 1
                raise DatasetError(
                    f"{where}: frame {int(frame[k])} has two timestamps "
                    f"({int(t_ns[k - 1])} and {int(t_ns[k])} ns)"
                )
            if np.any(~same & (dt <= 0)):
                k = int(np.argmax(~same & (dt <= 0))) + 1
                raise DatasetError(
                    f"{where}: timestamps go backwards: frame {int(frame[k])} at "
                    f"{int(t_ns[k])} ns is not after frame {int(frame[k - 1])} at "
                    f"{int(t_ns[k - 1])} ns"
                )
        if self.yaw is not None:
            object.__setattr__(self, "yaw", _read_only(_yaw_array(self.yaw, m, ids, agent, where)))
        object.__setattr__(self, "agent_ids", ids)
        object.__setattr__(self, "kinds", kinds)
        object.__setattr__(self, "agent", _read_only(agent))
        object.__setattr__(self, "frame", _read_only(frame))
        object.__setattr__(self, "t_ns", _read_only(t_ns))
        object.__setattr__(self, "xy", _read_only(xy))
        object.__setattr__(self, "source", source)

    @classmethod
    def from_samples(
        cls,
        *,
        scene: str,
        agent_ids: Any,
        kinds: Any,
        agent: Any,
        frame: Any,
        t_ns: Any,
        xy: Any,
        frame_of_reference: str = "world",
        source: Mapping[str, str] | None = None,
        yaw: Any = None,
    ) -> Trajectories:
        """Sort samples by (frame, agent) and build a validated :class:`Trajectories`.

        Args:
            scene: scene name.
            agent_ids: (A,) agent ids.
            kinds: (A,) agent kinds.
            agent: (M,) agent index of each sample.
            frame: (M,) source frame number of each sample.
            t_ns: (M,) timestamp of each sample (ns).
            xy: (M, 2) positions (m).
            frame_of_reference: ``"world"`` or ``"robot"``.
            source: provenance metadata.
            yaw: (M,) heading (rad) of each sample, NaN where unknown, or None.
        """
        where = f"scene {scene!r}"
        agent_a = _int_array(agent, "agent", where)
        frame_a = _int_array(frame, "frame", where)
        t_a = _int_array(t_ns, "t_ns", where)
        try:
            xy_a = np.asarray(xy, dtype=np.float64).reshape(-1, 2)
        except (TypeError, ValueError):
            raise DatasetError(f"{where}: xy must be a numeric (M, 2) array") from None
        if not agent_a.shape == frame_a.shape == t_a.shape == (xy_a.shape[0],):
            raise DatasetError(f"{where}: sample arrays disagree in length")
        order = np.lexsort((agent_a, frame_a))
        yaw_a = None
        if yaw is not None:
            yaw_a = _yaw_array(yaw, xy_a.shape[0], tuple(agent_ids), agent_a, where)[order]
        return cls(
            scene=scene,
            agent_ids=tuple(agent_ids),
            kinds=tuple(kinds),
            agent=agent_a[order],
            frame=frame_a[order],
            t_ns=t_a[order],
            xy=xy_a[order],
            frame_of_reference=frame_of_reference,
            source=dict(source or {}),
            yaw=yaw_a,
        )

    @property
    def n_agents(self) -> int:
        """Number of agents (pedestrians and robot)."""
        return len(self.agent_ids)

    @property
    def n_samples(self) -> int:
        """Number of (agent, frame) samples."""
        return int(self.agent.shape[0])

    @property
    def robot_index(self) -> int | None:
        """Index of the robot in ``agent_ids``, or None when the scene has no robot."""
        return self.kinds.index(ROBOT) if ROBOT in self.kinds else None

    def frames(self) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
        """The scene's distinct frames: (F,) frame numbers and (F,) timestamps (ns)."""
        if self.n_samples == 0:
            return np.zeros(0, np.int64), np.zeros(0, np.int64)
        first = np.ones(self.n_samples, dtype=bool)
        first[1:] = np.diff(self.frame) != 0
        return self.frame[first].copy(), self.t_ns[first].copy()

    def track(
        self, agent_id: str
    ) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.float64]]:
        """One agent's samples in time order: (L,) frames, (L,) timestamps (ns), (L, 2) xy (m)."""
        mask = self._mask(agent_id)
        return self.frame[mask].copy(), self.t_ns[mask].copy(), self.xy[mask].copy()

    def track_yaw(self, agent_id: str) -> NDArray[np.float64]:
        """One agent's headings (rad) in time order, (L,), NaN where unknown."""
        mask = self._mask(agent_id)
        if self.yaw is None:
            return np.full(int(mask.sum()), np.nan)
        return self.yaw[mask].copy()

    def _mask(self, agent_id: str) -> NDArray[np.bool_]:
        try:
            idx = self.agent_ids.index(agent_id)
        except ValueError:
            raise DatasetError(f"scene {self.scene!r}: no agent {agent_id!r}") from None
        return np.asarray(self.agent == idx)

    def summary(self) -> dict[str, Any]:
        """Headline numbers: agents, frames, duration, median frame interval and speed."""
        frames, times = self.frames()
        robot = self.robot_index
        peds = np.array([k == PEDESTRIAN for k in self.kinds], dtype=bool)
        dt = np.diff(times) * 1e-9
        speeds: list[NDArray[np.float64]] = []
        for a in np.flatnonzero(peds):
            mask = self.agent == a
            t = self.t_ns[mask] * 1e-9
            if t.shape[0] > 1:
                d = np.linalg.norm(np.diff(self.xy[mask], axis=0), axis=1)
                speeds.append(d / np.diff(t))
        all_speeds = np.concatenate(speeds) if speeds else np.zeros(0)
        return {
            "scene": self.scene,
            "frame_of_reference": self.frame_of_reference,
            "pedestrians": int(peds.sum()),
            "robot": robot is not None,
            "samples": self.n_samples,
            "frames": int(frames.shape[0]),
            "start_ns": int(times[0]) if times.size else None,
            "duration_s": float((times[-1] - times[0]) * 1e-9) if times.size else 0.0,
            "median_dt_s": float(np.median(dt)) if dt.size else None,
            "median_speed_mps": float(np.median(all_speeds)) if all_speeds.size else None,
            "source": dict(self.source),
        }

    def equals(self, other: Trajectories) -> bool:
        """True when both scenes hold the same agents, samples and metadata, bit for bit."""
        return (
            self.scene == other.scene
            and self.agent_ids == other.agent_ids
            and self.kinds == other.kinds
            and self.frame_of_reference == other.frame_of_reference
            and dict(self.source) == dict(other.source)
            and np.array_equal(self.agent, other.agent)
            and np.array_equal(self.frame, other.frame)
            and np.array_equal(self.t_ns, other.t_ns)
            and np.array_equal(self.xy, other.xy)
            and (self.yaw is None) == (other.yaw is None)
            and (
                self.yaw is None
                or other.yaw is None
                or np.array_equal(self.yaw, other.yaw, equal_nan=True)
            )
        )


def _yaw_array(
    value: Any, m: int, ids: tuple[str, ...], agent: NDArray[np.int64], where: str
) -> NDArray[np.float64]:
    """(M,) float64 headings: NaN (unknown) or finite within [-2π, 2π] rad."""
    try:
        yaw = np.array(value, dtype=np.float64, order="C").reshape(-1)
    except (TypeError, ValueError):
        raise DatasetError(f"{where}: yaw must be a numeric (M,) array") from None
    if yaw.shape != (m,):
        raise DatasetError(f"{where}: yaw has {yaw.shape[0]} values for {m} samples")
    bad = np.isinf(yaw) | (np.abs(np.nan_to_num(yaw)) > MAX_YAW_RAD)
    if np.any(bad):
        k = int(np.argmax(bad))
        who = ids[agent[k]] if 0 <= agent[k] < len(ids) else "?"
        raise DatasetError(
            f"{where}: yaw {yaw[k]!r} of agent {who!r} is outside [-2π, 2π] rad "
            "(a heading in degrees?)"
        )
    return yaw


def _int_array(value: Any, name: str, where: str) -> NDArray[np.int64]:
    arr = np.asarray(value)
    if arr.size == 0:
        return np.zeros(0, dtype=np.int64)
    if arr.ndim != 1 or not np.issubdtype(arr.dtype, np.integer):
        raise DatasetError(f"{where}: {name} must be a 1-D integer array, got dtype {arr.dtype}")
    return np.array(arr, dtype=np.int64, order="C")
