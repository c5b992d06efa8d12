"""Exceptions raised inside user code (planners), turned into one :class:`UserCodeError`.

User code runs at a few points only: a ``module:attribute`` planner's import and
factory, and its ``reset`` and ``act``. Anything raised there, including
``SystemExit`` (``sys.exit()`` in a planner must not end srfm with exit status 0), is
turned into a :class:`~srfm.errors.UserCodeError` whose message is one line naming the
planner, the method and the exception, and which keeps the traceback for ``--debug``.
``KeyboardInterrupt`` passes through; srfm's own errors pass through unchanged.
"""

from __future__ import annotations

import traceback
from collections.abc import Callable
from typing import Final, TypeVar

from srfm.errors import SrfmError, UserCodeError

__all__ = ["call_user_code", "is_user_code", "user_code_error"]

T = TypeVar("T")

_MAX_MESSAGE: Final = 300


def _describe(exc: BaseException) -> str:
    if isinstance(exc, SystemExit):
        return f"called sys.exit({exc.code!r})"
    text = str(exc).strip().splitlines()
    detail = text[0] if text else ""
    if len(detail) > _MAX_MESSAGE:
        detail = detail[:_MAX_MESSAGE] + "..."
    return f"{type(exc).__name__}: {detail}" if detail else type(exc).__name__


def user_code_error(
    planner: str, method: str, exc: BaseException, where: str = ""
) -> UserCodeError:
    """The :class:`UserCodeError` for ``exc`` raised by ``planner``'s ``method``.

    Args:
        planner: the planner's name.
        method: what was called (``"act()"``, ``"reset()"``, ``"its factory"``).
        exc: the exception.
        where: optional context, e.g. ``" at step 12 (scenario crosswalk, seed 3)"``.
    """
    hint = ""
    if method == "its factory" and isinstance(exc, TypeError):
        hint = " (module:attribute must name a class or function callable without arguments)"
    message = f"planner {planner!r} failed in {method}{where}: {_describe(exc)}{hint}"
    return UserCodeError(message, "".join(traceback.format_exception(exc)))


def call_user_code(planner: str, method: str, func: Callable[[], T], where: str = "") -> T:
    """``func()``, with an exception raised in it turned into a :class:`UserCodeError`."""
    try:
        return func()
    except (KeyboardInterrupt, SrfmError):
        raise
    except BaseException as exc:
        raise user_code_error(planner, method, exc, where) from None


def is_user_code(obj: object) -> bool:
    """Whether ``obj``'s class comes from outside srfm (a renamed user planner counts as
    the user's: its wrapper holds it as ``inner``)."""
    module = type(obj).__module__ or ""
    if module == "srfm.planners._registry" and hasattr(obj, "inner"):
        return is_user_code(obj.inner)
    return not (module == "srfm" or module.startswith("srfm."))
