"""Reading inputs and writing outputs safely: the one place srfm touches files for users.

Reading (:func:`read_input_bytes`, :func:`read_input_text`): regular files only (a FIFO,
a device such as ``/dev/zero`` or a folder is refused without blocking), up to a stated
size, UTF-8 with an optional byte-order mark; every failure is the caller's error class
naming the file. :func:`parse_toml` and :func:`check_columns`: a TOML file or a CSV
header that names a key, a table or a column twice is an error naming it (never "the
last one wins").

Writing:

- :func:`atomic_write_bytes` / :func:`atomic_write_text`: a temporary file in the same
  folder, then a rename, so readers see the old file or the new one, never half of one;
  a failure (disk full, permission) is a :class:`~srfm.errors.WriteError` naming the file,
  and the old file is left as it was.
- :func:`write_file_set`: several files replaced as a whole (the reports of a
  benchmark): every file is staged first, then a journal commits the set, then the
  files are renamed into place; :func:`recover_file_set` finishes a set whose renames
  were cut short by a kill.
- :func:`check_writable`: before any work, whether an output can be created there.
- :func:`refuse_overwriting_inputs`: an output may not be one of the inputs, however the
  paths are spelled.
- :func:`claim_output_folder`: srfm writes reports only into a new or empty folder, or
  one it created itself (it leaves a marker file), unless forced.
- :func:`folder_lock`: one srfm process at a time per results folder.
"""

from __future__ import annotations

import contextlib
import errno
import functools
import json
import os
import re
import stat
import tempfile
from collections.abc import Iterable, Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any, Final

import numpy as np

from srfm.errors import FolderInUseError, OutputError, SrfmError, WriteError

__all__ = [
    "LOCK_FILE",
    "MAX_DATASET_FILE_BYTES",
    "MAX_DOCUMENT_BYTES",
    "MAX_TOML_BYTES",
    "OUTPUT_MARKER",
    "atomic_write_bytes",
    "atomic_write_text",
    "check_columns",
    "check_writable",
    "claim_output_folder",
    "folder_lock",
    "new_file_mode",
    "parse_toml",
    "read_input_bytes",
    "read_input_text",
    "recover_file_set",
    "refuse_overwriting_inputs",
    "remove_stale_temporaries",
    "same_file",
    "write_file_set",
]

MAX_TOML_BYTES: Final = 16 * 2**20
"""Largest scenario or parameter file read (16 MiB: ~100,000 listed pedestrians)."""
MAX_DOCUMENT_BYTES: Final = 64 * 2**20
"""Largest JSON document srfm reads back from its own folders (episode metrics, manifest)."""
MAX_DATASET_FILE_BYTES: Final = 2**30
"""Largest raw dataset file read by the adapters (1 GiB)."""

OUTPUT_MARKER: Final = ".srfm-output"
"""The marker file of a folder srfm created for its output (JSON: which command)."""
LOCK_FILE: Final = ".srfm.lock"
"""The lock file of a results folder (see :func:`folder_lock`)."""
_JOURNAL: Final = ".srfm-file-set.json"
_JOURNAL_SCHEMA: Final = "srfm.file_set/1"
_TEMP_SUFFIX: Final = ".tmp"
_TOML_AT: Final = re.compile(r"\(at line (\d+), column \d+\)$")
_TOML_TABLE_TWICE: Final = re.compile(r"^Cannot declare \((.*)\) twice")


# --------------------------------------------------------------------------------------
# Reading


def _reason(exc: OSError) -> str:
    return exc.strerror or str(exc)


