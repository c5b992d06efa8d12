"""The Python client (``srfm.planners.external.serve``) as a real process: it refuses
another protocol version, and an exception in the user's function reaches srfm as the
planner's error, ending only that episode."""

from __future__ import annotations

import socket
import struct
import subprocess
import sys
from pathlib import Path

import msgpack
import pytest

import srfm
from srfm.errors import PlannerFailureWarning
from srfm.planners.external import PROTOCOL_VERSION, define_external

RAISING = """
from srfm.planners.external import serve

def act(step, episode):
    if step.step == 4:
        raise ValueError("no path to the goal")
    return 0.1, 0.0

serve(act)
"""


def test_an_exception_in_act_is_the_planners_error(tmp_path: Path) -> None:
    script = tmp_path / "raising.py"
    script.write_text(RAISING, encoding="utf-8")
    name = define_external("raising", [sys.executable, str(script)])
    with pytest.warns(
        PlannerFailureWarning,
        match=r"reported an error: act\(\) raised ValueError: no path to the goal at step 4 "
        r"\(scenario circle, seed 0\)",
    ):
        record = srfm.run_episode("circle", 0, name)
    assert record.outcome == "planner_failed"
    assert record.end_step == 4


def _frame(message: object) -> bytes:
    body = msgpack.packb(message)
    return struct.pack(">I", len(body)) + body


def test_the_python_client_refuses_another_protocol_version(tmp_path: Path) -> None:
    path = tmp_path / "srfm.sock"
    server = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    server.bind(str(path))
    server.listen(1)
    code = "from srfm.planners.external import serve; serve(lambda s, e: (0.0, 0.0))"
    process = subprocess.Popen(
        [sys.executable, "-c", code], env={"SRFM_PLANNER_ADDRESS": f"unix:{path}"}
    )
    try:
        server.settimeout(120)
        conn, _ = server.accept()
        conn.settimeout(120)
        conn.sendall(_frame({"type": "hello", "protocol": PROTOCOL_VERSION + 1, "planner": "x"}))
        (n,) = struct.unpack(">I", conn.recv(4, socket.MSG_WAITALL))
        assert msgpack.unpackb(conn.recv(n, socket.MSG_WAITALL)) == {
            "type": "error",
            "message": f"this planner speaks protocol version {PROTOCOL_VERSION}, "
            f"srfm sent version {PROTOCOL_VERSION + 1}",
        }
        assert process.wait(timeout=120) == 0
    finally:
        process.kill()
        process.wait()
        server.close()
