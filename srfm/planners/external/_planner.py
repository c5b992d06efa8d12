"""srfm's end of the protocol: external planners by name, their processes and
connections, and :class:`ExternalPlanner`, which runs one like any planner.

An external planner is defined by a name and either a command (srfm starts the process,
which connects back to the Unix socket named in ``SRFM_PLANNER_ADDRESS``) or an address
a planner listens on (srfm connects). The definitions live in the environment variable
``SRFM_EXTERNAL_PLANNERS`` (JSON), so that every worker process of a benchmark, forked
or spawned, finds them; :func:`define_external` sets it.

Each process keeps one connection per definition (:class:`_Link`) and reuses it from
episode to episode: a benchmark worker starts the planner's process once. A connection
that failed (the process crashed, hung past the step timeout, answered garbage) is
dropped and its process killed; the next episode starts a new one.
"""

from __future__ import annotations

import atexit
import contextlib
import json
import math
import os
import shlex
import shutil
import signal
import subprocess
import tempfile
import time
from typing import Any, Final

import attrs
import numpy as np

from srfm._validate import planner_name
from srfm.errors import PlannerError, PlannerFailedError
from srfm.planners._base import FloatArray, Observation, PlannerContext
from srfm.planners.external import _wire
from srfm.planners.external._schema import PROTOCOL_VERSION, message_problem, message_spec

__all__ = [
    "ADDRESS_ENV",
    "DEFINITIONS_ENV",
    "PREFIX",
    "ExternalDefinition",
    "ExternalPlanner",
    "close_all",
    "define_external",
    "external_definition",
    "is_external",
    "limit_problem",
    "observe_message",
    "parse_external_option",
    "reset_message",
]

PREFIX: Final = "external:"
"""A planner named ``external:NAME`` is the external planner defined as NAME."""
DEFINITIONS_ENV: Final = "SRFM_EXTERNAL_PLANNERS"
ADDRESS_ENV: Final = _wire.ADDRESS_ENV
DEFAULT_STEP_TIMEOUT_S: Final = 1.0
DEFAULT_START_TIMEOUT_S: Final = 30.0
_LIMIT_TOLERANCE: Final = 1e-9  # relative: v_max computed by a planner may round up
_KILL_WAIT_S: Final = 2.0


@attrs.frozen(kw_only=True)
class ExternalDefinition:
    """An external planner: its name, and the command srfm starts or the address it
    connects to (exactly one of the two).

    Attributes:
        name: NAME of ``external:NAME``: letters, digits, ``-``, ``_``.
        command: the program and its arguments (no shell).
        address: ``unix:PATH`` or ``tcp:HOST:PORT`` of a planner that listens.
        step_timeout_s: the time a planner has to answer one observation (s).
        start_timeout_s: the time it has to connect and answer the handshake, and to
            answer a reset (s).
    """

    name: str
    command: tuple[str, ...] = ()
    address: str | None = None
    step_timeout_s: float = DEFAULT_STEP_TIMEOUT_S
    start_timeout_s: float = DEFAULT_START_TIMEOUT_S

    @property
    def label(self) -> str:
        """The name srfm runs it under, ``external:NAME``."""
        return PREFIX + self.name

    @property
    def source(self) -> str:
        """The command or the address, for messages."""
        return self.address if self.address is not None else shlex.join(self.command)


def _check_name(name: Any) -> str:
    if not isinstance(name, str):
        raise PlannerError(f"external planner name must be a string, got {name!r}")
    return planner_name(PREFIX + name, PlannerError).removeprefix(PREFIX)


def _check_timeout(value: Any, what: str) -> float:
    ok = isinstance(value, int | float) and not isinstance(value, bool)
    if not ok or not math.isfinite(value) or not 0.0 < value <= 3600.0:
        raise PlannerError(f"{what} must be a number of seconds in (0, 3600], got {value!r}")
    return float(value)


