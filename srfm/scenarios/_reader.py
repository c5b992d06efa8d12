"""Typed, checked access to the tables of a scenario file (:mod:`srfm.scenarios._schema`).

Every value is checked as it is read, and the message of a bad one names the file and
the key (``file: table.key: message``); :meth:`TableReader.finish` refuses the keys of
a table that nothing read.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np
from numpy.typing import NDArray

from srfm._text import plain
from srfm._validate import BOUNDS
from srfm.errors import ScenarioError

__all__ = ["TableReader"]

FloatArray = NDArray[np.float64]


class TableReader:
    """Typed access to one TOML table, recording which keys were read."""

    def __init__(self, data: Mapping[str, Any], where: str, file: str) -> None:
        self.data = data
        self.where = where
        self.file = file
        self.used: set[str] = set()

    def key(self, name: str) -> str:
        return f"{self.where}.{name}" if self.where else name

    def fail(self, name: str, message: str) -> ScenarioError:
        return ScenarioError(f"{self.file}: {self.key(name)}: {message}")

    def has(self, name: str) -> bool:
        return name in self.data

    def raw(self, name: str) -> Any:
        self.used.add(name)
        return self.data[name]

    def table(self, name: str) -> TableReader:
        value = self.raw(name) if name in self.data else {}
        if not isinstance(value, dict):
            raise self.fail(name, f"must be a table, got {plain(value)}")
        return TableReader(value, self.key(name), self.file)

    def string(self, name: str, default: str | None = None) -> str:
        if name not in self.data:
            if default is None:
                raise self.fail(name, "is required")
            return default
        value = self.raw(name)
        if not isinstance(value, str):
            raise self.fail(name, f"must be a string, got {plain(value)}")
        return value

    def number(
        self,
        name: str,
        default: float | None = None,
        *,
        minimum: float | None = None,
        strict: bool = False,
        maximum: float | None = None,
        kind: str | None = None,
    ) -> float:
        """A finite number; ``kind`` applies the physical bounds of
        :data:`srfm._validate.BOUNDS` (``minimum`` and ``maximum`` may only narrow them)."""
        if kind is not None:
            lo, hi, _ = BOUNDS[kind]
            minimum = lo if minimum is None else max(minimum, lo)
            maximum = hi if maximum is None else min(maximum, hi)
        if name not in self.data:
            if default is None:
                raise self.fail(name, "is required")
            return default
        value = self.raw(name)
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise self.fail(name, f"must be a number, got {plain(value)}")
        out = float(value)
        if not math.isfinite(out):
            raise self.fail(name, f"must be finite, got {plain(value)}")
        if minimum is not None and (out <= minimum if strict else out < minimum):
            raise self.fail(
                name, f"must be {'>' if strict else '>='} {minimum:g}, got {plain(value)}"
            )
        if maximum is not None and out > maximum:
            raise self.fail(name, f"must be <= {maximum:g}, got {plain(value)}")
        return out

    def bounded_array(
        self, name: str, cols: int, *, required: bool, kinds: tuple[str, ...]
    ) -> FloatArray | None:
        """:meth:`array` whose column j obeys :data:`srfm._validate.BOUNDS` ``[kinds[j]]``
        (a single kind applies to every column)."""
        out = self.array(name, cols, required=required)
        if out is None:
            return None
        rows = out.reshape(-1, out.shape[-1]) if out.size else out.reshape(0, max(cols, 2))
        for i, row in enumerate(rows):
            for j, item in enumerate(row):
                lo, hi, unit = BOUNDS[kinds[j] if len(kinds) > 1 else kinds[0]]
                if not lo <= item <= hi:
                    label = name if cols == 0 else f"{name}[{i}]"
                    raise self.fail(
                        label, f"values must be in [{lo:g}, {hi:g}] {unit}, got {plain(item)}"
                    )
        return out

    def integer(self, name: str, default: int, *, minimum: int, maximum: int) -> int:
        if name not in self.data:
            return default
        value = self.raw(name)
        if isinstance(value, bool) or not isinstance(value, int):
            raise self.fail(name, f"must be an integer, got {plain(value)}")
        if not minimum <= value <= maximum:
            raise self.fail(name, f"must be in [{minimum}, {maximum}], got {plain(value)}")
        return value

    def boolean(self, name: str, default: bool) -> bool:
        if name not in self.data:
            return default
        value = self.raw(name)
        if not isinstance(value, bool):
            raise self.fail(name, f"must be true or false, got {plain(value)}")
        return value

    def array(self, name: str, cols: int, *, required: bool) -> FloatArray | None:
        if name not in self.data:
            if required:
                raise self.fail(name, "is required")
            return None
        value = self.raw(name)
        rows = value if isinstance(value, list) else None
        if cols == 0:  # a flat vector of two numbers
            rows = [value] if isinstance(value, list) else None
        if rows is None:
            raise self.fail(name, f"must be an array, got {plain(value)}")
        width = 2 if cols == 0 else cols
        out = np.zeros((len(rows), width))
        for i, row in enumerate(rows):
            label = name if cols == 0 else f"{name}[{i}]"
            if not isinstance(row, list) or len(row) != width:
                raise self.fail(label, f"must be a list of {width} numbers, got {plain(row)}")
            for j, item in enumerate(row):
                if isinstance(item, bool) or not isinstance(item, int | float):
                    raise self.fail(label, f"must hold numbers, got {plain(item)}")
                if not math.isfinite(float(item)):
                    raise self.fail(label, f"must be finite, got {plain(item)}")
                out[i, j] = float(item)
        return out[0] if cols == 0 else out

    def per_agent(
        self, name: str, default: float, n: int | None, maximum: float
    ) -> FloatArray | float:
        if name not in self.data:
            return default
        value = self.data[name]
        if isinstance(value, list):
            self.used.add(name)
            if n is None:
                raise self.fail(name, "lists (one value per pedestrian) need listed starts")
            if len(value) != n:
                raise self.fail(name, f"needs one value per pedestrian ({n}), got {len(value)}")
            out = np.zeros(n)
            for i, item in enumerate(value):
                if isinstance(item, bool) or not isinstance(item, int | float):
                    raise self.fail(f"{name}[{i}]", f"must be a number, got {plain(item)}")
                if not 0.0 <= float(item) <= maximum:  # also false for NaN
                    raise self.fail(
                        f"{name}[{i}]", f"must be in [0, {maximum:g}], got {plain(item)}"
                    )
                out[i] = float(item)
            return out
        return self.number(name, minimum=0.0, maximum=maximum)

    def finish(self) -> None:
        unknown = sorted(set(self.data) - self.used)
        if unknown:
            raise ScenarioError(f"{self.file}: unknown key {self.key(unknown[0])!r}")


def check_wall_length(reader: TableReader, label: str, row: Any) -> None:
    """Refuse a wall ``[x1, y1, x2, y2, ...]`` whose ends coincide (every version): it
    has no length to be a wall; a post is a pillar ``[cx, cy, radius]``."""
    if row[0] == row[2] and row[1] == row[3]:
        raise reader.fail(
            label,
            f"has zero length (both ends at [{float(row[0])!r}, {float(row[1])!r}]); give two "
            "different ends, or a pillar [cx, cy, radius] for a post",
        )
