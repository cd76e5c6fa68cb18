"""Opening and reading the files of a participant's folder: only regular files inside it, every
read bounded, rows streamed.

A participant's folder holds only what the runners write. Anything else in the place of one of
their files (a symbolic link, even to a regular file; a FIFO; a folder; a device) is refused,
naming the file, before anything blocks, fills memory or writes through a link: files are opened
without following a symbolic link (``O_NOFOLLOW``), without waiting (``O_NONBLOCK``) and without
becoming a controlling terminal, and must then be regular files.

Reads are bounded: a results file may hold at most :data:`MAX_RESULTS_BYTES`, a row at most
:data:`MAX_ROW_BYTES`, and rows are read one at a time, so memory stays small whatever the file
holds.
"""

from __future__ import annotations

import csv
import errno
import os
import stat
from pathlib import Path

from ._session import SessionError

MAX_RESULTS_BYTES = 32 << 20
"""Largest results CSV read (32 MiB). The longest run a runner records, the correction tuning at
its largest plan (200 trials at each of 255 tactors), writes under 10 MB; Experiments 1-3 write
a few kilobytes to a few tens of kilobytes."""
MAX_ROW_BYTES = 8 << 10
"""Longest row read (8 KiB); a runner's rows are a few hundred bytes."""
_CHUNK = 64 << 10

_NOFOLLOW = getattr(os, "O_NOFOLLOW", 0)
_QUIET = (
    _NOFOLLOW
    | getattr(os, "O_NONBLOCK", 0)
    | getattr(os, "O_NOCTTY", 0)
    | getattr(os, "O_CLOEXEC", 0)
)


def not_regular(path) -> str:
    """The message for a file of a participant's folder that is not a regular file in it."""
    return (f"{path}: not a regular file in the participant's folder (a symbolic link, folder, "
            "FIFO or device is in its place); the folder holds only the runner's own files: "
            "move it away and start again")  # fmt: skip


def open_member(path, flags: int = os.O_RDONLY, error=SessionError) -> int:
    """Open a file of a participant's folder, refusing anything but a regular file in it.

    Parameters
    ----------
    path : path
    flags : int
        ``os.O_RDONLY``, or writing flags (``os.O_RDWR | os.O_CREAT | os.O_APPEND``, ...); the
        file is never opened through a symbolic link and never blocks.
    error : type of Exception
        Raised naming the file and why.

    Returns
    -------
    int
        An open descriptor of a regular file (the caller closes it).
    """
    try:
        fd = os.open(path, flags | _QUIET, 0o644)
    except FileNotFoundError:
        raise error(f"{path}: no such file") from None
    except OSError as exc:
        if exc.errno in (errno.ELOOP, errno.EISDIR, errno.ENXIO, errno.EMLINK):
            raise error(not_regular(path)) from None
        raise error(f"{path}: cannot open: {exc.strerror or exc}") from None
    try:
        if not stat.S_ISREG(os.fstat(fd).st_mode):
            raise error(not_regular(path))
    except BaseException:
        os.close(fd)
        raise
    return fd


def checked_size(fd: int, path, error=SessionError) -> int:
    """The size of the open file ``fd``; ``error`` if it is past :data:`MAX_RESULTS_BYTES`."""
    size = os.fstat(fd).st_size
    if size > MAX_RESULTS_BYTES:
        raise error(
            f"{path}: {size:,} bytes, more than the {MAX_RESULTS_BYTES >> 20} MiB a results file "
            "may hold (the longest run writes under 10 MB): not a results file of this software, "
            "or rows were added to it; move it away"
        )
    return size


def last_newline(fd: int, size: int) -> int:
    """Offset of the last line end in the first ``size`` bytes of ``fd``; -1 if there is none."""
    end = size
    while end > 0:
        start = max(0, end - _CHUNK)
        block = os.pread(fd, end - start, start)
        at = block.rfind(b"\n")
        if at >= 0:
            return start + at
        end = start
    return -1


def lines(fd: int, start: int, end: int):
    """The lines of ``fd`` from offset ``start`` up to offset ``end``, one at a time.

    Yields
    ------
    offset : int
        Where the line starts.
    line : bytes or None
        The line, with its line end if it has one; None for a line longer than
        :data:`MAX_ROW_BYTES` (skipped, never held in memory whole).
    """
    with open(fd, "rb", closefd=False) as f:
        f.seek(start)
        offset = start
        while offset < end:
            line = f.readline(min(MAX_ROW_BYTES + 1, end - offset))
            if not line:
                return  # the file shrank under us
            length = len(line)
            if length > MAX_ROW_BYTES or (not line.endswith(b"\n") and offset + length < end):
                while not line.endswith(b"\n") and offset + length < end:
                    line = f.readline(min(1 << 16, end - offset - length))
                    if not line:
                        break
                    length += len(line)
                yield offset, None
            else:
                yield offset, line
            offset += length


def parse_line(line: bytes | None) -> list[str]:
    """The fields of one CSV line; ``ValueError`` if it is too long (None, from :func:`lines`),
    not UTF-8 or not one CSV row."""
    if line is None:
        raise ValueError(f"a row longer than {MAX_ROW_BYTES} bytes")
    try:
        text = line.decode("utf-8")
    except UnicodeDecodeError:
        raise ValueError("not UTF-8 text") from None
    try:
        rows = list(csv.reader([text.rstrip("\n")]))
    except csv.Error as exc:
        raise ValueError(f"not a CSV row: {exc}") from None
    if len(rows) != 1:
        raise ValueError("not one CSV row")
    return rows[0]


def scan_rows(path, error=SessionError):
    """Stream the rows of a results CSV as the analysis reads them.

    Parameters
    ----------
    path : path
        The CSV; a regular file inside its folder of at most :data:`MAX_RESULTS_BYTES`.
    error : type of Exception
        Raised when the file cannot be read at all.

    Yields
    ------
    line : int
        The line number (the header is line 1).
    row : dict or None
        ``{column: value}``, or None for a line that cannot be read.
    problem : str
        Why the line cannot be read (empty for a row): not UTF-8, not one CSV row, the wrong
        number of fields, or a torn last line (no line end).
    """
    path = Path(path)
    fd = open_member(path, os.O_RDONLY, error)
    try:
        size = checked_size(fd, path, error)
        end = last_newline(fd, size) + 1
        first = os.pread(fd, min(end, MAX_ROW_BYTES), 0)
        nl = first.find(b"\n")
        if nl < 0:
            if size:
                raise error(f"{path}:1: no header line")
            return
        try:
            fields = parse_line(first[: nl + 1])
        except ValueError as exc:
            raise error(f"{path}:1: {exc}") from None
        number = 1
        for number, (_, line) in enumerate(lines(fd, nl + 1, end), start=2):
            try:
                values = parse_line(line)
                if len(values) != len(fields):
                    raise ValueError(f"{len(values)} fields, the header has {len(fields)}")
            except ValueError as exc:
                yield number, None, str(exc)
                continue
            yield number, dict(zip(fields, values)), ""
        if end < size:
            yield number + 1, None, "torn last row (no line end)"
    finally:
        os.close(fd)