def read_input_bytes(
    path: str | Path, *, max_bytes: int, error: type[SrfmError], what: str = "file"
) -> bytes:
    """The bytes of a regular file of at most ``max_bytes``.

    The file is opened without blocking (a FIFO cannot hang the caller) and checked to
    be a regular file before anything is read; the size is checked on the open file and
    again while reading, so a file that grows cannot exhaust memory either.

    Args:
        path: the file.
        max_bytes: the largest size accepted.
        error: the error class raised (e.g. :class:`~srfm.errors.ScenarioError`).
        what: what the file is, for the messages ("scenario file").

    Raises:
        error: missing, not a regular file, too large, or unreadable; the message names
            the file.
    """
    path = Path(path)
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_BINARY", 0))
    except FileNotFoundError:
        raise error(f"{path}: {what} not found") from None
    except IsADirectoryError:
        raise error(f"{path}: is a folder, expected a {what}") from None
    except OSError as exc:
        raise error(f"{path}: cannot read {what}: {_reason(exc)}") from None
    try:
        info = os.fstat(fd)
        if stat.S_ISDIR(info.st_mode):
            raise error(f"{path}: is a folder, expected a {what}")
        if not stat.S_ISREG(info.st_mode):
            raise error(f"{path}: not a regular file (a pipe or a device); expected a {what}")
        if info.st_size > max_bytes:
            raise error(
                f"{path}: {info.st_size:,} bytes, larger than the {max_bytes:,} bytes "
                f"accepted for a {what}"
            )
        chunks = []
        size = 0
        while True:
            chunk = os.read(fd, min(1 << 20, max_bytes + 1 - size))
            if not chunk:
                break
            chunks.append(chunk)
            size += len(chunk)
            if size > max_bytes:
                raise error(f"{path}: larger than the {max_bytes:,} bytes accepted for a {what}")
        return b"".join(chunks)
    except OSError as exc:
        raise error(f"{path}: cannot read {what}: {_reason(exc)}") from None
    finally:
        os.close(fd)


def toml_scalar(value: object) -> str | None:
    """The TOML text of one scalar, or None for any other type: a boolean, an integer,
    a float written by ``repr`` (it reads back bit for bit; callers that need finite
    numbers refuse inf and NaN first) or a string (a JSON string is a TOML basic
    string)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int | np.integer):
        return str(int(value))
    if isinstance(value, float | np.floating):
        return repr(float(value))
    if isinstance(value, str):
        return json.dumps(value)
    return None


def read_input_text(
    path: str | Path, *, max_bytes: int, error: type[SrfmError], what: str = "file"
) -> str:
    """:func:`read_input_bytes` decoded as UTF-8; a leading byte-order mark is dropped."""
    data = read_input_bytes(path, max_bytes=max_bytes, error=error, what=what)
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise error(f"{path}: not UTF-8 text (byte {exc.start}); expected a {what}") from None


def parse_toml(text: str, path: str | Path, error: type[SrfmError]) -> dict[str, Any]:
    """``text``, the content of the TOML file ``path``, parsed.

    Raises:
        error: not valid TOML, naming the file and the line; a key set twice or a table
            declared twice also names the key or the table (TOML forbids both).
    """
    import tomllib

    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise error(f"{path}: not valid TOML: {_toml_problem(text, str(exc))}") from None


def _toml_problem(text: str, message: str) -> str:
    """tomllib's ``message``, with the key or table it is about when it is a repeat."""
    at = _TOML_AT.search(message)
    if at is None:
        return message
    line = int(at.group(1))
    table = _TOML_TABLE_TWICE.match(message)
    if table is not None:
        names = [n.strip().strip("'\"") for n in table.group(1).split(",") if n.strip()]
        return f"table [{'.'.join(names)}] is declared twice (line {line})"
    if message.startswith("Cannot overwrite a value"):
        lines = text.splitlines()
        source = lines[line - 1].strip() if 0 < line <= len(lines) else ""
        if source.startswith("["):
            return f"table {source} names a key set earlier (line {line})"
        key = source.split("=", 1)[0].strip()
        if key:
            return f"key {key!r} repeats a key set earlier (line {line})"
    return message


