"""The protocol's framing: a MessagePack map after its length as a 4-byte big-endian
integer, over a stream socket; and the addresses a planner listens on or connects to.

Chosen by measurement (docs/performance.md, "External planners"): MessagePack over a
Unix socket had the shortest round trip of the candidates that exist both on PyPI and
as Debian C++ packages.
"""

from __future__ import annotations

import contextlib
import socket
import struct
import time
from typing import Any, Final

import msgpack

__all__ = [
    "ADDRESS_ENV",
    "MAX_MESSAGE_BYTES",
    "ClosedError",
    "Connection",
    "GarbageError",
    "NoAnswerError",
    "WireError",
    "connect",
    "encode",
    "listen",
    "parse_address",
]

ADDRESS_ENV: Final = "SRFM_PLANNER_ADDRESS"
"""The address a planner process started by srfm connects to (``unix:PATH``)."""

MAX_MESSAGE_BYTES: Final = 64 * 2**20
"""A longer announced message is garbage (the largest real one, a reset of a scenario
with thousands of walls, is a few hundred kB)."""

_LENGTH: Final = struct.Struct(">I")
_CHUNK: Final = 65536


class WireError(Exception):
    """The other end did not deliver a message; the text says how."""


class ClosedError(WireError):
    """The connection was closed (end of file, reset)."""


class NoAnswerError(WireError):
    """No whole message within the time allowed."""


class GarbageError(WireError):
    """Bytes that are not a framed MessagePack map."""


def encode(message: dict[str, Any]) -> bytes:
    """``message`` framed: its length, then its MessagePack bytes."""
    body: bytes = msgpack.packb(message, use_bin_type=True)
    return _LENGTH.pack(len(body)) + body


def parse_address(address: str) -> tuple[int, Any]:
    """``unix:PATH`` or ``tcp:HOST:PORT`` as (address family, socket address).

    Raises:
        ValueError: naming the address when it is neither.
    """
    if address.startswith("unix:") and len(address) > 5:
        return socket.AF_UNIX, address[5:]
    if address.startswith("tcp:"):
        host, _, port = address[4:].rpartition(":")
        if host and port.isdigit() and 0 < int(port) < 65536:
            return socket.AF_INET, (host, int(port))
    raise ValueError(
        f"address {address!r} is neither unix:PATH nor tcp:HOST:PORT (e.g. tcp:127.0.0.1:5555)"
    )


def _tuned(sock: socket.socket) -> socket.socket:
    if sock.family == socket.AF_INET:
        sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
    return sock


def connect(address: str, timeout_s: float) -> socket.socket:
    """A socket connected to ``address`` (:func:`parse_address`).

    Raises:
        ValueError: a malformed address.
        OSError: nothing accepts the connection within ``timeout_s``.
    """
    family, where = parse_address(address)
    sock = socket.socket(family, socket.SOCK_STREAM)
    sock.settimeout(timeout_s)
    try:
        sock.connect(where)
    except BaseException:
        sock.close()
        raise
    return _tuned(sock)


def listen(address: str) -> socket.socket:
    """A socket listening on ``address`` (:func:`parse_address`)."""
    family, where = parse_address(address)
    sock = socket.socket(family, socket.SOCK_STREAM)
    if family == socket.AF_INET:
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    sock.bind(where)
    sock.listen(64)
    return sock


class Connection:
    """Framed messages over a connected stream socket."""

    def __init__(self, sock: socket.socket) -> None:
        self.sock = _tuned(sock)
        self._buffer = b""

    def send(self, message: dict[str, Any]) -> None:
        """Send one message.

        Raises:
            ClosedError: the other end has gone.
        """
        self.send_bytes(encode(message))

    def send_bytes(self, data: bytes) -> None:
        """Send one framed message (:func:`encode`).

        Raises:
            ClosedError: the other end has gone.
        """
        try:
            self.sock.sendall(data)
        except OSError as exc:  # EPIPE, ECONNRESET, a closed socket
            raise ClosedError(f"the connection broke ({exc.strerror or exc})") from None

    def receive(self, timeout_s: float | None) -> Any:
        """The next message, decoded (any MessagePack value; the caller checks it).

        Args:
            timeout_s: the time allowed for the whole message (s); None waits forever.

        Raises:
            ClosedError: end of file or a reset before a whole message.
            NoAnswerError: no whole message within ``timeout_s``.
            GarbageError: an impossible length, or bytes that are not MessagePack.
        """
        deadline = None if timeout_s is None else time.monotonic() + timeout_s
        head = self._read(4, deadline)
        (n,) = _LENGTH.unpack(head)
        if n > MAX_MESSAGE_BYTES:
            raise GarbageError(
                f"announced a message of {n} bytes (more than {MAX_MESSAGE_BYTES}): "
                f"not this protocol's framing (first bytes {head!r})"
            )
        body = self._read(n, deadline)
        try:
            return msgpack.unpackb(body, raw=False)
        except Exception as exc:  # msgpack raises several unrelated types
            raise GarbageError(f"sent {n} bytes that are not MessagePack ({exc})") from None

    def _read(self, n: int, deadline: float | None) -> bytes:
        buffer = self._buffer
        sock = self.sock
        while len(buffer) < n:
            if deadline is None:
                sock.settimeout(None)
            else:
                left = deadline - time.monotonic()
                if left <= 0.0:
                    self._buffer = buffer
                    raise NoAnswerError("no answer in time")
                sock.settimeout(left)
            try:
                chunk = sock.recv(_CHUNK)
            except TimeoutError:
                self._buffer = buffer
                raise NoAnswerError("no answer in time") from None
            except OSError as exc:
                raise ClosedError(f"the connection broke ({exc.strerror or exc})") from None
            if not chunk:
                raise ClosedError("end of file")
            buffer += chunk
        self._buffer = buffer[n:]
        return buffer[:n]

    def close(self) -> None:
        """Close the socket (idempotent)."""
        with contextlib.suppress(OSError):
            self.sock.close()
