"""Round trip of one control step for each candidate wire format and transport of the
external planner protocol (docs/planners-any-language.md, docs/performance.md).

For each candidate this script starts a C++ peer (``tools/bench/external_transport/``,
built here with CMake and the system compiler against Debian's packages), sends it the
same observation an external planner gets at every step of a paper scenario (the
robot's state, its goal, 10 pedestrians with ids, positions, velocities and radii),
and times, with ``time.perf_counter_ns``, the whole round trip as srfm would pay it:
encode in Python, send, the peer decodes, computes a straight-to-goal command, encodes
and answers, Python receives and decodes the command. ``--steps`` round trips per
repetition after 200 unrecorded ones; the median and the 90th percentile over all
repetitions are reported, in µs.

Candidates (each exists on PyPI and as a Debian C++ development package):

- ``json-unix``: JSON lines (Python's ``json``; nlohmann-json3-dev) over a Unix socket;
- ``msgpack-unix``: MessagePack (``msgpack``; libmsgpack-cxx-dev), each message after
  its 4-byte big-endian length, over a Unix socket;
- ``msgpack-tcp``: the same over TCP loopback (TCP_NODELAY on both ends);
- ``msgpack-zmq``: MessagePack over ZeroMQ REQ/REP on ``ipc://`` (``pyzmq``;
  libzmq3-dev, cppzmq-dev).

Usage::

    .venv/bin/python tools/bench/bench_external_transport.py
    .venv/bin/python tools/bench/bench_external_transport.py --steps 5000 --repeats 5
    .venv/bin/python tools/bench/bench_external_transport.py --steps 3000 --repeats 5 \
        --json docs/results/performance/external_transport.json

``--json PATH`` also writes each candidate's figures and the run's record
(``tools/results/record.py``) for docs/performance.md's generated blocks.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import socket
import statistics
import struct
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import msgpack

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))
from tools.results.record import run_record, start

HERE = Path(__file__).resolve().parent
SOURCES = HERE / "external_transport"
CANDIDATES = ("json-unix", "msgpack-unix", "msgpack-tcp", "msgpack-zmq")
_LENGTH = struct.Struct(">I")


def observation(step: int) -> dict[str, Any]:
    """The observation of one step: a robot and 10 pedestrians (paper scenarios)."""
    n = 10
    return {
        "type": "observe",
        "step": step,
        "time_s": step / 15.0,
        "robot": [1.0 + 1e-3 * step, 2.0, 0.3, 0.5, 0.1, 0.51, 0.2],
        "goal": [10.0, 2.5],
        "ped_ids": list(range(n)),
        "ped_pos": [0.1 * i + 1e-4 * step for i in range(2 * n)],
        "ped_vel": [0.01 * i for i in range(2 * n)],
        "ped_radius": [0.3] * n,
    }


def build(build_dir: Path) -> None:
    """Configure and build the C++ peers (Release) into ``build_dir``."""
    build_dir.mkdir(parents=True, exist_ok=True)
    subprocess.run(
        ["cmake", "-S", str(SOURCES), "-B", str(build_dir), "-DCMAKE_BUILD_TYPE=Release"],
        check=True,
        stdout=subprocess.DEVNULL,
    )
    subprocess.run(["cmake", "--build", str(build_dir), "-j", "2"], check=True)


def _recv_exact(sock: socket.socket, n: int) -> bytes:
    data = b""
    while len(data) < n:
        chunk = sock.recv(n - len(data))
        if not chunk:
            raise RuntimeError("the peer closed the connection")
        data += chunk
    return data


def _stream_pair(kind: str, tmp: Path, peer: Path) -> tuple[socket.socket, subprocess.Popen[bytes]]:
    """Listen, start ``peer`` with the address, accept its connection."""
    if kind == "unix":
        path = tmp / f"{peer.name}.sock"
        server = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        server.bind(str(path))
        address = f"unix:{path}"
    else:
        server = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        server.bind(("127.0.0.1", 0))
        address = f"tcp:127.0.0.1:{server.getsockname()[1]}"
    server.listen(1)
    process = subprocess.Popen([str(peer), address])
    conn, _ = server.accept()
    server.close()
    if kind == "tcp":
        conn.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
    return conn, process


def round_trips(candidate: str, build_dir: Path, steps: int, repeats: int) -> list[float]:
    """Every timed round trip (µs) of ``candidate``."""
    messages = [observation(k) for k in range(steps)]
    with tempfile.TemporaryDirectory(prefix="srfm-transport-") as tmp_name:
        tmp = Path(tmp_name)
        step: Callable[[dict[str, Any]], list[float]]
        if candidate == "msgpack-zmq":
            import zmq

            address = f"ipc://{tmp / 'zmq.sock'}"
            process = subprocess.Popen([str(build_dir / "peer_zmq"), address])
            context = zmq.Context()
            req = context.socket(zmq.REQ)
            req.connect(address)

            def step(message: dict[str, Any]) -> list[float]:
                req.send(msgpack.packb(message))
                reply: dict[str, Any] = msgpack.unpackb(req.recv())
                return list(reply["command"])

            def stop() -> None:
                req.send(b"")
                req.close(linger=0)
                context.term()

        else:
            fmt, kind = candidate.split("-")
            peer = build_dir / ("peer_json" if fmt == "json" else "peer_msgpack")
            conn, process = _stream_pair(kind, tmp, peer)
            if fmt == "json":
                reader = conn.makefile("rb")

                def step(message: dict[str, Any]) -> list[float]:
                    conn.sendall(json.dumps(message, separators=(",", ":")).encode() + b"\n")
                    reply: dict[str, Any] = json.loads(reader.readline())
                    return list(reply["command"])

            else:

                def step(message: dict[str, Any]) -> list[float]:
                    body = msgpack.packb(message)
                    conn.sendall(_LENGTH.pack(len(body)) + body)
                    (n,) = _LENGTH.unpack(_recv_exact(conn, 4))
                    reply: dict[str, Any] = msgpack.unpackb(_recv_exact(conn, n))
                    return list(reply["command"])

            def stop() -> None:
                conn.shutdown(socket.SHUT_RDWR)  # also ends makefile()'s reader
                conn.close()

        times: list[float] = []
        try:
            for message in messages[:200]:
                step(message)
            clock = time.perf_counter_ns
            for _ in range(repeats):
                for message in messages:
                    t0 = clock()
                    step(message)
                    times.append((clock() - t0) / 1e3)
        finally:
            stop()
            process.wait(timeout=10)
    return times


def main() -> None:
    """Build the peers, time every candidate, print a Markdown table."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--steps", type=int, default=3000, help="round trips per repetition")
    parser.add_argument("--repeats", type=int, default=3, help="repetitions per candidate")
    parser.add_argument(
        "--build-dir",
        type=Path,
        default=Path(tempfile.gettempdir()) / "srfm-transport-bench",
        help="where the C++ peers are built",
    )
    parser.add_argument("--candidates", nargs="+", default=list(CANDIDATES), choices=CANDIDATES)
    parser.add_argument("--json", type=Path, default=None, help="also write the figures here")
    args = parser.parse_args()
    started, t0_run, load0 = start()
    build(args.build_dir)
    print(
        f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, {platform.node()}, "
        f"{os.cpu_count()} CPUs, Python {platform.python_version()}, "
        f"load average {os.getloadavg()[0]:.2f}"
    )
    print(f"{args.repeats} x {args.steps} round trips per candidate\n")
    print("| candidate | median (µs) | 90th percentile (µs) |")
    print("|---|---:|---:|")
    rows = {}
    for candidate in args.candidates:
        times = round_trips(candidate, args.build_dir, args.steps, args.repeats)
        p90 = statistics.quantiles(times, n=10)[-1]
        print(f"| {candidate} | {statistics.median(times):.1f} | {p90:.1f} |")
        sys.stdout.flush()
        rows[candidate] = {
            "round_trips": len(times),
            "median_us": round(statistics.median(times), 2),
            "p90_us": round(p90, 2),
        }
    if args.json is not None:
        doc = {
            "steps": args.steps,
            "repeats": args.repeats,
            "candidates": rows,
            "run": run_record(started, t0_run, load0),
        }
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(doc, indent=1) + "\n", encoding="utf-8")
        print(f"-> {args.json}")


if __name__ == "__main__":
    main()
