"""The MCAP layout: exact round trips, a real MCAP file for any reader, clear errors."""

from __future__ import annotations

import io
import json
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from mcap.reader import make_reader
from mcap.records import Chunk, DataEnd, Footer, MessageIndex
from mcap.stream_reader import StreamReader
from mcap.writer import Writer

from srfm.datasets import (
    FRAME_SCHEMA,
    PEDESTRIAN,
    ROBOT,
    SCHEMA_NAME,
    Trajectories,
    read_mcap,
    write_mcap,
)
from srfm.errors import DatasetError


def random_scene(rng: np.random.Generator, name: str, robot: bool) -> Trajectories:
    n_peds = int(rng.integers(1, 6))
    ids = [f"pedestrian:{int(i)}" for i in rng.choice(1000, n_peds, replace=False)]
    kinds = [PEDESTRIAN] * n_peds
    if robot:
        ids.append("robot")
        kinds.append(ROBOT)
    frames = np.sort(rng.choice(10_000, int(rng.integers(1, 20)), replace=False))
    t_ns = 1_700_000_000_000_000_000 + frames * 66_666_667 + rng.integers(0, 1000, frames.size)
    agent, frame, times = [], [], []
    for f, t in zip(frames.tolist(), t_ns.tolist(), strict=True):
        present = rng.random(len(ids)) < 0.7
        present[rng.integers(len(ids))] = True  # every frame has someone
        for a in np.flatnonzero(present).tolist():
            agent.append(a)
            frame.append(f)
            times.append(t)
    xy = rng.normal(0.0, 50.0, (len(agent), 2))
    return Trajectories.from_samples(
        scene=name,
        agent_ids=ids,
        kinds=kinds,
        agent=np.array(agent, dtype=np.int64),
        frame=np.array(frame, dtype=np.int64),
        t_ns=np.array(times, dtype=np.int64),
        xy=xy,
        source={"dataset": "test", "note": 'ünïcode, "quotes"'},
    )


