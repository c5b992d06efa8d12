"""The official TypeScript MCAP reader (``@mcap/core``) under Node.js, for the tests.

:func:`install` puts ``@mcap/core``, ``@mcap/support`` (zstd, lz4 and bz2 chunk
decompression; protobuf descriptors) and ``@mcap/nodejs`` (file access), at pinned
versions, into a cache folder it creates: ``$SRFM_TEST_NODE_CACHE``, else
``$XDG_CACHE_HOME/srfm-test-node``, else ``~/.cache/srfm-test-node``, one sub-folder per
set of versions. Concurrent test runs wait on a lock and install once; an interrupted
install leaves only a temporary folder that the next one ignores. :func:`read_mcap`
runs ``mcap_core_read.mjs`` on files and returns what the reader found.
"""

from __future__ import annotations

import contextlib
import fcntl
import functools
import hashlib
import json
import os
import shutil
import subprocess
import tempfile
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any, Final

PACKAGES: Final = {"@mcap/core": "2.2.2", "@mcap/support": "1.1.0", "@mcap/nodejs": "1.0.2"}
SCRIPT: Final = Path(__file__).with_name("mcap_core_read.mjs")
_DONE: Final = ".srfm-installed"


class NodeMissingError(RuntimeError):
    """``node`` or ``npm`` is not on the PATH."""


def cache_root() -> Path:
    """Where the Node packages are installed."""
    explicit = os.environ.get("SRFM_TEST_NODE_CACHE")
    if explicit:
        return Path(explicit)
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "srfm-test-node"


@contextlib.contextmanager
def _locked(root: Path) -> Iterator[None]:
    root.mkdir(parents=True, exist_ok=True)
    with (root / ".lock").open("w") as fh:
        fcntl.flock(fh, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(fh, fcntl.LOCK_UN)


def install() -> Path:
    """The folder whose ``node_modules`` hold the pinned packages (installed if needed).

    Raises:
        NodeMissingError: no ``node`` or ``npm``.
        RuntimeError: ``npm install`` failed (its output is in the message).
    """
    if shutil.which("node") is None or shutil.which("npm") is None:
        raise NodeMissingError("node and npm are not both on the PATH")
    root = cache_root()
    key = hashlib.sha256(json.dumps(PACKAGES, sort_keys=True).encode()).hexdigest()[:12]
    target = root / key
    if (target / _DONE).exists():
        return target
    with _locked(root):
        if (target / _DONE).exists():  # installed by a concurrent run
            return target
        tmp = Path(tempfile.mkdtemp(prefix=".install-", dir=root))
        manifest = {"name": "srfm-test-node", "private": True, "dependencies": PACKAGES}
        (tmp / "package.json").write_text(json.dumps(manifest, indent=2), encoding="utf-8")
        done = subprocess.run(
            ["npm", "install", "--no-audit", "--no-fund", "--loglevel=error"],
            cwd=tmp,
            capture_output=True,
            text=True,
            timeout=600,
            check=False,
        )
        if done.returncode != 0:
            shutil.rmtree(tmp, ignore_errors=True)
            raise RuntimeError(
                f"npm install {' '.join(f'{k}@{v}' for k, v in PACKAGES.items())} failed "
                f"(exit {done.returncode}):\n{done.stdout}\n{done.stderr}"
            )
        (tmp / _DONE).write_text("ok\n", encoding="utf-8")
        if target.exists():  # a stale, unfinished folder of an older layout
            shutil.rmtree(target)
        tmp.rename(target)
    return target


def read_mcap(prefix: Path, paths: Sequence[Path]) -> list[dict[str, Any]]:
    """What ``@mcap/core`` reads in each file (see ``mcap_core_read.mjs``)."""
    done = subprocess.run(
        ["node", str(SCRIPT), str(prefix), *(str(p) for p in paths)],
        capture_output=True,
        text=True,
        timeout=600,
        check=False,
    )
    if done.returncode != 0:
        raise RuntimeError(f"node {SCRIPT.name} failed:\n{done.stderr}")
    result: list[dict[str, Any]] = json.loads(done.stdout)
    return result


@functools.cache
def _installed() -> Path | str:
    try:
        return install()
    except NodeMissingError as exc:
        return f"skip: {exc}"
    except (RuntimeError, OSError, subprocess.TimeoutExpired) as exc:
        return f"fail: {exc}"


def prefix_or_skip() -> Path:
    """:func:`install` for a test: skips (saying why) only where Node.js is missing,
    fails when the packages cannot be installed."""
    import pytest

    got = _installed()
    if isinstance(got, Path):
        return got
    if got.startswith("skip: "):
        pytest.skip(
            "the @mcap/core cross-check of the MCAP files needs Node.js: "
            + got.removeprefix("skip: ")
        )
    pytest.fail("could not install the @mcap/core reader: " + got.removeprefix("fail: "))
