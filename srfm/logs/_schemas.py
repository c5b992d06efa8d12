"""The MCAP channels: versioned JSON schemas of srfm's own, Foxglove's scene schema.

srfm's channels use message encoding ``json`` and schema encoding ``jsonschema``;
every srfm message carries ``"schema_version"`` and a schema's name ends in
``.v<version>``, so that a reader can tell an old file from a new one before decoding a
message. The Foxglove scene (``/foxglove/scene``) uses Foxglove's official
``foxglove.SceneUpdate`` schema as the Foxglove SDK provides it (protobuf; see
:mod:`srfm.logs._foxglove`). Exact arrays are NumPy ``.npy`` files, base64 in the
JSON (``contentEncoding`` / ``contentMediaType`` say so in the schema).
"""

from __future__ import annotations

import functools
import json
from typing import Any, Final

import attrs

__all__ = [
    "CHANNELS",
    "READ_VERSIONS",
    "SCHEMA_VERSION",
    "ChannelSpec",
    "schema_bytes",
]

SCHEMA_VERSION: Final = 5
READ_VERSIONS: Final = (4, 5)
"""The log schema versions :func:`srfm.logs.read_log` reads: 4 (every array a plain
``.npy`` file) and 5 (the float64 trajectories, goals excepted, as bit planes)."""
NPY_MEDIA_TYPE: Final = "application/x-npy"
_DRAFT: Final = "https://json-schema.org/draft/2020-12/schema"


def _num(description: str) -> dict[str, Any]:
    return {"type": "number", "description": description}


def _int(description: str, minimum: int | None = 0) -> dict[str, Any]:
    out: dict[str, Any] = {"type": "integer", "description": description}
    if minimum is not None:
        out["minimum"] = minimum
    return out


def _nums(description: str) -> dict[str, Any]:
    return {"type": "array", "items": {"type": "number"}, "description": description}


def _nullable_nums(description: str) -> dict[str, Any]:
    return {
        "type": "array",
        "items": {"type": ["number", "null"]},
        "description": description,
    }


def _obj(
    properties: dict[str, Any], required: list[str] | None = None, **extra: Any
) -> dict[str, Any]:
    out: dict[str, Any] = {"type": "object", "properties": properties}
    required = list(properties) if required is None else required
    if required:
        out["required"] = required
    out.update(extra)
    return out


def _strip_descriptions(doc: Any) -> Any:
    """The schema without descriptions (the file repeats its schemas uncompressed)."""
    if isinstance(doc, dict):
        return {k: _strip_descriptions(v) for k, v in doc.items() if k != "description"}
    if isinstance(doc, list):
        return [_strip_descriptions(v) for v in doc]
    return doc


def _srfm_schema(name: str, description: str, properties: dict[str, Any], **kw: Any) -> bytes:
    title = f"srfm.logs.{name}.v{SCHEMA_VERSION}"
    # Field descriptions live in docs/logging.md: a file repeats its schemas uncompressed.
    body = _strip_descriptions(
        _obj({"schema_version": {"const": SCHEMA_VERSION}, **properties}, **kw)
    )
    doc = {"$schema": _DRAFT, "$id": title, "title": title, "description": description, **body}
    return json.dumps(doc, separators=(",", ":"), ensure_ascii=False).encode("utf-8")


_NPY: Final = {
    "type": "string",
    "contentEncoding": "base64",
    "contentMediaType": NPY_MEDIA_TYPE,
    "description": "a NumPy .npy file (format 1.0: little-endian float64, bool or uint8, "
    "C order, shape in its header), base64: numpy.load(io.BytesIO(base64.b64decode(s))); "
    "uint8 when the array is in bit-plane form (see planes)",
}

