"""Sessions and results on disk: one CSV row per trial, flushed as it happens.

A session lives in ``RESULTS_DIR/participant-<id>/``:

- ``session.json``: participant id, creation time, software version, seed, the order of
  conditions for each experiment, the device profile, the experiments' parameters and notes;
  written atomically (:class:`Session`, :func:`open_session`).
- ``exp1.csv``, ``exp2.csv``, ``exp3.csv``, ``calibration.csv``: one row per trial, appended,
  flushed and synced to disk before the next trial starts, so a crash loses at most the trial
  in progress (:class:`ResultsFile`). Starting the same participant again resumes where the
  files end.
- ``.lock``: held while a runner writes to the folder, so that two programs never record the
  same participant at once (:class:`ParticipantLock`).

Only regular files inside the folder are read or written (never through a symbolic link, never
a FIFO, folder or device), and every read is bounded (:data:`MAX_RESULTS_BYTES`,
:data:`MAX_ROW_BYTES`; rows are streamed): :func:`open_member`, :func:`scan_rows`.
"""

from ._files import MAX_RESULTS_BYTES, MAX_ROW_BYTES, open_member, scan_rows
from ._lock import LOCK_FILE, ParticipantLock
from ._rows import ResultsFile, now, read_rows
from ._session import (
    SESSION_FILE,
    Session,
    SessionError,
    check_participant,
    open_session,
    session_from_dict,
)

# isort: split
__all__ = [
    "LOCK_FILE",
    "MAX_RESULTS_BYTES",
    "MAX_ROW_BYTES",
    "SESSION_FILE",
    "ParticipantLock",
    "ResultsFile",
    "Session",
    "SessionError",
    "check_participant",
    "now",
    "open_member",
    "open_session",
    "read_rows",
    "scan_rows",
    "session_from_dict",
]
