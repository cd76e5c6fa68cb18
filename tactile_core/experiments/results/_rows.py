"""Results CSV files: one row per trial, each durable before the runner moves on."""

from __future__ import annotations

import csv
import datetime as dt
import io
import os
import re
from pathlib import Path

from ._files import (
    MAX_ROW_BYTES,
    checked_size,
    last_newline,
    lines,
    open_member,
    parse_line,
    scan_rows,
)
from ._session import SessionError, _short


class ResultsFile:
    """One experiment's CSV: one row per trial, each durable before the runner moves on.

    The file is opened once (:meth:`open`), as a regular file inside the participant's folder
    (never through a symbolic link, never a FIFO, folder or device), and every read, cut and
    append goes through that descriptor. It may hold at most :data:`MAX_RESULTS_BYTES`.

    Reading it back (:meth:`rows`) streams the rows one at a time. What a crash or a full disk
    can leave is repaired, never lost: a last row without its line end, or that is not one row
    of the header's fields, is moved to ``<file>.torn`` (appended, never deleted) and the file
    is cut back to its last complete row, so that trial is presented again. Junk after a torn
    row (lines that are not rows, as a file system can leave after a crash) goes with it; a
    header cut short, whatever follows it, is moved aside in the same way (no row is written
    before the header is complete). A malformed row with rows after it is refused with
    ``file:row: problem``. :attr:`recovered`
    says what was moved aside.

    :meth:`append` writes a row, flushes and syncs it; if that fails (a full disk) the file is
    cut back to where it was, so no half row is left behind, and the error is raised.

    Parameters
    ----------
    path : path
    fields : sequence of str
        Column names.
    """

    def __init__(self, path, fields):
        self.path = Path(path)
        self.fields = list(fields)
        self.header = _csv_line(self.fields)
        self.recovered = ""
        self._fd = None

    @property
    def torn_path(self) -> Path:
        """Where torn rows are kept."""
        return self.path.with_name(self.path.name + ".torn")

    def open(self) -> int:
        """Open (or create) the file for reading and appending; its descriptor.

        Raises
        ------
        SessionError
            If something other than a regular file is in its place.
        """
        if self._fd is None:
            self._fd = open_member(self.path, os.O_RDWR | os.O_CREAT | os.O_APPEND)
        return self._fd

    def load(self) -> list[dict]:
        """The complete rows (creating the file with its header if it is new or empty); see
        :meth:`rows`."""
        return [row for _, row in self.rows()]

    def rows(self):
        """Stream the complete rows, after moving aside what a crash left torn.

        Yields
        ------
        line : int
            The row's line number (the header is line 1).
        row : dict
            ``{column: value}``, values as strings.

        Raises
        ------
        SessionError
            Naming the file, the row (line number) and the problem.
        """
        fd = self.open()
        size = checked_size(fd, self.path)
        header = self.header.encode("utf-8")
        end = last_newline(fd, size) + 1
        head = os.pread(fd, min(size, MAX_ROW_BYTES), 0)
        if not head.startswith(header):
            self._torn_header(head, size, end, header)
            return
        for line, (offset, data) in enumerate(lines(fd, len(header), end), start=2):
            try:
                values = self._values(data)
            except ValueError as exc:
                if not self._rows_after(offset, end):  # a torn row, and junk after it: set aside
                    self._set_aside(offset, size, f"row {line} ({exc}) and what follows it")
                    self._cut(offset)
                    return
                raise SessionError(f"{self.path}:{line}: {exc}") from None
            yield line, dict(zip(self.fields, values))
        if end < size:  # a last row without its line end: torn (moved once all rows are read)
            self._set_aside(end, size, "a torn last row")
            self._cut(end)

    def _values(self, data) -> list[str]:
        values = parse_line(data)
        if len(values) != len(self.fields):
            raise ValueError(f"{len(values)} fields, the header has {len(self.fields)}")
        return values

    def _rows_after(self, offset: int, end: int) -> bool:
        """True if a line after the one at ``offset`` (up to ``end``) is a row of the header's
        fields: then the line at ``offset`` is not a torn last row but a broken one."""
        for at, data in lines(self._fd, offset, end):
            if at == offset:
                continue
            try:
                self._values(data)
            except ValueError:
                continue
            return True
        return False

    def _torn_header(self, head: bytes, size: int, end: int, header: bytes) -> None:
        """A file that does not start with the header: a header cut short (moved aside with
        whatever follows it, and written again) or another file (refused)."""
        first = head.split(b"\n", 1)[0]
        line = header.rstrip(b"\n")
        common = next((i for i, (a, b) in enumerate(zip(first, line)) if a != b),
                      min(len(first), len(line)))  # fmt: skip
        if size == 0:
            torn = False
        elif end == 0:  # no line end anywhere: the header line was never completed
            torn = line.startswith(first) or common > 0
        elif first == line[:common]:  # the header cut short, then a line end
            torn = common > 0 and line[common : common + 1] != b","  # cut inside a name
        else:  # the header cut short, then something else on its line
            torn = common > 0 and not _COLUMNS.fullmatch(first)
        if size and not torn:
            shown = first[:200].decode("utf-8", "replace")
            raise SessionError(
                f"{self.path}:1: columns {_short(shown)} differ from this software's "
                f"{','.join(self.fields)}"
            )
        if size:
            self._set_aside(0, size, "a header cut short")
        self._cut(0)
        self._write(header)

    def _set_aside(self, start: int, end: int, what: str) -> None:
        """Append bytes ``start:end`` of the file to ``.torn`` (synced), ending with a line end."""
        fd = open_member(self.torn_path, os.O_WRONLY | os.O_CREAT | os.O_APPEND)
        try:
            offset, last = start, b"\n"
            while offset < end:
                block = os.pread(self._fd, min(1 << 16, end - offset), offset)
                if not block:
                    break
                _write_all(fd, block)
                offset += len(block)
                last = block[-1:]
            if last != b"\n":
                _write_all(fd, b"\n")
            os.fsync(fd)
        finally:
            os.close(fd)
        note = f"{self.path.name}: {what} ({end - start} bytes) moved to {self.torn_path.name}"
        self.recovered = f"{self.recovered}; {note}" if self.recovered else note

    def _cut(self, size: int) -> None:
        os.ftruncate(self._fd, size)
        os.fsync(self._fd)

    def _write(self, data: bytes) -> None:
        _write_all(self._fd, data)
        os.fsync(self._fd)

    def append(self, row: dict) -> None:
        """Append ``row`` durably; on failure leave the file as it was and raise ``OSError``."""
        data = _csv_line([str(row.get(k, "")) for k in self.fields]).encode("utf-8")
        fd = self.open()
        size = os.fstat(fd).st_size
        try:
            _write_all(fd, data)
            os.fsync(fd)
        except OSError:
            try:
                os.ftruncate(fd, size)
                os.fsync(fd)
            except OSError:
                pass  # the next load() finds the torn row and moves it aside
            raise

    def close(self) -> None:
        """Close the file (idempotent)."""
        if self._fd is not None:
            os.close(self._fd)
            self._fd = None


