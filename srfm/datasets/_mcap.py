"""The MCAP layout of srfm datasets: one JSON channel per scene, one message per frame.

Layout (schema version 1; see ``datasets/README.md`` for the full description):

- one channel per scene, topic ``/trajectories/<scene>``, message encoding ``json``,
  schema ``srfm.datasets.AgentFrame.v1`` (encoding ``jsonschema``), channel metadata
  ``{"scene": <scene>}``;
- one message per frame of the scene, log time = publish time = the frame's timestamp
  in integer nanoseconds, holding every agent observed in that frame::

      {"schema_version": 1, "scene": "students003", "frame": 120,
       "timestamp_ns": 4800000000, "frame_of_reference": "world",
       "agents": [{"id": "12", "kind": "pedestrian", "x": 3.1, "y": 7.4}, ...]}

  (an agent whose source gives a heading also has ``"yaw"`` in rad, optional);

- a metadata record ``srfm.datasets`` (schema, schema version, dataset, srfm version,
  number of scenes) and one ``srfm.datasets.scene`` record per scene (scene, topic,
  frame of reference, agent table as JSON lists, and the adapter's source metadata
  under ``source.*`` keys);
- zstd-compressed chunks with every index, a summary section and CRCs (chunks, data
  section, summary), written by the ``mcap`` library's ``Writer`` with its defaults plus
  the data-section CRC, so any MCAP reader (``mcap`` CLI, Foxglove, ``rerun mcap``,
  ``@mcap/core``) opens it. The reader checks the chunk CRCs.
"""

from __future__ import annotations

import io
import json
import math
import re
import struct
import zlib
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any, Final

import attrs
import numpy as np

from srfm._io import atomic_write_bytes
from srfm._text import plain
from srfm._version import __version__
from srfm.datasets._trajectories import AGENT_KINDS, FRAMES_OF_REFERENCE, Trajectories
from srfm.errors import DatasetError

__all__ = [
    "FRAME_SCHEMA",
    "SCHEMA_NAME",
    "SCHEMA_VERSION",
    "DatasetFile",
    "read_mcap",
    "write_mcap",
]

SCHEMA_VERSION: Final = 1
SCHEMA_NAME: Final = f"srfm.datasets.AgentFrame.v{SCHEMA_VERSION}"
TOPIC_PREFIX: Final = "/trajectories/"
FILE_RECORD: Final = "srfm.datasets"
SCENE_RECORD: Final = "srfm.datasets.scene"
_SCHEMA_RE: Final = re.compile(r"^srfm\.datasets\.AgentFrame\.v(\d+)$")

FRAME_SCHEMA: Final[dict[str, Any]] = {
    "$schema": "https://json-schema.org/draft/2020-12/schema",
    "$id": SCHEMA_NAME,
    "title": SCHEMA_NAME,
    "description": (
        "Every agent observed in one frame of one dataset scene. Positions in metres in "
        "the scene's frame of reference; timestamp in integer nanoseconds."
    ),
    "type": "object",
    "properties": {
        "schema_version": {"const": SCHEMA_VERSION},
        "scene": {"type": "string", "description": "scene name (one channel per scene)"},
        "frame": {"type": "integer", "description": "source frame number"},
        "timestamp_ns": {"type": "integer", "minimum": 0, "description": "time (ns)"},
        "frame_of_reference": {"enum": list(FRAMES_OF_REFERENCE)},
        "agents": {
            "type": "array",
            "items": {
                "type": "object",
                "properties": {
                    "id": {"type": "string", "description": "agent id, unique in the scene"},
                    "kind": {"enum": list(AGENT_KINDS)},
                    "x": {"type": "number", "description": "x (m)"},
                    "y": {"type": "number", "description": "y (m)"},
                    "yaw": {
                        "type": "number",
                        "description": "heading (rad), only where the source gives one",
                    },
                },
                "required": ["id", "kind", "x", "y"],
                "additionalProperties": False,
            },
        },
    },
    "required": [
        "schema_version",
        "scene",
        "frame",
        "timestamp_ns",
        "frame_of_reference",
        "agents",
    ],
    "additionalProperties": False,
}


