"""Foxglove ``SceneUpdate`` messages (JSON) that draw a twin episode from above.

Entities on the ``/foxglove/scene`` topic, all in frame ``world`` (metres, z up):

- ``world`` (once, at time 0): the world bounds as a line loop, walls as line
  segments, pillars as cylinders;
- ``robot_goal`` and ``robot_path`` (once): the robot's goal and its whole path;
- ``goals`` (at time 0 and whenever a goal changes): the factual pedestrians' goals;
- ``pedestrians``, ``counterfactual`` and ``robot`` (every ``stride`` samples): factual
  pedestrians as blue discs with velocity arrows (length = 1 s of motion), their
  counterfactual twins as translucent grey discs, the robot as a red disc with a
  heading arrow.

Coordinates are rounded to 1 cm and angles to 0.001: the scene is for looking at; the
exact numbers are on the ``/srfm/...`` channels. Messages are formatted from string
templates rather than dictionaries because a benchmark writes hundreds of thousands.
"""

from __future__ import annotations

import math
from typing import Final

import numpy as np
from numpy.typing import NDArray

from srfm.models.state import Obstacles
from srfm.sim.record import EpisodeRecord

__all__ = ["scene_messages"]

FloatArray = NDArray[np.float64]

_IDENTITY: Final = '"orientation":{"x":0,"y":0,"z":0,"w":1}'
_BLUE: Final = '{"r":0.16,"g":0.43,"b":0.86,"a":1}'
_GHOST: Final = '{"r":0.55,"g":0.55,"b":0.55,"a":0.45}'
_RED: Final = '{"r":0.86,"g":0.2,"b":0.16,"a":1}'
_GREEN: Final = '{"r":0.2,"g":0.7,"b":0.3,"a":0.9}'
_YELLOW: Final = '{"r":0.95,"g":0.75,"b":0.1,"a":1}'
_GREY: Final = '{"r":0.3,"g":0.3,"b":0.3,"a":1}'

_CYL: Final = (
    '{"pose":{"position":{"x":%.2f,"y":%.2f,"z":%s},' + _IDENTITY + "},"
    '"size":{"x":%s,"y":%s,"z":%s},"bottom_scale":1,"top_scale":1,"color":%s}'
)
_ARROW: Final = (
    '{"pose":{"position":{"x":%.2f,"y":%.2f,"z":%s},'
    '"orientation":{"x":0,"y":0,"z":%.3f,"w":%.3f}},"shaft_length":%.2f,'
    '"shaft_diameter":0.04,"head_length":0.12,"head_diameter":0.12,"color":%s}'
)
_LINE: Final = (
    '{"type":%d,"pose":{"position":{"x":0,"y":0,"z":0},' + _IDENTITY + '},"thickness":%s,'
    '"scale_invariant":false,"points":[%s],"color":%s,"colors":[],"indices":[]}'
)
_POINT: Final = '{"x":%.2f,"y":%.2f,"z":0.01}'
_TEXT: Final = (
    '{"pose":{"position":{"x":%.2f,"y":%.2f,"z":0.5},' + _IDENTITY + '},"billboard":true,'
    '"font_size":0.3,"scale_invariant":false,"color":%s,"text":"%s"}'
)
_ENTITY: Final = (
    '{"timestamp":{"sec":%d,"nsec":%d},"frame_id":"world","id":"%s",'
    '"lifetime":{"sec":0,"nsec":0},"frame_locked":false,"metadata":[],'
    '"arrows":[%s],"cubes":[],"spheres":[],"cylinders":[%s],"lines":[%s],'
    '"triangles":[],"texts":[%s],"models":[]}'
)
_UPDATE: Final = '{"deletions":[],"entities":[%s]}'


def _entity_template(name: str, *, arrows: bool, cylinders: bool) -> str:
    """An entity with (sec, nsec) and the chosen primitive lists left to fill."""
    out = _ENTITY.replace('"id":"%s"', f'"id":"{name}"')
    out = out.replace('"lines":[%s]', '"lines":[]').replace('"texts":[%s]', '"texts":[]')
    if not arrows:
        out = out.replace('"arrows":[%s]', '"arrows":[]')
    if not cylinders:
        out = out.replace('"cylinders":[%s]', '"cylinders":[]')
    return out


