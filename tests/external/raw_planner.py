"""A planner that speaks the external planner protocol by hand (socket, struct, msgpack:
no srfm), drives straight to the goal like srfm's ``straight`` planner, and misbehaves
as told: the tests' stand-in for every way a real planner process can fail.

Usage: ``python raw_planner.py MODE[@STEP]``. With ``@STEP`` the mode acts at step STEP
of episodes of seed 0 only (other seeds run normally, so a test sees the next episode
start afresh); without it, at once. Modes:

straight  no misbehaviour            crash     exit with status 3
segv      killed by SIGSEGV           hang      sleep for a minute
garbage   bytes that are not msgpack  length    an impossible length
wrongtype a 'ready' for a command     nan       the command [nan, 0]
fast      10 x v_max                  strings   the command ["a", "b"]
error     an 'error' message          close     close the socket, keep running
version   answer hello with 99        noconnect exit with status 4 before connecting
resetcrash exit with status 5 when the episode of seed 0 is reset
"""

from __future__ import annotations

import math
import os
import signal
import socket
import struct
import sys
import time

import msgpack

LENGTH = struct.Struct(">I")


def send(sock: socket.socket, message: object) -> None:
    body = msgpack.packb(message)
    sock.sendall(LENGTH.pack(len(body)) + body)


def receive(sock: socket.socket) -> dict:
    def exact(n: int) -> bytes:
        data = b""
        while len(data) < n:
            chunk = sock.recv(n - len(data))
            if not chunk:
                sys.exit(0)  # srfm closed the connection
            data += chunk
        return data

    (n,) = LENGTH.unpack(exact(4))
    return msgpack.unpackb(exact(n))


def straight(obs: dict, episode: dict) -> list[float]:
    x, y, theta = obs["robot"][:3]
    dx = float(obs["goal"][0]) - x
    dy = float(obs["goal"][1]) - y
    vmax = episode["max_speed_mps"]
    error = math.remainder(math.atan2(dy, dx) - theta, 2.0 * math.pi)
    wmax = episode["max_angular_speed_radps"]
    return [vmax * max(math.cos(error), 0.0), max(-wmax, min(wmax, 2.0 * error))]


def main() -> None:
    mode, _, at = sys.argv[1].partition("@")
    step_at = int(at) if at else None
    if mode == "noconnect":
        sys.exit(4)
    family, where = socket.AF_UNIX, os.environ["SRFM_PLANNER_ADDRESS"][5:]
    sock = socket.socket(family, socket.SOCK_STREAM)
    sock.connect(where)
    receive(sock)  # hello
    send(
        sock,
        {"type": "hello", "protocol": 99 if mode == "version" else 1, "detection_range_m": 0.0},
    )
    episode: dict = {}
    while True:
        message = receive(sock)
        if message["type"] == "bye":
            return
        if message["type"] == "reset":
            episode = message
            if mode == "resetcrash" and episode["seed"] == 0:
                sys.exit(5)
            send(sock, {"type": "ready"})
            continue
        due = step_at is None or (episode["seed"] == 0 and message["step"] == step_at)
        if not due or mode in ("straight", "resetcrash"):
            send(sock, {"type": "command", "command": straight(message, episode)})
        elif mode == "crash":
            sys.exit(3)
        elif mode == "segv":
            os.kill(os.getpid(), signal.SIGSEGV)
        elif mode == "hang":
            time.sleep(60)
        elif mode == "garbage":
            sock.sendall(LENGTH.pack(5) + b"hello")
        elif mode == "length":
            sock.sendall(b"\xff\xff\xff\xff")
        elif mode == "wrongtype":
            send(sock, {"type": "ready"})
        elif mode == "nan":
            send(sock, {"type": "command", "command": [float("nan"), 0.0]})
        elif mode == "fast":
            send(sock, {"type": "command", "command": [10 * episode["max_speed_mps"], 0.0]})
        elif mode == "strings":
            send(sock, {"type": "command", "command": ["a", "b"]})
        elif mode == "error":
            send(sock, {"type": "error", "message": "the map server is down"})
        elif mode == "close":
            sock.close()
            time.sleep(60)
        else:
            raise SystemExit(f"unknown mode {mode!r}")


if __name__ == "__main__":
    main()