@attrs.frozen(kw_only=True)
class DatasetFile:
    """The content of one srfm dataset MCAP file.

    Attributes:
        path: the file.
        dataset: the dataset it was converted from (``jrdb``, ``eth-ucy``, ...).
        metadata: the file-level ``srfm.datasets`` metadata record.
        scenes: the scenes, in the order they were written.
    """

    path: Path
    dataset: str
    metadata: Mapping[str, str]
    scenes: tuple[Trajectories, ...]


def write_mcap(
    path: str | Path,
    scenes: Sequence[Trajectories],
    *,
    dataset: str,
    metadata: Mapping[str, str] | None = None,
    progress: Callable[[int], None] | None = None,
) -> None:
    """Write scenes to an MCAP file in the srfm dataset layout, atomically.

    The whole file is built in memory and then written to a temporary file that is
    renamed over ``path``, so a failure never leaves a partial file.

    Args:
        path: destination ``.mcap`` file.
        scenes: scenes with distinct names.
        dataset: the source dataset's name, stored in the file-level metadata.
        metadata: extra file-level metadata (string to string).
        progress: called with the number of frames written after each scene.

    Raises:
        DatasetError: no scenes, a scene without samples (the layout stores a scene
            as its frames), duplicate scene names, or bad metadata.
    """
    from mcap.writer import CompressionType, Writer

    path = Path(path)
    if not scenes:
        raise DatasetError(f"{path}: nothing to write (no scenes)")
    names = [s.scene for s in scenes]
    if len(set(names)) != len(names):
        dup = next(n for n in names if names.count(n) > 1)
        raise DatasetError(f"{path}: duplicate scene name {dup!r}")
    for scene in scenes:
        if scene.agent.shape[0] == 0:
            raise DatasetError(f"{path}: scene {scene.scene!r} has no samples; nothing to write")
    extra = dict(metadata or {})
    for key, value in extra.items():
        if not isinstance(key, str) or not isinstance(value, str):
            raise DatasetError(f"{path}: metadata must map str to str, got {plain(key)}: {value!r}")

    buf = io.BytesIO()
    writer = Writer(buf, compression=CompressionType.ZSTD, enable_data_crcs=True)
    writer.start(profile="", library=f"srfm {__version__}")
    schema_id = writer.register_schema(
        name=SCHEMA_NAME,
        encoding="jsonschema",
        data=json.dumps(FRAME_SCHEMA, sort_keys=True).encode("utf-8"),
    )
    for scene in scenes:
        topic = TOPIC_PREFIX + scene.scene
        channel_id = writer.register_channel(
            topic=topic,
            message_encoding="json",
            schema_id=schema_id,
            metadata={"scene": scene.scene},
        )
        count = 0
        for frame, t_ns, rows in _frames(scene):
            msg = {
                "schema_version": SCHEMA_VERSION,
                "scene": scene.scene,
                "frame": frame,
                "timestamp_ns": t_ns,
                "frame_of_reference": scene.frame_of_reference,
                "agents": [_agent_item(scene, k, a) for k, a in rows],
            }
            writer.add_message(
                channel_id=channel_id,
                log_time=t_ns,
                publish_time=t_ns,
                sequence=count,
                data=json.dumps(msg, allow_nan=False).encode("utf-8"),
            )
            count += 1
        record = {
            "scene": scene.scene,
            "topic": topic,
            "frame_of_reference": scene.frame_of_reference,
            "agent_ids": json.dumps(list(scene.agent_ids)),
            "agent_kinds": json.dumps(list(scene.kinds)),
        }
        record.update({f"source.{k}": v for k, v in scene.source.items()})
        writer.add_metadata(name=SCENE_RECORD, data=record)
        if progress is not None:
            progress(count)
    file_record = {
        "schema": SCHEMA_NAME,
        "schema_version": str(SCHEMA_VERSION),
        "dataset": dataset,
        "scenes": str(len(scenes)),
        "srfm_version": __version__,
    }
    file_record.update(extra)
    writer.add_metadata(name=FILE_RECORD, data=file_record)
    writer.finish()  # type: ignore[no-untyped-call]
    atomic_write_bytes(path, buf.getvalue())