def define_external(
    name: str,
    command: str | list[str] | tuple[str, ...] | None = None,
    *,
    address: str | None = None,
    step_timeout_s: float = DEFAULT_STEP_TIMEOUT_S,
    start_timeout_s: float = DEFAULT_START_TIMEOUT_S,
) -> str:
    """Define the external planner ``name``; returns ``"external:NAME"``, the planner
    name to run it under (:func:`srfm.run_episode`, the benchmark).

    The definition is kept in the environment variable ``SRFM_EXTERNAL_PLANNERS`` of
    this process, which worker processes inherit.

    Args:
        name: letters, digits, ``-``, ``_``.
        command: the planner's program and arguments: a list, or a string split like a
            shell would (no shell runs it). srfm starts it with ``SRFM_PLANNER_ADDRESS``
            set to the socket to connect to.
        address: instead of a command, ``unix:PATH`` or ``tcp:HOST:PORT`` where a
            planner listens; srfm opens one connection per worker.
        step_timeout_s: the time a planner has to answer one observation (s).
        start_timeout_s: the time to connect and answer the handshake or a reset (s).

    Raises:
        PlannerError: a bad name, neither or both of command and address, an empty
            command, a malformed address or timeout.
    """
    name = _check_name(name)
    if (command is None) == (address is None):
        raise PlannerError(f"external planner {name!r}: give either a command or an address")
    argv: tuple[str, ...] = ()
    if command is not None:
        try:
            argv = tuple(shlex.split(command) if isinstance(command, str) else command)
        except ValueError as exc:
            raise PlannerError(f"external planner {name!r}: command {command!r}: {exc}") from None
        if not argv or not all(isinstance(a, str) for a in argv):
            raise PlannerError(f"external planner {name!r}: the command is empty")
    if address is not None:
        try:
            _wire.parse_address(address)
        except ValueError as exc:
            raise PlannerError(f"external planner {name!r}: {exc}") from None
    definition = ExternalDefinition(
        name=name,
        command=argv,
        address=address,
        step_timeout_s=_check_timeout(step_timeout_s, "the step timeout"),
        start_timeout_s=_check_timeout(start_timeout_s, "the start timeout"),
    )
    table = _definitions()
    table[name] = attrs.asdict(definition)
    os.environ[DEFINITIONS_ENV] = json.dumps(table, sort_keys=True)
    return definition.label


def parse_external_option(text: str) -> tuple[str, str]:
    """``NAME=COMMAND`` or ``NAME=ADDRESS`` of the command line's ``--external`` as
    (NAME, the rest).

    Raises:
        PlannerError: no ``=``, or nothing on one side of it.
    """
    name, eq, rest = text.partition("=")
    if not eq or not name.strip() or not rest.strip():
        raise PlannerError(
            f"--external must be NAME=COMMAND or NAME=unix:PATH / NAME=tcp:HOST:PORT, got {text!r}"
        )
    return name.strip(), rest.strip()


def is_address(text: str) -> bool:
    """Whether the right side of ``--external NAME=...`` is an address, not a command."""
    return text.startswith(("unix:", "tcp:"))


def _definitions() -> dict[str, dict[str, Any]]:
    text = os.environ.get(DEFINITIONS_ENV, "")
    if not text:
        return {}
    try:
        table = json.loads(text)
    except json.JSONDecodeError:
        raise PlannerError(f"{DEFINITIONS_ENV} is not JSON: {text[:80]!r}") from None
    if not isinstance(table, dict):
        raise PlannerError(f"{DEFINITIONS_ENV} is not a JSON object")
    return table


def is_external(planner: str) -> bool:
    """Whether the planner name ``planner`` is an external planner's."""
    return planner.startswith(PREFIX)


def external_definition(name: str) -> ExternalDefinition:
    """The definition of ``external:NAME`` (``name`` with or without the prefix).

    Raises:
        PlannerError: no external planner of that name is defined.
    """
    bare = name.removeprefix(PREFIX)
    entry = _definitions().get(bare)
    if entry is None:
        raise PlannerError(
            f"planner {PREFIX + bare!r} is not defined: give --external {bare}=COMMAND "
            f"(or {bare}=unix:PATH, {bare}=tcp:HOST:PORT), or call "
            "srfm.planners.external.define_external first"
        )
    try:
        entry = {**entry, "command": tuple(entry.get("command", ()))}
        return ExternalDefinition(**entry)
    except TypeError as exc:
        raise PlannerError(f"{DEFINITIONS_ENV}: entry {bare!r} is malformed: {exc}") from None


# --- messages ---------------------------------------------------------------------------


def reset_message(context: PlannerContext) -> dict[str, Any]:
    """The ``reset`` message of an episode."""
    robot = context.robot
    world = context.world
    obstacles = context.obstacles
    return {
        "type": "reset",
        "scenario": context.scenario,
        "seed": int(context.seed),
        "dt_s": float(context.dt_s),
        "horizon_steps": int(context.horizon_steps),
        "kinematics": robot.kinematics,
        "radius_m": float(robot.radius_m),
        "max_speed_mps": float(robot.max_speed_mps),
        "max_angular_speed_radps": float(robot.max_angular_speed_radps),
        "max_accel_mps2": float(robot.max_accel_mps2),
        "max_angular_accel_radps2": float(robot.max_angular_accel_radps2),
        "goal_radius_m": float(robot.goal_radius_m),
        "goal": np.asarray(context.robot_goal, dtype=np.float64).tolist(),
        "world": [float(world.x_min), float(world.y_min), float(world.x_max), float(world.y_max)],
        "walls": np.asarray(obstacles.segments, dtype=np.float64).ravel().tolist(),
        "pillars": np.asarray(obstacles.circles, dtype=np.float64).ravel().tolist(),
    }


