"""Calling a numba kernel without numba's per-call type resolution.

A call of a numba dispatcher first works out the numba type of every argument. For
arrays and scalars that is done in C and costs well under a microsecond; for a
``typing.NamedTuple`` (how parameters go into the kernels) it runs in Python and costs
about 2 µs per tuple, more than the robot update itself. Code that calls a kernel once
per simulation step with the same kinds of arguments resolves the types once, with
:func:`specialize`, and then calls the compiled function directly.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numba

__all__ = ["specialize", "specialize_once"]


def specialize(kernel: Any, *args: Any) -> Callable[..., Any]:
    """The compiled function of ``kernel`` for the types of ``args``.

    Compiles (or loads from numba's cache) the specialisation of the ``@njit``
    dispatcher ``kernel`` for the numba types of the example arguments ``args`` and
    returns its entry point (numba's ``Dispatcher.compile``). The entry point converts
    its arguments as those types without checking them: every later call must pass
    arguments of the same kinds as ``args`` (same dtypes, dimensions and contiguity of
    arrays, same NamedTuple classes), which holds for buffers allocated once and
    parameter tuples of a fixed class.

    Args:
        kernel: an ``@njit`` function.
        *args: example arguments, of the types of every later call.

    Returns:
        A callable taking the same arguments as ``kernel``.
    """
    signature = tuple(numba.typeof(a) for a in args)  # type: ignore[no-untyped-call]
    entry: Callable[..., Any] = kernel.compile(signature)
    return entry


_ONCE: dict[Any, Callable[..., Any]] = {}


def specialize_once(kernel: Any, *args: Any) -> Callable[..., Any]:
    """:func:`specialize` for a kernel whose every call in this process passes
    arguments of one set of types: resolved at the first call, kept per kernel.

    For callers that build every argument themselves (the episode engine, the
    environment, :func:`srfm.step_crowd`): float64 or bool arrays, C-contiguous and
    writable, parameter tuples of fixed classes. Resolving the types costs tens of µs
    (a NamedTuple's type is worked out in Python), more than a small step.
    """
    entry = _ONCE.get(kernel)
    if entry is None:
        entry = specialize(kernel, *args)
        _ONCE[kernel] = entry
    return entry
