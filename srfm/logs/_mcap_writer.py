"""A small, fast MCAP writer: chunked, zstd-compressed, with CRCs and a summary section.

The ``mcap`` library's :class:`mcap.writer.Writer` builds every message record through
several Python calls (about 20 µs a message), which made writing a benchmark episode's
few hundred messages cost more than simulating it. This writer packs a message record
with one :func:`struct.pack` and joins a chunk's records once; the rare records
(header, schemas, channels, metadata, chunk, chunk index, statistics, summary offsets,
footer) are serialised by the ``mcap`` library's own record classes, so their layout is
the library's. The file has the same structure as the library writer's with
``IndexType.CHUNK | IndexType.METADATA`` and data CRCs on: schemas and channels inside
the chunk of their first message and repeated in the summary, no message index records,
a statistics record, chunk and metadata indexes, summary offsets, and CRCs of every
chunk, of the data section and of the summary.
"""

from __future__ import annotations

import struct
import zlib
from collections.abc import Mapping, Sequence
from typing import Final

from mcap.data_stream import RecordBuilder
from mcap.opcode import Opcode
from mcap.records import (
    Channel,
    Chunk,
    ChunkIndex,
    DataEnd,
    Footer,
    Header,
    McapRecord,
    Metadata,
    MetadataIndex,
    Schema,
    Statistics,
    SummaryOffset,
)

__all__ = ["McapBuilder"]

MAGIC: Final = b"\x89MCAP0\r\n"
_MESSAGE_HEAD: Final = struct.Struct("<BQHIQQ")  # opcode, length, channel, sequence, times
_MESSAGE_FIXED: Final = 2 + 4 + 8 + 8
_OP_MESSAGE: Final = int(Opcode.MESSAGE)
_ZSTD_LEVEL: Final = 3  # the mcap library's (zstandard's default level)


def _record(record: McapRecord) -> bytes:
    builder = RecordBuilder()
    record.write(builder)
    out: bytes = builder.end()  # type: ignore[no-untyped-call]
    return out