def observe_message(observation: Observation) -> dict[str, Any]:
    """The ``observe`` message of one step."""
    r = observation.robot
    return {
        "type": "observe",
        "step": observation.step,
        "time_s": observation.time_s,
        "robot": [r.x, r.y, r.theta, r.vx, r.vy, r.v, r.omega],
        "goal": observation.robot_goal.tolist(),
        "ped_ids": observation.ped_ids.tolist(),
        "ped_pos": observation.ped_pos.ravel().tolist(),
        "ped_vel": observation.ped_vel.ravel().tolist(),
        "ped_radius": observation.ped_radius.tolist(),
    }


def limit_problem(c0: float, c1: float, context: PlannerContext) -> str | None:
    """Why the command (c0, c1) is outside the robot's limits (None when it is not):
    |v| ≤ v_max and |ω| ≤ ω_max for a unicycle, |(vx, vy)| ≤ v_max for a holonomic
    robot, each with a relative tolerance of 1e-9."""
    robot = context.robot
    vmax = robot.max_speed_mps * (1.0 + _LIMIT_TOLERANCE)
    if robot.kinematics == "holonomic":
        if math.hypot(c0, c1) > vmax:
            return f"the speed |(vx, vy)| <= {robot.max_speed_mps!r} m/s"
        return None
    wmax = robot.max_angular_speed_radps * (1.0 + _LIMIT_TOLERANCE)
    if abs(c0) > vmax or abs(c1) > wmax:
        return (
            f"|v| <= {robot.max_speed_mps!r} m/s and |omega| <= "
            f"{robot.max_angular_speed_radps!r} rad/s"
        )
    return None


# --- connections --------------------------------------------------------------------------


def _exit_text(code: int) -> str:
    if code < 0:
        try:
            return f"was killed by signal {signal.Signals(-code).name}"
        except ValueError:
            return f"was killed by signal {-code}"
    return f"exited with status {code}"