def check_columns(header: Sequence[str], where: str, error: type[SrfmError]) -> None:
    """A CSV header names every column once.

    Raises:
        error: ``where``: the first column named twice (which of the two holds the data
            would be a guess).
    """
    seen: set[str] = set()
    for name in header:
        if name in seen:
            raise error(
                f"{where}: column {name!r} appears twice in the header "
                f"({','.join(header)}); which one holds the data is ambiguous"
            )
        seen.add(name)


# --------------------------------------------------------------------------------------
# Writing


@functools.cache
def new_file_mode() -> int:
    """The mode ``open()`` gives new files: 0o666 less the process umask. Every file
    srfm writes through a temporary (``mkstemp`` makes 0600 files) gets it."""
    mask = os.umask(0o022)
    os.umask(mask)
    return 0o666 & ~mask


def write_error(path: str | Path, exc: OSError) -> WriteError:
    """The :class:`WriteError` for ``exc`` raised while writing ``path`` (errno kept)."""
    reason = _reason(exc)
    if exc.errno == errno.ENOTDIR:
        reason = "a file stands where a folder is needed"
    err = WriteError(f"cannot write {path}: {reason}")
    err.errno = exc.errno
    err.strerror = exc.strerror
    err.filename = str(path)
    return err


def _write_temporary(path: Path, data: bytes, *, fsync: bool) -> Path:
    """``data`` in a new temporary file beside ``path``; returns the temporary's path."""
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=_TEMP_SUFFIX, dir=path.parent)
    try:
        os.fchmod(fd, new_file_mode())  # mkstemp makes 0600 files; match a plain open()
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
            if fsync:
                fh.flush()
                os.fsync(fh.fileno())
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return Path(tmp)


def atomic_write_bytes(path: str | Path, data: bytes, *, fsync: bool = True) -> None:
    """Write ``data`` to ``path`` so that readers see either the old or the new file.

    ``fsync=False`` skips flushing to disk: the file is still never seen half-written
    after the writing process is interrupted or killed, only a power cut could lose it
    (the benchmark's many small per-episode files use this).

    Raises:
        WriteError: the file could not be written (the message names it and the reason);
            an existing file at ``path`` is left unchanged.
    """
    path = Path(path)
    try:
        tmp = _write_temporary(path, data, fsync=fsync)
        try:
            os.replace(tmp, path)
        except BaseException:
            tmp.unlink(missing_ok=True)
            raise
    except OSError as exc:
        if isinstance(exc, WriteError):
            raise
        raise write_error(path, exc) from None


def atomic_write_text(path: str | Path, text: str, *, fsync: bool = True) -> None:
    """UTF-8 text version of :func:`atomic_write_bytes`."""
    atomic_write_bytes(path, text.encode("utf-8"), fsync=fsync)


def _fsync_folder(folder: Path) -> None:
    with contextlib.suppress(OSError, AttributeError):
        fd = os.open(folder, os.O_RDONLY)
        try:
            os.fsync(fd)
        finally:
            os.close(fd)


def write_file_set(folder: str | Path, files: Mapping[str, bytes]) -> None:
    """Replace several files of ``folder`` as a whole.

    1. every file is written to a temporary beside its target and flushed to disk (a
       full disk fails here, and the old files all stay as they were);
    2. a journal naming the temporaries is written atomically: the commit point;
    3. the temporaries are renamed over their targets, then the journal is removed.

    A process killed during step 3 leaves the journal: :func:`recover_file_set`
    (called by the next run on the folder, under its lock) completes the renames, so
    the files are always all old or, after recovery, all new.

    Args:
        folder: the folder; ``files`` maps paths relative to it to their contents.

    Raises:
        WriteError: a file could not be staged; nothing was replaced.
    """
    folder = Path(folder)
    staged: dict[str, str] = {}
    try:
        for name, data in files.items():
            target = folder / name
            try:
                tmp = _write_temporary(target, data, fsync=True)
            except OSError as exc:
                raise write_error(target, exc) from None
            staged[name] = os.path.relpath(tmp, folder)
        journal = {"schema": _JOURNAL_SCHEMA, "files": staged}
        atomic_write_text(folder / _JOURNAL, json.dumps(journal, indent=1) + "\n")
    except BaseException:
        for tmp_name in staged.values():
            (folder / tmp_name).unlink(missing_ok=True)
        raise
    recover_file_set(folder)


