"""The MCAP sink and reader: one file per twin episode, written with the ``mcap`` library.

Files are written by the ``mcap`` package's :class:`mcap.writer.Writer` with its
defaults (zstd chunks of up to 1 MiB, message, chunk, attachment and metadata indexes,
statistics, summary offsets, chunk and summary CRCs) plus the CRC of the data section;
any MCAP reader opens them. Message times are integer nanoseconds of simulated time
(sample k at ``round(k * dt * 1e9)``). What each channel holds:
:mod:`srfm.logs._schemas` and ``docs/logging.md``. Two profiles:

- ``full``: every channel, the Foxglove scene and the robot messages at every sample,
  exact per-sample pedestrian states, and exact velocities in the trajectory arrays: a
  complete :class:`~srfm.sim.record.EpisodeRecord` can be rebuilt bit for bit.
- ``compact`` (the benchmark's default): no per-sample pedestrian messages, the scene
  and the robot state and command messages every fifteenth sample (1 Hz, for looking
  and plotting), positions and goals exact but no pedestrian velocities, and the
  counterfactual crowd (identical for every planner of a scenario and seed) may live in
  a shared file that the episode names and fingerprints.

In both profiles the exact arrays of every sample (the robot's pose, velocity, activity
and command; each crowd's positions and goals) are NumPy ``.npy`` files, base64 in the
``/srfm/trajectories`` messages; that is what the reader uses. The reader checks every
CRC the file has (chunks and data section with the ``mcap`` library's stream reader,
the summary's here) and refuses files of another schema version, naming that version
and the srfm that wrote the file.
"""

from __future__ import annotations

import base64
import binascii
import functools
import hashlib
import io
import itertools
import json
import math
import re
import struct
import zlib
from collections.abc import Iterator, Mapping
from importlib import metadata
from pathlib import Path
from typing import Any, Final, Literal

import attrs
import numpy as np
from numpy.typing import NDArray

from srfm._io import atomic_write_bytes
from srfm._text import plain
from srfm._version import DISTRIBUTION
from srfm.errors import LogError, SrfmError
from srfm.logs._foxglove import scene_messages
from srfm.logs._planes import from_planes, to_planes
from srfm.logs._schemas import CHANNELS, READ_VERSIONS, SCHEMA_VERSION
from srfm.metrics import EpisodeMetrics
from srfm.models.params import SRFMParams
from srfm.scenarios import Scenario, episode_setup
from srfm.sim.record import EVENT_KINDS, ROBOT_OUTCOMES, EpisodeRecord, Event

__all__ = [
    "PROFILES",
    "LogFile",
    "LoggedEpisode",
    "Profile",
    "counterfactual_digest",
    "episode_from_log",
    "load_episode",
    "read_log",
    "write_counterfactual_mcap",
    "write_episode_mcap",
]

Profile = Literal["full", "compact"]
PROFILES: Final = ("full", "compact")
_SCENE_STRIDE: Final = {"full": 1, "compact": 15}
_METADATA: Final = "srfm"
_SEPARATORS: Final = (",", ":")
FloatArray = NDArray[np.float64]


@functools.cache
def _version() -> str:
    try:
        return metadata.version(DISTRIBUTION)
    except metadata.PackageNotFoundError:  # pragma: no cover - always installed
        return "unknown"


def times_ns(n_samples: int, dt_s: float) -> list[int]:
    """Message time (ns) of each sample: ``round(k * dt * 1e9)`` (in float64, rounded
    half to even like :func:`round`; NumPy does the same operations in the same order)."""
    k = np.arange(n_samples, dtype=np.float64)
    return np.rint(k * dt_s * 1e9).astype(np.int64).tolist()  # type: ignore[no-any-return]


def counterfactual_digest(pos: FloatArray, goal: FloatArray) -> str:
    """SHA-256 of the counterfactual positions and goals (float64, C order, with shapes)."""
    h = hashlib.sha256()
    for a in (pos, goal):
        arr = np.ascontiguousarray(a, dtype="<f8")
        h.update(repr(arr.shape).encode())
        h.update(arr.tobytes())
    return h.hexdigest()


_ENCODER: Final = json.JSONEncoder(separators=_SEPARATORS, allow_nan=False)


def _json(doc: Any) -> bytes:
    """Compact JSON, NaN refused (one encoder object: ``json.dumps`` with options
    builds a new one per call)."""
    return _ENCODER.encode(doc).encode("utf-8")


def _nan_to_none(values: list[float]) -> list[float | None]:
    return [None if math.isnan(v) else v for v in values]


@functools.lru_cache(maxsize=32)
def _crowd_speeds(scenario: Scenario, seed: int) -> tuple[list[float], list[float]]:
    """The desired and maximum speeds of a scenario's crowd for a seed. Scenarios are
    hashed by identity, so the writes that share them are those of one scenario object:
    an episode's file and its shared counterfactual file, or the episodes of one process
    that reuses its scenarios (a benchmark worker gets a copy with each task)."""
    crowd = episode_setup(scenario, seed).crowd
    return crowd.v0.tolist(), crowd.vmax.tolist()


