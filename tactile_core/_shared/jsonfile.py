"""Reading and writing the project's JSON files (device profiles, presets, sessions).

Reads are bounded: only a regular file is read (a FIFO, a device such as ``/dev/zero`` or a
folder is refused before anything blocks or fills memory), and at most :data:`MAX_JSON_BYTES`.
JSON's non-standard ``NaN`` and ``Infinity`` and integers of thousands of digits are refused
like any other malformed text. Writes are atomic.
"""

from __future__ import annotations

import hashlib
import json
import os
import stat
from pathlib import Path

from .outfile import atomic_file

MAX_JSON_BYTES = 1 << 20
"""Largest JSON file read (1 MiB): a profile, preset or session is a few kilobytes."""


def read_bytes(path, error=ValueError, *, max_bytes: int = MAX_JSON_BYTES) -> bytes:
    """The bytes of a regular file of at most ``max_bytes``; ``error`` names the path and why
    not."""
    path = Path(path)
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_NOCTTY", 0))
    except FileNotFoundError:
        raise error(f"{path}: no such file") from None
    except OSError as exc:
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


def parse_json(data: bytes, source, error=ValueError):
    """Parse JSON bytes; ``error`` names ``source`` and what is wrong."""
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise error(f"{source}: not UTF-8 text: {exc.reason} at byte {exc.start}") from None
    try:
        return json.loads(text, parse_constant=_no_constant)
    except json.JSONDecodeError as exc:
        raise error(f"{source}: not valid JSON: {exc.msg} at line {exc.lineno}") from None
    except RecursionError:
        raise error(f"{source}: not valid JSON: nested too deeply") from None
    except ValueError as exc:  # NaN/Infinity, or an integer of more than 4300 digits
        raise error(f"{source}: not valid JSON: {str(exc)[:120]}") from None


def read_json(path, error=ValueError, *, max_bytes: int = MAX_JSON_BYTES):
    """Parse a JSON file; any problem raises ``error`` with the path and what is wrong.

    Parameters
    ----------
    path : path
    error : type of Exception
        Raised for a missing, unreadable, oversized or irregular file, or text that is not JSON.
    max_bytes : int
        Size cap.
    """
    return parse_json(read_bytes(path, error, max_bytes=max_bytes), Path(path), error)


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
