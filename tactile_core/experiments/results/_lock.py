"""The participant lock: one program at a time writes a participant's results.

The lock is the operating system's: ``fcntl.flock`` on ``participant-<id>/.lock``, held on an
open descriptor for the whole run. The kernel decides every race (exactly one descriptor holds
an exclusive lock on a file) and releases the lock when its holder exits, however it exits (a
crash, ``kill -9``, a power cut), so there is no stale lock to judge and take over. The file's
text (host, process id, start time) only names the holder in the message a second writer gets.

Why the checks around it:

- The holder removes the file when it releases the lock, while still holding it. A process that
  opened the file just before that removal may then win the lock on a file nobody else can
  open any more; so, once locked, a writer checks that ``.lock`` in the folder is still the very
  file it locked (same device and inode) and otherwise starts again. Only the holder of the lock
  on the file at that path ever removes it, so the check cannot be overtaken.
- ``.lock`` is opened without following a symbolic link, without blocking and without becoming
  a controlling terminal, and must be a regular file: a FIFO, a folder or a device in its place
  is refused, naming it, before anything blocks.
- The holder's record is read with a bound (:data:`MAX_RECORD_BYTES`) and only shown, never
  acted upon (a process id of 2**40 is just text).
"""

from __future__ import annotations

import datetime as dt
import errno
import json
import os
import socket
import stat
from pathlib import Path

from ._session import SessionError

try:
    import fcntl
except ImportError:  # pragma: no cover - Windows: msvcrt's byte-range lock instead
    fcntl = None
    import msvcrt

LOCK_FILE = ".lock"
MAX_RECORD_BYTES = 4096
"""Most bytes of a lock file read to name its holder."""
_ATTEMPTS = 100
"""Times a writer starts again after finding that the file it locked was released and removed
(each time another writer made progress)."""

_OPEN_FLAGS = (
    os.O_RDWR | os.O_CREAT | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_NONBLOCK", 0)
    | getattr(os, "O_NOCTTY", 0) | getattr(os, "O_CLOEXEC", 0)
)  # fmt: skip


def _process_start(pid: int) -> str | None:
    """A token that tells one process from a later one with the same PID (Linux: its start
    time in clock ticks since boot), or None where it cannot be read."""
    try:
        with open(f"/proc/{int(pid)}/stat", encoding="ascii") as f:
            return f.read(MAX_RECORD_BYTES).rsplit(")", 1)[1].split()[19]
    except (OSError, IndexError, ValueError, OverflowError):
        return None