def _agent_item(scene: Trajectories, k: int, a: int) -> dict[str, Any]:
    item: dict[str, Any] = {
        "id": scene.agent_ids[a],
        "kind": scene.kinds[a],
        "x": float(scene.xy[k, 0]),
        "y": float(scene.xy[k, 1]),
    }
    if scene.yaw is not None and not math.isnan(scene.yaw[k]):
        item["yaw"] = float(scene.yaw[k])
    return item


def _frames(scene: Trajectories) -> list[tuple[int, int, list[tuple[int, int]]]]:
    """(frame, t_ns, [(sample index, agent index), ...]) per frame, in time order."""
    out: list[tuple[int, int, list[tuple[int, int]]]] = []
    if scene.n_samples == 0:
        return out
    bounds = np.flatnonzero(np.diff(scene.frame)) + 1
    starts = np.concatenate([[0], bounds])
    ends = np.concatenate([bounds, [scene.n_samples]])
    for s, e in zip(starts.tolist(), ends.tolist(), strict=True):
        rows = [(k, int(scene.agent[k])) for k in range(s, e)]
        out.append((int(scene.frame[s]), int(scene.t_ns[s]), rows))
    return out


_MAGIC_BYTES: Final = 8
_FOOTER_BYTES: Final = 29  # opcode, length, summary start, summary offset start, CRC
_DATA_END_BYTES: Final = 13  # opcode, length, data section CRC
_OP_FOOTER: Final = 0x02
_OP_DATA_END: Final = 0x0F


def _check_file_crcs(path: Path, data: bytes) -> None:
    """Validate the two whole-file CRC-32s of an MCAP file (the data section's, in its
    DataEnd record, and the summary section's, in its footer).

    The mcap reader checks each chunk's CRC but neither of these, so a flip in a
    record outside the chunks (header, metadata, attachments' framing, the summary)
    would otherwise be read silently. A CRC of 0 means "not recorded" (MCAP spec).

    Raises:
        DatasetError: a CRC does not match, or the file's framing is not MCAP's.
    """
    end = len(data) - _MAGIC_BYTES
    if end - _FOOTER_BYTES - _DATA_END_BYTES < _MAGIC_BYTES:
        raise DatasetError(f"{path}: not a readable MCAP file (too short)")
    op, _, summary_start, _, summary_crc = struct.unpack("<BQQQI", data[end - _FOOTER_BYTES : end])
    data_end = (summary_start if summary_start else end - _FOOTER_BYTES) - _DATA_END_BYTES
    if op != _OP_FOOTER or not _MAGIC_BYTES <= data_end <= end - _FOOTER_BYTES:
        raise DatasetError(f"{path}: not a readable MCAP file (bad footer)")
    op, _, data_crc = struct.unpack("<BQI", data[data_end : data_end + _DATA_END_BYTES])
    if op != _OP_DATA_END:
        raise DatasetError(f"{path}: not a readable MCAP file (no DataEnd record)")
    if data_crc and zlib.crc32(data[:data_end]) != data_crc:
        raise DatasetError(
            f"{path}: not a readable MCAP file (damaged: the data section's CRC does not match)"
        )
    if summary_start and summary_crc and zlib.crc32(data[summary_start : end - 4]) != summary_crc:
        raise DatasetError(
            f"{path}: not a readable MCAP file (damaged: the summary section's CRC does not match)"
        )


