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
"""

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
# What ``tactile_core.experiments.results`` held when it was one module stays importable from
# here; not part of the interface.
from ..._shared import validate as _validate  # noqa: F401
from ..._shared.jsonfile import read_json, write_json_atomic  # noqa: F401
from ...rendering.scene import PAPER_PIPELINE, Pipeline  # noqa: F401
from ..stats import order_for, order_for_set  # noqa: F401
from ._lock import _alive, _process_start  # noqa: F401
from ._rows import _csv_line  # noqa: F401
from ._session import _FIELDS, _ID, _KIND_NAMES, _SALT, _short  # noqa: F401

__all__ = [
    "LOCK_FILE",
    "SESSION_FILE",
    "ParticipantLock",
    "ResultsFile",
    "Session",
    "SessionError",
    "check_participant",
    "now",
    "open_session",
    "read_rows",
    "session_from_dict",
]
