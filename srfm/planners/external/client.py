"""The Python client of the protocol: any function as an external planner.

A few lines make a program that srfm can run as ``--external NAME="python my_planner.py"``::

    from srfm.planners.external import serve

    def act(step, episode):
        return episode.max_speed_mps, 0.0  # full speed ahead

    serve(act)

:func:`serve` connects to the socket srfm names in ``SRFM_PLANNER_ADDRESS`` when srfm
started the program; given an ``address`` (``unix:PATH``, ``tcp:HOST:PORT``) it listens
there instead and answers every connection (one per benchmark worker) in a thread of
its own, for ``--external NAME=tcp:HOST:PORT``.

The client needs only this module, :mod:`srfm.planners.external._wire` and ``msgpack``; it does
not run srfm's simulation.
"""

from __future__ import annotations

import os
import socket
import sys
import threading
from collections.abc import Callable, Sequence
from typing import Any

import attrs
import numpy as np
from numpy.typing import NDArray

from srfm.planners.external import _wire
from srfm.planners.external._schema import PROTOCOL_VERSION, message_problem, message_spec

__all__ = ["Episode", "Step", "serve"]

FloatArray = NDArray[np.float64]


@attrs.frozen(kw_only=True, eq=False)
class Episode:
    """What srfm says about an episode at its start (the ``reset`` message).

    Attributes:
        scenario: the scenario's name.
        seed: the episode seed (seed any random generator from it).
        dt_s: the time step (s).
        horizon_steps: the episode's number of steps.
        kinematics: ``"unicycle"`` (commands v, ω) or ``"holonomic"`` (vx, vy).
        radius_m: the robot's radius (m).
        max_speed_mps: v_max (m/s).
        max_angular_speed_radps: ω_max (rad/s).
        max_accel_mps2: the largest change of linear velocity per second (m/s²).
        max_angular_accel_radps2: the largest change of ω per second (rad/s²).
        goal_radius_m: the goal counts as reached within this distance (m).
        goal: (2,) the goal (m).
        world: (x_min, y_min, x_max, y_max) (m).
        walls: (w, 4) wall segments (x1, y1, x2, y2) (m).
        pillars: (p, 3) pillars (x, y, radius) (m).
    """

    scenario: str
    seed: int
    dt_s: float
    horizon_steps: int
    kinematics: str
    radius_m: float
    max_speed_mps: float
    max_angular_speed_radps: float
    max_accel_mps2: float
    max_angular_accel_radps2: float
    goal_radius_m: float
    goal: FloatArray
    world: tuple[float, float, float, float]
    walls: FloatArray
    pillars: FloatArray

    @classmethod
    def from_message(cls, m: dict[str, Any]) -> Episode:
        """The episode of a ``reset`` message (already checked)."""
        return cls(
            scenario=m["scenario"],
            seed=m["seed"],
            dt_s=float(m["dt_s"]),
            horizon_steps=m["horizon_steps"],
            kinematics=m["kinematics"],
            radius_m=float(m["radius_m"]),
            max_speed_mps=float(m["max_speed_mps"]),
            max_angular_speed_radps=float(m["max_angular_speed_radps"]),
            max_accel_mps2=float(m["max_accel_mps2"]),
            max_angular_accel_radps2=float(m["max_angular_accel_radps2"]),
            goal_radius_m=float(m["goal_radius_m"]),
            goal=np.array(m["goal"], dtype=np.float64),
            world=(
                float(m["world"][0]),
                float(m["world"][1]),
                float(m["world"][2]),
                float(m["world"][3]),
            ),
            walls=np.array(m["walls"], dtype=np.float64).reshape(-1, 4),
            pillars=np.array(m["pillars"], dtype=np.float64).reshape(-1, 3),
        )


@attrs.frozen(kw_only=True, eq=False)
class Step:
    """What the robot sees at one step (the ``observe`` message).

    Attributes:
        step: the step index (0 at the start).
        time_s: the simulated time (s).
        x, y, theta: the robot's pose (m, rad).
        vx, vy: its world-frame velocity in the last step (m/s).
        v, omega: its speed and turn rate (m/s, rad/s).
        goal: (2,) what to steer to: the goal, or the route's next waypoint (m).
        ped_ids: (k,) the observed pedestrians' indices.
        ped_pos: (k, 2) their positions (m).
        ped_vel: (k, 2) their velocities (m/s).
        ped_radius: (k,) their radii (m).
    """

    step: int
    time_s: float
    x: float
    y: float
    theta: float
    vx: float
    vy: float
    v: float
    omega: float
    goal: FloatArray
    ped_ids: NDArray[np.int64]
    ped_pos: FloatArray
    ped_vel: FloatArray
    ped_radius: FloatArray

    @classmethod
    def from_message(cls, m: dict[str, Any]) -> Step:
        """The step of an ``observe`` message (already checked)."""
        x, y, theta, vx, vy, v, omega = (float(a) for a in m["robot"])
        return cls(
            step=m["step"],
            time_s=float(m["time_s"]),
            x=x,
            y=y,
            theta=theta,
            vx=vx,
            vy=vy,
            v=v,
            omega=omega,
            goal=np.array(m["goal"], dtype=np.float64),
            ped_ids=np.array(m["ped_ids"], dtype=np.int64),
            ped_pos=np.array(m["ped_pos"], dtype=np.float64).reshape(-1, 2),
            ped_vel=np.array(m["ped_vel"], dtype=np.float64).reshape(-1, 2),
            ped_radius=np.array(m["ped_radius"], dtype=np.float64),
        )


