"""The protocol's schema (``protocol.toml`` beside this file): its version, its messages,
a check of one message against it, and the Markdown table of its fields."""

from __future__ import annotations

import functools
import math
import re
import tomllib
from pathlib import Path
from typing import Any, Final

import attrs

__all__ = [
    "PROTOCOL_VERSION",
    "SCHEMA_FILE",
    "Field",
    "MessageSpec",
    "field_table",
    "message_problem",
    "message_spec",
    "messages",
]

SCHEMA_FILE: Final = Path(__file__).with_name("protocol.toml")
_LIST = re.compile(r"(float|int)\[(\d*)([a-z]?)\]")


@attrs.frozen
class Field:
    """One field of a message: its name, type (``int``, ``float``, ``str``,
    ``float|nil``, ``float[2]``, ``float[2k]``...), unit and description."""

    name: str
    type: str
    unit: str
    doc: str


@attrs.frozen
class MessageSpec:
    """One message: its ``type``, who sends it, the message that answers it (empty:
    none), its description and its fields (``type`` itself not counted)."""

    type: str
    sender: str
    answer: str
    doc: str
    fields: tuple[Field, ...]


@functools.cache
def _schema() -> tuple[int, tuple[MessageSpec, ...]]:
    doc = tomllib.loads(SCHEMA_FILE.read_text(encoding="utf-8"))
    specs = tuple(
        MessageSpec(
            type=m["type"],
            sender=m["sender"],
            answer=m.get("answer", ""),
            doc=m["doc"],
            fields=tuple(
                Field(f["name"], f["type"], f.get("unit", ""), f["doc"])
                for f in m.get("fields", [])
            ),
        )
        for m in doc["messages"]
    )
    return int(doc["version"]), specs


PROTOCOL_VERSION: Final = _schema()[0]
"""The version of the protocol srfm speaks (``version`` of ``protocol.toml``)."""


def messages() -> tuple[MessageSpec, ...]:
    """Every message of the protocol, in the schema's order."""
    return _schema()[1]


def message_spec(type_: str, sender: str) -> MessageSpec:
    """The message ``type_`` sent by ``sender`` (``"srfm"`` or ``"planner"``)."""
    for spec in messages():
        if spec.type == type_ and spec.sender == sender:
            return spec
    raise KeyError(f"no message {type_!r} from {sender}")


def _value_problem(value: Any, type_: str) -> str | None:
    """Why ``value`` is not of the schema type ``type_`` (None when it is)."""
    if type_ == "str":
        return None if isinstance(value, str) else "a string"
    if type_ == "int":
        return None if isinstance(value, int) and not isinstance(value, bool) else "an integer"
    if type_ in ("float", "float|nil"):
        if value is None and type_ == "float|nil":
            return None
        ok = isinstance(value, int | float) and not isinstance(value, bool)
        return None if ok and math.isfinite(value) else "a finite number"
    match = _LIST.fullmatch(type_)
    if match is None:
        raise ValueError(f"unknown schema type {type_!r}")
    item, count, per = match.groups()
    if not isinstance(value, list | tuple):
        return "a list"
    if per == "" and len(value) != int(count):
        return f"a list of {count}"
    if per and count and len(value) % int(count):
        return f"a list whose length is a multiple of {count}"
    for x in value:
        if _value_problem(x, item) is not None:
            return f"a list of {'integers' if item == 'int' else 'finite numbers'}"
    return None


def message_problem(message: Any, spec: MessageSpec) -> str | None:
    """Why ``message`` is not the message ``spec`` (None when it is): not a map, another
    ``type``, a missing field or a field of the wrong type. Other keys are allowed."""
    if not isinstance(message, dict):
        return f"expected a map, got {type(message).__name__}"
    if message.get("type") != spec.type:
        return f"expected a {spec.type!r} message, got type {message.get('type')!r}"
    for field in spec.fields:
        if field.name not in message:
            return f"{spec.type!r} message without {field.name!r}"
        problem = _value_problem(message[field.name], field.type)
        if problem is not None:
            value = repr(message[field.name])
            if len(value) > 60:
                value = value[:60] + "..."
            return f"{spec.type!r} message: {field.name!r} must be {problem}, got {value}"
    return None


def field_table() -> str:
    """Every message and field as one Markdown table (docs/planners-any-language.md)."""
    lines = [
        "| message | from | field | type | unit | meaning |",
        "|---|---|---|---|---|---|",
    ]
    for spec in messages():
        answer = f" Answered by `{spec.answer}`." if spec.answer else ""
        lines.append(
            f"| `{spec.type}` | {spec.sender} | `type` | str | | {_cell(spec.doc)}{answer} |"
        )
        for field in spec.fields:
            lines.append(
                f"| | | `{field.name}` | {_cell(field.type)} | {field.unit} | {_cell(field.doc)} |"
            )
    return "\n".join(lines) + "\n"


def _cell(text: str) -> str:
    """``text`` in a Markdown table cell (its ``|`` escaped)."""
    return text.replace("|", "\\|")