def _scenario_info(scenario: Scenario, record: EpisodeRecord) -> dict[str, Any]:
    """What a reader needs to know about the world and the agents (exact floats)."""
    v0, vmax = _crowd_speeds(scenario, record.seed)
    w = scenario.world
    robot = scenario.robot
    pedestrians: dict[str, Any] = {
        "radius_m": record.ped_radius.tolist(),
        "desired_speed_mps": v0,
        "max_speed_mps": vmax,
        "goal_radius_m": scenario.ped_goal_radius_m,
    }
    if record.ped_enter_step is not None:
        pedestrians["enter_step"] = record.ped_enter_step.tolist()
    return {
        "scenario": record.scenario,
        "scenario_description": scenario.description,
        "seed": record.seed,
        "dt_s": record.dt_s,
        "horizon_steps": record.horizon_steps,
        "n_pedestrians": record.n_pedestrians,
        "params": record.params.as_dict(),
        "world": {"x_min": w.x_min, "x_max": w.x_max, "y_min": w.y_min, "y_max": w.y_max},
        "obstacles": {
            "segments": scenario.obstacles.segments.tolist(),
            "circles": scenario.obstacles.circles.tolist(),
        },
        "pedestrians": pedestrians,
        "robot": {
            "kinematics": record.robot_kinematics,
            "radius_m": record.robot_radius,
            "max_speed_mps": robot.max_speed_mps,
            "max_angular_speed_radps": robot.max_angular_speed_radps,
            "goal_radius_m": robot.goal_radius_m,
            "goal": record.robot_goal.tolist(),
        },
    }


def metrics_doc(metrics: EpisodeMetrics) -> dict[str, Any]:
    """The JSON document of one episode's metrics (NaN as null)."""
    return {"schema_version": SCHEMA_VERSION, **metrics.to_document()}


class _Writer:
    """An :class:`mcap.writer.Writer` into memory that registers srfm's channels as
    they are first used."""

    def __init__(self, kind: str, info: Mapping[str, str]) -> None:
        from mcap.writer import Writer

        self._buf = io.BytesIO()
        self._w = Writer(self._buf, enable_data_crcs=True)
        self._w.start(profile="", library=f"srfm {_version()}")
        self._schemas: dict[str, int] = {}
        self._channels: dict[str, int] = {}
        self._sequence: dict[int, int] = {}
        self._w.add_metadata(
            _METADATA, {"kind": kind, "schema_version": str(SCHEMA_VERSION), **info}
        )

    def channel(self, key: str) -> int:
        if key not in self._channels:
            spec = CHANNELS[key]
            if spec.schema_name not in self._schemas:
                self._schemas[spec.schema_name] = self._w.register_schema(
                    name=spec.schema_name, encoding=spec.schema_encoding, data=spec.schema
                )
            cid: int = self._w.register_channel(
                topic=spec.topic,
                message_encoding=spec.message_encoding,
                schema_id=self._schemas[spec.schema_name],
            )
            self._channels[key] = cid
            self._sequence[cid] = 0
        return self._channels[key]

    def add(self, key: str, t_ns: int, data: bytes) -> None:
        cid = self.channel(key)
        seq = self._sequence[cid]
        self._w.add_message(
            channel_id=cid, log_time=t_ns, data=data, publish_time=t_ns, sequence=seq
        )
        self._sequence[cid] = seq + 1

    def finish(self) -> bytes:
        self._w.finish()  # type: ignore[no-untyped-call]
        return self._buf.getvalue()


def _identity(record: EpisodeRecord, planner: str | None) -> dict[str, str]:
    return {
        "scenario": record.scenario,
        "seed": str(record.seed),
        "planner": planner or "",
        "srfm_version": _version(),
    }


def npy_bytes(array: NDArray[Any]) -> bytes:
    """An array as a NumPy ``.npy`` file (format 1.0, little-endian, C order, no pickles)."""
    a = np.ascontiguousarray(array, dtype=array.dtype.newbyteorder("<"))
    buf = io.BytesIO()
    np.lib.format.write_array(buf, a, version=(1, 0), allow_pickle=False)
    return buf.getvalue()


def _trajectories(group: str, samples: int, arrays: Mapping[str, NDArray[Any]]) -> bytes:
    """The ``/srfm/trajectories`` message of one group: the base64 text of each array's
    ``.npy`` file, every float64 array but the goals in its bit-plane form
    (:mod:`srfm.logs._planes`; ``"planes"`` gives their shapes). Formatted directly
    rather than by :func:`json.dumps`, which scans the base64 text for characters to
    escape (it has none): 3.0 ms against 0.6 ms for a compact episode's 320 kB of text
    (measured on this machine)."""
    head = f'{{"schema_version":{SCHEMA_VERSION},"group":"{group}","samples":{int(samples)},'
    parts = [head.encode("ascii"), b'"arrays":{']
    shapes: dict[str, list[int]] = {}
    for i, (name, array) in enumerate(arrays.items()):
        if array.dtype == np.float64 and name != "goal":
            shapes[name] = list(array.shape)
            array = to_planes(array)
        parts += [b',"' if i else b'"', name.encode("ascii"), b'":"']
        parts += [base64.b64encode(npy_bytes(array)), b'"']
    parts += [b'},"planes":', _json(shapes), b"}"]
    return b"".join(parts)


