"""MkDocs hook of the documentation site (mkdocs.yml): every public name of srfm, each
name of ``srfm.__all__``, must have a docstring. A missing one is a warning, which
``mkdocs build --strict`` (``make docs``) turns into a failure."""

from __future__ import annotations

import logging
from pathlib import Path
from typing import Any

import griffe

ROOT = Path(__file__).resolve().parents[1]
log = logging.getLogger("mkdocs.hooks.srfm")


def undocumented() -> list[str]:
    """The names of ``srfm.__all__`` whose definition has no docstring."""
    package = griffe.load("srfm", search_paths=[str(ROOT)], docstring_parser="google")
    missing = []
    for name in package.exports or ():
        member = package[name]
        target = member.final_target if member.is_alias else member
        if target.docstring is None or not target.docstring.value.strip():
            missing.append(name)
    return missing


def on_config(config: Any) -> Any:
    """Warn about every public name without a docstring."""
    for name in undocumented():
        log.warning("srfm.%s has no docstring (every name of srfm.__all__ needs one)", name)
    return config
