"""The MCAP sink and reader: channels, schemas, exact rebuilds, the Foxglove scene, the
official @mcap/core reader, CRCs, old schema versions and damaged files."""

from __future__ import annotations

import base64
import io
import json
import math
from collections import Counter, defaultdict
from pathlib import Path
from typing import Any

import attrs
import numpy as np
import pytest
from mcap.reader import make_reader
from mcap.records import Chunk, DataEnd, Footer, MessageIndex
from mcap.stream_reader import StreamReader
from mcap.writer import Writer

from srfm.errors import LogError
from srfm.logs import (
    CHANNELS,
    SCHEMA_VERSION,
    _mcap,
    load_episode,
    read_log,
    write_counterfactual_mcap,
    write_episode_mcap,
)
from srfm.metrics import episode_metrics
from srfm.sim.record import EpisodeRecord
from tests.logs.conftest import check_json_schema, same_bits

DATA = Path(__file__).with_name("data")


def _messages(path: Path) -> tuple[Any, list[tuple[Any, Any, Any]]]:
    """Summary and messages as the mcap library's seeking reader returns them."""
    with path.open("rb") as fh:
        reader = make_reader(fh, validate_crcs=True)
        summary = reader.get_summary()
        msgs = list(reader.iter_messages(log_time_order=False))
    return summary, msgs


def _check_json_messages(summary: Any, msgs: list[tuple[Any, Any, Any]]) -> None:
    """Every JSON message fits the JSON schema its channel names in the file."""
    schemas = {
        c.topic: json.loads(summary.schemas[c.schema_id].data)
        for c in summary.channels.values()
        if c.message_encoding == "json"
    }
    for _, channel, message in msgs:
        if channel.topic in schemas:
            check_json_schema(json.loads(message.data), schemas[channel.topic], channel.topic)


def _by_topic(msgs: list[tuple[Any, Any, Any]]) -> dict[str, list[tuple[int, dict[str, Any]]]]:
    """The JSON messages by topic (the protobuf scene is decoded by @mcap/core)."""
    out: dict[str, list[tuple[int, dict[str, Any]]]] = defaultdict(list)
    for _, channel, message in msgs:
        if channel.message_encoding == "json":
            out[channel.topic].append((message.log_time, json.loads(message.data)))
    return out


def _frames(record: EpisodeRecord, stride: int) -> list[int]:
    n = record.time_s.shape[0]
    return sorted({*range(0, n, stride), n - 1})


def _goal_steps(record: EpisodeRecord) -> set[int]:
    """Samples where the scene redraws the goals: the first, after a goal changed, and
    where pedestrians entered."""
    changed = np.flatnonzero(np.any(record.factual_goal[1:] != record.factual_goal[:-1], (1, 2)))
    entered = np.flatnonzero(np.diff(record.present().sum(axis=1)))
    return {0, *(int(k) + 1 for k in changed), *(int(k) + 1 for k in entered)}


def expected_counts(record: EpisodeRecord, profile: str, *, shared: bool) -> dict[str, int]:
    """Messages per topic of an episode file."""
    n = record.time_s.shape[0]
    stride = 1 if profile == "full" else 15
    robot_steps = list(range(n)) if profile == "full" else _frames(record, stride)
    commands = [
        k
        for k in robot_steps
        if k < n - 1 and record.robot_active[k] and not math.isnan(record.robot_cmd[k, 0])
    ]
    counts = {
        "/srfm/episode": 1,
        "/srfm/robot/state": len(robot_steps),
        "/srfm/robot/command": len(commands),
        "/foxglove/scene": 1 + len(_goal_steps(record)) + len(_frames(record, stride)),
        "/srfm/events": len(record.events),
        "/srfm/metrics": 1,
        "/srfm/trajectories": 2 if shared else 3,
    }
    if profile == "full":
        counts["/srfm/pedestrians/factual"] = counts["/srfm/pedestrians/counterfactual"] = n
    return {k: v for k, v in counts.items() if v}


def _assert_same_record(a: EpisodeRecord, b: EpisodeRecord, *, velocities: bool = True) -> None:
    for name, arr in a.arrays().items():
        if not velocities and name in ("factual_vel", "counterfactual_vel"):
            continue
        assert same_bits(arr, b.arrays()[name]), name
    for field in (
        "scenario",
        "seed",
        "planner",
        "dt_s",
        "horizon_steps",
        "robot_radius",
        "robot_kinematics",
        "outcome",
        "end_step",
        "events",
    ):
        assert getattr(a, field) == getattr(b, field), field
    assert a.params == b.params


@pytest.fixture
def full_log(tmp_path: Path, episode, short_scenario):  # type: ignore[no-untyped-def]
    scenario, record, metrics = episode(short_scenario, 3, "dwa")
    path = tmp_path / "full.mcap"
    write_episode_mcap(path, record, scenario=scenario, metrics=metrics, profile="full")
    return path, scenario, record, metrics


def test_full_log_rebuilds_the_record_bit_for_bit(full_log) -> None:  # type: ignore[no-untyped-def]
    path, _, record, metrics = full_log
    logged = load_episode(path)
    assert logged.exact_velocities
    assert logged.counterfactual_path is None
    _assert_same_record(record, logged.record)
    again = episode_metrics(logged.record)
    for name, value in metrics.values.items():
        assert np.float64(again.values[name]).tobytes() == np.float64(value).tobytes(), name
    assert logged.online_metrics is not None
    for name, arr in metrics.pedestrians.items():
        assert same_bits(logged.online_metrics.pedestrians[name], arr), name