def _robot_arrays(record: EpisodeRecord) -> bytes:
    """The robot's exact pose, velocity, activity and commands: what the reader uses."""
    return _trajectories(
        "robot",
        record.time_s.shape[0],
        {
            "pose": record.robot_pose,
            "vel": record.robot_vel,
            "active": record.robot_active,
            "cmd": record.robot_cmd,
        },
    )


def _pedestrian_arrays(record: EpisodeRecord, twin: str, profile: Profile) -> bytes:
    arrays = {
        "pos": getattr(record, f"{twin}_pos"),
        "goal": getattr(record, f"{twin}_goal"),
    }
    if profile == "full":
        arrays["vel"] = getattr(record, f"{twin}_vel")
    return _trajectories(twin, record.time_s.shape[0], arrays)


def _standard_times(record: EpisodeRecord) -> FloatArray:
    """The sample times :func:`srfm.sim.episode.run_episode` uses: ``arange(T + 1) * dt``."""
    return np.arange(record.horizon_steps + 1, dtype=np.float64) * record.dt_s


def _pedestrian_states(record: EpisodeRecord, twin: str) -> Iterator[bytes]:
    pos = getattr(record, f"{twin}_pos")
    vel = getattr(record, f"{twin}_vel")
    goal = getattr(record, f"{twin}_goal")
    cols = [a[:, :, c].tolist() for a in (pos, vel, goal) for c in (0, 1)]
    for k in range(pos.shape[0]):
        x, y, vx, vy, gx, gy = (c[k] for c in cols)
        yield _json(
            {
                "schema_version": SCHEMA_VERSION,
                "twin": twin,
                "step": k,
                "x": x,
                "y": y,
                "vx": vx,
                "vy": vy,
                "goal_x": gx,
                "goal_y": gy,
            }
        )


def _robot_state(k: int, pose: list[float], vel: list[float], active: bool) -> bytes:
    """The ``/srfm/robot/state`` message of sample ``k``: what :func:`_json` makes of
    the same fields (floats as their shortest ``repr``, which is JSON's), formatted
    directly; the caller has checked that pose and velocity are finite."""
    x, y, th = pose
    vx, vy = vel
    return (
        f'{{"schema_version":{SCHEMA_VERSION},"step":{k},"x":{x!r},"y":{y!r},'
        f'"theta":{th!r},"vx":{vx!r},"vy":{vy!r},"active":{"true" if active else "false"}}}'
    ).encode("ascii")


