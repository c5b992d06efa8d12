"""Replay a recorded robot: a planner that follows a robot trajectory from a dataset,
and the scenario of a recorded scene for it (issue 15, item 4).

:func:`recorded_encounter` turns a world-frame dataset scene with a robot (e.g. one
NavWareSet recording) into a fixed :class:`srfm.scenarios.Scenario` (every pedestrian
from its first to its last observed position, with its observed desired speed; the
robot from its first to its last recorded position, holonomic, fast enough to keep up)
and a :class:`RecordedRobotPlanner` that drives the robot along the recorded path in
recorded time. Both go to :func:`srfm.run_episode` like any scenario and planner; the
twin simulation then gives the deviation the benchmark attributes to the recorded robot.

On the command line the recording travels in the scenario file: the scenario carries
the robot's trajectory as ``[robot.recording]`` (schema version 2), :func:`scenario_toml`
writes it (``srfm data scenario`` does, for every robot scene of a dataset MCAP), and
the registered planner ``recorded`` replays the recording of whatever scenario it is
reset on::

    srfm data convert navwareset ../shared/data/navwareset_quant nws.mcap
    srfm data scenario nws.mcap scenes/
    srfm simulate --scenario scenes/recorded-<scene>.toml --planner recorded
    srfm benchmark -s scenes/recorded-<scene>.toml -p recorded --seeds 0
"""

from __future__ import annotations

import math
import re
import tomllib
from collections.abc import Mapping
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from srfm._io import toml_scalar
from srfm.datasets import PEDESTRIAN, Trajectories
from srfm.errors import PlannerError, ScenarioError
from srfm.models.robot import RobotConfig
from srfm.planners._base import FloatArray, Observation, PlannerContext
from srfm.scenarios import Scenario, parse_scenario

__all__ = ["RecordedRobotPlanner", "recorded_encounter", "recorded_scenario_doc", "scenario_toml"]

# Helbing & Molnár 1995, as in srfm.fitting: top speed 1.3 times the desired speed.
_VMAX_FACTOR = 1.3
_MARGIN_M = 2.0


class RecordedRobotPlanner:
    """Drive a holonomic robot along a recorded trajectory, in recorded time.

    At simulated time t the command is the velocity that takes the robot from where it
    is to the recorded position at t + dt (linear interpolation between recorded
    samples; the last position after the recording ends), so the robot tracks the
    recording and corrects any lag in one step, within the robot's limits.

    Args:
        times_s: (n,) recorded times (s), strictly increasing, starting at 0.
        xy: (n, 2) recorded positions (m).

    Without ``times_s`` and ``xy`` (the registered planner ``recorded``) it replays the
    recording of the scenario it is reset on (``[robot.recording]``).
    """

    name = "recorded"
    detection_range_m: float | None = 0.0

    def __init__(self, times_s: ArrayLike | None = None, xy: ArrayLike | None = None) -> None:
        self._dt = 0.0
        self._from_scenario = times_s is None and xy is None
        if self._from_scenario:
            self._t = np.zeros(0)
            self._xy = np.zeros((0, 2))
            return
        if times_s is None or xy is None:
            raise PlannerError("a recorded trajectory needs both times_s and xy")
        t = np.asarray(times_s, dtype=np.float64)
        p = np.asarray(xy, dtype=np.float64)
        if t.ndim != 1 or t.shape[0] < 2 or p.shape != (t.shape[0], 2):
            raise PlannerError(
                f"a recorded trajectory needs n >= 2 times (n,) and positions (n, 2), got "
                f"{t.shape} and {p.shape}"
            )
        if not (np.all(np.isfinite(t)) and np.all(np.isfinite(p))):
            raise PlannerError("a recorded trajectory must be finite (no NaN or inf)")
        if t[0] != 0.0 or np.any(np.diff(t) <= 0.0):
            raise PlannerError("recorded times must start at 0 s and increase strictly")
        self._t = t
        self._xy = p

    def position_at(self, time_s: float) -> FloatArray:
        """The recorded position (m) at ``time_s`` (the ends held outside the record)."""
        return np.array(
            [
                np.interp(time_s, self._t, self._xy[:, 0]),
                np.interp(time_s, self._t, self._xy[:, 1]),
            ]
        )

    def reset(self, context: PlannerContext, rng: np.random.Generator) -> None:
        """Remember the step (and take the scenario's recording when the planner was
        made without one); the robot must be holonomic (the recording gives no
        commands, only positions)."""
        if self._from_scenario:
            recording = context.robot_recording
            if recording is None:
                raise PlannerError(
                    f"scenario {context.scenario!r} has no robot recording to replay: the "
                    "recorded planner needs [robot.recording] (schema_version 2; "
                    "`srfm data scenario` writes such scenarios from a dataset)"
                )
            self._t = recording.times_s
            self._xy = recording.xy
        if context.robot.kinematics != "holonomic":
            raise PlannerError(
                "the recorded planner drives a holonomic robot; the scenario's robot is "
                f"{context.robot.kinematics!r}"
            )
        self._dt = context.dt_s

    def act(self, observation: Observation) -> FloatArray:
        """The velocity (vx, vy) to the recorded position one step ahead."""
        if self._dt <= 0.0:
            raise PlannerError("the recorded planner was not reset")
        target = self.position_at(observation.time_s + self._dt)
        here = np.array([observation.robot.x, observation.robot.y])
        return np.asarray((target - here) / self._dt)


