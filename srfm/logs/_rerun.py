"""The Rerun sink: one ``.rrd`` recording per twin episode, with a default blueprint.

The sink never calls ``rr.init`` and never touches the global recording: each call makes
its own :class:`rerun.RecordingStream`, saves it to a temporary file next to the target
and renames it into place. Data go in column by column (``send_columns``), one call per
entity for the whole episode, so a recording costs tens of milliseconds.

Entity tree (timelines ``step`` = sample index and ``sim_time`` = simulated time)::

    /world                                 static y-flip transform (the 2-D view shows y up)
    /world/bounds                          static Boxes2D: the world rectangle
    /world/obstacles/walls                 static LineStrips2D (when the scenario has walls)
    /world/obstacles/pillars               static Points2D with radii (when it has pillars)
    /world/pedestrians/factual             Points2D per step: pedestrians that feel the robot
    /world/pedestrians/factual/velocity    Arrows2D per step: velocity × 1 s
    /world/pedestrians/factual/goals       Points2D at step 0 and whenever a goal changes
    /world/pedestrians/factual/paths       static LineStrips2D: whole trajectories
    /world/pedestrians/counterfactual      Points2D per step: the ghost twins (no robot force)
    /world/pedestrians/counterfactual/paths  static LineStrips2D
    /world/robot                           Points2D per step: the robot body
    /world/robot/heading                   Arrows2D per step
    /world/robot/path                      static LineStrips2D: the robot's path to end_step
    /world/robot/goal                      static Points2D
    /world/forces/{goal,pedestrians,robot,obstacles}
                                           Arrows2D per step, optional: SRFM force components
                                           on the factual pedestrians × 0.5 s²
    /metrics/twin_separation               Scalars per step: distance of each pedestrian to
                                           its counterfactual twin (m), one series each
    /metrics/robot_distance                Scalars per step: closest factual pedestrian (m)
    /events                                TextLog: robot and pedestrian events
    /episode/summary                       static TextDocument: identity, outcome, metrics
"""

from __future__ import annotations

import hashlib
import math
import os
import tempfile
import uuid
from pathlib import Path
from typing import TYPE_CHECKING, Any, Final

import numpy as np
from numpy.typing import NDArray

from srfm._io import new_file_mode
from srfm.errors import LogError
from srfm.metrics import EpisodeMetrics
from srfm.scenarios import Scenario, episode_setup
from srfm.sim.record import EpisodeRecord, Event

if TYPE_CHECKING:
    import rerun as rr

__all__ = ["FORCE_ARROW_SCALE_S2", "VELOCITY_ARROW_S", "write_rrd"]

APPLICATION_ID: Final = "srfm"
VELOCITY_ARROW_S: Final = 1.0
"""Velocity arrows show the motion of this many seconds."""
FORCE_ARROW_SCALE_S2: Final = 0.5
"""Force arrows: metres of arrow per m/s² of force (unit mass)."""

_BLUE: Final = (40, 110, 220)
_GHOST: Final = (150, 150, 150, 110)
_RED: Final = (220, 50, 40)
_GREEN: Final = (50, 180, 80)
_YELLOW: Final = (240, 190, 25)
_GREY: Final = (90, 90, 90)
_FORCE_COLORS: Final = {
    "goal": (50, 180, 80),
    "pedestrians": (240, 150, 20),
    "robot": (220, 50, 40),
    "obstacles": (140, 60, 200),
}

FloatArray = NDArray[np.float64]


def _blueprint(scenario: Scenario) -> Any:
    import rerun.blueprint as rrb

    w = scenario.world
    pad = 0.5
    world_view = rrb.Spatial2DView(
        origin="/",
        contents="/world/**",
        name="world (y up)",
        # In view space: the /world transform flips y.
        visual_bounds=rrb.VisualBounds2D(
            x_range=[w.x_min - pad, w.x_max + pad], y_range=[-(w.y_max + pad), -(w.y_min - pad)]
        ),
    )
    side = rrb.Vertical(
        rrb.TimeSeriesView(origin="/metrics", name="deviation and robot distance (m)"),
        rrb.TextDocumentView(origin="/episode", name="episode"),
        rrb.TextLogView(origin="/events", name="events"),
        row_shares=[3, 2, 2],
    )
    root = rrb.Horizontal(world_view, side, column_shares=[3, 2])
    # Fixed view and container ids (rerun draws them at random): the same scenario gives
    # the same blueprint.
    for k, part in enumerate((root, world_view, side, *side.contents)):
        part.id = uuid.UUID(int=k + 1)
    return rrb.Blueprint(
        root,
        rrb.TimePanel(timeline="sim_time", state="expanded"),
        collapse_panels=False,
    )