def write_episode_mcap(
    path: str | Path,
    record: EpisodeRecord,
    *,
    scenario: Scenario,
    metrics: EpisodeMetrics | None = None,
    profile: Profile = "full",
    scene_stride: int | None = None,
    counterfactual_file: str | None = None,
    benchmark: Mapping[str, Any] | None = None,
    fsync: bool = True,
) -> int:
    """Write one twin episode to an MCAP file, atomically.

    Args:
        path: the ``.mcap`` file to write (folders are created).
        record: the finished episode.
        scenario: the scenario it ran (for the world, obstacles and agent limits).
        metrics: its metrics (stored as the online numbers; also names the planner).
        profile: ``"full"`` or ``"compact"`` (see the module docstring).
        scene_stride: draw the Foxglove scene (and, in ``compact``, publish the robot
            messages) every this many samples (default 1 for ``full``, 15 for
            ``compact``).
        counterfactual_file: leave the counterfactual crowd out of this file and name
            the shared file that holds it, relative to ``path``'s folder.
        benchmark: the benchmark request (scenarios, planners, seeds, reference) that
            fixes the order of the tables ``srfm score`` rebuilds.
        fsync: flush the file to disk before renaming it into place.

    Returns:
        The size of the file (bytes).
    """
    if profile not in PROFILES:
        raise LogError(f"unknown MCAP profile {plain(profile)}; choose from {list(PROFILES)}")
    stride = _SCENE_STRIDE[profile] if scene_stride is None else scene_stride
    if stride < 1:
        raise LogError(f"scene stride must be at least 1, got {stride}")
    if not (np.isfinite(record.robot_pose).all() and np.isfinite(record.robot_vel).all()):
        raise LogError(f"{path}: the robot's pose or velocity is not finite; cannot log it")
    planner = metrics.planner if metrics is not None else record.planner
    n_samples = int(record.time_s.shape[0])
    t_ns = times_ns(n_samples, record.dt_s)
    info = {
        "schema_version": SCHEMA_VERSION,
        "kind": "episode",
        "profile": profile,
        "srfm_version": _version(),
        **_scenario_info(scenario, record),
        "planner": planner,
        "outcome": record.outcome,
        "end_step": record.end_step,
        # Full logs publish the robot at every sample, compact ones at the scene's frames
        # (for plotting); the exact values of every sample are in the robot block.
        "robot_states": "all" if profile == "full" else "frames",
        "counterfactual": {
            "file": counterfactual_file,
            "sha256": counterfactual_digest(record.counterfactual_pos, record.counterfactual_goal),
        },
        "benchmark": dict(benchmark) if benchmark is not None else None,
    }
    if not np.array_equal(record.time_s, _standard_times(record)):
        info["time_s"] = record.time_s.tolist()  # only when arange(T + 1) * dt differs
    w = _Writer("episode", _identity(record, planner))
    w.add("episode", 0, _json(info))
    w_bounds = scenario.world
    scenes = scene_messages(
        record,
        t_ns,
        bounds=(w_bounds.x_min, w_bounds.x_max, w_bounds.y_min, w_bounds.y_max),
        obstacles=scenario.obstacles,
        stride=stride,
        velocities=profile == "full",
    )
    scene_at: dict[int, list[bytes]] = {}
    for k, data in scenes:
        scene_at.setdefault(k, []).append(data)
    events_at: dict[int, list[Event]] = {}
    for e in record.events:
        events_at.setdefault(e.step, []).append(e)
    robot_steps = range(n_samples) if profile == "full" else range(0, n_samples, stride)
    robot_at = {*robot_steps, n_samples - 1}
    pose = record.robot_pose.tolist()
    rvel = record.robot_vel.tolist()
    cmd = record.robot_cmd.tolist()
    active = record.robot_active.tolist()
    kin = record.robot_kinematics
    peds = (
        [list(_pedestrian_states(record, twin)) for twin in ("factual", "counterfactual")]
        if profile == "full"
        else []
    )
    for k in sorted(robot_at | scene_at.keys() | events_at.keys()):
        t = t_ns[k]
        for key, msgs in zip(("factual", "counterfactual"), peds, strict=False):
            w.add(key, t, msgs[k])
        if k in robot_at:
            w.add("robot_state", t, _robot_state(k, pose[k], rvel[k], active[k]))
            if k < n_samples - 1 and active[k] and not math.isnan(cmd[k][0]):
                command = {
                    "schema_version": SCHEMA_VERSION,
                    "step": k,
                    "kinematics": kin,
                    "command": cmd[k],
                }
                w.add("robot_command", t, _json(command))
        for e in events_at.get(k, ()):
            w.add(
                "events",
                t,
                _json(
                    {
                        "schema_version": SCHEMA_VERSION,
                        "step": e.step,
                        "time_s": e.time_s,
                        "kind": e.kind,
                        "agent": e.agent,
                        "twin": e.twin,
                    }
                ),
            )
        for data in scene_at.get(k, ()):
            w.add("scene", t, data)
    end = t_ns[-1]
    if metrics is not None:
        w.add("metrics", end, _json(metrics_doc(metrics)))
    w.add("trajectories", end, _robot_arrays(record))
    w.add("trajectories", end, _pedestrian_arrays(record, "factual", profile))
    if counterfactual_file is None:
        w.add("trajectories", end, _pedestrian_arrays(record, "counterfactual", profile))
    data = w.finish()
    atomic_write_bytes(path, data, fsync=fsync)
    return len(data)


def write_counterfactual_mcap(
    path: str | Path,
    record: EpisodeRecord,
    *,
    scenario: Scenario,
    profile: Profile = "compact",
    fsync: bool = True,
) -> int:
    """Write the counterfactual crowd of an episode (shared by every planner) atomically.

    Returns:
        The size of the file (bytes).
    """
    info = {
        "schema_version": SCHEMA_VERSION,
        "kind": "counterfactual",
        "profile": profile,
        "srfm_version": _version(),
        **_scenario_info(scenario, record),
        "planner": None,
        "outcome": None,
        "end_step": None,
        "robot_states": None,
        "counterfactual": {
            "file": None,
            "sha256": counterfactual_digest(record.counterfactual_pos, record.counterfactual_goal),
        },
        "benchmark": None,
    }
    w = _Writer("counterfactual", _identity(record, None))
    w.add("episode", 0, _json(info))
    end = round(record.horizon_steps * record.dt_s * 1e9)
    w.add("trajectories", end, _pedestrian_arrays(record, "counterfactual", profile))
    data = w.finish()
    atomic_write_bytes(path, data, fsync=fsync)
    return len(data)


# --- reading ---------------------------------------------------------------------------


@attrs.frozen(kw_only=True, eq=False)
class LogFile:
    """The srfm content of one MCAP file, decoded and checked for shape.

    Attributes:
        path: the file.
        info: the ``/srfm/episode`` message.
        groups: the ``/srfm/trajectories`` arrays by group and name.
        events: the ``/srfm/events`` messages, in file order.
        robot_states: the ``/srfm/robot/state`` messages, in file order.
        robot_commands: the ``/srfm/robot/command`` messages, in file order.
        metrics: the ``/srfm/metrics`` message, or None.
    """

    path: Path
    info: Mapping[str, Any]
    groups: Mapping[str, Mapping[str, NDArray[Any]]]
    events: tuple[Mapping[str, Any], ...]
    robot_states: tuple[Mapping[str, Any], ...]
    robot_commands: tuple[Mapping[str, Any], ...]
    metrics: Mapping[str, Any] | None

    @property
    def kind(self) -> str:
        """``"episode"`` or ``"counterfactual"``."""
        return str(self.info["kind"])


