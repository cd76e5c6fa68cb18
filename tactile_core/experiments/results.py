"""Sessions and results on disk: one CSV row per trial, flushed as it happens.

A session lives in ``RESULTS_DIR/participant-<id>/``:

- ``session.json``: participant id, creation time, software version, seed, the order of
  conditions for each experiment, the device profile, the experiments' parameters and notes;
  written atomically.
- ``exp1.csv``, ``exp2.csv``, ``exp3.csv``, ``calibration.csv``: one row per trial, appended,
  flushed and synced to disk before the next trial starts, so a crash loses at most the trial
  in progress. Starting the same participant again resumes where the files end.
"""

from __future__ import annotations

import csv
import datetime as dt
import os
import re
from dataclasses import asdict, dataclass, field
from pathlib import Path

from .._version import __version__
from ..jsonfile import read_json, write_json_atomic
from .stats import order_for

SESSION_FILE = "session.json"
_ID = re.compile(r"^[A-Za-z0-9_.-]{1,64}$")


def check_participant(participant) -> str:
    """A participant id usable as a folder name: letters, digits, ``_.-``, up to 64."""
    if not isinstance(participant, str) or not _ID.match(participant):
        raise ValueError(
            "participant must be 1-64 letters, digits, '_', '.' or '-' (it names a folder), "
            f"got {participant!r}"
        )
    return participant


@dataclass
class Session:
    """What a participant's results were recorded under."""

    participant: str
    index: int = 0
    seed: int = 0
    created: str = ""
    software_version: str = __version__
    device_profile: str = "palm-5x6"
    orders: dict = field(default_factory=dict)
    parameters: dict = field(default_factory=dict)
    notes: str = ""
    folder: str = ""

    def order(self, experiment: str) -> str:
        """This participant's order of conditions (letters A-D) for ``experiment``."""
        if experiment not in self.orders:
            self.orders[experiment] = order_for(self.index, seed=self.seed + _SALT[experiment])
            self.save()
        return self.orders[experiment]

    def save(self) -> None:
        """Write ``session.json`` (atomically)."""
        data = asdict(self)
        data.pop("folder")
        write_json_atomic(Path(self.folder) / SESSION_FILE, data)


_SALT = {"exp1": 101, "exp2": 202, "exp3": 303, "calibration": 404}


def open_session(
    results_dir,
    participant: str,
    *,
    index: int | None = None,
    seed: int = 0,
    device_profile: str = "palm-5x6",
    notes: str = "",
) -> Session:
    """Create a participant's session folder, or open it again to resume.

    Parameters
    ----------
    results_dir : path
        Folder holding one ``participant-<id>`` folder per participant.
    participant : str
        Identifier (a folder name).
    index : int, optional
        The participant's position in recruitment, which decides the counterbalanced orders
        (no two of the first 12 share one). Default: the number of participants already in
        ``results_dir``.
    seed : int
        Seeds the order assignment and each experiment's random choices.
    """
    participant = check_participant(participant)
    root = Path(results_dir)
    folder = root / f"participant-{participant}"
    path = folder / SESSION_FILE
    if path.exists():
        data = read_json(path)
        try:
            return Session(**{**data, "folder": str(folder)})
        except TypeError as exc:
            raise ValueError(f"{path}: cannot resume this session: {exc}") from None
    root.mkdir(parents=True, exist_ok=True)
    if index is None:
        index = len([p for p in root.glob("participant-*") if (p / SESSION_FILE).exists()])
    folder.mkdir(exist_ok=True)
    session = Session(
        participant=participant,
        index=int(index),
        seed=int(seed),
        created=dt.datetime.now().isoformat(timespec="seconds"),
        device_profile=device_profile,
        notes=notes,
        folder=str(folder),
    )
    session.save()
    return session


class ResultsWriter:
    """Appends one row per trial to a CSV, synced to disk at once.

    Parameters
    ----------
    path : path
        The CSV file; created with a header, or appended to (the header must match).
    fields : sequence of str
        Column names.
    """

    def __init__(self, path, fields):
        self.path = Path(path)
        self.fields = list(fields)
        new = not self.path.exists() or self.path.stat().st_size == 0
        if not new:
            with self.path.open(encoding="utf-8", newline="") as f:
                header = next(csv.reader(f), [])
            if header != self.fields:
                raise ValueError(f"{self.path}: columns {header} differ from {self.fields}")
        self._file = self.path.open("a", encoding="utf-8", newline="")
        self._writer = csv.DictWriter(self._file, fieldnames=self.fields)
        if new:
            self._writer.writeheader()
            self._sync()

    def _sync(self) -> None:
        self._file.flush()
        os.fsync(self._file.fileno())

    def write(self, row: dict) -> None:
        """Append ``row`` and make it durable before returning."""
        self._writer.writerow({k: row.get(k, "") for k in self.fields})
        self._sync()

    def close(self) -> None:
        """Close the file."""
        if not self._file.closed:
            self._file.close()


def read_rows(path) -> list[dict]:
    """Rows of a results CSV (an empty list if it does not exist)."""
    path = Path(path)
    if not path.exists():
        return []
    with path.open(encoding="utf-8", newline="") as f:
        return list(csv.DictReader(f))


def now() -> str:
    """Timestamp for a results row."""
    return dt.datetime.now().isoformat(timespec="milliseconds")