def recorded_encounter(
    scene: Trajectories, *, dt_s: float = 1.0 / 15.0, name: str | None = None
) -> tuple[Scenario, RecordedRobotPlanner]:
    """The scenario of a recorded scene and the planner that replays its robot.

    The scenario is :func:`recorded_scenario_doc`'s (its ``[robot.recording]`` holds
    the robot's trajectory); the planner replays that recording.

    Raises:
        ScenarioError: the scene is in the robot's frame, has no robot or no
            pedestrian, or has fewer than two robot samples.
    """
    doc = recorded_scenario_doc(scene, dt_s=dt_s, name=name)
    scenario = parse_scenario(doc, f"recorded scene {scene.scene!r}")
    recording = scenario.robot_recording
    assert recording is not None
    return scenario, RecordedRobotPlanner(recording.times_s, recording.xy)


def recorded_scenario_doc(
    scene: Trajectories, *, dt_s: float = 1.0 / 15.0, name: str | None = None
) -> dict[str, Any]:
    """The scenario document (schema version 2) of a recorded scene with a robot.

    Pedestrians start at their first observed position and head for their last, with
    the desired speed v0 = the 80th percentile of their 1 s speeds (as in
    :mod:`srfm.fitting`) and top speed 1.3 v0; all start at time 0, i.e. the waits in
    the recording before people set off are not reproduced. The robot (holonomic,
    radius 0.2 m) starts at its first recorded position and its goal is its last, with
    a goal radius of 0.1 m; its top speed is 1.2 times the fastest recorded step and its
    acceleration limit 20 m/s², so the limits do not bend the recorded path. The world
    is the bounding box of every sample plus 2 m. The horizon covers the recording
    plus 5 s.

    Raises:
        ScenarioError: the scene is in the robot's frame, has no robot or no
            pedestrian, or has fewer than two robot samples.
    """
    if scene.frame_of_reference != "world":
        raise ScenarioError(f"scene {scene.scene!r} is not in a world frame")
    robot = scene.robot_index
    if robot is None:
        raise ScenarioError(f"scene {scene.scene!r} has no robot to replay")
    peds = [a for a, k in enumerate(scene.kinds) if k == PEDESTRIAN]
    if not peds:
        raise ScenarioError(f"scene {scene.scene!r} has no pedestrian")
    t0 = int(scene.t_ns.min())
    rmask = scene.agent == robot
    r_t = (scene.t_ns[rmask] - t0).astype(np.float64) * 1e-9
    r_xy = scene.xy[rmask]
    if r_t.shape[0] < 2:
        raise ScenarioError(f"scene {scene.scene!r} has fewer than two robot samples")
    # the recording's clock starts with the robot's first sample
    steps = np.linalg.norm(np.diff(r_xy, axis=0), axis=1) / np.diff(r_t)
    starts, goals, v0 = [], [], []
    for a in peds:
        m = scene.agent == a
        xy = scene.xy[m]
        t = (scene.t_ns[m] - t0).astype(np.float64) * 1e-9
        starts.append(xy[0].tolist())
        goals.append(xy[-1].tolist())
        later = np.searchsorted(t, t + 1.0)
        ok = later < t.shape[0]
        if np.any(ok):
            span = t[later[ok]] - t[ok]
            speeds = np.linalg.norm(xy[later[ok]] - xy[ok], axis=1) / span
            v0.append(max(0.1, float(np.quantile(speeds, 0.8))))
        else:
            v0.append(1.0)
    lo = scene.xy.min(axis=0) - _MARGIN_M
    hi = scene.xy.max(axis=0) + _MARGIN_M
    duration = float((scene.t_ns.max() - t0) * 1e-9)
    label = name or re.sub(r"[^a-z0-9_-]+", "-", scene.scene.lower()).strip("-_")[:90]
    heading = math.atan2(*(r_xy[min(5, r_xy.shape[0] - 1)] - r_xy[0])[::-1])
    doc: dict[str, Any] = {
        "schema_version": 2,
        "name": f"recorded-{label}" if label else "recorded",
        "description": f"recorded scene {scene.scene!r} (robot replayed)",
        "kind": "fixed",
        "simulation": {"dt_s": dt_s, "horizon_steps": math.ceil((duration + 5.0) / dt_s)},
        "world": {
            "x_min": float(lo[0]),
            "x_max": float(hi[0]),
            "y_min": float(lo[1]),
            "y_max": float(hi[1]),
        },
        "robot": {
            "start": r_xy[0].tolist(),
            "goal": r_xy[-1].tolist(),
            "heading_rad": heading,
            "kinematics": "holonomic",
            "radius_m": RobotConfig().radius_m,
            "max_speed_mps": max(0.1, 1.2 * float(steps.max())),
            "max_accel_mps2": 20.0,
            "goal_radius_m": 0.1,
            "recording": {
                "times_s": (r_t - r_t[0]).tolist(),
                "xy": r_xy.tolist(),
            },
        },
        "pedestrians": {
            "radius_m": 0.3,
            "desired_speed_mps": v0,
            "max_speed_mps": [_VMAX_FACTOR * v for v in v0],
            "goal_radius_m": 0.3,
            "noise_m": 0.0,
            "starts": starts,
            "goals": goals,
        },
    }
    return doc