EPISODE: Final = _srfm_schema(
    "Episode",
    "Who, what and how of one logged twin episode (published once, at time 0).",
    {
        "kind": {
            "enum": ["episode", "counterfactual"],
            "description": "episode: a whole twin episode; counterfactual: the "
            "counterfactual crowd of a (scenario, seed), shared by every planner of a "
            "benchmark",
        },
        "profile": {"enum": ["full", "compact"]},
        "srfm_version": {"type": "string"},
        "scenario": {"type": "string"},
        "scenario_description": {"type": "string"},
        "seed": _int("episode seed"),
        "planner": {"type": ["string", "null"], "description": "null in counterfactual files"},
        "dt_s": _num("step (s)"),
        "horizon_steps": _int("T: both twins have T + 1 samples"),
        "n_pedestrians": _int("N"),
        "params": {"type": "object", "description": "SRFM parameters of the factual crowd"},
        "world": _obj({k: _num(f"{k} (m)") for k in ("x_min", "x_max", "y_min", "y_max")}),
        "obstacles": _obj(
            {
                "segments": {"type": "array", "description": "walls (x1, y1, x2, y2) in m"},
                "circles": {"type": "array", "description": "pillars (cx, cy, radius) in m"},
            }
        ),
        "pedestrians": _obj(
            {
                "radius_m": _nums("(N,) radii"),
                "desired_speed_mps": _nums("(N,) desired speeds v0"),
                "max_speed_mps": _nums("(N,) speed caps"),
                "goal_radius_m": _num("arrival radius"),
                "enter_step": {
                    "type": "array",
                    "items": {"type": "integer"},
                    "description": "(N,) the sample at which each pedestrian appears, "
                    "in increasing order (before it, it stands at its start and counts for "
                    "nothing); absent when every pedestrian is there from sample 0",
                },
            },
            required=["radius_m", "desired_speed_mps", "max_speed_mps", "goal_radius_m"],
        ),
        "robot": _obj(
            {
                "kinematics": {"enum": ["unicycle", "holonomic"]},
                "radius_m": _num("robot radius"),
                "goal": _nums("(2,) robot goal (m)"),
            },
            additionalProperties=True,
        ),
        "outcome": {"type": ["string", "null"]},
        "end_step": {"type": ["integer", "null"]},
        "robot_states": {
            "enum": ["all", "frames", None],
            "description": "when /srfm/robot/state and /srfm/robot/command are published: "
            "all: every sample (full logs); frames: at the Foxglove scene's agent frames "
            "only (compact logs); the exact robot of every sample is the robot group of "
            "/srfm/trajectories; null in counterfactual files",
        },
        "counterfactual": _obj(
            {
                "file": {
                    "type": ["string", "null"],
                    "description": "null: in this file; else the counterfactual file, "
                    "relative to this file's folder",
                },
                "sha256": {
                    "type": "string",
                    "description": "SHA-256 of the counterfactual arrays (positions, "
                    "goals), checked by srfm score",
                },
            }
        ),
        "benchmark": {
            "type": ["object", "null"],
            "description": "the benchmark request this episode belongs to (table order)",
        },
    },
)

PEDESTRIAN_STATES: Final = _srfm_schema(
    "PedestrianStates",
    "Every pedestrian of one twin at one sample (exact float64 values).",
    {
        "twin": {"enum": ["factual", "counterfactual"]},
        "step": _int("sample index k (state after k steps, at the message's log time)"),
        "x": _nums("(N,) x (m)"),
        "y": _nums("(N,) y (m)"),
        "vx": _nums("(N,) x velocity (m/s)"),
        "vy": _nums("(N,) y velocity (m/s)"),
        "goal_x": _nums("(N,) current goal x (m)"),
        "goal_y": _nums("(N,) current goal y (m)"),
    },
)

ROBOT_STATE: Final = _srfm_schema(
    "RobotState",
    "The robot at one sample (exact float64 values).",
    {
        "step": _int("sample index (its time is the message's log time)"),
        "x": _num("x (m)"),
        "y": _num("y (m)"),
        "theta": _num("heading (rad)"),
        "vx": _num("world-frame velocity applied in the step that ended here (m/s)"),
        "vy": _num("(m/s)"),
        "active": {"type": "boolean", "description": "the robot's episode is running"},
    },
)

ROBOT_COMMAND: Final = _srfm_schema(
    "RobotCommand",
    "The command the planner returned at one step (published while the robot is active).",
    {
        "step": _int("step index k: the command moves the robot from sample k to k + 1"),
        "kinematics": {"enum": ["unicycle", "holonomic"]},
        "command": _nums("(v m/s, omega rad/s) for unicycle, (vx, vy) m/s for holonomic"),
    },
)

