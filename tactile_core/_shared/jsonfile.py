"""Reading and writing the project's JSON files (device profiles, presets, sessions).

Reads are bounded: only a regular file is read (a FIFO, a device such as ``/dev/zero`` or a
folder is refused before anything blocks or fills memory), and at most :data:`MAX_JSON_BYTES`,
nested at most :data:`MAX_JSON_DEPTH` deep (a file nested hundreds deep would parse, then break
every function that walks it). JSON's non-standard ``NaN`` and ``Infinity`` and integers of
thousands of digits are refused like any other malformed text. Writes are atomic.
"""

from __future__ import annotations

import errno
import hashlib
import json
import os
import stat
from pathlib import Path

from .outfile import atomic_file

MAX_JSON_BYTES = 1 << 20
"""Largest JSON file read (1 MiB): a profile, preset or session is a few kilobytes."""
MAX_JSON_DEPTH = 20
"""Deepest nesting of arrays and objects read: the deepest file the tool writes (a participant's
``session.json``, with the record of each run) nests about 6 deep."""


def read_bytes(
    path, error=ValueError, *, max_bytes: int = MAX_JSON_BYTES, follow_symlinks: bool = True
) -> bytes:
    """The bytes of a regular file of at most ``max_bytes``; ``error`` names the path and why
    not. With ``follow_symlinks=False`` a symbolic link is refused too (the files of a
    participant's folder)."""
    path = Path(path)
    flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_NOCTTY", 0)
    if not follow_symlinks:
        flags |= getattr(os, "O_NOFOLLOW", 0)
    try:
        fd = os.open(path, flags)
    except FileNotFoundError:
        raise error(f"{path}: no such file") from None
    except OSError as exc:
        if not follow_symlinks and exc.errno in (errno.ELOOP, errno.EMLINK):
            raise error(f"{path}: not a regular file (a symbolic link)") from None
        raise error(f"{path}: cannot read: {exc.strerror or exc}") from None
    try:
        info = os.fstat(fd)
        if not stat.S_ISREG(info.st_mode):
            raise error(f"{path}: not a regular file")
        if info.st_size > max_bytes:
            raise error(f"{path}: {info.st_size} bytes, larger than the {max_bytes} allowed")
        with os.fdopen(fd, "rb", closefd=False) as f:
            data = f.read(max_bytes + 1)
    except OSError as exc:
        raise error(f"{path}: cannot read: {exc.strerror or exc}") from None
    finally:
        os.close(fd)
    if len(data) > max_bytes:
        raise error(f"{path}: larger than the {max_bytes} bytes allowed")
    return data


def _no_constant(name):
    raise ValueError(f"{name} is not a number JSON allows")


def parse_json(data: bytes, source, error=ValueError, *, max_depth: int = MAX_JSON_DEPTH):
    """Parse JSON bytes; ``error`` names ``source`` and what is wrong (including nesting past
    ``max_depth``). A leading UTF-8 byte order mark is skipped (Windows' Notepad and
    bHaptics' Designer write one)."""
    try:
        text = data.removeprefix(b"\xef\xbb\xbf").decode("utf-8")
    except UnicodeDecodeError as exc:
        raise error(f"{source}: not UTF-8 text: {exc.reason} at byte {exc.start}") from None
    try:
        value = json.loads(text, parse_constant=_no_constant)
    except json.JSONDecodeError as exc:
        where = f"line {exc.lineno}, column {exc.colno}"  # ("… starting at" ends some messages)
        at = where if exc.msg.endswith(" at") else f"at {where}"
        raise error(f"{source}: not valid JSON: {exc.msg} {at}") from None
    except RecursionError:
        raise error(f"{source}: nested too deeply (more than {max_depth} levels of arrays and "
                    "objects; no file of this tool nests that deep)") from None  # fmt: skip
    except ValueError as exc:  # NaN/Infinity, or an integer of more than 4300 digits
        raise error(f"{source}: not valid JSON: {str(exc)[:120]}") from None
    if depth(value, max_depth) > max_depth:
        raise error(f"{source}: nested too deeply (more than {max_depth} levels of arrays and "
                    "objects; no file of this tool nests that deep)")  # fmt: skip
    return value


def depth(value, limit: int = MAX_JSON_DEPTH) -> int:
    """How deep arrays and objects nest in a parsed JSON value (0 for a number or string),
    counted without recursion and only up to ``limit + 1``.

    >>> depth({"a": [1, [2]]})
    3
    """
    deepest, stack = 0, [(value, 1)]
    while stack:
        item, level = stack.pop()
        if isinstance(item, (dict, list)):
            deepest = max(deepest, level)
            if level > limit:
                return level
            children = item.values() if isinstance(item, dict) else item
            stack.extend((child, level + 1) for child in children)
    return deepest


def read_json(
    path, error=ValueError, *, max_bytes: int = MAX_JSON_BYTES, follow_symlinks: bool = True
):
    """Parse a JSON file; any problem raises ``error`` with the path and what is wrong.

    Parameters
    ----------
    path : path
    error : type of Exception
        Raised for a missing, unreadable, oversized or irregular file, text that is not JSON,
        or nesting deeper than :data:`MAX_JSON_DEPTH`.
    max_bytes : int
        Size cap.
    follow_symlinks : bool
        False: refuse a symbolic link (the files of a participant's folder).
    """
    data = read_bytes(path, error, max_bytes=max_bytes, follow_symlinks=follow_symlinks)
    return parse_json(data, Path(path), error)


def read_json_digest(path, error=ValueError, *, max_bytes: int = MAX_JSON_BYTES):
    """:func:`read_json` and the SHA-256 (hex) of the file's bytes."""
    data = read_bytes(path, error, max_bytes=max_bytes)
    return parse_json(data, Path(path), error), hashlib.sha256(data).hexdigest()


def write_text_atomic(path, text: str) -> Path:
    """Write ``text`` to ``path`` atomically (see :func:`~.outfile.atomic_file`)."""
    with atomic_file(path) as f:
        f.write(text)
    return Path(path)


def write_json_atomic(path, data) -> Path:
    """Write ``data`` as indented JSON to ``path`` atomically (see :func:`write_text_atomic`)."""
    return write_text_atomic(path, json.dumps(data, indent=2, allow_nan=False) + "\n")