def scenario_toml(doc: Mapping[str, Any]) -> str:
    """A scenario document as TOML text that reads back to the same document.

    Keys are written in order: top-level values first, then one table per nested
    mapping (``[robot]``, ``[robot.recording]``, ...). Values are strings, booleans,
    integers, finite floats (written by ``repr``, so they read back bit for bit) and
    lists of them (nested lists too).

    Raises:
        ScenarioError: a value that TOML cannot hold or that does not read back.
    """
    lines: list[str] = []

    def value(v: Any, key: str) -> str:
        if isinstance(v, float | np.floating) and not math.isfinite(float(v)):
            raise ScenarioError(f"scenario key {key!r}: {v!r} is not a finite number")
        if isinstance(v, list | tuple):
            return "[" + ", ".join(value(x, key) for x in v) + "]"
        text = toml_scalar(v)
        if text is not None:
            return text
        raise ScenarioError(f"scenario key {key!r}: cannot write {type(v).__name__} to TOML")

    def table(mapping: Mapping[str, Any], path: str) -> None:
        if path:
            lines.extend(["", f"[{path}]"])
        nested = []
        for key, v in mapping.items():
            if not re.fullmatch(r"[A-Za-z0-9_-]+", key):
                raise ScenarioError(f"scenario key {key!r} is not a bare TOML key")
            if isinstance(v, Mapping):
                nested.append((key, v))
            else:
                lines.append(f"{key} = {value(v, f'{path}.{key}' if path else key)}")
        for key, v in nested:
            table(v, f"{path}.{key}" if path else key)

    table(doc, "")
    text = "\n".join(lines) + "\n"
    if _plain(tomllib.loads(text)) != _plain(doc):
        raise ScenarioError("the scenario document does not read back from TOML unchanged")
    return text


def _plain(v: Any) -> Any:
    """A document with tuples as lists and NumPy scalars as Python numbers."""
    if isinstance(v, Mapping):
        return {k: _plain(x) for k, x in v.items()}
    if isinstance(v, list | tuple):
        return [_plain(x) for x in v]
    if isinstance(v, np.generic):
        return v.item()
    return v