_GROUPS: Final = ("factual", "counterfactual", "robot")
_READ_TOPICS: Final = {
    CHANNELS[k].topic: k
    for k in ("episode", "trajectories", "events", "metrics", "robot_state", "robot_command")
}


_PLANES_SINCE: Final = 5  # the first log schema version with bit-plane arrays
_MAGIC: Final = b"\x89MCAP0\r\n"
_FOOTER_BYTES: Final = 1 + 8 + 8 + 8 + 4  # opcode, length, two offsets, summary CRC
_SRFM_SCHEMA: Final = re.compile(r"^srfm\.logs\.[A-Za-z]+\.v(\d+)$")


def _mcap_errors() -> tuple[type[BaseException], ...]:
    import zstandard
    from mcap.exceptions import McapError

    return (
        McapError,
        struct.error,
        zstandard.ZstdError,
        EOFError,
        ValueError,
        KeyError,
        IndexError,
        TypeError,
        RuntimeError,
        UnicodeDecodeError,
    )


@attrs.frozen(kw_only=True)
class _Contents:
    """What :func:`_contents` found in a file."""

    library: str
    meta: Mapping[str, str]
    schema_names: frozenset[str]
    messages: list[tuple[str, str, bytes]]


def _corrupt(path: Path, detail: str) -> LogError:
    return LogError(f"{path}: not a readable MCAP file (truncated or corrupt: {detail})")


def _check_summary_crc(path: Path, data: bytes, summary_start: int, crc: int) -> None:
    """The footer's CRC of the summary section (the ``mcap`` library's readers do not
    check it): CRC-32 of everything from the summary's start up to the CRC field."""
    footer_at = len(data) - len(_MAGIC) - _FOOTER_BYTES
    if footer_at < 0 or data[footer_at] != 0x02 or not data.endswith(_MAGIC):
        raise _corrupt(path, "bytes after the footer")
    summary = memoryview(data)[summary_start : footer_at + _FOOTER_BYTES - 4]
    if crc != 0 and summary_start != 0 and zlib.crc32(summary) != crc:
        raise _corrupt(path, "the summary section fails its CRC")


def _contents(path: Path, data: bytes) -> _Contents:
    """Header library, the ``srfm`` metadata record, schema names and (channel key,
    schema name, payload) of our topics. The whole file is read with the ``mcap``
    library's stream reader, which checks the magic bytes, every record, every chunk's
    CRC and the data section's CRC; the summary's CRC is checked here."""
    from mcap.records import Channel, Footer, Header, Message, Metadata, Schema
    from mcap.stream_reader import StreamReader

    library = ""
    meta: dict[str, str] = {}
    schemas: dict[int, str] = {}
    channels: dict[int, Channel] = {}
    out: list[tuple[str, str, bytes]] = []
    footer: Footer | None = None
    try:
        for record in StreamReader(io.BytesIO(data), validate_crcs=True).records:
            if isinstance(record, Message):
                channel = channels[record.channel_id]
                key = _READ_TOPICS.get(channel.topic)
                if key is not None:
                    out.append((key, schemas.get(channel.schema_id, ""), record.data))
            elif isinstance(record, Schema):
                schemas[record.id] = record.name
            elif isinstance(record, Channel):
                channels[record.id] = record
            elif isinstance(record, Metadata) and record.name == _METADATA:
                meta = dict(record.metadata)
            elif isinstance(record, Header):
                library = record.library
            elif isinstance(record, Footer):
                footer = record
    except SrfmError:
        raise
    except _mcap_errors() as exc:
        raise _corrupt(path, str(exc) or type(exc).__name__) from None
    if footer is None:  # pragma: no cover - the stream reader stops at the footer
        raise _corrupt(path, "no footer")
    _check_summary_crc(path, data, footer.summary_start, footer.summary_crc)
    return _Contents(
        library=library, meta=meta, schema_names=frozenset(schemas.values()), messages=out
    )


def _writer_of(contents: _Contents) -> str:
    """``srfm X.Y.Z`` that wrote the file, from its metadata or header."""
    version = contents.meta.get("srfm_version")
    if not version and contents.library.startswith("srfm "):
        version = contents.library.removeprefix("srfm ")
    return f"srfm {version}" if version else "an unknown srfm version"


def _check_version(path: Path, contents: _Contents) -> int:
    """The file's log schema version; refuse one this srfm does not read, naming it and
    its writer."""
    versions = {
        int(m.group(1)) for name in contents.schema_names if (m := _SRFM_SCHEMA.match(name))
    }
    declared = contents.meta.get("schema_version", "")
    if declared.isdigit():
        versions.add(int(declared))
    other = sorted(versions - set(READ_VERSIONS))
    if other:
        readable = " or ".join(str(v) for v in READ_VERSIONS)
        raise LogError(
            f"{path}: log schema version {other[0]}, written by {_writer_of(contents)}; "
            f"this srfm ({_version()}) reads version {readable} only: read the file "
            "with the srfm release that wrote it, or run the episode again to log it anew"
        )
    if len(versions) > 1:
        raise LogError(f"{path}: mixes log schema versions {sorted(versions)}")
    return versions.pop() if versions else SCHEMA_VERSION