def test_channels_schemas_and_every_message_follow_the_schemas(full_log) -> None:  # type: ignore[no-untyped-def]
    path, _, record, _ = full_log
    summary, msgs = _messages(path)
    topics = {c.topic: c for c in summary.channels.values()}
    expected = {c.topic for k, c in CHANNELS.items()}
    assert set(topics) == expected
    schemas = {}
    for channel in summary.channels.values():
        schema = summary.schemas[channel.schema_id]
        if channel.topic == "/foxglove/scene":
            from foxglove.messages import SceneUpdate

            # Foxglove's official schema, as the Foxglove SDK ships it.
            official = SceneUpdate.get_schema()
            assert (schema.name, schema.encoding) == ("foxglove.SceneUpdate", "protobuf")
            assert schema.data == official.data
            assert channel.message_encoding == "protobuf"
            continue
        assert channel.message_encoding == "json"
        assert schema.encoding == "jsonschema"
        schemas[channel.topic] = json.loads(schema.data)
    assert all(s["title"].endswith(f".v{SCHEMA_VERSION}") for s in schemas.values())
    for _, channel, message in msgs:
        if channel.topic in schemas:
            check_json_schema(json.loads(message.data), schemas[channel.topic], channel.topic)
    by = _by_topic(msgs)
    n = record.time_s.shape[0]
    dt_ns = [round(k * record.dt_s * 1e9) for k in range(n)]
    for topic in (
        "/srfm/pedestrians/factual",
        "/srfm/pedestrians/counterfactual",
        "/srfm/robot/state",
    ):
        assert [t for t, _ in by[topic]] == dt_ns, topic
        assert [m["step"] for _, m in by[topic]] == list(range(n)), topic
    for k in (0, n // 2, n - 1):
        m = by["/srfm/pedestrians/factual"][k][1]
        assert np.array_equal(np.column_stack([m["x"], m["y"]]), record.factual_pos[k])
        assert np.array_equal(np.column_stack([m["vx"], m["vy"]]), record.factual_vel[k])
    active_cmds = int(np.count_nonzero(~np.isnan(record.robot_cmd[:, 0])))
    assert len(by["/srfm/robot/command"]) == active_cmds
    assert len(by["/srfm/events"]) == len(record.events)
    assert len(by["/srfm/metrics"]) == len(by["/srfm/episode"]) == 1
    info = by["/srfm/episode"][0][1]
    assert (info["scenario"], info["seed"], info["planner"]) == ("short", 3, "dwa")
    assert info["obstacles"]["segments"] == [[0.5, 14.5, 14.5, 14.5]]
    assert summary.statistics.message_count == len(msgs)
    assert {c.compression for c in summary.chunk_indexes} == {"zstd"}


def _scene(decoded: dict[str, Any]) -> dict[str, list[tuple[int, dict[str, Any]]]]:
    """The scene's entities by id as (log time, entity), from @mcap/core's decoding."""
    entities: dict[str, list[tuple[int, dict[str, Any]]]] = defaultdict(list)
    for message in decoded["scene"]:
        for e in message["entities"]:
            assert e["frameId"] == "world"
            sec, nsec = e["timestamp"]
            assert sec * 10**9 + nsec == message["logTime"]
            entities[e["id"]].append((message["logTime"], e))
    return entities


def test_foxglove_scene_draws_the_run(full_log, mcap_core) -> None:  # type: ignore[no-untyped-def]
    """Decoded by @mcap/core and protobufjs from the schema in the file: the world, the
    crowd, the ghosts, the robot with its path and goal, the pedestrians' goals."""
    path, scenario, record, _ = full_log
    (decoded,) = mcap_core([path])
    entities = _scene(decoded)
    assert set(entities) == {
        "world",
        "robot_goal",
        "robot_path",
        "goals",
        "pedestrians",
        "counterfactual",
        "robot",
    }
    world = entities["world"][0][1]
    loop, wall = world["lines"]
    assert loop["type"] == 1  # LINE_LOOP
    w = scenario.world
    assert loop["points"] == [
        [w.x_min, w.y_min],
        [w.x_max, w.y_min],
        [w.x_max, w.y_max],
        [w.x_min, w.y_max],
    ]
    assert wall["type"] == 2  # LINE_LIST: the wall
    assert wall["points"] == [[0.5, 14.5], [14.5, 14.5]]
    assert world["cylinders"] == [[2.0, 2.0, 0.8, 1.0]]  # the pillar: centre, diameter
    goal = entities["robot_goal"][0][1]
    assert goal["texts"] == ["robot goal"]
    assert np.allclose(goal["cylinders"][0][:2], record.robot_goal, atol=0.005)
    (path_line,) = entities["robot_path"][0][1]["lines"]
    assert path_line["type"] == 0  # LINE_STRIP
    # The path: exact positions of the robot, one every 10 cm of travel, first and last.
    pts = np.array(path_line["points"])
    full = record.robot_pose[: record.end_step + 1, :2]
    assert np.array_equal(pts[[0, -1]], full[[0, -1]])
    at = [int(np.flatnonzero((full == p).all(axis=1))[0]) for p in pts]
    assert at == sorted(set(at))
    assert np.linalg.norm(np.diff(pts[:-1], axis=0), axis=1).max() <= 0.1 + 0.04
    goals = entities["goals"][0][1]["cylinders"]
    assert np.abs(np.array(goals)[:, :2] - record.factual_goal[0]).max() <= 0.005
    n = record.time_s.shape[0]
    assert len(entities["pedestrians"]) == len(entities["counterfactual"]) == n  # every sample
    # The ghosts: the counterfactual twins that are apart from their factual twin (by
    # 1 cm or more, as drawn); where the twins coincide the factual disc covers them.
    drawn = 0
    for k, (_, ghosts) in enumerate(entities["counterfactual"]):
        apart = np.any(
            np.rint(record.factual_pos[k] * 100) != np.rint(record.counterfactual_pos[k] * 100),
            axis=1,
        )
        gxy = np.array(ghosts["cylinders"]).reshape(-1, 4)[:, :2]
        assert len(gxy) == np.count_nonzero(apart)
        assert np.abs(gxy - record.counterfactual_pos[k][apart]).max(initial=0) <= 0.005
        assert all(c[3] < 1 for c in ghosts["cylinders"])  # translucent
        drawn += len(gxy)
    assert drawn > 0  # the robot moved someone in this episode
    for k in (0, n // 3, n - 1):
        _, peds = entities["pedestrians"][k]
        xy = np.array(peds["cylinders"])[:, :2]
        assert np.abs(xy - record.factual_pos[k]).max() <= 0.005
        _, robot = entities["robot"][k]
        assert np.abs(np.array(robot["cylinders"][0][:2]) - record.robot_pose[k, :2]).max() <= 0.005
        _, _, qz, qw, _ = robot["arrows"][0]
        yaw = 2 * math.atan2(qz, qw)
        err = (yaw - record.robot_pose[k, 2] + math.pi) % (2 * math.pi) - math.pi
        assert abs(err) <= math.radians(2.6)
        for arrow in peds["arrows"]:  # velocity arrows: 1 s of motion, 5 cm steps
            assert 0.05 - 1e-9 <= arrow[4] <= 1.25 + 0.05


def test_compact_log_with_a_shared_counterfactual(tmp_path: Path, episode) -> None:  # type: ignore[no-untyped-def]
    scenario, record, metrics = episode("crosswalk", 2, "straight")
    cf = tmp_path / "_counterfactual" / "seed-000002.mcap"
    path = tmp_path / "straight" / "seed-000002.mcap"
    cf_size = write_counterfactual_mcap(cf, record, scenario=scenario)
    size = write_episode_mcap(
        path,
        record,
        scenario=scenario,
        metrics=metrics,
        profile="compact",
        counterfactual_file="../_counterfactual/seed-000002.mcap",
    )
    # The budget of a 100-seed benchmark (docs/logging.md): a 750-step episode.
    assert size < 175_000
    assert cf_size < 135_000
    logged = load_episode(path)
    assert not logged.exact_velocities
    assert logged.counterfactual_path == cf.resolve()
    _assert_same_record(record, logged.record, velocities=False)
    # Without logged velocities: finite differences of the exact positions.
    assert np.abs(logged.record.factual_vel[1:] - record.factual_vel[1:]).max() < 1e-9
    again = episode_metrics(logged.record)
    assert all(
        np.float64(again.values[k]).tobytes() == np.float64(v).tobytes()
        for k, v in metrics.values.items()
    )
    summary, msgs = _messages(path)
    counts = Counter(c.topic for _, c, _ in msgs)
    _check_json_messages(summary, msgs)
    cf_summary, cf_msgs = _messages(cf)
    for _, channel, message in cf_msgs:
        schema = json.loads(cf_summary.schemas[channel.schema_id].data)
        check_json_schema(json.loads(message.data), schema, channel.topic)
    assert "/srfm/pedestrians/factual" not in counts
    # 1 Hz: the scene, the robot states and (while it drives) its commands at the
    # agent frames only; the exact robot of every sample is in its block.
    assert record.outcome == "goal_reached"
    n = record.time_s.shape[0]
    frame_steps = sorted({*range(0, n, 15), n - 1})
    assert counts["/foxglove/scene"] == 1 + 1 + len(frame_steps)  # static, goals, frames
    by = _by_topic(msgs)
    assert [m["step"] for _, m in by["/srfm/robot/state"]] == frame_steps
    driving = [k for k in frame_steps[:-1] if record.robot_active[k]]
    assert driving
    assert [m["step"] for _, m in by["/srfm/robot/command"]] == driving
    for _, m in by["/srfm/robot/state"]:
        k = m["step"]
        assert [m["x"], m["y"], m["theta"]] == record.robot_pose[k].tolist()
        assert m["active"] is bool(record.robot_active[k])
    (robot,) = [m for _, m in by["/srfm/trajectories"] if m["group"] == "robot"]
    assert set(robot["arrays"]) == {"pose", "vel", "active", "cmd"}
    assert by["/srfm/episode"][0][1]["robot_states"] == "frames"
    # Message times never decrease within the chunk of the per-sample messages.
    times = [m.log_time for _, c, m in msgs if c.topic != "/srfm/trajectories"]
    assert times == sorted(times)


def test_times_that_arange_cannot_reproduce_are_stored(tmp_path: Path, episode) -> None:  # type: ignore[no-untyped-def]
    scenario, record, metrics = episode("concert", 0, "straight")
    odd = attrs.evolve(record, time_s=record.time_s + 0.5)
    write_episode_mcap(tmp_path / "a.mcap", odd, scenario=scenario, metrics=metrics)
    assert same_bits(load_episode(tmp_path / "a.mcap").record.time_s, odd.time_s)


def test_writes_are_atomic(tmp_path: Path, episode) -> None:  # type: ignore[no-untyped-def]
    scenario, record, metrics = episode("concert", 0, "straight")
    path = tmp_path / "a.mcap"
    path.write_bytes(b"old")
    write_episode_mcap(path, record, scenario=scenario, metrics=metrics, profile="compact")
    assert read_log(path).kind == "episode"
    before = path.read_bytes()
    bad = attrs.evolve(record, robot_pose=np.full_like(record.robot_pose, np.nan))
    with pytest.raises(LogError, match="not finite"):
        write_episode_mcap(path, bad, scenario=scenario, metrics=metrics)
    assert path.read_bytes() == before
    assert [p.name for p in tmp_path.iterdir()] == ["a.mcap"]


# --- damaged, foreign and inconsistent files ----------------------------------------


@pytest.fixture
def good_bytes(tmp_path: Path, episode) -> bytes:  # type: ignore[no-untyped-def]
    scenario, record, metrics = episode("concert", 1, "straight")
    path = tmp_path / "good.mcap"
    write_episode_mcap(path, record, scenario=scenario, metrics=metrics, profile="compact")
    return path.read_bytes()


@pytest.mark.parametrize("keep", [0, 8, 20, 1000, 0.5, -100, -1])
def test_truncated_files_are_log_errors_naming_the_file(
    tmp_path: Path, good_bytes: bytes, keep: float
) -> None:
    n = int(len(good_bytes) * keep) if isinstance(keep, float) else keep
    path = tmp_path / "cut.mcap"
    path.write_bytes(good_bytes[:n])
    with pytest.raises(LogError, match=r"cut\.mcap: not (a readable )?an? MCAP|cut\.mcap: not"):
        load_episode(path)


@pytest.mark.parametrize("where", [0.3, 0.6, 0.9])
def test_corrupted_bytes_are_log_errors(tmp_path: Path, good_bytes: bytes, where: float) -> None:
    data = bytearray(good_bytes)
    i = int(len(data) * where)
    data[i] ^= 0x5A
    path = tmp_path / "flipped.mcap"
    path.write_bytes(bytes(data))
    with pytest.raises(LogError, match=r"flipped\.mcap"):
        load_episode(path)


def test_foreign_mcap_is_a_log_error(tmp_path: Path) -> None:
    buf = io.BytesIO()
    w = Writer(buf)
    w.start()
    sid = w.register_schema(name="camera.Image", encoding="jsonschema", data=b"{}")
    cid = w.register_channel(topic="/camera", message_encoding="json", schema_id=sid)
    w.add_message(channel_id=cid, log_time=1, publish_time=1, data=b"{}")
    w.finish()
    path = tmp_path / "foreign.mcap"
    path.write_bytes(buf.getvalue())
    with pytest.raises(LogError, match=r"foreign\.mcap: not an srfm run log"):
        load_episode(path)


def test_a_file_of_the_previous_schema_version_is_refused_naming_it() -> None:
    """A real file written by srfm before this schema (version 2: own container writer,
    own array codec) is refused with its version and the srfm that wrote it."""
    path = DATA / "schema-v2-episode.mcap"
    with pytest.raises(
        LogError,
        match=r"schema-v2-episode\.mcap: log schema version 2, written by srfm 0\.1\.0; "
        r"this srfm \(.+\) reads version 4 or 5 only",
    ):
        load_episode(path)


@pytest.mark.parametrize(
    ("version", "library", "metadata", "writer"),
    [
        (1, "mcap-python", None, "an unknown srfm version"),
        (SCHEMA_VERSION + 1, "srfm 7.0.0", None, r"srfm 7\.0\.0"),
        (SCHEMA_VERSION + 1, "srfm 7.0.0", "8.1.0", r"srfm 8\.1\.0"),
    ],
)
def test_other_schema_versions_are_named(
    tmp_path: Path, version: int, library: str, metadata: str | None, writer: str
) -> None:
    """Older and newer files: refused before any message is decoded, naming the
    version and the srfm that wrote the file (metadata first, else the MCAP header)."""
    buf = io.BytesIO()
    w = Writer(buf)
    w.start(library=library)
    if metadata is not None:
        w.add_metadata("srfm", {"schema_version": str(version), "srfm_version": metadata})
    name = f"srfm.logs.Episode.v{version}"
    sid = w.register_schema(name=name, encoding="jsonschema", data=b"{}")
    cid = w.register_channel(topic="/srfm/episode", message_encoding="json", schema_id=sid)
    w.add_message(channel_id=cid, log_time=0, publish_time=0, data=b"not even json")
    w.finish()
    path = tmp_path / "other.mcap"
    path.write_bytes(buf.getvalue())
    with pytest.raises(
        LogError,
        match=rf"other\.mcap: log schema version {version}, written by {writer}; this srfm",
    ):
        load_episode(path)


@pytest.mark.parametrize("content", [b"", b"hello world\n", b"\x89MCAP0\r\n"])
def test_non_mcap_files_are_log_errors(tmp_path: Path, content: bytes) -> None:
    path = tmp_path / "x.mcap"
    path.write_bytes(content)
    with pytest.raises(LogError, match=r"x\.mcap: not"):
        load_episode(path)


def test_missing_and_mismatched_counterfactual_files(tmp_path: Path, episode) -> None:  # type: ignore[no-untyped-def]
    scenario, record, metrics = episode("concert", 1, "straight")
    _, other, _ = episode("concert", 2, "straight")
    path = tmp_path / "dir" / "ep.mcap"
    write_episode_mcap(
        path,
        record,
        scenario=scenario,
        metrics=metrics,
        profile="compact",
        counterfactual_file="../cf.mcap",
    )
    with pytest.raises(LogError, match=r"ep\.mcap: its counterfactual file .*cf\.mcap is missing"):
        load_episode(path)
    write_counterfactual_mcap(tmp_path / "cf.mcap", other, scenario=scenario)
    with pytest.raises(LogError, match=r"cf\.mcap: seed 2 does not match"):
        load_episode(path)
    # Same identity, other content: the fingerprint catches it.
    forged = attrs.evolve(other, seed=1)
    write_counterfactual_mcap(tmp_path / "cf.mcap", forged, scenario=scenario)
    with pytest.raises(LogError, match="does not match the fingerprint"):
        load_episode(path)
    with pytest.raises(LogError, match="a shared counterfactual file, not an episode"):
        load_episode(tmp_path / "cf.mcap")


def test_rerun_mcap_check_accepts_every_kind_of_file(tmp_path: Path, episode) -> None:  # type: ignore[no-untyped-def]
    """An independent reader: rerun's MCAP checker (structure, timelines, chunk order)."""
    import subprocess
    import sys

    scenario, record, metrics = episode("concert", 4, "straight")
    files = {
        "full": tmp_path / "full.mcap",
        "compact": tmp_path / "compact.mcap",
        "counterfactual": tmp_path / "cf.mcap",
    }
    write_episode_mcap(files["full"], record, scenario=scenario, metrics=metrics)
    write_episode_mcap(
        files["compact"],
        record,
        scenario=scenario,
        metrics=metrics,
        profile="compact",
        counterfactual_file="cf.mcap",
    )
    write_counterfactual_mcap(files["counterfactual"], record, scenario=scenario)
    for kind, path in files.items():
        done = subprocess.run(
            [sys.executable, "-m", "rerun", "mcap", "check", str(path)],
            capture_output=True,
            text=True,
            timeout=120,
        )
        assert done.returncode == 0, (kind, done.stdout, done.stderr)
        rows = [line.split() for line in done.stdout.splitlines() if "/srfm/" in line]
        assert rows, (kind, done.stdout)
        assert all(row[0] == "ok" for row in rows), (kind, done.stdout)
    done = subprocess.run(
        [
            sys.executable,
            "-m",
            "rerun",
            "mcap",
            "convert",
            str(files["full"]),
            "-o",
            str(tmp_path / "converted.rrd"),
        ],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "converted.rrd").stat().st_size > 0


# --- every profile, every reader ------------------------------------------------------


@pytest.fixture
def every_kind(tmp_path: Path, episode, short_scenario):  # type: ignore[no-untyped-def]
    """Full, compact (own counterfactual), compact with a shared counterfactual file, and
    that file, of one short episode with a wall and a pillar."""
    scenario, record, metrics = episode(short_scenario, 5, "orca")
    files = {
        "full": tmp_path / "full.mcap",
        "compact": tmp_path / "compact.mcap",
        "compact-shared": tmp_path / "planner" / "shared.mcap",
        "counterfactual": tmp_path / "_counterfactual" / "cf.mcap",
    }
    write_episode_mcap(files["full"], record, scenario=scenario, metrics=metrics)
    write_episode_mcap(
        files["compact"], record, scenario=scenario, metrics=metrics, profile="compact"
    )
    write_counterfactual_mcap(files["counterfactual"], record, scenario=scenario)
    write_episode_mcap(
        files["compact-shared"],
        record,
        scenario=scenario,
        metrics=metrics,
        profile="compact",
        counterfactual_file="../_counterfactual/cf.mcap",
    )
    return files, record, metrics


def test_mcap_core_reads_every_kind_of_file(every_kind, mcap_core) -> None:  # type: ignore[no-untyped-def]
    """The official TypeScript reader (@mcap/core's McapIndexedReader) opens every file
    (summary CRC, chunk CRCs, zstd chunks) and finds the expected messages per channel."""
    files, record, _ = every_kind
    results = {Path(r["file"]).name: r for r in mcap_core(list(files.values()))}
    expected = {
        "full": expected_counts(record, "full", shared=False),
        "compact": expected_counts(record, "compact", shared=False),
        "compact-shared": expected_counts(record, "compact", shared=True),
        "counterfactual": {"/srfm/episode": 1, "/srfm/trajectories": 1},
    }
    for kind, path in files.items():
        r = results[path.name]
        assert r["counts"] == expected[kind], kind
        assert r["statistics"]["channelMessageCounts"] == expected[kind], kind
        assert r["statistics"]["messageCount"] == sum(expected[kind].values())
        assert r["ordered"]
        assert r["library"].startswith("srfm ")
        assert r["metadata"]["srfm"]["schema_version"] == str(SCHEMA_VERSION)
        assert r["chunks"]
        assert all(c["compression"] == "zstd" and c["messageIndexes"] > 0 for c in r["chunks"])
        for topic, channel in r["channels"].items():
            encoding = "protobuf" if topic == "/foxglove/scene" else "json"
            assert channel["messageEncoding"] == encoding
        # The arrays are .npy files that a reader in another language parses.
        # Float64 arrays but the goals are uint8 bit planes of the shape in "planes".
        for group, arrays in r["arrays"].items():
            planes = r["planes"][group]
            assert set(planes) == {n for n in arrays if n not in ("goal", "active")}
            for name, header in arrays.items():
                assert header["dataBytes"] == header["expectedBytes"], (group, name)
                if name in planes:
                    m = math.prod(planes[name])
                    assert header["descr"] == "|u1", (group, name)
                    assert header["shape"] == [64, (m + 7) // 8], (group, name)
                else:
                    assert header["descr"] in ("<f8", "|b1"), (group, name)
    compact = results[files["compact"].name]
    assert compact["planes"]["factual"]["pos"] == list(record.factual_pos.shape)
    assert compact["arrays"]["factual"]["goal"]["shape"] == list(record.factual_goal.shape)
    # Compact scenes leave the velocity arrows out.
    peds = [e for m in compact["scene"] for e in m["entities"] if e["id"] == "pedestrians"]
    assert len(peds) == len(_frames(record, 15))
    assert not any(e["arrows"] for e in peds)


@pytest.mark.parametrize("kind", ["full", "compact", "compact-shared"])
def test_round_trip_of_every_profile(every_kind, kind: str) -> None:  # type: ignore[no-untyped-def]
    files, record, metrics = every_kind
    logged = load_episode(files[kind])
    assert logged.exact_velocities is (kind == "full")
    _assert_same_record(record, logged.record, velocities=kind == "full")
    again = episode_metrics(logged.record)
    assert logged.online_metrics is not None
    for name, value in metrics.values.items():
        assert np.float64(again.values[name]).tobytes() == np.float64(value).tobytes(), name
        assert (
            np.float64(logged.online_metrics.values[name]).tobytes() == np.float64(value).tobytes()
        )
    assert (logged.counterfactual_path is not None) is (kind == "compact-shared")


def _from_planes_by_hand(planes: np.ndarray, shape: list[int]) -> np.ndarray:
    """docs/logging.md's decoder of the bit-plane form, written from its definition
    (unpackbits, not srfm's 8 x 8 bit transposes)."""
    m = math.prod(shape)
    bits = np.unpackbits(planes, axis=1, count=m, bitorder="little")  # (64, M)
    z = np.packbits(bits.T.copy(), axis=1, bitorder="little").view("<u8").reshape(-1)
    z = np.moveaxis(z.reshape(*shape[1:], shape[0]), -1, 0)  # time first again
    d = (z >> np.uint64(1)) ^ (np.uint64(0) - (z & np.uint64(1)))  # undo the zigzag
    u = np.cumsum(np.cumsum(d, axis=0), axis=0)  # undo the differences (modulo 2**64)
    return np.ascontiguousarray(u).view("<f8")


def test_arrays_read_without_srfm(every_kind) -> None:  # type: ignore[no-untyped-def]
    """The exact arrays with the mcap library, json, base64 and numpy alone, the
    bit-plane form decoded as docs/logging.md says."""
    files, record, _ = every_kind
    with files["full"].open("rb") as fh:
        found = {}
        for _, _, message in make_reader(fh).iter_messages(topics=["/srfm/trajectories"]):
            doc = json.loads(message.data)
            for name, text in doc["arrays"].items():
                array = np.load(io.BytesIO(base64.b64decode(text)))
                if name in doc["planes"]:
                    array = _from_planes_by_hand(array, doc["planes"][name])
                found[f"{doc['group']}.{name}"] = array
    assert same_bits(found["factual.pos"], record.factual_pos)
    assert same_bits(found["factual.goal"], record.factual_goal)
    assert same_bits(found["counterfactual.vel"], record.counterfactual_vel)
    assert same_bits(found["robot.pose"], record.robot_pose)
    assert same_bits(found["robot.active"], record.robot_active)
    assert same_bits(found["robot.cmd"], record.robot_cmd)  # NaN payloads included


def test_bit_planes_are_exact_and_smaller(episode) -> None:  # type: ignore[no-untyped-def]
    """Every bit comes back (NaN payloads, signed zeros, infinities, one sample, sizes
    that are not a multiple of 8), and a real episode's positions take at most 70 % of
    the bytes of the plain .npy file once zstd (level 3, as the MCAP chunks) has
    compressed them."""
    import zstandard

    from srfm.logs._planes import from_planes, to_planes

    rng = np.random.default_rng(5)
    odd = rng.normal(size=(9, 3, 2)) * 100.0
    flat = odd.reshape(-1)
    flat[:3] = (np.nan, -0.0, -np.inf)
    flat[3:4].view(np.uint64)[:] = 0xFFF0_0000_0000_0ABC  # a NaN with a payload
    for a in (odd, odd[:1], odd[:2, 0, :1], rng.normal(size=(1,)), rng.normal(size=(13,))):
        planes = to_planes(a)
        assert planes.dtype == np.uint8
        assert planes.shape == (64, (a.size + 7) // 8)
        assert same_bits(from_planes(planes, a.shape), np.ascontiguousarray(a))
        assert same_bits(_from_planes_by_hand(planes, list(a.shape)), np.ascontiguousarray(a))
    _, record, _ = episode("concert", 0, "straight")
    zstd = zstandard.ZstdCompressor(level=3)
    plain = len(zstd.compress(_mcap.npy_bytes(record.factual_pos)))
    planes = len(zstd.compress(_mcap.npy_bytes(to_planes(record.factual_pos))))
    assert planes < 0.7 * plain, (planes, plain)


@pytest.mark.parametrize(
    ("planes", "shape", "match"),
    [
        (
            np.zeros((64, 2), np.uint8),
            [3, 3, 2],
            r"do not hold a float64 array of shape \(3, 3, 2\)",
        ),
        (np.zeros((64, 1), np.float64), [2, 2], r"expected uint8 \(64, 1\)"),
        (np.zeros((64, 1), np.uint8), [2, "2"], r"not a list of sizes"),
        (np.zeros((64, 1), np.uint8), 4, r"not a list of sizes"),
    ],
)
def test_malformed_bit_planes_are_named(planes: np.ndarray, shape: Any, match: str) -> None:
    text = base64.b64encode(_mcap.npy_bytes(planes)).decode()
    with pytest.raises(LogError, match=rf"^f\.mcap: factual\.pos: .*{match}"):
        _mcap.array_from_npy(text, "f.mcap: factual.pos", shape)


def test_a_file_of_log_schema_4_still_reads() -> None:
    """A real compact file of log schema 4 (every array a plain .npy file), written by
    srfm before the bit planes: read, its arrays as stored, its metrics recomputed
    from it bit for bit."""
    path = DATA / "schema-v4-compact-episode.mcap"
    logged = load_episode(path)
    assert logged.info["schema_version"] == 4
    with path.open("rb") as fh:
        for _, _, message in make_reader(fh).iter_messages(topics=["/srfm/trajectories"]):
            doc = json.loads(message.data)
            assert "planes" not in doc
            if doc["group"] == "factual":
                pos = np.load(io.BytesIO(base64.b64decode(doc["arrays"]["pos"])))
    assert same_bits(logged.record.factual_pos, pos)
    again = episode_metrics(logged.record)
    assert logged.online_metrics is not None
    for name, value in logged.online_metrics.values.items():
        assert np.float64(again.values[name]).tobytes() == np.float64(value).tobytes(), name


def test_a_file_mixing_schema_versions_is_refused(tmp_path: Path) -> None:
    buf = io.BytesIO()
    w = Writer(buf)
    w.start(library="srfm 0.1.0")
    w.add_metadata("srfm", {"schema_version": "4"})
    sid = w.register_schema(
        name=f"srfm.logs.Episode.v{SCHEMA_VERSION}", encoding="jsonschema", data=b"{}"
    )
    cid = w.register_channel(topic="/srfm/episode", message_encoding="json", schema_id=sid)
    w.add_message(channel_id=cid, log_time=0, publish_time=0, data=b"{}")
    w.finish()
    path = tmp_path / "mixed.mcap"
    path.write_bytes(buf.getvalue())
    with pytest.raises(LogError, match=r"mixed\.mcap: mixes log schema versions \[4, 5\]"):
        load_episode(path)


def test_every_crc_is_written_and_checked(every_kind, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    """The mcap library's default indexes and CRCs plus the data section's CRC; the
    reader checks chunks, data section and summary."""
    files, _, _ = every_kind
    data = files["compact"].read_bytes()
    records = list(StreamReader(io.BytesIO(data), emit_chunks=True, validate_crcs=True).records)
    chunks = [r for r in records if isinstance(r, Chunk)]
    (end,) = [r for r in records if isinstance(r, DataEnd)]
    (footer,) = [r for r in records if isinstance(r, Footer)]
    assert chunks
    assert all(c.uncompressed_crc != 0 for c in chunks)
    assert end.data_section_crc != 0
    assert footer.summary_crc != 0
    assert any(isinstance(r, MessageIndex) for r in records)
    damaged = {
        # A bit in a chunk's compressed data: zstd or the chunk CRC notices.
        "chunk": data.index(chunks[0].data) + len(chunks[0].data) // 2,
        # The library string of the header: only the data section CRC covers it.
        "header": data.index(b"srfm "),
        # A byte of a summary record: only the summary CRC covers it.
        "summary": footer.summary_start + 20,
    }
    for where, at in damaged.items():
        flipped = bytearray(data)
        flipped[at] ^= 0x04
        path = tmp_path / f"{where}.mcap"
        path.write_bytes(bytes(flipped))
        with pytest.raises(LogError, match=rf"{where}\.mcap: not a readable MCAP file"):
            read_log(path)
    extra = tmp_path / "extra.mcap"
    extra.write_bytes(data + b"more")
    with pytest.raises(LogError, match=r"extra\.mcap: not a readable"):
        read_log(extra)


def test_the_robot_arrays_are_required_and_checked(
    tmp_path: Path, episode, monkeypatch: pytest.MonkeyPatch
) -> None:  # type: ignore[no-untyped-def]
    scenario, record, metrics = episode("concert", 0, "straight")

    def short_pose(r):  # type: ignore[no-untyped-def]
        arrays = {
            "pose": r.robot_pose[:-1],
            "vel": r.robot_vel,
            "active": r.robot_active,
            "cmd": r.robot_cmd,
        }
        return _mcap._trajectories("robot", r.time_s.shape[0], arrays)

    monkeypatch.setattr(_mcap, "_robot_arrays", short_pose)
    write_episode_mcap(tmp_path / "short.mcap", record, scenario=scenario, metrics=metrics)
    with pytest.raises(LogError, match=r"short\.mcap: robot\.pose has shape"):
        load_episode(tmp_path / "short.mcap")

    def as_ints(r):  # type: ignore[no-untyped-def]
        arrays = {"pose": r.robot_pose.astype(np.int64)}
        return _mcap._trajectories("robot", r.time_s.shape[0], arrays)

    monkeypatch.setattr(_mcap, "_robot_arrays", as_ints)
    write_episode_mcap(tmp_path / "ints.mcap", record, scenario=scenario, metrics=metrics)
    with pytest.raises(LogError, match=r"ints\.mcap: robot\.pose: a \.npy array of int64"):
        load_episode(tmp_path / "ints.mcap")

    monkeypatch.setattr(_mcap, "_robot_arrays", lambda r: b"")
    original = _mcap._Writer.add

    def no_robot(self, key: str, t_ns: int, data: bytes) -> None:  # type: ignore[no-untyped-def]
        if data:
            original(self, key, t_ns, data)

    monkeypatch.setattr(_mcap._Writer, "add", no_robot)
    write_episode_mcap(tmp_path / "none.mcap", record, scenario=scenario, metrics=metrics)
    with pytest.raises(LogError, match=r"none\.mcap: the robot's trajectory block is missing"):
        load_episode(tmp_path / "none.mcap")


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("not base64!", "not a base64 .npy array"),
        (base64.b64encode(b"\x93NUMPY garbage").decode(), "not a base64 .npy array"),
        (12, "expected the base64 text of a .npy file"),
    ],
)
def test_malformed_arrays_are_named(text: Any, match: str) -> None:
    with pytest.raises(LogError, match=rf"^f\.mcap: factual\.pos: {match}"):
        _mcap.array_from_npy(text, "f.mcap: factual.pos")


def test_the_foxglove_layout_shows_srfm_topics() -> None:
    """docs/foxglove_layout.json: Foxglove's exported-layout format, every panel placed,
    every topic one that srfm writes."""
    from tests.conftest import REPO

    layout = json.loads((REPO / "docs" / "foxglove_layout.json").read_text(encoding="utf-8"))
    assert set(layout) >= {"configById", "layout", "globalVariables", "playbackConfig"}

    def leaves(node: Any) -> list[str]:
        if isinstance(node, str):
            return [node]
        assert node["direction"] in ("row", "column")
        return leaves(node["first"]) + leaves(node["second"])

    panels = layout["configById"]
    assert sorted(leaves(layout["layout"])) == sorted(panels)
    topics = {c.topic for c in CHANNELS.values()}
    three_d = panels["3D!srfm-scene"]
    assert set(three_d["topics"]) == {"/foxglove/scene"}
    assert three_d["followTf"] == "world"
    assert three_d["cameraState"]["perspective"] is False  # top-down
    for panel_id, config in panels.items():
        paths = [config.get("topicPath")] + [p["value"] for p in config.get("paths", [])]
        for path in filter(None, paths):
            assert path.split(".")[0] in topics, (panel_id, path)


def test_official_readers_take_a_run_with_entering_pedestrians(
    tmp_path: Path, episode, mcap_core
) -> None:  # type: ignore[no-untyped-def]
    """corridor_flow (people enter during the run): the mcap library and @mcap/core read
    the file, every JSON message fits its schema (with ``pedestrians.enter_step``), and
    the Foxglove scene draws at each frame exactly the pedestrians there."""
    scenario, record, metrics = episode("corridor_flow", 1, "dwa")
    path = tmp_path / "flow.mcap"
    write_episode_mcap(path, record, scenario=scenario, metrics=metrics, profile="compact")
    summary, msgs = _messages(path)
    _check_json_messages(summary, msgs)
    (info,) = _by_topic(msgs)["/srfm/episode"]
    assert record.ped_enter_step is not None
    assert info[1]["pedestrians"]["enter_step"] == record.ped_enter_step.tolist()
    (decoded,) = mcap_core([path])
    assert decoded["counts"] == expected_counts(record, "compact", shared=False)
    present = record.present()
    frames = _frames(record, 15)
    peds = _scene(decoded)["pedestrians"]
    assert len(peds) == len(frames)
    counts = []
    for k, (_, entity) in zip(frames, peds, strict=True):
        m = int(present[k].sum())
        xy = np.array(entity["cylinders"]).reshape(-1, 4)[:, :2]
        assert len(xy) == m, k
        assert np.abs(xy - record.factual_pos[k, :m]).max(initial=0) <= 0.005
        counts.append(m)
    assert counts[0] == 0 < counts[-1] == record.factual_pos.shape[1]


@pytest.mark.parametrize("dt", [1 / 15, 0.0667, 0.1, 0.05, 0.01, 1 / 3, 0.125])
def test_message_times_are_the_rounded_sample_times(dt: float) -> None:
    """The vectorised message times equal ``round(k * dt * 1e9)`` sample by sample."""
    got = _mcap.times_ns(20_000, dt)
    assert got == [round(k * dt * 1e9) for k in range(20_000)]
    assert all(type(t) is int for t in got[:3])


def test_robot_state_text_is_the_json_of_its_fields() -> None:
    """The directly formatted ``/srfm/robot/state`` message is byte for byte what the JSON
    encoder makes of the same fields, for awkward floats too."""
    rng = np.random.default_rng(5)
    values = [0.0, -0.0, 1e-300, -5e-324, 1e22, 123456789.125, 1 / 3, *rng.normal(0, 50, 40)]
    for k in range(len(values) - 5):
        x, y, th, vx, vy = (float(v) for v in values[k : k + 5])
        for active in (True, False):
            doc = {
                "schema_version": SCHEMA_VERSION,
                "step": k,
                "x": x,
                "y": y,
                "theta": th,
                "vx": vx,
                "vy": vy,
                "active": active,
            }
            assert _mcap._robot_state(k, [x, y, th], [vx, vy], active) == _mcap._json(doc)