class _Link:
    """One connection to an external planner, and the process srfm started for it."""

    def __init__(
        self,
        definition: ExternalDefinition,
        conn: _wire.Connection,
        process: subprocess.Popen[bytes] | None,
    ) -> None:
        self.definition = definition
        self.conn = conn
        self.process = process
        self.pid = os.getpid()
        self.detection_range_m: float | None = None

    @classmethod
    def open(cls, definition: ExternalDefinition) -> _Link:
        """Start the process or connect, then the handshake.

        Raises:
            PlannerError: the process cannot start or does not connect, nothing listens
                at the address, or the handshake fails (another protocol version).
        """
        label = definition.label
        timeout = definition.start_timeout_s
        if definition.address is not None:
            try:
                sock = _wire.connect(definition.address, timeout)
            except OSError as exc:
                raise PlannerError(
                    f"planner {label!r}: cannot connect to {definition.address}: "
                    f"{exc.strerror or exc}"
                ) from None
            link = cls(definition, _wire.Connection(sock), None)
        else:
            link = cls._start(definition)
        try:
            link._handshake()
        except BaseException:
            link.close(polite=False)
            raise
        return link

    @classmethod
    def _start(cls, definition: ExternalDefinition) -> _Link:
        label = definition.label
        folder = tempfile.mkdtemp(prefix="srfm-planner-")
        address = f"unix:{os.path.join(folder, 'socket')}"
        server = _wire.listen(address)
        try:
            env = {**os.environ, ADDRESS_ENV: address}
            try:
                # stdout to srfm's stderr: a planner's prints must not mix with a
                # command's output (srfm simulate --json).
                process = subprocess.Popen(
                    definition.command, env=env, stdin=subprocess.DEVNULL, stdout=2
                )
            except OSError as exc:
                raise PlannerError(
                    f"planner {label!r}: cannot start {definition.source!r}: {exc.strerror or exc}"
                ) from None
            deadline = time.monotonic() + definition.start_timeout_s
            server.settimeout(0.05)
            while True:
                try:
                    sock, _ = server.accept()
                    break
                except TimeoutError:
                    pass
                code = process.poll()
                if code is not None:
                    raise PlannerError(
                        f"planner {label!r}: {definition.source!r} {_exit_text(code)} before "
                        f"connecting to srfm (it must connect to ${ADDRESS_ENV})"
                    )
                if time.monotonic() > deadline:
                    _kill(process)
                    raise PlannerError(
                        f"planner {label!r}: {definition.source!r} did not connect to "
                        f"${ADDRESS_ENV} within {definition.start_timeout_s!r} s"
                    )
        finally:
            server.close()
            shutil.rmtree(folder, ignore_errors=True)
        return cls(definition, _wire.Connection(sock), process)

    def _handshake(self) -> None:
        label = self.definition.label
        try:
            self.conn.send({"type": "hello", "protocol": PROTOCOL_VERSION, "planner": label})
            reply = self.conn.receive(self.definition.start_timeout_s)
        except _wire.WireError as exc:
            raise PlannerError(
                f"planner {label!r} failed the handshake: {self.failure_text(exc)}"
            ) from None
        if isinstance(reply, dict) and reply.get("type") == "error":
            raise PlannerError(
                f"planner {label!r} refused the handshake: {str(reply.get('message'))[:300]}"
            )
        version = reply.get("protocol") if isinstance(reply, dict) else None
        if isinstance(version, int) and version != PROTOCOL_VERSION:
            raise PlannerError(
                f"planner {label!r} speaks protocol version {version}, srfm speaks version "
                f"{PROTOCOL_VERSION}: use a client of version {PROTOCOL_VERSION} "
                "(docs/planners-any-language.md)"
            )
        problem = message_problem(reply, message_spec("hello", "planner"))
        if problem is not None:
            raise PlannerError(f"planner {label!r} answered the handshake with garbage: {problem}")
        detection = reply["detection_range_m"]
        if detection is not None and detection < 0.0:
            raise PlannerError(
                f"planner {label!r}: detection_range_m must be nil or >= 0, got {detection!r}"
            )
        self.detection_range_m = None if detection is None else float(detection)

    def exchange(self, data: bytes, timeout_s: float) -> Any:
        """Send one framed message and return the answer.

        Raises:
            WireError: the planner's process or connection failed to answer.
        """
        self.conn.send_bytes(data)
        return self.conn.receive(timeout_s)

    def failure_text(self, exc: _wire.WireError) -> str:
        """What the planner did, from the failure of an exchange (the process's exit
        status where it has one)."""
        timeout = self.definition.step_timeout_s
        if isinstance(exc, _wire.NoAnswerError):
            return f"did not answer within its timeout ({timeout!r} s per step)"
        if isinstance(exc, _wire.GarbageError):
            return f"answered garbage: {exc}"
        if self.process is not None:
            try:
                code = self.process.wait(timeout=_KILL_WAIT_S)
            except subprocess.TimeoutExpired:
                return f"closed its connection ({exc}) but kept running"
            return f"crashed: its process {_exit_text(code)}"
        return f"closed the connection ({exc})"

    def close(self, *, polite: bool) -> None:
        """Close the connection; ``polite``: say bye and let the process exit, else kill
        it at once."""
        if os.getpid() != self.pid:  # inherited by a fork: the parent's to close
            return
        if polite:
            with contextlib.suppress(_wire.WireError):
                self.conn.send({"type": "bye"})
        self.conn.close()
        if self.process is not None:
            if polite:
                try:
                    self.process.wait(timeout=_KILL_WAIT_S)
                except subprocess.TimeoutExpired:
                    _kill(self.process)
            else:
                _kill(self.process)


def _kill(process: subprocess.Popen[bytes]) -> None:
    if process.poll() is None:
        process.kill()
    with contextlib.suppress(subprocess.TimeoutExpired):
        process.wait(timeout=_KILL_WAIT_S)


_LINKS: dict[ExternalDefinition, _Link] = {}


def _link(definition: ExternalDefinition) -> _Link:
    """This process's connection to ``definition``, opened when there is none."""
    link = _LINKS.get(definition)
    if link is None:
        link = _Link.open(definition)
        _LINKS[definition] = link
    return link


def _drop(definition: ExternalDefinition, *, polite: bool) -> None:
    link = _LINKS.pop(definition, None)
    if link is not None:
        link.close(polite=polite)


def close_all() -> None:
    """Close every connection of this process, saying bye (at exit)."""
    for definition in list(_LINKS):
        _drop(definition, polite=True)


def _forget_after_fork() -> None:
    """In a forked child: the parent's connections are not this process's to use."""
    for link in _LINKS.values():
        with contextlib.suppress(OSError):
            link.conn.sock.close()  # the child's copy of the descriptor only
    _LINKS.clear()


