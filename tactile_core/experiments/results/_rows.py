"""Results CSV files: one row per trial, each durable before the runner moves on."""

from __future__ import annotations

import csv
import datetime as dt
import io
import os
from pathlib import Path

from ._session import SessionError, _short


class ResultsFile:
    """One experiment's CSV: one row per trial, each durable before the runner moves on.

    Reading it back (:meth:`load`) finds a last row that a crash or a full disk left torn (no
    line end, or not the header's number of fields): those bytes are moved to ``<file>.torn``
    (appended, never deleted) and the file is cut back to its last complete row, so that trial
    is presented again. Any other malformed row is refused with ``file:row: problem``.

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
        self._fd = None

    @property
    def torn_path(self) -> Path:
        """Where torn rows are kept."""
        return self.path.with_name(self.path.name + ".torn")

    def load(self) -> list[dict]:
        """The complete rows (creating the file with its header if it is new or empty).

        Raises
        ------
        SessionError
            Naming the file, the row (line number) and the problem.
        """
        data = self.path.read_bytes() if self.path.exists() else b""
        header = self.header.encode("utf-8")
        if not data.startswith(header):
            if header.startswith(data):  # empty, or a header cut short: no trial recorded
                if data:
                    self._move_aside(data)
                self._rewrite(header)
                return []
            first = data.split(b"\n", 1)[0].decode("utf-8", "replace")
            raise SessionError(
                f"{self.path}:1: columns {_short(first)} differ from this software's "
                f"{','.join(self.fields)}"
            )
        body = data[len(header) :]
        cut = body.rfind(b"\n") + 1
        if cut < len(body):  # a last row without its line end: torn
            self._move_aside(body[cut:])
            self._truncate(len(header) + cut)
            body = body[:cut]
        rows = []
        try:
            text = body.decode("utf-8")
        except UnicodeDecodeError as exc:
            line = body[: exc.start].count(b"\n") + 2
            raise SessionError(f"{self.path}:{line}: not UTF-8 text") from None
        lines = text.split("\n")[:-1] if text else []
        for i, line in enumerate(lines):
            values = next(csv.reader([line]), [])
            if len(values) != len(self.fields):
                if i == len(lines) - 1:  # malformed last row: treated as torn
                    self.drop_last_row(line)
                    break
                raise SessionError(
                    f"{self.path}:{i + 2}: {len(values)} fields, the header has {len(self.fields)}"
                )
            rows.append(dict(zip(self.fields, values)))
        return rows

    def drop_last_row(self, line: str | None = None) -> None:
        """Move the file's last row to ``.torn`` and cut the file before it."""
        data = self.path.read_bytes()
        start = data.rstrip(b"\n").rfind(b"\n") + 1
        self._move_aside(data[start:])
        self._truncate(start)

    def _move_aside(self, data: bytes) -> None:
        with self.torn_path.open("ab") as f:
            f.write(data if data.endswith(b"\n") else data + b"\n")
            f.flush()
            os.fsync(f.fileno())

    def _truncate(self, size: int) -> None:
        with self.path.open("r+b") as f:
            f.truncate(size)
            f.flush()
            os.fsync(f.fileno())

    def _rewrite(self, header: bytes) -> None:
        with self.path.open("wb") as f:
            f.write(header)
            f.flush()
            os.fsync(f.fileno())

    def append(self, row: dict) -> None:
        """Append ``row`` durably; on failure leave the file as it was and raise ``OSError``."""
        data = _csv_line([str(row.get(k, "")) for k in self.fields]).encode("utf-8")
        if self._fd is None:
            self._fd = os.open(self.path, os.O_WRONLY | os.O_APPEND)
        size = os.fstat(self._fd).st_size
        try:
            view = memoryview(data)
            while view:
                view = view[os.write(self._fd, view) :]
            os.fsync(self._fd)
        except OSError:
            try:
                os.ftruncate(self._fd, size)
                os.fsync(self._fd)
            except OSError:
                pass  # the next load() finds the torn row and moves it aside
            raise

    def close(self) -> None:
        """Close the file (idempotent)."""
        if self._fd is not None:
            os.close(self._fd)
            self._fd = None


def _csv_line(values) -> str:
    out = io.StringIO()
    csv.writer(out, lineterminator="\n").writerow(values)
    return out.getvalue()


def read_rows(path) -> list[dict]:
    """Rows of a results CSV as dictionaries.

    Lines are read as the runner writes them: a last line without its line end (a torn row) is
    left out.

    Parameters
    ----------
    path : path

    Returns
    -------
    list of dict
        ``{column: value}`` per row, values as strings; empty if the file does not exist.
    """
    path = Path(path)
    if not path.exists():
        return []
    with path.open(encoding="utf-8", newline="") as f:
        text = f.read()
    if text and not text.endswith("\n"):
        text = text[: text.rfind("\n") + 1]
    return list(csv.DictReader(io.StringIO(text)))


def now() -> str:
    """Timestamp for a results row: local time, ISO 8601 to the millisecond.

    Returns
    -------
    str
        E.g. ``"2025-03-01T14:02:03.456"``.
    """
    return dt.datetime.now().isoformat(timespec="milliseconds")