# One frame of the agents: pedestrians (arrows, discs), their twins (discs), the robot.
_FRAME: Final = _UPDATE % ",".join(
    (
        _entity_template("pedestrians", arrows=True, cylinders=True),
        _entity_template("counterfactual", arrows=False, cylinders=True),
        _entity_template("robot", arrows=True, cylinders=True),
    )
)

_YAW_STEP: Final = math.radians(5.0)
_LENGTH_STEP: Final = 0.05
_PED_HEIGHT: Final = 0.4
_ROBOT_HEIGHT: Final = 0.5


def _entity(
    t_ns: int,
    name: str,
    *,
    arrows: list[str] | None = None,
    cylinders: list[str] | None = None,
    lines: list[str] | None = None,
    texts: list[str] | None = None,
) -> str:
    return _ENTITY % (
        t_ns // 1_000_000_000,
        t_ns % 1_000_000_000,
        name,
        ",".join(arrows or ()),
        ",".join(cylinders or ()),
        ",".join(lines or ()),
        ",".join(texts or ()),
    )


def _disc_template(diameter: str, height: float, color: str) -> str:
    """A cylinder standing on the ground with only its centre (x, y) left to fill."""
    filled = _CYL % (0.0, 0.0, repr(height / 2), diameter, diameter, repr(height), color)
    return filled.replace('"x":0.00,"y":0.00', '"x":%.2f,"y":%.2f', 1)


def _arrow_template(z: float, color: str) -> str:
    """An arrow at height ``z`` with (x, y, qz, qw, shaft length) left to fill."""
    return _ARROW.replace("%s", repr(round(z, 3)), 1).replace("%s", color, 1)


class _Frames:
    """The agents of the drawn frames, formatted one frame at a time with a single
    ``%`` each for the discs (the template of a whole frame is built once)."""

    def __init__(
        self,
        pos: FloatArray,
        diameters: list[str],
        height: float,
        color: str,
    ) -> None:
        n = pos.shape[1]
        self.template = ",".join(_disc_template(d, height, color) for d in diameters[:n])
        self.rows = [tuple(r) for r in pos.reshape(pos.shape[0], 2 * n).tolist()]

    def at(self, i: int) -> str:
        return self.template % self.rows[i]


class _ArrowTable:
    """Arrow parameters of a list of frames, computed at once (row i: frame i).

    Directions are rounded to 5 degrees and lengths to 5 cm (the repeated text then
    compresses well); arrows shorter than 2.5 cm are left out.
    """

    def __init__(
        self, pos: FloatArray, direction: FloatArray, length: FloatArray, z: float, color: str
    ) -> None:
        yaw = np.round(np.arctan2(direction[..., 1], direction[..., 0]) / _YAW_STEP) * _YAW_STEP
        rounded = np.round(length / _LENGTH_STEP) * _LENGTH_STEP
        table = np.stack(
            [pos[..., 0], pos[..., 1], np.sin(yaw / 2), np.cos(yaw / 2), rounded], axis=-1
        )
        n = pos.shape[1]
        self.one = _arrow_template(z, color)
        self.template = ",".join([self.one] * n)
        self.rows = table.reshape(table.shape[0], 5 * n).tolist()
        self.drawn = (rounded >= 0.025).tolist()

    def at(self, i: int) -> str:
        drawn = self.drawn[i]
        row = self.rows[i]
        if all(drawn):
            return self.template % tuple(row)
        one = self.one
        return ",".join(one % tuple(row[5 * j : 5 * j + 5]) for j, d in enumerate(drawn) if d)