def _decode(path: Path, key: str, schema: str, payload: bytes, version: int) -> dict[str, Any]:
    expected = CHANNELS[key].schema_name.removesuffix(f".v{SCHEMA_VERSION}") + f".v{version}"
    if schema != expected:
        raise LogError(f"{path}: {CHANNELS[key].topic} has schema {schema!r}, not srfm's")
    try:
        doc = json.loads(payload)
    except (UnicodeDecodeError, ValueError) as exc:
        raise LogError(f"{path}: a {CHANNELS[key].topic} message is not JSON: {exc}") from None
    if not isinstance(doc, dict) or doc.get("schema_version") != version:
        raise LogError(f"{path}: a {CHANNELS[key].topic} message has no schema_version {version}")
    return doc


def array_from_npy(text: Any, where: str, planes: Any = None) -> NDArray[Any]:
    """Decode the base64 text of a ``.npy`` file holding a float64 or bool array, or,
    with ``planes`` (the array's shape), the uint8 bit planes of a float64 array
    (:mod:`srfm.logs._planes`).

    Raises:
        LogError: ``where`` names the array; the text is not base64, not a ``.npy``
            file, or holds another type (object arrays are never unpickled), or the
            planes do not fit the shape.
    """
    if not isinstance(text, str):
        raise LogError(f"{where}: expected the base64 text of a .npy file")
    try:
        raw = base64.b64decode(text, validate=True)
        array = np.lib.format.read_array(io.BytesIO(raw), allow_pickle=False)
    except (binascii.Error, ValueError, EOFError, OSError) as exc:
        raise LogError(f"{where}: not a base64 .npy array ({exc})") from None
    if planes is not None:
        ok = isinstance(planes, list) and all(type(n) is int and n >= 0 for n in planes)
        try:
            if not ok:
                raise ValueError(f"the shape {planes!r:.100} is not a list of sizes")
            return from_planes(array, tuple(planes))
        except ValueError as exc:
            raise LogError(f"{where}: {exc}") from None
    if array.dtype.kind == "f" and array.dtype.itemsize == 8:
        return np.array(array, dtype=np.float64, order="C")
    if array.dtype.kind == "b":
        return np.array(array, dtype=np.bool_, order="C")
    raise LogError(f"{where}: a .npy array of {array.dtype}, expected float64 or bool")


def read_log(path: str | Path) -> LogFile:
    """Read and check the srfm channels of one MCAP file.

    Raises:
        LogError: naming the file, when it cannot be read, is truncated or corrupt, is
            not an srfm log, was written in another log schema version (the message
            names it and the srfm that wrote it), or holds malformed arrays.
    """
    path = Path(path)
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise LogError(f"{path}: cannot read: {exc.strerror or exc}") from None
    if not data.startswith(_MAGIC):
        raise LogError(f"{path}: not an MCAP file (no MCAP magic bytes)")
    contents = _contents(path, data)
    version = _check_version(path, contents)
    info: dict[str, Any] | None = None
    groups: dict[str, dict[str, NDArray[Any]]] = {}
    lists: dict[str, list[dict[str, Any]]] = {
        "events": [],
        "robot_state": [],
        "robot_command": [],
    }
    metrics: dict[str, Any] | None = None
    for key, schema, payload in contents.messages:
        doc = _decode(path, key, schema, payload, version)
        if key == "episode":
            if info is not None:
                raise LogError(f"{path}: more than one /srfm/episode message")
            info = doc
        elif key == "trajectories":
            group = str(doc.get("group"))
            arrays = doc.get("arrays")
            planes = doc.get("planes") if version >= _PLANES_SINCE else {}
            if (
                not isinstance(arrays, dict)
                or not isinstance(planes, dict)
                or not set(planes) <= set(arrays)
                or group in groups
                or group not in _GROUPS
            ):
                raise LogError(f"{path}: malformed or repeated trajectory group {group!r}")
            groups[group] = {
                name: array_from_npy(text, f"{path}: {group}.{name}", planes.get(name))
                for name, text in arrays.items()
            }
        elif key in lists:
            lists[key].append(doc)
        else:
            metrics = doc
    if info is None:
        raise LogError(
            f"{path}: not an srfm run log (no /srfm/episode channel); "
            "srfm score reads files written by srfm simulate/benchmark --out"
        )
    if info.get("kind") not in ("episode", "counterfactual"):
        raise LogError(f"{path}: unknown log kind {info.get('kind')!r}")
    return LogFile(
        path=path,
        info=info,
        groups=groups,
        events=tuple(lists["events"]),
        robot_states=tuple(lists["robot_state"]),
        robot_commands=tuple(lists["robot_command"]),
        metrics=metrics,
    )


