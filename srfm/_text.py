"""Text of messages: ``count(1, "scenario")`` is "1 scenario", ``count(3, "seed")`` "3
seeds"; ``plain(value)`` is a value as an error message shows it.

Imports nothing of srfm (nor NumPy), so that every layer can use it.
"""

from __future__ import annotations

from typing import Any, Final

__all__ = ["count", "plain"]

PLAIN_LIMIT: Final = 200
"""Longest :func:`plain` text (characters); longer ones end in "…"."""
_ARRAY_ITEMS: Final = 8
"""Values of a NumPy array shown before "…" (its shape follows)."""


def count(n: int, noun: str, plural: str | None = None) -> str:
    """``n`` and ``noun``, in the plural (``plural``, or ``noun + "s"``) unless ``n`` is 1."""
    return f"{n} {noun if n == 1 else plural or noun + 's'}"


def plain(value: object) -> str:
    """``repr(value)`` as an error message quotes it: NumPy numbers as plain numbers
    (``-0.5``, not ``np.float64(-0.5)``), NumPy arrays as lists (a large one as its first
    values and its shape), also inside tuples, lists and dicts; on one line and at most
    :data:`PLAIN_LIMIT` characters. Any other value is its ``repr``."""
    text = repr(_python(value))
    if "\n" in text:
        text = " ".join(text.split())
    if len(text) > PLAIN_LIMIT:
        text = text[: PLAIN_LIMIT - 1] + "…"
    return text


def _python(value: Any) -> Any:
    """``value`` with every NumPy number and array replaced by Python numbers and lists."""
    if type(value).__module__ == "numpy" and hasattr(value, "tolist"):
        shape = getattr(value, "shape", ())
        size = getattr(value, "size", 1)
        if shape and size > _ARRAY_ITEMS:
            head = ", ".join(repr(v) for v in value.reshape(-1)[:_ARRAY_ITEMS].tolist())
            return _Shown(f"[{head}, …] (shape {tuple(int(n) for n in shape)})")
        return value.tolist()
    if isinstance(value, tuple) and not hasattr(value, "_fields"):
        return tuple(_python(v) for v in value)
    if isinstance(value, list):
        return [_python(v) for v in value]
    if isinstance(value, dict):
        return {_python(k): _python(v) for k, v in value.items()}
    return value


class _Shown:
    """Text that :func:`repr` shows as it is (a large array's summary)."""

    def __init__(self, text: str) -> None:
        self.text = text

    def __repr__(self) -> str:
        return self.text