@settings(
    max_examples=25, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(seed=st.integers(0, 2**32 - 1))
def test_round_trip_is_exact(tmp_path: Path, seed: int) -> None:
    rng = np.random.default_rng(seed)
    scenes = [random_scene(rng, f"scene_{k}", robot=k % 2 == 0) for k in range(3)]
    path = tmp_path / "d.mcap"
    write_mcap(path, scenes, dataset="test", metadata={"origin": "hypothesis"})
    back = read_mcap(path)
    assert back.dataset == "test"
    assert back.metadata["origin"] == "hypothesis"
    assert len(back.scenes) == 3
    for a, b in zip(scenes, back.scenes, strict=True):
        assert a.equals(b), a.scene


def test_a_scene_without_samples_is_refused(tmp_path: Path) -> None:
    rng = np.random.default_rng(3)
    full = random_scene(rng, "full", robot=False)
    empty = Trajectories.from_samples(
        scene="empty",
        agent_ids=["pedestrian:1"],
        kinds=[PEDESTRIAN],
        agent=np.zeros(0, dtype=np.int64),
        frame=np.zeros(0, dtype=np.int64),
        t_ns=np.zeros(0, dtype=np.int64),
        xy=np.zeros((0, 2)),
        source={},
    )
    path = tmp_path / "d.mcap"
    with pytest.raises(DatasetError, match="scene 'empty' has no samples"):
        write_mcap(path, [full, empty], dataset="test")
    assert not path.exists()


@pytest.fixture
def written(tmp_path: Path) -> tuple[Path, list[Trajectories]]:
    rng = np.random.default_rng(7)
    scenes = [random_scene(rng, "alpha", robot=True), random_scene(rng, "beta", robot=False)]
    path = tmp_path / "d.mcap"
    write_mcap(path, scenes, dataset="test")
    return path, scenes


def test_layout_is_plain_mcap_with_json_schema_channels(
    written: tuple[Path, list[Trajectories]],
) -> None:
    path, scenes = written
    with path.open("rb") as fh:
        reader = make_reader(fh)
        summary = reader.get_summary()
        assert summary is not None
        assert {s.name for s in summary.schemas.values()} == {SCHEMA_NAME}
        schema = next(iter(summary.schemas.values()))
        assert schema.encoding == "jsonschema"
        assert json.loads(schema.data) == FRAME_SCHEMA
        topics = sorted(c.topic for c in summary.channels.values())
        assert topics == ["/trajectories/alpha", "/trajectories/beta"]
        assert all(c.message_encoding == "json" for c in summary.channels.values())
        assert summary.statistics is not None
        n_frames = sum(s.frames()[0].size for s in scenes)
        assert summary.statistics.message_count == n_frames
        metadata = {m.name: m.metadata for m in reader.iter_metadata()}
        assert metadata["srfm.datasets"]["schema"] == SCHEMA_NAME
        assert metadata["srfm.datasets"]["schema_version"] == "1"
        for _, channel, message in reader.iter_messages():
            msg = json.loads(message.data)
            assert isinstance(message.log_time, int)
            assert message.log_time == msg["timestamp_ns"] == message.publish_time
            assert set(msg) == set(FRAME_SCHEMA["required"])
            assert channel.metadata["scene"] == msg["scene"]
    # Chunks are compressed (a streaming reader sees the raw chunk records).
    with path.open("rb") as fh:
        chunks = [
            r
            for r in StreamReader(fh, emit_chunks=True, validate_crcs=True).records
            if isinstance(r, Chunk)
        ]
    assert chunks
    assert all(c.compression == "zstd" for c in chunks)


def test_write_is_atomic_and_validates_first(tmp_path: Path) -> None:
    rng = np.random.default_rng(1)
    scene = random_scene(rng, "same", robot=False)
    path = tmp_path / "out.mcap"
    with pytest.raises(DatasetError, match="duplicate scene name 'same'"):
        write_mcap(path, [scene, scene], dataset="x")
    assert not path.exists()
    assert list(tmp_path.iterdir()) == []
    with pytest.raises(DatasetError, match="no scenes"):
        write_mcap(path, [], dataset="x")
    # An existing file survives a failed write untouched.
    path.write_bytes(b"old")
    with pytest.raises(DatasetError):
        write_mcap(path, [scene, scene], dataset="x")
    assert path.read_bytes() == b"old"


def test_read_missing_and_non_mcap_files(tmp_path: Path) -> None:
    with pytest.raises(DatasetError, match="file not found"):
        read_mcap(tmp_path / "nope.mcap")
    bad = tmp_path / "bad.mcap"
    bad.write_text("not an mcap file at all")
    with pytest.raises(DatasetError, match=r"bad\.mcap: not a readable MCAP file"):
        read_mcap(bad)


def _handmade(
    path: Path,
    schema_name: str,
    messages: list[tuple[int, bytes]],
    *,
    library: str = "test",
    srfm_version: str | None = None,
) -> None:
    with path.open("wb") as fh:
        w = Writer(fh)
        w.start(library=library)
        if srfm_version is not None:
            w.add_metadata("srfm.datasets", {"srfm_version": srfm_version})
        sid = w.register_schema(name=schema_name, encoding="jsonschema", data=b"{}")
        cid = w.register_channel("/trajectories/x", "json", sid, {"scene": "x"})
        for t, data in messages:
            w.add_message(cid, log_time=t, data=data, publish_time=t)
        w.finish()


def _msg(**changes: object) -> bytes:
    msg: dict[str, object] = {
        "schema_version": 1,
        "scene": "x",
        "frame": 3,
        "timestamp_ns": 100,
        "frame_of_reference": "world",
        "agents": [{"id": "p", "kind": "pedestrian", "x": 1.0, "y": 2.0}],
    }
    msg.update(changes)
    return json.dumps(msg).encode()


def test_read_foreign_mcap_and_newer_schema(tmp_path: Path) -> None:
    other = tmp_path / "other.mcap"
    _handmade(other, "foxglove.SceneUpdate", [(1, b"{}")])
    with pytest.raises(DatasetError, match="not an srfm dataset file"):
        read_mcap(other)
    newer = tmp_path / "newer.mcap"
    _handmade(newer, "srfm.datasets.AgentFrame.v2", [(100, _msg())], srfm_version="9.1.0")
    with pytest.raises(
        DatasetError,
        match=r"newer\.mcap: dataset schema version 2, written by srfm 9\.1\.0; this srfm "
        r"\(.*\) reads version 1 only",
    ):
        read_mcap(newer)
    # Without the metadata record, the MCAP header names the writer; or nothing does.
    _handmade(newer, "srfm.datasets.AgentFrame.v0", [(100, _msg())], library="srfm 0.0.1")
    with pytest.raises(DatasetError, match=r"version 0, written by srfm 0\.0\.1;"):
        read_mcap(newer)
    _handmade(newer, "srfm.datasets.AgentFrame.v2", [(100, _msg())])
    with pytest.raises(DatasetError, match="written by an unknown srfm version;"):
        read_mcap(newer)


def test_every_crc_is_written_and_a_damaged_chunk_is_refused(
    written: tuple[Path, list[Trajectories]], tmp_path: Path
) -> None:
    path, _ = written
    data = path.read_bytes()
    records = list(StreamReader(io.BytesIO(data), emit_chunks=True, validate_crcs=True).records)
    chunks = [r for r in records if isinstance(r, Chunk)]
    (end,) = [r for r in records if isinstance(r, DataEnd)]
    (footer,) = [r for r in records if isinstance(r, Footer)]
    assert all(c.uncompressed_crc != 0 for c in chunks)
    assert end.data_section_crc != 0
    assert footer.summary_crc != 0
    assert any(isinstance(r, MessageIndex) for r in records)  # the library's default indexes
    flipped = bytearray(data)
    flipped[data.index(chunks[0].data) + len(chunks[0].data) // 2] ^= 0x10
    bad = tmp_path / "flipped.mcap"
    bad.write_bytes(bytes(flipped))
    with pytest.raises(DatasetError, match=r"flipped\.mcap: not a readable MCAP file"):
        read_mcap(bad)


@pytest.mark.parametrize(
    ("data", "match"),
    [
        (b"{not json", "not valid JSON"),
        (
            _msg(agents=[{"id": "p", "kind": "pedestrian", "x": "1", "y": 2.0}]),
            "x must be a finite",
        ),
        (b'{"schema_version": 1}', "missing key 'agents'"),
        (_msg(timestamp_ns=99), "differs from the log time"),
        (_msg(agents=[{"id": "p", "kind": "pedestrian", "x": float("nan"), "y": 0.0}]), "finite"),
        (_msg(frame=1.5), "frame must be an integer"),
    ],
)
def test_malformed_messages_name_topic_and_time(tmp_path: Path, data: bytes, match: str) -> None:
    path = tmp_path / "m.mcap"
    _handmade(path, SCHEMA_NAME, [(100, data)])
    with pytest.raises(DatasetError, match=match) as info:
        read_mcap(path)
    assert "topic '/trajectories/x', message at log time 100 ns" in str(info.value)


def test_messages_without_scene_metadata_still_read(tmp_path: Path) -> None:
    path = tmp_path / "m.mcap"
    _handmade(path, SCHEMA_NAME, [(100, _msg()), (200, _msg(frame=4, timestamp_ns=200))])
    (scene,) = read_mcap(path).scenes
    assert scene.agent_ids == ("p",)
    assert scene.frame.tolist() == [3, 4]
    assert scene.t_ns.tolist() == [100, 200]


def test_mcap_core_reads_dataset_files(written: tuple[Path, list[Trajectories]]) -> None:
    """The official TypeScript reader (@mcap/core, under Node.js) opens a dataset file
    and finds one message per frame on each scene's channel."""
    from tests.logs.node_reader import prefix_or_skip, read_mcap

    path, scenes = written
    (result,) = read_mcap(prefix_or_skip(), [path])
    assert result["ok"], result.get("error")
    expected = {f"/trajectories/{s.scene}": int(s.frames()[0].size) for s in scenes}
    assert result["counts"] == expected
    assert result["statistics"]["channelMessageCounts"] == expected
    assert result["metadata"]["srfm.datasets"]["schema"] == SCHEMA_NAME
    assert all(c["compression"] == "zstd" and c["messageIndexes"] > 0 for c in result["chunks"])
    assert result["ordered"]