_COLUMNS = re.compile(rb"[A-Za-z_][A-Za-z0-9_]*(,[A-Za-z_][A-Za-z0-9_]*)*")
"""A header line: column names separated by commas."""


def _write_all(fd: int, data: bytes) -> None:
    view = memoryview(data)
    while view:
        view = view[os.write(fd, view) :]


def _csv_line(values) -> str:
    out = io.StringIO()
    csv.writer(out, lineterminator="\n").writerow(values)
    return out.getvalue()


def read_rows(path) -> list[dict]:
    """Rows of a results CSV as dictionaries.

    Lines are read as the runner writes them: a last line without its line end (a torn row),
    and a line that is not one row of the header's fields, are left out. The file is read as
    :func:`scan_rows` reads it (a regular file inside its folder, bounded, streamed).

    Parameters
    ----------
    path : path

    Returns
    -------
    list of dict
        ``{column: value}`` per row, values as strings; empty if the file does not exist.

    Raises
    ------
    SessionError
        If the file is not a regular file in its folder, or too large.
    """
    path = Path(path)
    if not os.path.lexists(path):
        return []
    return [row for _, row, problem in scan_rows(path) if row is not None]


def now() -> str:
    """Timestamp for a results row: local time, ISO 8601 to the millisecond.

    Returns
    -------
    str
        E.g. ``"2025-03-01T14:02:03.456"``.
    """
    return dt.datetime.now().isoformat(timespec="milliseconds")
