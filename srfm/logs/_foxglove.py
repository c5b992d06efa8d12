"""Foxglove ``SceneUpdate`` messages that draw a twin episode from above.

The messages are built and encoded by the Foxglove SDK (``foxglove-sdk``,
:mod:`foxglove.messages`): protobuf messages of Foxglove's official schema, whose
``FileDescriptorSet`` the SDK also provides (:func:`scene_schema`). Entities on the
``/foxglove/scene`` topic, all in frame ``world`` (metres, z up):

- ``world`` (once, at time 0): the world bounds as a line loop, walls as line
  segments, pillars as grey cylinders;
- ``robot_goal`` and ``robot_path`` (once): the robot's goal (a green disc and a label)
  and its whole path (a red line through its positions every 10 cm of travel);
- ``goals`` (at time 0 and whenever a goal changes): the factual pedestrians' goals
  (yellow discs);
- ``pedestrians``, ``counterfactual`` and ``robot`` (every ``stride`` samples and at the
  last one): factual pedestrians as blue discs (in full logs with velocity arrows,
  length = 1 s of motion), their counterfactual twins as translucent grey discs (the
  ghosts; drawn where they are apart from their factual twin, elsewhere the blue disc
  would cover them), the robot as a red disc with a heading arrow.

Positions are rounded to 1 cm, arrow directions to 5 degrees and lengths to 5 cm, so
that primitives can be reused (an agent standing still costs a dictionary look-up
rather than three SDK objects): the scene is for looking at, the exact numbers are on
the ``/srfm/...`` channels.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, Final

import numpy as np
from numpy.typing import NDArray

from srfm.models.state import Obstacles
from srfm.sim.record import EpisodeRecord

if TYPE_CHECKING:
    from foxglove.messages import Color, Pose, Quaternion, SceneEntity, Timestamp, Vector3

__all__ = ["SCENE_TOPIC", "scene_messages", "scene_schema"]

FloatArray = NDArray[np.float64]
RGBA = tuple[float, float, float, float]

SCENE_TOPIC: Final = "/foxglove/scene"
FRAME_ID: Final = "world"

_BLUE: Final[RGBA] = (0.16, 0.43, 0.86, 1.0)
_GHOST: Final[RGBA] = (0.55, 0.55, 0.55, 0.45)
_RED: Final[RGBA] = (0.86, 0.2, 0.16, 1.0)
_GREEN: Final[RGBA] = (0.2, 0.7, 0.3, 0.9)
_YELLOW: Final[RGBA] = (0.95, 0.75, 0.1, 1.0)
_GREY: Final[RGBA] = (0.3, 0.3, 0.3, 1.0)

_YAW_STEPS: Final = 72  # arrow directions in 5-degree steps
_LENGTH_STEP: Final = 0.05
_PED_HEIGHT: Final = 0.4
_GHOST_HEIGHT: Final = 0.36
_ROBOT_HEIGHT: Final = 0.5
_PATH_SPACING: Final = 0.1  # m between the drawn points of the robot's path


def scene_schema() -> tuple[str, str, bytes]:
    """(name, encoding, data) of Foxglove's ``SceneUpdate`` schema, from the SDK:
    ``("foxglove.SceneUpdate", "protobuf", <FileDescriptorSet>)``."""
    from foxglove.messages import SceneUpdate

    schema = SceneUpdate.get_schema()
    return schema.name, schema.encoding, schema.data


def _color(rgba: RGBA) -> Color:
    from foxglove.messages import Color

    r, g, b, a = rgba
    return Color(r=r, g=g, b=b, a=a)


class _Builder:
    """Primitives of one episode's scene; shared sub-messages (colours, sizes,
    orientations) are built once."""

    def __init__(self) -> None:
        from foxglove import messages as fm

        self.fm = fm
        self.identity = fm.Quaternion(x=0.0, y=0.0, z=0.0, w=1.0)
        self.colors = {rgba: _color(rgba) for rgba in (_BLUE, _GHOST, _RED, _GREEN, _YELLOW, _GREY)}
        self._sizes: dict[float, dict[float, Vector3]] = {}  # by height, then diameter
        self._yaws: dict[int, Quaternion] = {}
        # Primitives by rounded position and style: standing agents (most of an
        # episode, once pedestrians have arrived) reuse the same objects.
        self._primitives: dict[tuple[Any, ...], Any] = {}
        self._poses: dict[tuple[int, int, float, int], Pose] = {}
        self._discs: dict[tuple[float, RGBA, float], dict[tuple[int, int, float], Any]] = {}
        self._stamp: tuple[int, Timestamp] = (0, fm.Timestamp(sec=0, nsec=0))

    def yaw(self, step: int) -> Quaternion:
        """The rotation about z by ``step`` × 5 degrees."""
        step %= _YAW_STEPS
        if step not in self._yaws:
            half = math.pi * step / _YAW_STEPS
            self._yaws[step] = self.fm.Quaternion(x=0.0, y=0.0, z=math.sin(half), w=math.cos(half))
        return self._yaws[step]

    def pose(self, x: int, y: int, z: float, yaw_step: int = 0) -> Pose:
        """The pose at (x, y) in whole cm, height ``z`` m, turned by ``yaw_step`` × 5
        degrees (shared by every primitive there: a pedestrian and its ghost twin, while
        they coincide, and an agent standing still)."""
        key = (x, y, z, yaw_step)
        pose = self._poses.get(key)
        if pose is None:
            fm = self.fm
            pose = self._poses[key] = fm.Pose(
                position=fm.Vector3(x=x / 100, y=y / 100, z=z), orientation=self.yaw(yaw_step)
            )
        return pose

    def discs(
        self,
        xs: list[int],
        ys: list[int],
        diameters: list[float],
        height: float,
        rgba: RGBA,
        centre: float | None = None,
    ) -> list[Any]:
        """Upright cylinders of ``height`` at (x, y) in whole cm, centred at height
        ``centre`` (default: standing on the ground).

        The hot loop of a scene (about 600 discs a compact episode, most of them at a
        new position): no method call per disc but the SDK's constructors, and the discs
        of one style (height, colour, centre) are cached by (x, y, diameter) in a
        dictionary of their own, so that an agent standing still costs a look-up."""
        z = height / 2 if centre is None else centre
        style = (height, rgba, z)
        cache = self._discs.get(style)
        if cache is None:
            cache = self._discs[style] = {}
        sizes = self._sizes.setdefault(height, {})
        fm = self.fm
        cylinder, pose, vector = fm.CylinderPrimitive, fm.Pose, fm.Vector3
        color = self.colors[rgba]
        flat = self.yaw(0)
        out = []
        for x, y, d in zip(xs, ys, diameters, strict=False):
            key = (x, y, d)
            disc = cache.get(key)
            if disc is None:
                size = sizes.get(d)
                if size is None:
                    size = sizes[d] = vector(x=d, y=d, z=height)
                disc = cache[key] = cylinder(
                    pose=pose(position=vector(x=x / 100, y=y / 100, z=z), orientation=flat),
                    size=size,
                    bottom_scale=1.0,
                    top_scale=1.0,
                    color=color,
                )
            out.append(disc)
        return out

    def arrows(
        self,
        xs: list[int],
        ys: list[int],
        yaw_steps: list[int],
        length_steps: list[int],
        z: float,
        rgba: RGBA,
    ) -> list[Any]:
        """Arrows from (x, y) in whole cm at height ``z``, pointing ``yaw_steps`` × 5
        degrees from the x axis, ``length_steps`` × 5 cm long (none when 0)."""
        arrow_type = self.fm.ArrowPrimitive
        cache = self._primitives
        color = self.colors[rgba]
        out = []
        for x, y, k, n in zip(xs, ys, yaw_steps, length_steps, strict=True):
            if n <= 0:
                continue
            key = (x, y, k, n, z, rgba)
            arrow = cache.get(key)
            if arrow is None:
                arrow = cache[key] = arrow_type(
                    pose=self.pose(x, y, z, k),
                    shaft_length=n * _LENGTH_STEP,
                    shaft_diameter=0.04,
                    head_length=0.12,
                    head_diameter=0.12,
                    color=color,
                )
            out.append(arrow)
        return out

    def line(
        self, kind: str, points: list[tuple[float, float]], thickness: float, rgba: RGBA
    ) -> Any:
        fm = self.fm
        return fm.LinePrimitive(
            type=getattr(fm.LinePrimitiveLineType, kind),
            pose=fm.Pose(position=fm.Vector3(x=0.0, y=0.0, z=0.0), orientation=self.identity),
            thickness=thickness,
            scale_invariant=False,
            points=[fm.Point3(x=x, y=y, z=0.01) for x, y in points],
            color=self.colors[rgba],
        )

    def entity(
        self,
        t_ns: int,
        name: str,
        *,
        arrows: list[Any] | None = None,
        cylinders: list[Any] | None = None,
        lines: list[Any] | None = None,
        texts: list[Any] | None = None,
    ) -> SceneEntity:
        if self._stamp[0] != t_ns:  # the entities of one message share their timestamp
            sec, nsec = divmod(t_ns, 1_000_000_000)
            self._stamp = (t_ns, self.fm.Timestamp(sec=sec, nsec=nsec))
        return self.fm.SceneEntity(
            timestamp=self._stamp[1],
            frame_id=FRAME_ID,
            id=name,
            arrows=arrows,
            cylinders=cylinders,
            lines=lines,
            texts=texts,
        )

    def update(self, entities: list[SceneEntity]) -> bytes:
        return self.fm.SceneUpdate(entities=entities).encode()


def _cm_array(xy: FloatArray) -> NDArray[np.int64]:
    """Coordinates (m) rounded to whole centimetres."""
    return np.rint(xy * 100.0).astype(np.int64)


def _cm(xy: FloatArray) -> tuple[list[Any], list[Any]]:
    """The x and the y of coordinates (m, last axis) rounded to whole centimetres, as
    (nested) lists of ints."""
    c = _cm_array(xy)
    return c[..., 0].tolist(), c[..., 1].tolist()


def _arrow_table(direction: FloatArray, length: FloatArray) -> tuple[list[Any], list[Any]]:
    """Per frame and agent: yaw in 5-degree steps and length in 5-cm steps (0 when
    shorter than 2.5 cm)."""
    yaw = np.arctan2(direction[..., 1], direction[..., 0])
    steps = np.rint(yaw / (2 * math.pi / _YAW_STEPS)).astype(np.int64) % _YAW_STEPS
    lengths = np.rint(length / _LENGTH_STEP).astype(np.int64)
    return steps.tolist(), lengths.tolist()


def _thinned(path: FloatArray, spacing: float = _PATH_SPACING) -> FloatArray:
    """The first point of a path, each point reached after ``spacing`` m of travel since
    the last one kept, and the last point (a drawn path needs no point every 3 cm)."""
    if path.shape[0] <= 2:
        return path
    keep = [0]
    steps = np.linalg.norm(np.diff(path, axis=0), axis=1).tolist()
    travelled = 0.0
    for i, step in enumerate(steps, start=1):
        travelled += step
        if travelled >= spacing:
            keep.append(i)
            travelled = 0.0
    if keep[-1] != path.shape[0] - 1:
        keep.append(path.shape[0] - 1)
    return path[keep]


def _static(
    b: _Builder,
    record: EpisodeRecord,
    bounds: tuple[float, float, float, float],
    obstacles: Obstacles,
) -> bytes:
    x0, x1, y0, y1 = bounds
    lines = [b.line("LineLoop", [(x0, y0), (x1, y0), (x1, y1), (x0, y1)], 0.05, _GREY)]
    if obstacles.segments.shape[0]:
        pts = [(a, c) for s in obstacles.segments.tolist() for a, c in (s[:2], s[2:])]
        lines.append(b.line("LineList", pts, 0.1, _GREY))
    circles = obstacles.circles.tolist()
    pillars: list[Any] = []
    for cx, cy, r in circles:
        pillars += b.discs(*_cm(np.array([[cx, cy]])), [2 * r], 1.0, _GREY)
    world = b.entity(0, "world", cylinders=pillars, lines=lines)
    gx, gy = (float(v) for v in record.robot_goal)
    fm = b.fm
    label = fm.TextPrimitive(
        pose=fm.Pose(position=fm.Vector3(x=gx, y=gy, z=0.5), orientation=b.identity),
        billboard=True,
        font_size=0.3,
        scale_invariant=False,
        color=b.colors[_GREEN],
        text="robot goal",
    )
    goal = b.entity(
        0,
        "robot_goal",
        cylinders=b.discs(*_cm(record.robot_goal[None, :]), [0.4], 0.02, _GREEN),
        texts=[label],
    )
    path_xy = [(x, y) for x, y in _thinned(record.robot_pose[: record.end_step + 1, :2]).tolist()]
    path = b.entity(
        0, "robot_path", lines=[b.line("LineStrip", path_xy, 0.04, _RED)] if path_xy else []
    )
    return b.update([world, goal, path])


def scene_messages(
    record: EpisodeRecord,
    times_ns: list[int],
    *,
    bounds: tuple[float, float, float, float],
    obstacles: Obstacles,
    stride: int,
    velocities: bool = True,
) -> list[tuple[int, bytes]]:
    """Every scene message of an episode as (sample index, protobuf bytes), in time order.

    Args:
        record: the episode.
        times_ns: (T + 1,) message time of each sample (ns).
        bounds: world (x_min, x_max, y_min, y_max) in m.
        obstacles: walls and pillars.
        stride: draw the agents every ``stride`` samples (and at the last sample).
        velocities: draw the pedestrians' velocity arrows (they half the cost of a
            frame; compact logs leave them out).
    """
    b = _Builder()
    n_samples = record.time_s.shape[0]
    ped_d = [2 * float(r) for r in record.ped_radius]
    robot_d = [2 * record.robot_radius]
    frames = sorted({*range(0, n_samples, stride), n_samples - 1})
    idx = np.array(frames)
    # Per-frame tables, computed for the drawn samples only (row i is frames[i]).
    ped_cm = _cm_array(record.factual_pos[idx])
    ghost_cm = _cm_array(record.counterfactual_pos[idx])
    px, py = ped_cm[..., 0].tolist(), ped_cm[..., 1].tolist()
    gx, gy = ghost_cm[..., 0].tolist(), ghost_cm[..., 1].tolist()
    # The ghosts drawn: those apart from their factual twin (rounded), by frame.
    apart = [np.flatnonzero(a).tolist() for a in np.any(ghost_cm != ped_cm, axis=2)]
    pose = record.robot_pose[idx]
    rx, ry = _cm(pose[:, None, :2])
    ped_yaw: list[Any] = []
    ped_len: list[Any] = []
    if velocities:
        vel = record.factual_vel[idx]
        ped_yaw, ped_len = _arrow_table(vel, np.linalg.norm(vel, axis=2))
    heading = np.stack([np.cos(pose[:, 2]), np.sin(pose[:, 2])], axis=1)[:, None, :]
    robot_yaw, robot_len = _arrow_table(
        heading, np.full((len(frames), 1), max(0.4, 2 * record.robot_radius))
    )
    out: list[tuple[int, bytes]] = [(0, _static(b, record, bounds, obstacles))]
    goal_changes = np.flatnonzero(
        np.any(record.factual_goal[1:] != record.factual_goal[:-1], (1, 2))
    )
    goal_steps = {0, *(int(k) + 1 for k in goal_changes)}
    row = {k: i for i, k in enumerate(frames)}
    goal_d = [0.2] * record.n_pedestrians
    # The pedestrians there at a sample are the first ones (entries: srfm.sim); a
    # sample where more appear redraws the goals.
    counts = record.present().sum(axis=1).tolist()
    goal_steps |= {k for k in range(1, n_samples) if counts[k] != counts[k - 1]}
    for k in sorted(goal_steps | set(frames)):
        t = times_ns[k]
        m = counts[k]
        if k in goal_steps:
            goals = b.discs(*_cm(record.factual_goal[k, :m]), goal_d[:m], 0.01, _YELLOW)
            out.append((k, b.update([b.entity(t, "goals", cylinders=goals)])))
        i = row.get(k)
        if i is None:
            continue
        ghosts = [j for j in apart[i] if j < m]
        entities = [
            b.entity(
                t,
                "pedestrians",
                cylinders=b.discs(px[i][:m], py[i][:m], ped_d[:m], _PED_HEIGHT, _BLUE),
                arrows=(
                    b.arrows(
                        px[i][:m],
                        py[i][:m],
                        ped_yaw[i][:m],
                        ped_len[i][:m],
                        _PED_HEIGHT + 0.02,
                        _BLUE,
                    )
                    if velocities
                    else None
                ),
            ),
            # Translucent, lower, centred like the pedestrians: where the twins coincide
            # the factual disc would cover the ghost anyway.
            b.entity(
                t,
                "counterfactual",
                cylinders=b.discs(
                    [gx[i][j] for j in ghosts],
                    [gy[i][j] for j in ghosts],
                    [ped_d[j] for j in ghosts],
                    _GHOST_HEIGHT,
                    _GHOST,
                    _PED_HEIGHT / 2,
                ),
            ),
            b.entity(
                t,
                "robot",
                cylinders=b.discs(rx[i], ry[i], robot_d, _ROBOT_HEIGHT, _RED),
                arrows=b.arrows(
                    rx[i], ry[i], robot_yaw[i], robot_len[i], _ROBOT_HEIGHT + 0.02, _RED
                ),
            ),
        ]
        out.append((k, b.update(entities)))
    return out