def read_mcap(path: str | Path) -> DatasetFile:
    """Read an srfm dataset MCAP file written by :func:`write_mcap`.

    Args:
        path: the ``.mcap`` file.

    Returns:
        The scenes and the file-level metadata.

    Raises:
        DatasetError: the file is missing, not MCAP, has no srfm dataset channel, uses a
            newer schema version, or holds a malformed message (the message names the
            topic and log time).
    """
    import zstandard
    from mcap.exceptions import McapError
    from mcap.reader import make_reader

    path = Path(path)
    try:
        with path.open("rb") as fh:
            _check_file_crcs(path, fh.read())
            fh.seek(0)
            reader = make_reader(fh, validate_crcs=True)
            library = reader.get_header().library
            meta_records = [(m.name, dict(m.metadata)) for m in reader.iter_metadata()]
            file_meta = next((m for name, m in meta_records if name == FILE_RECORD), None)
            writer = _writer_of(library, file_meta)
            raw: dict[int, list[tuple[str, str, int, bytes]]] = {}
            for schema, channel, message in reader.iter_messages(log_time_order=False):
                if schema is None or not schema.name.startswith("srfm.datasets.AgentFrame"):
                    continue
                _check_schema(path, schema.name, schema.encoding, channel.message_encoding, writer)
                raw.setdefault(channel.id, []).append(
                    (
                        channel.topic,
                        channel.metadata.get("scene", ""),
                        message.log_time,
                        message.data,
                    )
                )
    except FileNotFoundError:
        raise DatasetError(f"{path}: file not found") from None
    except IsADirectoryError:
        raise DatasetError(f"{path}: is a directory, expected an .mcap file") from None
    except (
        McapError,
        struct.error,
        zstandard.ZstdError,
        EOFError,
        ValueError,
        KeyError,
        OverflowError,
        MemoryError,
        UnicodeDecodeError,
    ) as exc:
        # a damaged file: any decoding failure is the file's fault, named as such
        if isinstance(exc, DatasetError):
            raise
        raise DatasetError(
            f"{path}: not a readable MCAP file ({type(exc).__name__}: {exc})"
        ) from None
    except OSError as exc:
        raise DatasetError(f"{path}: cannot read: {exc.strerror}") from None

    scene_meta = {m.get("scene", ""): m for name, m in meta_records if name == SCENE_RECORD}
    if not raw:
        if file_meta is None:
            raise DatasetError(
                f"{path}: not an srfm dataset file (no channel with schema {SCHEMA_NAME})"
            )
        raise DatasetError(f"{path}: srfm dataset file without any frame message")
    scenes = [
        _scene_from_messages(path, messages, scene_meta) for _, messages in sorted(raw.items())
    ]
    names = [s.scene for s in scenes]
    if len(set(names)) != len(names):
        dup = next(n for n in names if names.count(n) > 1)
        raise DatasetError(f"{path}: scene {dup!r} appears on two channels")
    meta = dict(file_meta or {})
    return DatasetFile(
        path=path, dataset=meta.get("dataset", "unknown"), metadata=meta, scenes=tuple(scenes)
    )


def _writer_of(library: str, file_meta: Mapping[str, str] | None) -> str:
    """``srfm X.Y.Z`` that wrote a file, from its metadata or MCAP header."""
    version = (file_meta or {}).get("srfm_version")
    if not version and library.startswith("srfm "):
        version = library.removeprefix("srfm ")
    return f"srfm {version}" if version else "an unknown srfm version"


def _check_schema(path: Path, name: str, encoding: str, message_encoding: str, writer: str) -> None:
    match = _SCHEMA_RE.match(name)
    if match is None:
        raise DatasetError(f"{path}: unrecognised srfm dataset schema name {name!r}")
    version = int(match.group(1))
    if version != SCHEMA_VERSION:
        raise DatasetError(
            f"{path}: dataset schema version {version}, written by {writer}; this srfm "
            f"({__version__}) reads version {SCHEMA_VERSION} only: convert the data again"
        )
    if encoding != "jsonschema" or message_encoding != "json":
        raise DatasetError(
            f"{path}: schema {name!r} must use schema encoding 'jsonschema' and message "
            f"encoding 'json', got {plain(encoding)} and {message_encoding!r}"
        )