def recording_id(
    record: EpisodeRecord, metrics: EpisodeMetrics | None = None, forces: bool = False
) -> str:
    """The recording id of an episode's ``.rrd`` file: ``SCENARIO-PLANNER-SEED-DIGEST``,
    the digest a SHA-256 over everything the file shows (every array of the record, its
    outcome and events, the metrics, whether forces are drawn). Two identical runs give
    the same id (the viewer treats their files as one recording); any difference gives
    another."""
    h = hashlib.sha256()
    for name, arr in sorted(record.arrays().items()):
        h.update(f"{name} {arr.dtype} {arr.shape}".encode())
        h.update(np.ascontiguousarray(arr).tobytes())
    h.update(repr((record.scenario, record.planner, record.seed, record.outcome)).encode())
    h.update(repr((record.end_step, record.events, forces)).encode())
    if metrics is not None:
        h.update(repr(sorted(metrics.values.items())).encode())
    return f"{record.scenario}-{record.planner}-{record.seed}-{h.hexdigest()[:16]}"


def _summary(record: EpisodeRecord, metrics: EpisodeMetrics | None) -> str:
    lines = [
        f"# {record.scenario}, seed {record.seed}, planner {record.planner}",
        "",
        f"- robot: **{record.outcome.replace('_', ' ')}** at step {record.end_step} "
        f"({record.end_step * record.dt_s:.2f} s) of {record.horizon_steps}",
        f"- pedestrians: {record.n_pedestrians}, dt {record.dt_s:.4f} s",
    ]
    if metrics is not None:
        lines += ["", "| metric | value |", "|---|---|"]
        for name, value in metrics.values.items():
            text = "—" if math.isnan(value) else f"{value:.4g}"
            lines.append(f"| {name} | {text} |")
    return "\n".join(lines) + "\n"


def _strips(pos: FloatArray) -> list[FloatArray]:
    """(T + 1, N, 2) trajectories as N line strips."""
    return [np.ascontiguousarray(pos[:, i]) for i in range(pos.shape[1])]


def _log_static(
    rec: rr.RecordingStream,
    record: EpisodeRecord,
    scenario: Scenario,
    metrics: EpisodeMetrics | None,
) -> None:
    import rerun as rr

    w = scenario.world
    rec.log("world", rr.Transform3D(mat3x3=[[1, 0, 0], [0, -1, 0], [0, 0, 1]]), static=True)
    rec.log(
        "world/bounds",
        rr.Boxes2D(
            mins=[w.x_min, w.y_min], sizes=[w.x_max - w.x_min, w.y_max - w.y_min], colors=[_GREY]
        ),
        static=True,
    )
    obstacles = scenario.obstacles
    if obstacles.segments.shape[0]:
        rec.log(
            "world/obstacles/walls",
            rr.LineStrips2D(list(obstacles.segments.reshape(-1, 2, 2)), colors=[_GREY], radii=0.05),
            static=True,
        )
    if obstacles.circles.shape[0]:
        rec.log(
            "world/obstacles/pillars",
            rr.Points2D(obstacles.circles[:, :2], radii=obstacles.circles[:, 2], colors=[_GREY]),
            static=True,
        )
    labels = [f"pedestrian {i}" for i in range(record.n_pedestrians)]
    rec.log(
        "world/pedestrians/factual",
        rr.Points2D.from_fields(
            radii=record.ped_radius, colors=[_BLUE], labels=labels, show_labels=False
        ),
        static=True,
    )
    rec.log(
        "world/pedestrians/counterfactual",
        rr.Points2D.from_fields(
            radii=record.ped_radius, colors=[_GHOST], labels=labels, show_labels=False
        ),
        static=True,
    )
    rec.log(
        "world/pedestrians/factual/paths",
        rr.LineStrips2D(_strips(record.factual_pos), colors=[(*_BLUE, 90)], radii=0.02),
        static=True,
    )
    rec.log(
        "world/pedestrians/counterfactual/paths",
        rr.LineStrips2D(_strips(record.counterfactual_pos), colors=[_GHOST], radii=0.02),
        static=True,
    )
    rec.log(
        "world/robot",
        rr.Points2D.from_fields(
            radii=[record.robot_radius], colors=[_RED], labels=["robot"], show_labels=False
        ),
        static=True,
    )
    rec.log(
        "world/robot/path",
        rr.LineStrips2D([record.robot_pose[: record.end_step + 1, :2]], colors=[_RED], radii=0.03),
        static=True,
    )
    rec.log(
        "world/robot/goal",
        rr.Points2D([record.robot_goal], radii=0.15, colors=[_GREEN], labels=["robot goal"]),
        static=True,
    )
    names = [f"pedestrian {i}" for i in range(record.n_pedestrians)]
    rec.log("metrics/twin_separation", rr.SeriesLines(names=names), static=True)
    rec.log(
        "metrics/robot_distance",
        rr.SeriesLines(names=["closest pedestrian"], colors=[_RED]),
        static=True,
    )
    rec.log(
        "episode/summary",
        rr.TextDocument(_summary(record, metrics), media_type=rr.MediaType.MARKDOWN),
        static=True,
    )


