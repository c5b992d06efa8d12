"""srfm's own MCAP writer against the mcap library's readers (summary, CRCs, records)."""

from __future__ import annotations

import io
import zlib
from collections import Counter
from pathlib import Path

import pytest
from mcap.reader import make_reader
from mcap.records import Chunk, DataEnd, Footer, Header, Metadata, Schema
from mcap.stream_reader import CRCValidationError, StreamReader

from srfm.errors import LogError
from srfm.logs import _mcap, load_episode, write_episode_mcap
from srfm.logs._codec import encode_array
from srfm.logs._mcap_writer import McapBuilder


def _build() -> bytes:
    b = McapBuilder(library="test")
    b.metadata("srfm", {"kind": "test"})
    s1 = b.schema("a.v1", "jsonschema", b"{}")
    c1 = b.channel("/a", "json", s1)
    b.add(c1, 30, b'{"i":0}')
    b.add_many(c1, [10, 20], [b'{"i":1}', b'{"i":2}'])  # out of time order: allowed
    b.end_chunk()
    b.end_chunk()  # nothing to write: no empty chunk
    s2 = b.schema("b.v1", "jsonschema", b'{"type":"object"}')
    c2 = b.channel("/b", "json", s2)
    b.end_chunk()  # no message yet: the schema and channel records wait for one
    b.add(c2, 5, b"{}")
    b.add_many(c2, [], [])
    return b.finish()


def test_the_seeking_reader_finds_the_summary_and_every_message() -> None:
    data = _build()
    reader = make_reader(io.BytesIO(data), validate_crcs=True)
    summary = reader.get_summary()
    assert summary is not None
    stats = summary.statistics
    assert (stats.message_count, stats.schema_count, stats.channel_count) == (4, 2, 2)
    assert (stats.chunk_count, stats.metadata_count, stats.attachment_count) == (2, 1, 0)
    assert (stats.message_start_time, stats.message_end_time) == (5, 30)
    assert dict(stats.channel_message_counts) == {1: 3, 2: 1}
    assert [(i.message_start_time, i.message_end_time) for i in summary.chunk_indexes] == [
        (10, 30),
        (5, 5),
    ]
    assert {s.name for s in summary.schemas.values()} == {"a.v1", "b.v1"}
    msgs = [(c.topic, m.log_time, m.publish_time, m.data) for _, c, m in reader.iter_messages()]
    assert msgs == [
        ("/b", 5, 5, b"{}"),
        ("/a", 10, 10, b'{"i":1}'),
        ("/a", 20, 20, b'{"i":2}'),
        ("/a", 30, 30, b'{"i":0}'),
    ]
    assert next(iter(reader.iter_metadata())).metadata == {"kind": "test"}


def test_the_streaming_reader_checks_every_crc() -> None:
    data = _build()
    records = list(StreamReader(io.BytesIO(data), emit_chunks=True, validate_crcs=True).records)
    kinds = Counter(type(r).__name__ for r in records)
    assert isinstance(records[0], Header)
    assert isinstance(records[1], Metadata)
    assert kinds["Chunk"] == 2
    assert kinds["MessageIndex"] == 0
    assert kinds["DataEnd"] == 1
    chunks = [r for r in records if isinstance(r, Chunk)]
    assert all(c.compression == "zstd" and c.uncompressed_crc != 0 for c in chunks)
    (end,) = [r for r in records if isinstance(r, DataEnd)]
    data_end_at = data.index(b"\x0f\x04\x00\x00\x00\x00\x00\x00\x00")
    assert end.data_section_crc == zlib.crc32(data[:data_end_at])
    # Schemas are in the data section (inside chunks) and repeated in the summary.
    assert kinds["Schema"] == 2  # the summary's
    inside = list(StreamReader(io.BytesIO(data), validate_crcs=True).records)
    assert sum(isinstance(r, Schema) for r in inside) == 4


def test_a_flipped_byte_in_a_chunk_fails_its_crc() -> None:
    data = bytearray(_build())
    data[data.index(b"zstd") + 30] ^= 0x01
    with pytest.raises(CRCValidationError, match="Chunk"):
        list(StreamReader(io.BytesIO(bytes(data)), validate_crcs=True).records)
    with pytest.raises(CRCValidationError, match="Chunk"):
        list(make_reader(io.BytesIO(bytes(data)), validate_crcs=True).iter_messages())


def test_the_footer_holds_the_crc_of_the_summary() -> None:
    data = _build()
    (footer,) = [r for r in StreamReader(io.BytesIO(data)).records if isinstance(r, Footer)]
    footer_at = len(data) - 8 - (1 + 8 + 8 + 8 + 4)
    assert data[footer_at] == 0x02
    assert footer.summary_crc == zlib.crc32(data[footer.summary_start : footer_at + 1 + 8 + 16])
    assert 0 < footer.summary_start < footer.summary_offset_start < footer_at


def test_the_robot_block_is_required_and_checked(
    tmp_path: Path, episode, monkeypatch: pytest.MonkeyPatch
) -> None:  # type: ignore[no-untyped-def]
    scenario, record, metrics = episode("concert", 0, "straight")

    def short_pose(r):  # type: ignore[no-untyped-def]
        arrays = {
            "pose": encode_array(r.robot_pose[:-1]),
            "vel": encode_array(r.robot_vel),
            "active": encode_array(r.robot_active),
            "cmd": encode_array(r.robot_cmd),
        }
        return _mcap._trajectories("robot", r.time_s.shape[0], arrays)

    monkeypatch.setattr(_mcap, "_robot_arrays", short_pose)
    write_episode_mcap(tmp_path / "short.mcap", record, scenario=scenario, metrics=metrics)
    with pytest.raises(LogError, match=r"short\.mcap: robot\.pose has shape"):
        load_episode(tmp_path / "short.mcap")

    original = _mcap._Writer.add

    def no_robot(self, key: str, t_ns: int, data: bytes) -> None:  # type: ignore[no-untyped-def]
        if not data.startswith(b'{"schema_version":2,"group":"robot"'):
            original(self, key, t_ns, data)

    monkeypatch.setattr(_mcap._Writer, "add", no_robot)
    write_episode_mcap(tmp_path / "none.mcap", record, scenario=scenario, metrics=metrics)
    with pytest.raises(LogError, match=r"none\.mcap: the robot's trajectory block is missing"):
        load_episode(tmp_path / "none.mcap")