Act = Callable[[Step, Episode], Sequence[float]]
Reset = Callable[[Episode], None]


class _ProtocolError(Exception):
    """srfm sent something this client cannot use; told back as an ``error``."""


def _checked(message: Any, type_: str) -> dict[str, Any]:
    problem = message_problem(message, message_spec(type_, "srfm"))
    if problem is not None:
        raise _ProtocolError(problem)
    return dict(message)


def _session(
    conn: _wire.Connection, act: Act, reset: Reset | None, detection_range_m: float | None
) -> None:
    """Answer one connection until srfm says bye or closes it."""
    hello = conn.receive(None)
    version = hello.get("protocol") if isinstance(hello, dict) else None
    problem = message_problem(hello, message_spec("hello", "srfm"))
    if version != PROTOCOL_VERSION or problem is not None:
        if version != PROTOCOL_VERSION:
            problem = (
                f"this planner speaks protocol version {PROTOCOL_VERSION}, "
                f"srfm sent version {version!r}"
            )
        conn.send({"type": "error", "message": str(problem)})
        return
    conn.send(
        {"type": "hello", "protocol": PROTOCOL_VERSION, "detection_range_m": detection_range_m}
    )
    episode: Episode | None = None
    while True:
        message = conn.receive(None)
        kind = message.get("type") if isinstance(message, dict) else None
        try:
            if kind == "observe":
                if episode is None:
                    raise _ProtocolError("observe before reset")
                command = act(Step.from_message(_checked(message, "observe")), episode)
                c0, c1 = command
                conn.send({"type": "command", "command": [float(c0), float(c1)]})
            elif kind == "reset":
                episode = Episode.from_message(_checked(message, "reset"))
                if reset is not None:
                    reset(episode)
                conn.send({"type": "ready"})
            elif kind == "bye":
                return
            else:
                raise _ProtocolError(f"unknown message type {kind!r}")
        except _ProtocolError as exc:
            conn.send({"type": "error", "message": f"cannot use srfm's message: {exc}"})
            return
        except Exception as exc:  # the user's act or reset raised: say so, then stop
            what = "reset" if kind == "reset" else "act"
            conn.send({"type": "error", "message": f"{what}() raised {type(exc).__name__}: {exc}"})
            raise


def _serve_socket(
    sock: socket.socket, act: Act, reset: Reset | None, detection_range_m: float | None
) -> None:
    conn = _wire.Connection(sock)
    try:
        _session(conn, act, reset, detection_range_m)
    except _wire.ClosedError:
        pass  # srfm went away: nothing to answer
    finally:
        conn.close()


def serve(
    act: Act,
    *,
    reset: Reset | None = None,
    detection_range_m: float | None = None,
    address: str | None = None,
) -> None:
    """Run ``act`` as an external planner.

    Args:
        act: ``act(step, episode) -> (c0, c1)``: the command for a :class:`Step` of an
            :class:`Episode`: (v, ω) for a unicycle, world-frame (vx, vy) for a
            holonomic robot, finite and within the episode's limits.
        reset: called with each new :class:`Episode` before its first step.
        detection_range_m: only pedestrians closer than this (m) are observed; None:
            all of them.
        address: listen here (``unix:PATH``, ``tcp:HOST:PORT``) and answer every
            connection in a thread of its own, until interrupted; without it, connect to
            ``$SRFM_PLANNER_ADDRESS`` (srfm started this program) and return when srfm
            closes the connection.

    Raises:
        RuntimeError: neither ``address`` nor ``SRFM_PLANNER_ADDRESS``.
    """
    if address is None:
        target = os.environ.get(_wire.ADDRESS_ENV)
        if not target:
            raise RuntimeError(
                f"{_wire.ADDRESS_ENV} is not set: srfm sets it when it starts this program "
                "(--external NAME=COMMAND); to run it on its own, give serve() an address"
            )
        _serve_socket(_wire.connect(target, 30.0), act, reset, detection_range_m)
        return
    server = _wire.listen(address)
    print(f"srfm planner listening on {address}", file=sys.stderr, flush=True)
    try:
        while True:
            sock, _ = server.accept()
            threading.Thread(
                target=_serve_socket, args=(sock, act, reset, detection_range_m), daemon=True
            ).start()
    finally:
        server.close()