@attrs.frozen(kw_only=True, eq=False)
class LoggedEpisode:
    """An episode rebuilt from its MCAP log.

    Attributes:
        path: the episode's file.
        record: the rebuilt record (velocities exact only when ``exact_velocities``;
            otherwise finite differences of the exact positions, 0 at sample 0).
        info: the ``/srfm/episode`` message.
        online_metrics: the metrics stored when the episode ran, or None.
        exact_velocities: whether the pedestrian velocities were logged.
        counterfactual_path: the shared counterfactual file used, if any.
    """

    path: Path
    record: EpisodeRecord
    info: Mapping[str, Any]
    online_metrics: EpisodeMetrics | None
    exact_velocities: bool
    counterfactual_path: Path | None


def _get(path: Path, doc: Mapping[str, Any], key: str, kind: type | tuple[type, ...]) -> Any:
    value = doc.get(key)
    if not isinstance(value, kind) or (isinstance(value, bool) and kind is not bool):
        raise LogError(f"{path}: /srfm/episode field {key!r} is missing or malformed")
    return value


def _array(
    path: Path, group: Mapping[str, NDArray[Any]], name: str, shape: tuple[int, ...], what: str
) -> NDArray[Any]:
    if name not in group:
        raise LogError(f"{path}: no {what}.{name} array")
    a = group[name]
    if a.shape != shape:
        raise LogError(f"{path}: {what}.{name} has shape {a.shape}, expected {shape}")
    return a


def _derived_velocity(pos: FloatArray, dt: float) -> FloatArray:
    vel = np.zeros_like(pos)
    vel[1:] = np.diff(pos, axis=0) / dt
    return vel


def _times(path: Path, info: Mapping[str, Any], samples: int, dt: float) -> FloatArray:
    if "time_s" not in info:
        return np.arange(samples, dtype=np.float64) * dt
    try:
        times = np.array(info["time_s"], dtype=np.float64)
    except (TypeError, ValueError):
        times = np.zeros(0)
    if times.shape != (samples,):
        raise LogError(f"{path}: /srfm/episode time_s is malformed")
    return times


def _robot(
    path: Path, log: LogFile, samples: int
) -> tuple[FloatArray, FloatArray, NDArray[np.bool_], FloatArray]:
    """Robot pose, velocity, activity and commands from the exact robot block (the
    per-sample robot messages are for plotting)."""
    if "robot" not in log.groups:
        raise LogError(f"{path}: the robot's trajectory block is missing")
    g = log.groups["robot"]
    pose = _array(path, g, "pose", (samples, 3), "robot")
    vel = _array(path, g, "vel", (samples, 2), "robot")
    active = _array(path, g, "active", (samples,), "robot")
    cmd = _array(path, g, "cmd", (samples - 1, 2), "robot")
    if active.dtype != np.bool_ or pose.dtype != np.float64 or cmd.dtype != np.float64:
        raise LogError(f"{path}: the robot block has arrays of the wrong type")
    return pose, vel, active, cmd


def _events(path: Path, docs: tuple[Mapping[str, Any], ...]) -> tuple[Event, ...]:
    out = []
    for d in docs:
        kind = d.get("kind")
        if kind not in EVENT_KINDS:
            raise LogError(f"{path}: unknown event kind {kind!r}")
        try:
            out.append(
                Event(
                    step=int(d["step"]),
                    time_s=float(d["time_s"]),
                    kind=kind,
                    agent=int(d["agent"]),
                    twin=str(d["twin"]),
                )
            )
        except (KeyError, TypeError, ValueError):
            raise LogError(f"{path}: malformed event {dict(d)!r}") from None
    return tuple(out)


def _metrics(path: Path, doc: Mapping[str, Any] | None) -> EpisodeMetrics | None:
    if doc is None:
        return None

    try:
        return EpisodeMetrics.from_document(doc)
    except (KeyError, TypeError, ValueError):
        raise LogError(f"{path}: malformed /srfm/metrics message") from None


def load_episode(
    path: str | Path, *, counterfactuals: dict[Path, LogFile] | None = None
) -> LoggedEpisode:
    """Rebuild an episode (record and online metrics) from its MCAP log alone.

    Args:
        path: an episode ``.mcap`` written by :func:`write_episode_mcap`.
        counterfactuals: a cache of shared counterfactual files already read, by
            resolved path (filled as files are read).

    Raises:
        LogError: the file (or the counterfactual file it names) is unreadable, foreign,
            inconsistent, or does not match its fingerprint.
    """
    return episode_from_log(read_log(path), counterfactuals=counterfactuals)


def _enter_steps(path: Path, value: Any, n: int, horizon: int) -> NDArray[np.int64] | None:
    """The pedestrians' entry samples of a log (None when it has none): N integers in
    0..horizon, in increasing order."""
    if value is None:
        return None
    ok = isinstance(value, list) and len(value) == n
    ok = ok and all(type(v) is int and 0 <= v <= horizon for v in value)
    if not ok or any(b < a for a, b in itertools.pairwise(value)):
        raise LogError(
            f"{path}: pedestrians.enter_step must be {n} increasing sample indices in "
            f"0..{horizon}, got {value!r:.200}"
        )
    return np.array(value, dtype=np.int64)