def recover_file_set(folder: str | Path) -> int:
    """Finish the renames of a :func:`write_file_set` cut short; return how many were done.

    Call it before deleting stale temporaries (the journal's temporaries are not stale).
    """
    folder = Path(folder)
    journal_path = folder / _JOURNAL
    if not journal_path.is_file():
        return 0
    try:
        journal = json.loads(journal_path.read_text(encoding="utf-8"))
        files = journal["files"] if journal.get("schema") == _JOURNAL_SCHEMA else None
    except (OSError, ValueError, KeyError, TypeError, AttributeError):
        files = None
    done = 0
    if isinstance(files, dict):
        for name, tmp_name in files.items():
            tmp = folder / str(tmp_name)
            target = folder / str(name)
            # Both inside the folder: a journal is srfm's own, but never trust a path.
            if not (_inside(tmp, folder) and _inside(target, folder)):
                continue
            if tmp.is_file():
                try:
                    os.replace(tmp, target)
                except OSError as exc:
                    raise write_error(target, exc) from None
                done += 1
    _fsync_folder(folder)
    journal_path.unlink(missing_ok=True)
    return done


def _inside(path: Path, folder: Path) -> bool:
    try:
        path.resolve().relative_to(folder.resolve())
    except ValueError:
        return False
    return True


def remove_stale_temporaries(folder: str | Path) -> int:
    """Delete the temporary files (``.<name>.<random>.tmp``) left anywhere under
    ``folder`` by a killed run; return how many. Call it only while holding the
    folder's lock, after :func:`recover_file_set`."""
    folder = Path(folder)
    count = 0
    if folder.is_dir():
        for tmp in folder.rglob(f".*{_TEMP_SUFFIX}"):
            if tmp.is_file():
                tmp.unlink(missing_ok=True)
                count += 1
    return count


# --------------------------------------------------------------------------------------
# Checks before the work


def same_file(a: str | Path, b: str | Path) -> bool:
    """Whether two paths name the same file, however spelled (links, ``..``, case)."""
    try:
        return os.path.samefile(a, b)
    except OSError:
        return Path(a).resolve() == Path(b).resolve()


def refuse_overwriting_inputs(
    output: str | Path, inputs: Iterable[str | Path], *, option: str = "the output"
) -> None:
    """Raise :class:`OutputError` if ``output`` is one of ``inputs``."""
    for source in inputs:
        if same_file(output, source):
            raise OutputError(
                f"{option} {output} is the input {source}: srfm never writes over its "
                "input; choose another output"
            )


def check_writable(path: str | Path, *, folder: bool = False) -> None:
    """Check, before any work, that ``path`` (a file, or a folder when ``folder``) can be
    created or replaced: no file stands where a folder is needed, and a file can be
    created in the nearest existing folder (probed with a temporary file, so read-only
    file systems, permissions and quotas are all seen). Nothing is left behind.

    Raises:
        OutputError: a file where a folder is needed, or a folder where a file is.
        WriteError: the nearest existing folder refuses a new file.
    """
    path = Path(path)
    if path.exists():
        if folder and not path.is_dir():
            raise OutputError(f"{path} exists and is not a folder")
        if not folder and path.is_dir():
            raise OutputError(f"{path} is a folder; give a file name")
    start = path if folder else path.parent
    existing = Path(os.path.abspath(start))
    while not existing.exists() and existing != existing.parent:
        existing = existing.parent
    if not existing.is_dir():
        raise OutputError(f"cannot write {path}: {existing} is a file, not a folder")
    try:
        fd, tmp = tempfile.mkstemp(prefix=".srfm-probe.", suffix=_TEMP_SUFFIX, dir=existing)
        os.close(fd)
        os.unlink(tmp)
    except OSError as exc:
        raise write_error(path, exc) from None


