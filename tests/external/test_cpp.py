"""The C++ client (clients/cpp), built here with CMake and the system compiler: its
straight-to-goal planner gives the built-in ``straight`` planner's episode record on
every paper scenario, its reactive planner runs, it refuses another protocol version,
and it serves several workers from one listening address."""

from __future__ import annotations

import re
import socket
import struct
import subprocess
import time
from pathlib import Path

import msgpack
import numpy as np
import pytest

import srfm
from srfm.planners.external import PROTOCOL_VERSION, define_external
from srfm.scenarios import EVALUATION_SCENARIOS
from tests.conftest import REPO, record_digest

HEADER = REPO / "clients" / "cpp" / "include" / "srfm" / "planner.hpp"


def test_the_client_states_the_schema_version() -> None:
    text = HEADER.read_text(encoding="utf-8")
    (version,) = re.findall(r"constexpr int kProtocolVersion = (\d+);", text)
    assert int(version) == PROTOCOL_VERSION


@pytest.mark.parametrize("scenario", EVALUATION_SCENARIOS)
def test_cpp_straight_gives_the_builtin_straight_record(cpp_build: Path, scenario: str) -> None:
    name = define_external("cpp-straight", [str(cpp_build / "straight_planner")])
    for seed in (0, 3):
        builtin = srfm.run_episode(scenario, seed, "straight")
        external = srfm.run_episode(scenario, seed, name)
        assert external.planner == "external:cpp-straight"
        assert external.outcome == builtin.outcome
        assert record_digest(external) == record_digest(builtin)


def test_cpp_reactive_planner_runs_and_sees_people(cpp_build: Path) -> None:
    name = define_external("cpp-reactive", [str(cpp_build / "reactive_planner")])
    record = srfm.run_episode("crosswalk", 0, name)
    straight = srfm.run_episode("crosswalk", 0, "straight")
    assert record.outcome == "goal_reached"
    # It turns away from people within 2 m: not the straight planner's commands.
    assert not np.array_equal(record.robot_cmd, straight.robot_cmd, equal_nan=True)
    assert record_digest(srfm.run_episode("crosswalk", 0, name)) == record_digest(record)


def _frame(message: object) -> bytes:
    body = msgpack.packb(message)
    return struct.pack(">I", len(body)) + body


def _read(sock: socket.socket) -> dict[str, object]:
    head = sock.recv(4, socket.MSG_WAITALL)
    (n,) = struct.unpack(">I", head)
    reply: dict[str, object] = msgpack.unpackb(sock.recv(n, socket.MSG_WAITALL))
    return reply


def test_cpp_client_refuses_another_protocol_version(cpp_build: Path, tmp_path: Path) -> None:
    path = tmp_path / "srfm.sock"
    server = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    server.bind(str(path))
    server.listen(1)
    process = subprocess.Popen(
        [str(cpp_build / "straight_planner")], env={"SRFM_PLANNER_ADDRESS": f"unix:{path}"}
    )
    try:
        server.settimeout(30)
        conn, _ = server.accept()
        conn.settimeout(30)
        conn.sendall(_frame({"type": "hello", "protocol": PROTOCOL_VERSION + 1, "planner": "x"}))
        reply = _read(conn)
        assert reply == {
            "type": "error",
            "message": f"this planner speaks protocol version {PROTOCOL_VERSION}, "
            f"srfm sent version {PROTOCOL_VERSION + 1}",
        }
        assert process.wait(timeout=30) == 1
    finally:
        process.kill()
        process.wait()
        server.close()


def test_cpp_client_reports_a_malformed_message(cpp_build: Path, tmp_path: Path) -> None:
    path = tmp_path / "srfm.sock"
    server = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    server.bind(str(path))
    server.listen(1)
    process = subprocess.Popen(
        [str(cpp_build / "straight_planner")], env={"SRFM_PLANNER_ADDRESS": f"unix:{path}"}
    )
    try:
        server.settimeout(30)
        conn, _ = server.accept()
        conn.settimeout(30)
        conn.sendall(_frame({"type": "hello", "protocol": PROTOCOL_VERSION, "planner": "x"}))
        assert _read(conn) == {
            "type": "hello",
            "protocol": PROTOCOL_VERSION,
            "detection_range_m": 0.0,
        }
        conn.sendall(_frame({"type": "reset", "scenario": "x"}))
        reply = _read(conn)
        assert reply["type"] == "error"
        assert "without 'seed'" in str(reply["message"])
        assert process.wait(timeout=30) == 1
    finally:
        process.kill()
        process.wait()
        server.close()


def test_cpp_listening_planner_serves_parallel_connections(cpp_build: Path, tmp_path: Path) -> None:
    address = f"unix:{tmp_path / 'planner.sock'}"
    server = subprocess.Popen([str(cpp_build / "straight_planner"), "--listen", address])
    try:
        deadline = time.monotonic() + 30
        while not (tmp_path / "planner.sock").exists():
            assert time.monotonic() < deadline
            assert server.poll() is None
            time.sleep(0.05)
        name = define_external("cpp-listening", address=address)
        first = srfm.run_episode("circle", 0, name)
        assert record_digest(first) == record_digest(srfm.run_episode("circle", 0, "straight"))
        # A second connection while the first is open (a second benchmark worker).
        from srfm.planners.external._planner import _Link, _link, external_definition

        other = _Link.open(external_definition(name))
        try:
            assert other.detection_range_m == 0.0
            assert _link(external_definition(name)) is not other
        finally:
            other.close(polite=True)
    finally:
        server.kill()
        server.wait()


def test_cpp_straight_on_a_holonomic_robot(cpp_build: Path) -> None:
    import attrs

    scenario = srfm.load_scenario("crosswalk")
    scenario = attrs.evolve(scenario, robot=attrs.evolve(scenario.robot, kinematics="holonomic"))
    name = define_external("cpp-straight", [str(cpp_build / "straight_planner")])
    external = srfm.run_episode(scenario, 0, name)
    assert external.robot_kinematics == "holonomic"
    assert record_digest(external) == record_digest(srfm.run_episode(scenario, 0, "straight"))


def test_cpp_reactive_planner_on_a_scenario_with_walls(cpp_build: Path) -> None:
    """Walls and pillars cross the protocol; the planner steers to the route's waypoints."""
    name = define_external("cpp-reactive", [str(cpp_build / "reactive_planner")])
    record = srfm.run_episode("narrow_doorway", 0, name)
    assert record.outcome == "goal_reached"


def test_the_client_reads_every_field_the_schema_names() -> None:
    from srfm.planners.external._schema import message_spec

    source = (REPO / "clients" / "cpp" / "src" / "planner.cpp").read_text(encoding="utf-8")
    read = set(re.findall(r'\(f, "(\w+)"', source))
    wanted = {f.name for kind in ("reset", "observe") for f in message_spec(kind, "srfm").fields}
    assert read == wanted
