"""The MCAP sink and reader: channels, schemas, exact rebuilds, Foxglove scene, errors."""

from __future__ import annotations

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
from mcap.writer import Writer

from srfm.errors import LogError
from srfm.logs import (
    CHANNELS,
    load_episode,
    read_log,
    write_counterfactual_mcap,
    write_episode_mcap,
)
from srfm.metrics import episode_metrics
from srfm.sim.record import EpisodeRecord
from tests.logs.conftest import check_json_schema, same_bits


def _messages(path: Path) -> tuple[Any, list[tuple[Any, Any, Any]]]:
    """Summary and messages as the mcap library's seeking reader returns them."""
    with path.open("rb") as fh:
        reader = make_reader(fh, validate_crcs=True)
        summary = reader.get_summary()
        msgs = list(reader.iter_messages(log_time_order=False))
    return summary, msgs


def _by_topic(msgs: list[tuple[Any, Any, Any]]) -> dict[str, list[tuple[int, dict[str, Any]]]]:
    out: dict[str, list[tuple[int, dict[str, Any]]]] = defaultdict(list)
    for _, channel, message in msgs:
        out[channel.topic].append((message.log_time, json.loads(message.data)))
    return out


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
        assert channel.message_encoding == "json"
        assert schema.encoding == "jsonschema"
        schemas[channel.topic] = json.loads(schema.data)
    assert schemas["/foxglove/scene"]["title"] == "foxglove.SceneUpdate"
    assert all(s["title"].endswith(".v2") for t, s in schemas.items() if t.startswith("/srfm"))
    for _, channel, message in msgs:
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


def test_foxglove_scene_draws_the_run(full_log) -> None:  # type: ignore[no-untyped-def]
    path, scenario, record, _ = full_log
    _, msgs = _messages(path)
    scene = _by_topic(msgs)["/foxglove/scene"]
    entities: dict[str, list[tuple[int, dict[str, Any]]]] = defaultdict(list)
    for t, update in scene:
        for e in update["entities"]:
            assert e["frame_id"] == "world"
            assert e["timestamp"]["sec"] * 10**9 + e["timestamp"]["nsec"] == t
            entities[e["id"]].append((t, e))
    world = entities["world"][0][1]
    loop = world["lines"][0]
    assert loop["type"] == 1
    w = scenario.world
    assert [(p["x"], p["y"]) for p in loop["points"]] == [
        (w.x_min, w.y_min),
        (w.x_max, w.y_min),
        (w.x_max, w.y_max),
        (w.x_min, w.y_max),
    ]
    assert len(world["lines"][1]["points"]) == 2  # the wall
    assert len(world["cylinders"]) == 1  # the pillar
    n = record.time_s.shape[0]
    assert len(entities["pedestrians"]) == n  # full profile: every sample
    for k in (0, n // 3, n - 1):
        _, peds = entities["pedestrians"][k]
        xy = np.array(
            [[c["pose"]["position"]["x"], c["pose"]["position"]["y"]] for c in peds["cylinders"]]
        )
        assert np.abs(xy - record.factual_pos[k]).max() <= 0.0051
        _, ghosts = entities["counterfactual"][k]
        gxy = np.array(
            [[c["pose"]["position"]["x"], c["pose"]["position"]["y"]] for c in ghosts["cylinders"]]
        )
        assert np.abs(gxy - record.counterfactual_pos[k]).max() <= 0.0051
        _, robot = entities["robot"][k]
        q = robot["arrows"][0]["pose"]["orientation"]
        yaw = 2 * math.atan2(q["z"], q["w"])
        err = (yaw - record.robot_pose[k, 2] + math.pi) % (2 * math.pi) - math.pi
        assert abs(err) <= math.radians(2.6)
        for arrow in peds["arrows"]:  # velocity arrows: 1 s of motion, 5 cm steps
            assert 0.025 <= arrow["shaft_length"] <= 1.25 + 0.05


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
    assert cf_size < 95_000
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
    schemas = {
        c.topic: json.loads(summary.schemas[c.schema_id].data) for c in summary.channels.values()
    }
    for _, channel, message in msgs:
        check_json_schema(json.loads(message.data), schemas[channel.topic], channel.topic)
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


@pytest.mark.parametrize("version", [1, 3])
def test_other_schema_versions_are_named(tmp_path: Path, version: int) -> None:
    """Version 1 files (robot only as per-sample messages) and future ones are refused."""
    buf = io.BytesIO()
    w = Writer(buf)
    w.start()
    name = f"srfm.logs.Episode.v{version}"
    sid = w.register_schema(name=name, encoding="jsonschema", data=b"{}")
    cid = w.register_channel(topic="/srfm/episode", message_encoding="json", schema_id=sid)
    data = b'{"schema_version":%d}' % version
    w.add_message(channel_id=cid, log_time=0, publish_time=0, data=data)
    w.finish()
    path = tmp_path / "other.mcap"
    path.write_bytes(buf.getvalue())
    with pytest.raises(
        LogError,
        match=rf"other\.mcap: /srfm/episode uses schema {name}, this srfm reads "
        r"srfm\.logs\.Episode\.v2",
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
