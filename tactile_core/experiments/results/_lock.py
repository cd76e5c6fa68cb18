"""The participant lock: one program at a time writes a participant's results."""

from __future__ import annotations

import datetime as dt
import json
import os
import secrets
import socket
from pathlib import Path

from ._session import SessionError

LOCK_FILE = ".lock"


def _process_start(pid: int) -> str | None:
    """A token that tells one process from a later one with the same PID (Linux: its start
    time in clock ticks since boot), or None where it cannot be read."""
    try:
        with open(f"/proc/{pid}/stat", encoding="ascii") as f:
            return f.read().rsplit(")", 1)[1].split()[19]
    except (OSError, IndexError):
        return None


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def _write_new(path: Path, data: bytes) -> None:
    """Create ``path`` (``FileExistsError`` if it exists) holding ``data``, synced to disk."""
    fd = os.open(path, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644)
    try:
        view = memoryview(data)
        while view:
            view = view[os.write(fd, view) :]
        os.fsync(fd)
    finally:
        os.close(fd)


class ParticipantLock:
    """An exclusive lock on a participant's folder while a runner writes to it.

    ``participant-<id>/.lock`` is created exclusively and holds the host, the process id and its
    start time. A second writer is refused with a message naming the holder. A lock left by a
    process that no longer runs on this host (killed, crashed) is stale: it is taken over. A lock
    from another host is never taken over (its process cannot be checked from here); the message
    says which file to remove.
    """

    def __init__(self, folder):
        self.path = Path(folder) / LOCK_FILE
        self.held = False
        self.acquire()

    def _record(self) -> dict:
        pid = os.getpid()
        return {
            "host": socket.gethostname(),
            "pid": pid,
            "process_start": _process_start(pid),
            "since": dt.datetime.now().isoformat(timespec="seconds"),
        }

    def acquire(self) -> None:
        data = json.dumps(self._record()).encode("utf-8")
        for _ in range(3):
            if self._publish(data):
                self.held = True
                return
            holder = self._holder()
            if holder is not None and not self._stale(holder):
                raise SessionError(
                    f"{self.path.parent}: this participant is being recorded by PID "
                    f"{holder.get('pid')} on {holder.get('host')} since "
                    f"{holder.get('since')}; a second copy may not write to it. If that "
                    f"program is gone, remove {self.path}"
                ) from None
            self.path.unlink(missing_ok=True)  # stale or unreadable: take it over
        raise SessionError(f"{self.path}: could not take the participant's lock")

    def _publish(self, data: bytes) -> bool:
        """Create the lock holding ``data``, whole or not at all; False if a lock is there.

        The record is written to a temporary file and hard-linked into place, so that no other
        process ever reads a lock still being written: it would take the empty file for one left
        half-written by a crash, and take it over while its owner writes. Where the file system
        has no hard links (FAT, some network shares) the lock is created in place.
        """
        tmp = self.path.with_name(f"{LOCK_FILE}-{os.getpid()}-{secrets.token_hex(4)}.tmp")
        try:
            _write_new(tmp, data)
            try:
                os.link(tmp, self.path)
            except FileExistsError:
                return False
            except OSError:
                pass  # no hard links here
            else:
                return True
        finally:
            tmp.unlink(missing_ok=True)
        try:
            _write_new(self.path, data)
        except FileExistsError:
            return False
        return True

    def _holder(self) -> dict | None:
        try:
            data = json.loads(self.path.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            return None  # half-written (by a version that wrote it in place, or where there
            # are no hard links) by a process killed while creating it: stale
        return data if isinstance(data, dict) else None

    def _stale(self, holder: dict) -> bool:
        if holder.get("host") != socket.gethostname():
            return False
        pid = holder.get("pid")
        if not isinstance(pid, int) or isinstance(pid, bool) or pid <= 0:
            return True
        if not _alive(pid):
            return True
        started = holder.get("process_start")
        return started is not None and _process_start(pid) not in (None, started)

    def release(self) -> None:
        """Remove the lock if this runner holds it (idempotent)."""
        if self.held:
            self.held = False
            holder = self._holder()
            if holder is None or holder.get("pid") == os.getpid():
                self.path.unlink(missing_ok=True)