atexit.register(close_all)
os.register_at_fork(after_in_child=_forget_after_fork)


# --- the planner ----------------------------------------------------------------------------


class ExternalPlanner:
    """A planner in another process, reached through the protocol
    (docs/planners-any-language.md).

    Made by :func:`srfm.planners.make_planner` for ``external:NAME``. The process is
    started (or the address connected to) when srfm first reads the planner's
    ``detection_range_m``, at the start of its first episode, and kept for later ones.
    A failure inside an episode (a crash, a timeout, garbage, a non-finite command or
    one outside the robot's limits) raises :class:`~srfm.errors.PlannerFailedError` from
    :meth:`act` (at the episode's first step when the reset failed); the connection is
    dropped and its process killed, and the next episode starts afresh.

    Args:
        name: NAME (or ``external:NAME``) of a defined external planner
            (:func:`define_external`).
    """

    def __init__(self, name: str) -> None:
        self.definition = external_definition(name)
        self.name = self.definition.label
        self._context: PlannerContext | None = None
        self._failure: str | None = None
        self._where = ""
        self._detection: float | None = None
        self._detection_set = False

    @property
    def detection_range_m(self) -> float | None:
        """The range the planner stated in its handshake (reading it opens the
        connection), unless set here."""
        if self._detection_set:
            return self._detection
        return _link(self.definition).detection_range_m

    @detection_range_m.setter
    def detection_range_m(self, value: float | None) -> None:
        self._detection = value
        self._detection_set = True

    def reset(self, context: PlannerContext, rng: np.random.Generator) -> None:
        """Send the episode's ``reset``; a failure is raised by the first :meth:`act`.

        Raises:
            PlannerError: the planner cannot be started or refuses the handshake.
        """
        self._context = context
        self._where = f" (scenario {context.scenario}, seed {context.seed})"
        self._failure = None
        link = _link(self.definition)
        try:
            reply = link.exchange(
                _wire.encode(reset_message(context)), self.definition.start_timeout_s
            )
        except _wire.WireError as exc:
            self._fail(link.failure_text(exc), "at reset")
            return
        except BaseException:
            _drop(self.definition, polite=False)
            raise
        if type(reply) is dict and reply.get("type") == "ready":
            return
        self._fail(self._answer_problem(reply, "ready"), "at reset")

    def act(self, observation: Observation) -> FloatArray:
        """Send the observation and return the planner's command, checked.

        Raises:
            PlannerFailedError: the planner failed (one line saying how).
        """
        if self._failure is not None:
            raise PlannerFailedError(self._failure)
        context = self._context
        if context is None:
            raise PlannerError(f"planner {self.name!r}: act() before reset()")
        at = f"at step {observation.step}"
        link = _link(self.definition)
        try:
            reply = link.exchange(
                _wire.encode(observe_message(observation)), self.definition.step_timeout_s
            )
        except _wire.WireError as exc:
            raise self._fail(link.failure_text(exc), at) from None
        except BaseException:
            _drop(self.definition, polite=False)
            raise
        if type(reply) is not dict or reply.get("type") != "command":
            raise self._fail(self._answer_problem(reply, "command"), at)
        command = reply.get("command")
        if type(command) is not list or len(command) != 2:
            raise self._fail(self._answer_problem(reply, "command"), at)
        c0, c1 = command
        if not (type(c0) in (float, int) and type(c1) in (float, int)):
            raise self._fail(f"answered a command that is not two numbers: {command!r}", at)
        c0 = float(c0)
        c1 = float(c1)
        if not (math.isfinite(c0) and math.isfinite(c1)):
            raise self._fail(f"answered a non-finite command [{c0!r}, {c1!r}]", at)
        problem = limit_problem(c0, c1, context)
        if problem is not None:
            raise self._fail(
                f"answered the command [{c0!r}, {c1!r}], outside the robot's limits ({problem})",
                at,
            )
        return np.array([c0, c1])

    def _answer_problem(self, reply: Any, expected: str) -> str:
        if type(reply) is dict and reply.get("type") == "error":
            return f"reported an error: {str(reply.get('message'))[:300]}"
        problem = message_problem(reply, message_spec(expected, "planner"))
        return f"answered garbage: {problem}"

    def _fail(self, what: str, at: str) -> PlannerFailedError:
        """Drop the connection (killing the process) and remember the failure's line."""
        _drop(self.definition, polite=False)
        line = (
            f"planner {self.name!r} ({self.definition.source}) {what} {at}{self._where}; "
            "its episode ends with the outcome planner_failed"
        )
        self._failure = line
        return PlannerFailedError(line)