def _alive(pid) -> bool:
    """True if a process ``pid`` runs (or cannot be checked); False for any pid that is not a
    positive process id of this system."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    except (OverflowError, ValueError, TypeError, OSError):
        return False
    return True


def _try_lock(fd: int) -> bool:
    """Take the exclusive lock on ``fd`` without waiting; False if another holds it."""
    try:
        if fcntl is not None:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        else:  # pragma: no cover
            os.lseek(fd, 0, os.SEEK_SET)
            msvcrt.locking(fd, msvcrt.LK_NBLCK, 1)
    except OSError as exc:
        if exc.errno in (errno.EWOULDBLOCK, errno.EAGAIN, errno.EACCES, errno.EDEADLK):
            return False
        raise
    return True


class ParticipantLock:
    """An exclusive lock on a participant's folder while a runner writes to it.

    ``participant-<id>/.lock`` is locked with the operating system's file lock for as long as
    this object holds it; it names the host, the process id and its start time for the message
    a second writer gets. A second writer, in this process or another, is refused naming the
    holder. A lock left behind by a process that ended (killed, crashed) holds nothing: the
    kernel released it when the process ended, and the next writer simply takes it.

    Parameters
    ----------
    folder : path
        The participant's folder (it must exist).

    Raises
    ------
    SessionError
        When another program holds the lock, or ``.lock`` is not a regular file (a symbolic
        link, FIFO, folder or device), or the folder's file system has no file locks.
    """

    def __init__(self, folder):
        self.path = Path(folder) / LOCK_FILE
        self.held = False
        self._fd: int | None = None
        self.acquire()

    def _record(self) -> bytes:
        pid = os.getpid()
        return json.dumps({
            "host": socket.gethostname(),
            "pid": pid,
            "process_start": _process_start(pid),
            "since": dt.datetime.now().isoformat(timespec="seconds"),
        }).encode("utf-8")  # fmt: skip

    def acquire(self) -> None:
        """Take the lock (idempotent); see the class for what is refused."""
        if self.held:
            return
        for _ in range(_ATTEMPTS):
            fd = self._open()
            try:
                locked = self._lock(fd)
                if not locked:
                    raise SessionError(self._refusal(fd))
                if self._same_file(fd):
                    self._write_record(fd)
                    self._fd, fd = fd, None
                    self.held = True
                    return
            finally:
                if fd is not None:
                    os.close(fd)  # also lets go of a lock on a file released meanwhile
        raise SessionError(f"{self.path}: could not take the participant's lock: other "
                           "programs keep taking and releasing it")  # fmt: skip

    def _open(self) -> int:
        try:
            fd = os.open(self.path, _OPEN_FLAGS, 0o644)
        except OSError as exc:
            if exc.errno in (errno.ELOOP, errno.EISDIR, errno.ENXIO, errno.EMLINK):
                raise SessionError(self._not_regular()) from None
            raise SessionError(f"{self.path}: cannot open the participant's lock: "
                               f"{exc.strerror or exc}") from None  # fmt: skip
        try:
            if not stat.S_ISREG(os.fstat(fd).st_mode):
                raise SessionError(self._not_regular())
        except BaseException:
            os.close(fd)
            raise
        return fd

    def _not_regular(self) -> str:
        return (f"{self.path}: not a regular file (a symbolic link, folder, FIFO or device is "
                "in its place); the participant's folder holds only the runner's own files: "
                "move it away and start again")  # fmt: skip

    def _lock(self, fd: int) -> bool:
        try:
            return _try_lock(fd)
        except OSError as exc:
            raise SessionError(
                f"{self.path}: the file system of {self.path.parent} has no file locks "
                f"({exc.strerror or exc}); record to a local folder"
            ) from None

    def _same_file(self, fd: int) -> bool:
        """True if ``.lock`` in the folder is still the file locked on ``fd``."""
        try:
            now = os.stat(self.path, follow_symlinks=False)
        except FileNotFoundError:
            return False
        mine = os.fstat(fd)
        return (now.st_dev, now.st_ino) == (mine.st_dev, mine.st_ino)

    def _write_record(self, fd: int) -> None:
        try:
            os.ftruncate(fd, 0)
            os.pwrite(fd, self._record(), 0)
        except OSError:
            pass  # the record only names the holder; the lock holds without it

    def _refusal(self, fd: int) -> str:
        try:
            data = os.pread(fd, MAX_RECORD_BYTES, 0)
            holder = json.loads(data.decode("utf-8"))
        except (OSError, ValueError, RecursionError):
            holder = None
        who = "another program"
        if isinstance(holder, dict):
            pid, host, since = (str(holder.get(k, "?"))[:64] for k in ("pid", "host", "since"))
            who = f"PID {pid} on {host} since {since}"
        return (
            f"{self.path.parent}: this participant is being recorded by {who}; a second "
            "copy may not write to it. Close that program first (its lock ends with it)"
        )

    def release(self) -> None:
        """Remove the lock file and let go of the lock if this object holds it (idempotent)."""
        if not self.held:
            return
        self.held = False
        fd, self._fd = self._fd, None
        try:
            if self._same_file(fd):
                self.path.unlink(missing_ok=True)  # while still holding it: see the notes
        except OSError:
            pass  # left in place, it holds nothing once closed
        finally:
            os.close(fd)