def _marker_kind(folder: Path) -> str | None:
    try:
        doc = json.loads((folder / OUTPUT_MARKER).read_text(encoding="utf-8"))
        return str(doc["kind"])
    except (OSError, ValueError, KeyError, TypeError):
        return None


def claim_output_folder(
    folder: str | Path,
    *,
    kind: str,
    force: bool = False,
    accept: Iterable[str] = (),
    legacy_markers: Iterable[str] = (),
    mark: bool = True,
) -> Path:
    """Make ``folder`` srfm's output folder for ``kind`` (e.g. ``"benchmark"``), or refuse.

    Accepted: a new folder (created), an empty one, one whose marker file says srfm
    made it for ``kind`` or one of ``accept``, or one holding one of ``legacy_markers``
    (e.g. a benchmark's ``manifest.json`` from before the marker existed). A non-empty
    folder srfm did not create is refused unless ``force``: its files may be the
    user's own and would be overwritten. A folder made by another srfm command is
    refused too (its reports would be mixed), unless ``force``.

    ``mark=False`` leaves no marker (``srfm simulate --out``, whose folder holds only
    ``logs/``, recognised through ``legacy_markers``).

    Returns:
        The folder, created, with its marker.

    Raises:
        OutputError: refused (the message says why and how to proceed).
        WriteError: the folder or its marker cannot be written.
    """
    folder = Path(folder)
    check_writable(folder, folder=True)
    if folder.is_dir():
        owner = _marker_kind(folder) if (folder / OUTPUT_MARKER).exists() else None
        legacy = any((folder / name).exists() for name in legacy_markers)
        if owner is not None:
            if owner != kind and owner not in set(accept) and not force:
                raise OutputError(
                    f"{folder} holds the output of `srfm {owner}`; give another folder "
                    f"for `srfm {kind}` (or --force to write into it anyway)"
                )
            return folder
        if not legacy and not force:
            entries = sorted(
                p.name for p in folder.iterdir() if p.name not in (LOCK_FILE, OUTPUT_MARKER)
            )
            if entries:
                shown = ", ".join(entries[:3]) + (", ..." if len(entries) > 3 else "")
                raise OutputError(
                    f"{folder} is a non-empty folder that srfm did not create ({shown}); "
                    "srfm does not write its files among yours: give a new or empty "
                    "folder, or --force to write into it anyway"
                )
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise write_error(folder, exc) from None
    if mark:
        marker = {"schema": "srfm.output_folder/1", "kind": kind}
        atomic_write_text(folder / OUTPUT_MARKER, json.dumps(marker) + "\n")
    return folder


@contextlib.contextmanager
def folder_lock(folder: str | Path) -> Iterator[None]:
    """Hold the lock of ``folder`` (a lock file in it) for the duration of the block.

    The lock is an advisory OS file lock (``filelock``: ``flock`` on POSIX), so it is
    released by the kernel when its holder dies, however it dies; forked workers share
    it with their parent. A second srfm process on the same folder gets
    :class:`FolderInUseError` at once instead of touching the first one's files.

    Raises:
        FolderInUseError: another process holds the lock.
        WriteError: the lock file cannot be created.
    """
    from filelock import FileLock, Timeout

    folder = Path(folder)
    path = folder / LOCK_FILE
    lock = FileLock(path, timeout=0)
    try:
        lock.acquire()
    except Timeout:
        raise FolderInUseError(
            f"{folder} is in use by another srfm run (it holds {path}); wait for that run "
            "to finish, or give another folder"
        ) from None
    except OSError as exc:
        raise write_error(path, exc) from None
    try:
        yield
    finally:
        lock.release()