class McapBuilder:
    """Builds one MCAP file in memory.

    Schemas and channels are registered once (:meth:`schema`, :meth:`channel`); their
    records go into the chunk being built, before its first message on them. Messages
    are added with :meth:`add` or, many at once, :meth:`add_many`; :meth:`end_chunk`
    closes the chunk (the next messages start a new one) and :meth:`finish` returns the
    whole file.
    """

    def __init__(self, *, library: str, profile: str = "") -> None:
        self._data: list[bytes] = [MAGIC, _record(Header(profile=profile, library=library))]
        self._offset = sum(len(b) for b in self._data)
        self._schemas: list[Schema] = []
        self._channels: list[Channel] = []
        self._chunk: list[bytes] = []
        self._chunk_times: list[int] = []
        self._chunk_indexes: list[ChunkIndex] = []
        self._metadata_indexes: list[MetadataIndex] = []
        self._counts: dict[int, int] = {}
        self._start = 0
        self._end = 0
        self._messages = 0
        import zstandard

        self._zstd = zstandard.ZstdCompressor(level=_ZSTD_LEVEL)

    def _emit(self, data: bytes) -> int:
        """Append to the data section; return the offset where ``data`` starts."""
        offset = self._offset
        self._data.append(data)
        self._offset += len(data)
        return offset

    def metadata(self, name: str, values: Mapping[str, str]) -> None:
        """A metadata record in the data section (indexed in the summary)."""
        data = _record(Metadata(name=name, metadata=dict(values)))
        offset = self._emit(data)
        self._metadata_indexes.append(MetadataIndex(offset=offset, length=len(data), name=name))

    def schema(self, name: str, encoding: str, data: bytes) -> int:
        """Register a schema; returns its id (1, 2, ...)."""
        schema = Schema(id=len(self._schemas) + 1, name=name, encoding=encoding, data=data)
        self._schemas.append(schema)
        self._chunk.append(_record(schema))
        return schema.id

    def channel(self, topic: str, message_encoding: str, schema_id: int) -> int:
        """Register a channel; returns its id (1, 2, ...)."""
        channel = Channel(
            id=len(self._channels) + 1,
            schema_id=schema_id,
            topic=topic,
            message_encoding=message_encoding,
            metadata={},
        )
        self._channels.append(channel)
        self._counts[channel.id] = 0
        self._chunk.append(_record(channel))
        return channel.id

    def add(self, channel_id: int, t_ns: int, data: bytes) -> None:
        """One message; log time = publish time = ``t_ns``, sequence 0."""
        self._chunk.append(
            _MESSAGE_HEAD.pack(_OP_MESSAGE, _MESSAGE_FIXED + len(data), channel_id, 0, t_ns, t_ns)
        )
        self._chunk.append(data)
        self._chunk_times.append(t_ns)
        self._counts[channel_id] += 1

    def add_many(self, channel_id: int, times: Sequence[int], data: Sequence[bytes]) -> None:
        """Messages on one channel, in the given order (``times[i]`` for ``data[i]``)."""
        pack = _MESSAGE_HEAD.pack
        fixed = _MESSAGE_FIXED
        op = _OP_MESSAGE
        chunk = self._chunk
        for t, d in zip(times, data, strict=True):
            chunk.append(pack(op, fixed + len(d), channel_id, 0, t, t))
            chunk.append(d)
        self._chunk_times.extend(times)
        self._counts[channel_id] += len(data)

    def end_chunk(self) -> None:
        """Write the chunk being built (if it holds a message); later messages start
        a new chunk. Schema and channel records of a chunk without messages stay for
        the next one."""
        if not self._chunk_times:
            return
        records = b"".join(self._chunk)
        start, end = min(self._chunk_times), max(self._chunk_times)
        compressed = self._zstd.compress(records)
        chunk = _record(
            Chunk(
                message_start_time=start,
                message_end_time=end,
                uncompressed_size=len(records),
                uncompressed_crc=zlib.crc32(records),
                compression="zstd",
                data=compressed,
            )
        )
        offset = self._emit(chunk)
        self._chunk_indexes.append(
            ChunkIndex(
                message_start_time=start,
                message_end_time=end,
                chunk_start_offset=offset,
                chunk_length=len(chunk),
                message_index_offsets={},
                message_index_length=0,
                compression="zstd",
                compressed_size=len(compressed),
                uncompressed_size=len(records),
            )
        )
        self._start = start if self._messages == 0 else min(self._start, start)
        self._end = max(self._end, end)
        self._messages += len(self._chunk_times)
        self._chunk = []
        self._chunk_times = []

    def finish(self) -> bytes:
        """Close the last chunk and return the whole file."""
        self.end_chunk()
        data_crc = 0
        for piece in self._data:
            data_crc = zlib.crc32(piece, data_crc)
        self._emit(_record(DataEnd(data_section_crc=data_crc)))
        summary_start = self._offset
        groups: list[tuple[Opcode, list[McapRecord]]] = [
            (Opcode.SCHEMA, list(self._schemas)),
            (Opcode.CHANNEL, list(self._channels)),
            (
                Opcode.STATISTICS,
                [
                    Statistics(
                        message_count=self._messages,
                        schema_count=len(self._schemas),
                        channel_count=len(self._channels),
                        attachment_count=0,
                        metadata_count=len(self._metadata_indexes),
                        chunk_count=len(self._chunk_indexes),
                        message_start_time=self._start,
                        message_end_time=self._end,
                        channel_message_counts=dict(self._counts),
                    )
                ],
            ),
            (Opcode.CHUNK_INDEX, list(self._chunk_indexes)),
            (Opcode.METADATA_INDEX, list(self._metadata_indexes)),
        ]
        summary: list[bytes] = []
        length = 0
        offsets: list[bytes] = []
        for opcode, records in groups:
            if not records:
                continue
            group = b"".join(_record(r) for r in records)
            offsets.append(
                _record(
                    SummaryOffset(
                        group_opcode=opcode,
                        group_start=summary_start + length,
                        group_length=len(group),
                    )
                )
            )
            summary.append(group)
            length += len(group)
        summary_offset_start = summary_start + length
        summary_data = b"".join(summary + offsets)
        summary_crc = zlib.crc32(
            struct.pack("<BQQQ", Opcode.FOOTER, 8 + 8 + 4, summary_start, summary_offset_start),
            zlib.crc32(summary_data),
        )
        footer = Footer(
            summary_start=summary_start,
            summary_offset_start=summary_offset_start,
            summary_crc=summary_crc,
        )
        return b"".join([*self._data, summary_data, _record(footer), MAGIC])