def _forces(record: EpisodeRecord, scenario: Scenario) -> dict[str, FloatArray]:
    """(T + 1, N, 2) SRFM force components on the factual crowd at every sample."""
    from srfm.models import RobotBody, force_components
    from srfm.models.state import CrowdState

    crowd0 = episode_setup(scenario, record.seed).crowd
    out = {k: np.zeros_like(record.factual_pos) for k in _FORCE_COLORS}
    counts = record.present().sum(axis=1)
    for k in range(record.time_s.shape[0]):
        m = int(counts[k])  # those there (the first m) feel and exert forces
        crowd = CrowdState(
            pos=np.ascontiguousarray(record.factual_pos[k, :m]),
            vel=np.ascontiguousarray(record.factual_vel[k, :m]),
            goal=np.ascontiguousarray(record.factual_goal[k, :m]),
            radius=crowd0.radius[:m],
            v0=crowd0.v0[:m],
            vmax=crowd0.vmax[:m],
        )
        x, y = record.robot_pose[k, :2]
        # the robot's velocity as the crowd felt it (0 once its episode has ended)
        vx, vy = record.robot_vel[k] if record.robot_active[k] else (0.0, 0.0)
        body = RobotBody(
            x=float(x), y=float(y), radius=record.robot_radius, vx=float(vx), vy=float(vy)
        )
        fc = force_components(crowd, record.params, body, scenario.obstacles)
        out["goal"][k, :m] = fc.goal
        out["pedestrians"][k, :m] = fc.pedestrians
        out["robot"][k, :m] = fc.robot
        out["obstacles"][k, :m] = fc.obstacles
    return out