EVENT: Final = _srfm_schema(
    "Event",
    "Something that happened at the end of a step.",
    {
        "step": _int("sample at which it was detected"),
        "time_s": _num("time of that sample (s)"),
        "kind": {
            "enum": [
                "robot_goal_reached",
                "robot_collision",
                "robot_out_of_bounds",
                "robot_timeout",
                "ped_arrival",
            ]
        },
        "agent": _int("pedestrian index, or -1", minimum=-1),
        "twin": {"enum": ["factual", "counterfactual", ""]},
    },
)

TRAJECTORIES: Final = _srfm_schema(
    "Trajectories",
    "Exact arrays of every sample of one group (published once, at the end), as "
    ".npy files: what srfm score reads.",
    {
        "group": {"enum": ["factual", "counterfactual", "robot"]},
        "samples": _int("T + 1"),
        "arrays": {
            "type": "object",
            "description": "factual, counterfactual: pos, goal (T + 1, N, 2) and, in full "
            "logs, vel; robot: pose (T + 1, 3) as (x, y, theta), vel (T + 1, 2), active "
            "(T + 1,) bool, cmd (T, 2) (NaN where the planner was not asked)",
            "additionalProperties": _NPY,
        },
        "planes": {
            "type": "object",
            "description": "the arrays stored in bit-plane form (every float64 array but "
            "the goals), with their shapes: the .npy file holds the (64, ceil(M / 8)) "
            "uint8 bit planes of the zigzagged second differences in time of the M "
            "values' IEEE-754 bit patterns, time last (docs/logging.md#exact-arrays)",
            "additionalProperties": {"type": "array", "items": {"type": "integer"}},
        },
    },
)

METRICS: Final = _srfm_schema(
    "EpisodeMetrics",
    "The episode's metrics as computed online (NaN written as null).",
    {
        "scenario": {"type": "string"},
        "planner": {"type": "string"},
        "seed": _int("seed"),
        "outcome": {"type": "string"},
        "end_step": _int("end step"),
        "metrics": {
            "type": "object",
            "additionalProperties": {"type": ["number", "null"]},
            "description": "every EPISODE_METRICS entry (docs/metrics.md)",
        },
        "pedestrians": {
            "type": "object",
            "additionalProperties": _nullable_nums("(N,) one value per pedestrian"),
            "description": "every PEDESTRIAN_METRICS entry",
        },
    },
)


@attrs.frozen
class ChannelSpec:
    """One MCAP channel.

    Attributes:
        topic: the channel's topic.
        schema_name: the schema's name (``srfm.logs.<Name>.v<version>`` or
            ``foxglove.SceneUpdate``).
        schema_encoding: ``jsonschema`` (srfm's) or ``protobuf`` (Foxglove's).
        message_encoding: ``json`` (srfm's) or ``protobuf`` (Foxglove's).
    """

    topic: str
    schema_name: str
    schema_encoding: str
    message_encoding: str
    _schema: bytes | None = attrs.field(default=None, alias="schema", repr=False)

    @property
    def schema(self) -> bytes:
        """The schema's data (Foxglove's is loaded from the SDK when first asked for)."""
        if self._schema is not None:
            return self._schema
        return _foxglove_schema()[2]


@functools.cache
def _foxglove_schema() -> tuple[str, str, bytes]:
    from srfm.logs._foxglove import scene_schema

    return scene_schema()


def _spec(topic: str, schema: bytes) -> ChannelSpec:
    return ChannelSpec(topic, json.loads(schema)["title"], "jsonschema", "json", schema=schema)


CHANNELS: Final[dict[str, ChannelSpec]] = {
    "episode": _spec("/srfm/episode", EPISODE),
    "factual": _spec("/srfm/pedestrians/factual", PEDESTRIAN_STATES),
    "counterfactual": _spec("/srfm/pedestrians/counterfactual", PEDESTRIAN_STATES),
    "robot_state": _spec("/srfm/robot/state", ROBOT_STATE),
    "robot_command": _spec("/srfm/robot/command", ROBOT_COMMAND),
    "events": _spec("/srfm/events", EVENT),
    "trajectories": _spec("/srfm/trajectories", TRAJECTORIES),
    "metrics": _spec("/srfm/metrics", METRICS),
    "scene": ChannelSpec("/foxglove/scene", "foxglove.SceneUpdate", "protobuf", "protobuf"),
}
"""Every channel srfm writes, by key; docs/logging.md lists them."""


def schema_bytes(key: str) -> bytes:
    """The schema data of channel ``key`` (for tests and docs)."""
    return CHANNELS[key].schema