def _scene_from_messages(
    path: Path,
    messages: list[tuple[str, str, int, bytes]],
    scene_meta: Mapping[str, Mapping[str, str]],
) -> Trajectories:
    topic, channel_scene = messages[0][0], messages[0][1]
    meta = scene_meta.get(channel_scene, {})
    ids: list[str] = []
    kinds: list[str] = []
    if meta:
        try:
            ids = list(json.loads(meta["agent_ids"]))
            kinds = list(json.loads(meta["agent_kinds"]))
        except (KeyError, TypeError, json.JSONDecodeError):
            raise DatasetError(
                f"{path}: scene metadata of {channel_scene!r} has no valid agent table"
            ) from None
    index = {a: i for i, a in enumerate(ids)}
    agent: list[int] = []
    frame: list[int] = []
    t_ns: list[int] = []
    xy: list[tuple[float, float]] = []
    yaw: list[float] = []
    frame_of_reference: str | None = None
    scene_name = channel_scene
    for _, _, log_time, data in messages:
        where = f"{path}: topic {topic!r}, message at log time {log_time} ns"
        try:
            msg = json.loads(data)
        except (json.JSONDecodeError, UnicodeDecodeError) as exc:
            raise DatasetError(f"{where}: not valid JSON ({exc})") from None
        if not isinstance(msg, dict):
            raise DatasetError(f"{where}: expected a JSON object")
        missing = sorted(set(FRAME_SCHEMA["required"]) - set(msg))
        if missing:
            raise DatasetError(f"{where}: missing key {missing[0]!r}")
        if msg["schema_version"] != SCHEMA_VERSION:
            raise DatasetError(f"{where}: schema_version {msg['schema_version']!r} != 1")
        scene_name = msg["scene"]
        if channel_scene and scene_name != channel_scene:
            raise DatasetError(f"{where}: scene {scene_name!r} on the channel of {channel_scene!r}")
        fr = _json_int(msg["frame"], "frame", where)
        ts = _json_int(msg["timestamp_ns"], "timestamp_ns", where)
        if ts != log_time:
            raise DatasetError(f"{where}: timestamp_ns {ts} differs from the log time")
        ref = msg["frame_of_reference"]
        if frame_of_reference is None:
            frame_of_reference = ref
        elif ref != frame_of_reference:
            raise DatasetError(f"{where}: frame_of_reference changes to {ref!r}")
        agents = msg["agents"]
        if not isinstance(agents, list):
            raise DatasetError(f"{where}: agents must be a list")
        for j, item in enumerate(agents):
            at = f"{where}, agents[{j}]"
            if not isinstance(item, dict) or not {"id", "kind", "x", "y"} <= set(item):
                raise DatasetError(f"{at}: expected an object with id, kind, x, y")
            aid, kind = item["id"], item["kind"]
            if not isinstance(aid, str):
                raise DatasetError(f"{at}: id must be a string, got {plain(aid)}")
            if aid not in index:
                if meta:
                    raise DatasetError(f"{at}: agent {aid!r} is not in the scene's agent table")
                index[aid] = len(ids)
                ids.append(aid)
                kinds.append(kind)
            if kinds[index[aid]] != kind:
                raise DatasetError(f"{at}: agent {aid!r} changes kind to {kind!r}")
            agent.append(index[aid])
            frame.append(fr)
            t_ns.append(ts)
            xy.append((_json_float(item["x"], "x", at), _json_float(item["y"], "y", at)))
            yaw.append(_json_float(item["yaw"], "yaw", at) if "yaw" in item else math.nan)
    source = {k.removeprefix("source."): v for k, v in meta.items() if k.startswith("source.")}
    try:
        return Trajectories.from_samples(
            scene=scene_name,
            agent_ids=ids,
            kinds=kinds,
            agent=np.array(agent, dtype=np.int64),
            frame=np.array(frame, dtype=np.int64),
            t_ns=np.array(t_ns, dtype=np.int64),
            xy=np.array(xy, dtype=np.float64).reshape(-1, 2),
            frame_of_reference=frame_of_reference or meta.get("frame_of_reference", "world"),
            source=source,
            yaw=None if all(math.isnan(v) for v in yaw) else np.array(yaw, dtype=np.float64),
        )
    except DatasetError as exc:
        raise DatasetError(f"{path}: topic {topic!r}: {exc}") from None


def _json_int(value: Any, name: str, where: str) -> int:
    if isinstance(value, bool) or not isinstance(value, int):
        raise DatasetError(f"{where}: {name} must be an integer, got {plain(value)}")
    return value


def _json_float(value: Any, name: str, where: str) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise DatasetError(f"{where}: {name} must be a finite number, got {plain(value)}")
    return float(value)
