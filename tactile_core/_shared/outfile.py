"""Files the tool writes: checked before the work starts, written atomically.

:func:`check_output` refuses, up front, a path that could not be written at the end (a missing
folder, a folder in its place, a device, a folder without write permission), so that a long
recording or simulation is never lost to a typo. :func:`atomic_file` writes through a temporary
file in the same folder, synced, then renamed over the target: a crash or a full disk leaves
either the previous file or the new one, never a truncated or empty file in its place.
"""

from __future__ import annotations

import contextlib
import errno
import os
import secrets
import stat
import sys
from pathlib import Path


class OutputError(ValueError):
    """An output path that cannot be written; the message names it and says why."""


def check_output(path, suffixes=(), what: str = "output file") -> Path:
    """Check that ``path`` can be written (without writing it); return it as a Path.

    Parameters
    ----------
    path : str or Path
    suffixes : sequence of str
        Allowed extensions (lower case, with the dot); empty: any.
    what : str
        What the file is, for the message ("--record", "export").

    Raises
    ------
    OutputError
    """
    if not isinstance(path, (str, os.PathLike)) or not str(path):
        raise OutputError(f"{what} must be a file path, got {path!r}")
    path = Path(path)
    if suffixes and path.suffix.lower() not in suffixes:
        raise OutputError(f"{what} must end in {' or '.join(suffixes)}, got {str(path)!r}")
    if path.is_dir():
        raise OutputError(f"{what} {str(path)!r} is a folder, not a file")
    if path.exists() and not path.is_file():
        raise OutputError(f"{what} {str(path)!r} exists and is not a regular file")
    folder = path.parent if str(path.parent) else Path(".")
    if not folder.is_dir():
        raise OutputError(f"{what} {str(path)!r}: the folder {str(folder)!r} does not exist")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise OutputError(f"{what} {str(path)!r}: no permission to write in {str(folder)!r}")
    return path


def check_folder(path, what: str = "folder", create: bool = True) -> Path:
    """A folder to write into: created (with its parents) if missing; refused if a file is in
    its place or it cannot be written."""
    if not isinstance(path, (str, os.PathLike)) or not str(path):
        raise OutputError(f"{what} must be a folder path, got {path!r}")
    path = Path(path)
    if path.exists() and not path.is_dir():
        raise OutputError(f"{what} {str(path)!r} is a file, not a folder")
    if not path.exists():
        if not create:
            raise OutputError(f"{what} {str(path)!r} does not exist")
        try:
            path.mkdir(parents=True)
        except OSError as exc:
            raise OutputError(f"{what} {str(path)!r} cannot be created: {exc.strerror}") from None
    if not os.access(path, os.W_OK | os.X_OK):
        raise OutputError(f"{what} {str(path)!r}: no permission to write in it")
    return path


def _stem_for_temporary(name: str) -> str:
    """``name`` cut so that ``.NAME.<12 hex>.tmp`` stays within 255 bytes (a file system's
    longest name): a valid name of 238-255 bytes could not be written through a temporary
    file named after it whole."""
    room = 255 - len(".") - len(".") - 12 - len(".tmp")
    encoded = os.fsencode(name)
    if len(encoded) <= room:
        return name
    return encoded[:room].decode(sys.getfilesystemencoding(), errors="ignore") or "out"


@contextlib.contextmanager
def atomic_file(path, *, binary: bool = False):
    """Open a temporary file beside ``path`` for writing; on success sync it and rename it over
    ``path``. On any error the temporary file is removed and ``path`` is left as it was. A
    ``path`` that exists and is not a regular file (``/dev/null``, a FIFO, a folder) is refused
    with an ``OSError`` (``EINVAL``) before anything is written: the rename would replace it.

    The file gets the permissions a plain ``open(path, "w")`` would give it: those of the file
    it replaces, or for a new file ``0666`` less the umask (``0644`` under the usual ``022``),
    never the ``0600`` of a private temporary file.
    """
    path = Path(path)
    try:
        there = os.stat(path)
    except OSError:
        there = None
    if there is not None and not stat.S_ISREG(there.st_mode):  # the rename would replace it
        raise OSError(errno.EINVAL, "not a regular file (a folder, device or FIFO), which "
                      "writing would replace", str(path))  # fmt: skip
    folder = path.parent if str(path.parent) else Path(".")
    flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_CLOEXEC", 0)
    tmp = None  # the name being created or made: removed on any way out, a signal's included
    try:
        for _ in range(100):
            tmp = folder / f".{_stem_for_temporary(path.name)}.{secrets.token_hex(6)}.tmp"
            try:  # (a signal handled as os.open returns finds tmp set: it is removed below)
                fd = os.open(tmp, flags | getattr(os, "O_NOFOLLOW", 0), 0o666)  # umask applies
                break
            except FileExistsError:
                tmp = None  # another's file: never removed
                continue
        else:  # pragma: no cover - 100 random names taken
            raise FileExistsError(f"{folder}: no free temporary name for {path.name}")
        try:
            old = os.stat(path)
        except OSError:
            old = None
        if old is not None and stat.S_ISREG(old.st_mode) and hasattr(os, "fchmod"):
            os.fchmod(fd, stat.S_IMODE(old.st_mode))  # keep the replaced file's permissions
        mode = "wb" if binary else "w"
        kwargs = {} if binary else {"encoding": "utf-8", "newline": ""}
        with os.fdopen(fd, mode, **kwargs) as f:
            yield f
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        if tmp is not None:
            Path(tmp).unlink(missing_ok=True)
        raise