def episode_from_log(
    log: LogFile, *, counterfactuals: dict[Path, LogFile] | None = None
) -> LoggedEpisode:
    """:func:`load_episode` on a file already read with :func:`read_log`."""
    p = log.path
    info = log.info
    if log.kind != "episode":
        raise LogError(f"{p}: a shared counterfactual file, not an episode")
    scenario = _get(p, info, "scenario", str)
    seed = _get(p, info, "seed", int)
    dt = float(_get(p, info, "dt_s", (int, float)))
    horizon = _get(p, info, "horizon_steps", int)
    n = _get(p, info, "n_pedestrians", int)
    outcome = _get(p, info, "outcome", str)
    end_step = _get(p, info, "end_step", int)
    if outcome not in ROBOT_OUTCOMES:
        raise LogError(f"{p}: unknown robot outcome {outcome!r}")
    if info.get("robot_states") not in ("all", "frames"):
        raise LogError(f"{p}: /srfm/episode field 'robot_states' is missing or malformed")
    try:
        params = SRFMParams(**_get(p, info, "params", dict))
        radius = np.array(info["pedestrians"]["radius_m"], dtype=np.float64)
        enter_step = _enter_steps(p, info["pedestrians"].get("enter_step"), n, horizon)
        robot = info["robot"]
        robot_goal = np.array(robot["goal"], dtype=np.float64)
        robot_radius = float(robot["radius_m"])
        robot_goal_radius = float(robot["goal_radius_m"])
        kinematics = str(robot["kinematics"])
        cf_ref = info["counterfactual"]
        cf_file, cf_digest = cf_ref["file"], str(cf_ref["sha256"])
    except (KeyError, TypeError, ValueError, SrfmError) as exc:
        raise LogError(f"{p}: malformed /srfm/episode message ({exc})") from None
    samples = horizon + 1
    ped_shape = (samples, n, 2)
    if "factual" not in log.groups:
        raise LogError(f"{p}: the trajectories of the factual crowd are missing")
    f = log.groups["factual"]
    cf_path: Path | None = None
    if cf_file is None:
        if "counterfactual" not in log.groups:
            raise LogError(f"{p}: the counterfactual trajectories are missing")
        c = log.groups["counterfactual"]
    else:
        cf_path = (p.parent / str(cf_file)).resolve()
        cache = counterfactuals if counterfactuals is not None else {}
        if cf_path not in cache:
            if not cf_path.exists():
                raise LogError(f"{p}: its counterfactual file {cf_path} is missing")
            cache[cf_path] = read_log(cf_path)
        cf_log = cache[cf_path]
        ci = cf_log.info
        if cf_log.kind != "counterfactual" or "counterfactual" not in cf_log.groups:
            raise LogError(f"{cf_path}: not a shared counterfactual file (named by {p})")
        for key in ("scenario", "seed", "dt_s", "horizon_steps", "n_pedestrians", "params"):
            if ci.get(key) != info.get(key):
                raise LogError(
                    f"{cf_path}: {key} {ci.get(key)!r} does not match {p} ({info.get(key)!r})"
                )
        c = cf_log.groups["counterfactual"]
    f_pos = _array(p, f, "pos", ped_shape, "factual")
    c_pos = _array(p, c, "pos", ped_shape, "counterfactual")
    f_goal = _array(p, f, "goal", ped_shape, "factual")
    c_goal = _array(p, c, "goal", ped_shape, "counterfactual")
    if counterfactual_digest(c_pos, c_goal) != cf_digest:
        where = cf_path if cf_path is not None else p
        raise LogError(f"{where}: the counterfactual crowd does not match the fingerprint in {p}")
    exact = "vel" in f and "vel" in c
    f_vel = _array(p, f, "vel", ped_shape, "factual") if exact else _derived_velocity(f_pos, dt)
    c_vel = (
        _array(p, c, "vel", ped_shape, "counterfactual") if exact else _derived_velocity(c_pos, dt)
    )
    pose, rvel, active, cmd = _robot(p, log, samples)
    if radius.shape != (n,) or robot_goal.shape != (2,):
        raise LogError(f"{p}: pedestrian radii or robot goal have the wrong shape")
    if not 0 <= end_step <= horizon:
        raise LogError(f"{p}: end_step {end_step} outside 0..{horizon}")
    record = EpisodeRecord(
        scenario=scenario,
        seed=seed,
        planner=_get(p, info, "planner", str),
        params=params,
        dt_s=dt,
        horizon_steps=horizon,
        time_s=_times(p, info, samples, dt),
        ped_radius=radius,
        factual_pos=f_pos,
        factual_vel=f_vel,
        counterfactual_pos=c_pos,
        counterfactual_vel=c_vel,
        factual_goal=f_goal,
        counterfactual_goal=c_goal,
        robot_pose=pose,
        robot_vel=rvel,
        robot_cmd=cmd,
        robot_active=active,
        robot_goal=robot_goal,
        robot_radius=robot_radius,
        robot_goal_radius_m=robot_goal_radius,
        robot_kinematics=kinematics,
        outcome=outcome,
        end_step=end_step,
        events=_events(p, log.events),
        ped_enter_step=enter_step,
    )
    return LoggedEpisode(
        path=p,
        record=record,
        info=info,
        online_metrics=_metrics(p, log.metrics),
        exact_velocities=exact,
        counterfactual_path=cf_path,
    )