def _log_temporal(
    rec: rr.RecordingStream, record: EpisodeRecord, scenario: Scenario, forces: bool
) -> None:
    import rerun as rr

    n_samples = int(record.time_s.shape[0])
    n = record.n_pedestrians
    steps = np.arange(n_samples)
    index = [
        rr.TimeColumn("step", sequence=steps),
        rr.TimeColumn("sim_time", duration=record.time_s),
    ]
    # The pedestrians there at each sample are the first ones (entries: srfm.sim): a
    # sample's instances are rows [:count] of the arrays, matching the static labels.
    present = record.present()
    per_step = present.sum(axis=1).tolist()

    def there(a: FloatArray) -> FloatArray:
        """The rows of the pedestrians there, sample by sample, as (M, ...)."""
        return np.asarray(a[present])

    def points(entity: str, pos: FloatArray) -> None:
        rec.send_columns(
            entity, index, rr.Points2D.columns(positions=there(pos)).partition(per_step)
        )

    def arrows(
        entity: str,
        origins: FloatArray,
        vectors: FloatArray,
        lengths: list[int],
        idx: list[Any] | None = None,
    ) -> None:
        rec.send_columns(
            entity,
            idx or index,
            rr.Arrows2D.columns(
                origins=origins.reshape(-1, 2), vectors=vectors.reshape(-1, 2)
            ).partition(lengths),
        )

    points("world/pedestrians/factual", record.factual_pos)
    points("world/pedestrians/counterfactual", record.counterfactual_pos)
    arrows(
        "world/pedestrians/factual/velocity",
        there(record.factual_pos),
        there(record.factual_vel * VELOCITY_ARROW_S),
        per_step,
    )
    rec.log(
        "world/pedestrians/factual/velocity",
        rr.Arrows2D.from_fields(colors=[_BLUE], radii=0.02),
        static=True,
    )
    goal = record.factual_goal
    changed = np.concatenate([[0], 1 + np.flatnonzero(np.any(goal[1:] != goal[:-1], axis=(1, 2)))])
    rec.send_columns(
        "world/pedestrians/factual/goals",
        [
            rr.TimeColumn("step", sequence=changed),
            rr.TimeColumn("sim_time", duration=record.time_s[changed]),
        ],
        rr.Points2D.columns(positions=goal[changed][present[changed]]).partition(
            [per_step[k] for k in changed]
        ),
    )
    rec.log(
        "world/pedestrians/factual/goals",
        rr.Points2D.from_fields(radii=0.08, colors=[_YELLOW]),
        static=True,
    )
    pose = record.robot_pose
    rec.send_columns("world/robot", index, rr.Points2D.columns(positions=pose[:, :2]))
    heading = np.stack([np.cos(pose[:, 2]), np.sin(pose[:, 2])], axis=1) * max(
        0.4, 2 * record.robot_radius
    )
    arrows("world/robot/heading", pose[:, :2], heading, [1] * n_samples)
    rec.log("world/robot/heading", rr.Arrows2D.from_fields(colors=[_RED], radii=0.03), static=True)
    if forces:
        for name, f in _forces(record, scenario).items():
            entity = f"world/forces/{name}"
            arrows(entity, there(record.factual_pos), there(f * FORCE_ARROW_SCALE_S2), per_step)
            rec.log(
                entity,
                rr.Arrows2D.from_fields(colors=[_FORCE_COLORS[name]], radii=0.015),
                static=True,
            )
    sep = record.twin_separation_m()
    rec.send_columns(
        "metrics/twin_separation",
        index,
        rr.Scalars.columns(scalars=there(sep)).partition(per_step),
    )
    gaps = np.linalg.norm(record.factual_pos - pose[:, None, :2], axis=2)
    dist = np.where(present, gaps, np.inf).min(axis=1) if n else np.full(n_samples, np.inf)
    dist[np.isinf(dist)] = np.nan  # nobody there
    rec.send_columns("metrics/robot_distance", index, rr.Scalars.columns(scalars=dist))
    events = record.events
    if events:  # one column for all of them (a log call each cost more than the rest)
        rec.send_columns(
            "events",
            [
                rr.TimeColumn("step", sequence=[e.step for e in events]),
                rr.TimeColumn("sim_time", duration=[e.time_s for e in events]),
            ],
            rr.TextLog.columns(
                text=[_event_text(e) for e in events],
                level=["WARN" if e.kind == "robot_collision" else "INFO" for e in events],
            ),
        )


def _event_text(e: Event) -> str:
    """The line of the events log that tells ``e``."""
    if e.kind == "ped_arrival":
        return f"pedestrian {e.agent} ({e.twin}) arrived"
    if e.kind == "robot_collision":
        return "robot collision" + (f" with pedestrian {e.agent}" if e.agent >= 0 else "")
    return e.kind.replace("_", " ")


def write_rrd(
    path: str | Path,
    record: EpisodeRecord,
    *,
    scenario: Scenario,
    metrics: EpisodeMetrics | None = None,
    forces: bool = False,
) -> int:
    """Write one twin episode as a Rerun recording, atomically.

    Args:
        path: the ``.rrd`` file to write (folders are created).
        record: the finished episode.
        scenario: the scenario it ran (world bounds, obstacles, agent limits).
        metrics: shown in the episode summary when given.
        forces: also log the SRFM force components on the factual pedestrians at every
            sample (recomputed from the recorded states; off by default).

    Returns:
        The size of the file (bytes).
    """
    import rerun as rr

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp_name = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    os.close(fd)
    tmp = Path(tmp_name)
    rec = rr.RecordingStream(
        APPLICATION_ID,
        recording_id=recording_id(record, metrics, forces),
        send_properties=False,
    )
    try:
        rec.set_log_tick_enabled(False)  # only the step and sim_time timelines
        rec.set_log_time_enabled(False)
        rec.save(tmp, default_blueprint=_blueprint(scenario))
        rec.send_recording_name(f"{record.scenario} · {record.planner} · seed {record.seed}")
        _log_static(rec, record, scenario, metrics)
        _log_temporal(rec, record, scenario, forces)
        rec.flush()
        rec.disconnect()
        size = tmp.stat().st_size
        if size == 0:
            raise LogError(f"{path}: rerun wrote an empty recording")
        os.chmod(tmp, new_file_mode())  # as every output, not mkstemp's 0600
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    return size