def _static(
    record: EpisodeRecord,
    bounds: tuple[float, float, float, float],
    obstacles: Obstacles,
) -> str:
    x0, x1, y0, y1 = bounds
    corners = ",".join(_POINT % p for p in ((x0, y0), (x1, y0), (x1, y1), (x0, y1)))
    lines = [_LINE % (1, "0.05", corners, _GREY)]
    if obstacles.segments.shape[0]:
        pts = ",".join(
            _POINT % (a, b) for s in obstacles.segments.tolist() for a, b in (s[:2], s[2:])
        )
        lines.append(_LINE % (2, "0.1", pts, _GREY))
    pillars = [
        _CYL % (cx, cy, "0.5", repr(2 * r), repr(2 * r), "1.0", _GREY)
        for cx, cy, r in obstacles.circles.tolist()
    ]
    world = _entity(0, "world", cylinders=pillars, lines=lines)
    gx, gy = (float(v) for v in record.robot_goal)
    goal = _entity(
        0,
        "robot_goal",
        cylinders=[_CYL % (gx, gy, "0.01", "0.4", "0.4", "0.02", _GREEN)],
        texts=[_TEXT % (gx, gy, _GREEN, "robot goal")],
    )
    path_xy = record.robot_pose[: record.end_step + 1, :2]
    pts = ",".join(_POINT % (a, b) for a, b in path_xy.tolist())
    path = _entity(0, "robot_path", lines=[_LINE % (0, "0.04", pts, _RED)] if pts else [])
    return _UPDATE % ",".join((world, goal, path))


def _goals(t_ns: int, goals: FloatArray) -> str:
    discs = [_CYL % (x, y, "0.005", "0.2", "0.2", "0.01", _YELLOW) for x, y in goals.tolist()]
    return _UPDATE % _entity(t_ns, "goals", cylinders=discs)


def scene_messages(
    record: EpisodeRecord,
    times_ns: list[int],
    *,
    bounds: tuple[float, float, float, float],
    obstacles: Obstacles,
    stride: int,
) -> list[tuple[int, bytes]]:
    """Every scene message of an episode as (sample index, JSON bytes), in time order.

    Args:
        record: the episode.
        times_ns: (T + 1,) message time of each sample (ns).
        bounds: world (x_min, x_max, y_min, y_max) in m.
        obstacles: walls and pillars.
        stride: draw the agents every ``stride`` samples (and at the last sample).
    """
    n_samples = record.time_s.shape[0]
    ped_d = [repr(round(2 * float(r), 3)) for r in record.ped_radius]
    robot_d = [repr(round(2 * record.robot_radius, 3))]
    frames = sorted({*range(0, n_samples, stride), n_samples - 1})
    idx = np.array(frames)
    # Per-frame tables, computed for the drawn samples only (row i is frames[i]).
    f_pos = record.factual_pos[idx]
    peds = _Frames(f_pos, ped_d, _PED_HEIGHT, _BLUE)
    ghosts = _Frames(record.counterfactual_pos[idx], ped_d, _PED_HEIGHT * 0.9, _GHOST)
    pose = record.robot_pose[idx]
    robot = _Frames(pose[:, None, :2], robot_d, _ROBOT_HEIGHT, _RED)
    vel = record.factual_vel[idx]
    ped_arrows = _ArrowTable(f_pos, vel, np.linalg.norm(vel, axis=2), _PED_HEIGHT + 0.02, _BLUE)
    heading = np.stack([np.cos(pose[:, 2]), np.sin(pose[:, 2])], axis=1)[:, None, :]
    robot_arrows = _ArrowTable(
        pose[:, None, :2],
        heading,
        np.full((len(frames), 1), max(0.4, 2 * record.robot_radius)),
        _ROBOT_HEIGHT + 0.02,
        _RED,
    )
    out: list[tuple[int, bytes]] = [(0, _static(record, bounds, obstacles).encode())]
    goal_changes = np.flatnonzero(
        np.any(record.factual_goal[1:] != record.factual_goal[:-1], (1, 2))
    )
    goal_steps = {0, *(int(k) + 1 for k in goal_changes)}
    row = {k: i for i, k in enumerate(frames)}
    for k in sorted(goal_steps | set(frames)):
        t = times_ns[k]
        if k in goal_steps:
            out.append((k, _goals(t, record.factual_goal[k]).encode()))
        i = row.get(k)
        if i is None:
            continue
        sec, nsec = divmod(t, 1_000_000_000)
        update = _FRAME % (
            sec,
            nsec,
            ped_arrows.at(i),
            peds.at(i),
            sec,
            nsec,
            ghosts.at(i),
            sec,
            nsec,
            robot_arrows.at(i),
            robot.at(i),
        )
        out.append((k, update.encode()))
    return out
