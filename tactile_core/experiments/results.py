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
import io
import json
import os
import re
import socket
from dataclasses import asdict, dataclass, field
from pathlib import Path

from .._shared import validate as _validate
from .._shared.jsonfile import read_json, write_json_atomic
from .._version import __version__
from ..rendering.scene import PAPER_PIPELINE, Pipeline
from .stats import order_for, order_for_set

SESSION_FILE = "session.json"
_ID = re.compile(r"^[A-Za-z0-9_.-]{1,64}$")


class SessionError(ValueError):
    """A session file or results file that cannot be used: names the file, the row or field,
    and the problem."""


def check_participant(participant) -> str:
    """A participant id usable as a folder name: letters, digits, ``_.-``, up to 64."""
    if not isinstance(participant, str) or not _ID.fullmatch(participant):
        shown = (
            repr(participant) if len(repr(participant)) <= 80 else repr(participant)[:77] + "..."
        )
        raise ValueError(
            "participant must be 1-64 letters, digits, '_', '.' or '-' (it names a folder), "
            f"got {shown}"
        )
    return participant


@dataclass
class Session:
    """What a participant's results were recorded under.

    Attributes
    ----------
    participant : str
    index : int
        Position in recruitment (decides the counterbalanced orders).
    seed : int
    created : str
    software_version : str
        The version that created the session.
    device_profile : str
        Name of the device profile at creation.
    orders : dict
        ``{experiment: order}`` (letters A-D).
    parameters : dict
        Session parameters (e.g. ``exp3_emphasis``).
    notes : str
    pipeline : dict
        The session's :class:`~tactile_core.rendering.scene.Pipeline` (rate, filter and sub-samples,
        dithering); the paper's by default.
    runs : dict
        ``{experiment: record}``: what each experiment ran (pipeline, levels, mu and gamma of
        each condition, the device profile's name, SHA-256 and calibration, the software
        version), written when the experiment first starts and checked on every resume.
    folder : str
    """

    participant: str
    index: int = 0
    seed: int = 0
    created: str = ""
    software_version: str = __version__
    device_profile: str = "palm-5x6"
    orders: dict = field(default_factory=dict)
    parameters: dict = field(default_factory=dict)
    notes: str = ""
    pipeline: dict = field(default_factory=lambda: PAPER_PIPELINE.to_dict())
    runs: dict = field(default_factory=dict)
    folder: str = ""

    @property
    def path(self) -> Path:
        """The ``session.json`` file."""
        return Path(self.folder) / SESSION_FILE

    def order(self, experiment: str, n: int = 4, paper: bool = True) -> str:
        """This participant's order of conditions (letters A onwards) for ``experiment``.

        ``paper``: one of the paper's 12 orders of four conditions (:data:`ORDERS`); otherwise
        a row of a balanced Latin square of ``n`` (:func:`order_for_set`). Either is dealt by
        recruitment index with the session's seed, and kept in ``session.json``."""
        if experiment not in self.orders:
            seed = self.seed + _SALT[experiment]
            self.orders[experiment] = (
                order_for(self.index, seed=seed) if paper
                else order_for_set(self.index, n, seed=seed)
            )  # fmt: skip
            self.save()
        return self.orders[experiment]

    def get_pipeline(self) -> Pipeline:
        """The session's pipeline."""
        return Pipeline.from_dict(self.pipeline, source=f"{self.path}: pipeline")

    def record_run(self, experiment: str, record: dict) -> None:
        """Record what ``experiment`` runs, or check that a resumed run is the same.

        Raises
        ------
        SessionError
            Naming the file and what differs, when the experiment was started under another
            pipeline, device profile, calibration or correction.
        """
        old = self.runs.get(experiment)
        if old is None:
            self.runs[experiment] = record
            self.save()
            return
        for key in ("pipeline", "conditions", "device_profile"):
            if old.get(key) != record.get(key):
                raise SessionError(
                    f"{self.path}: {experiment} was started with {key} {_short(old.get(key))}; "
                    f"this run has {_short(record.get(key))}. Resume it with the same "
                    f"settings, or start a new participant"
                )

    def save(self) -> None:
        """Write ``session.json`` (atomically)."""
        data = asdict(self)
        data.pop("folder")
        write_json_atomic(self.path, data)


def _short(value) -> str:
    text = repr(value)
    return text if len(text) <= 200 else text[:197] + "..."


_SALT = {"exp1": 101, "exp2": 202, "exp3": 303, "calibration": 404, "correction": 505}
_FIELDS = {
    "participant": str, "index": int, "seed": int, "created": str, "software_version": str,
    "device_profile": str, "orders": dict, "parameters": dict, "notes": str, "pipeline": dict,
    "runs": dict,
}  # fmt: skip


def session_from_dict(data, path) -> Session:
    """Validate the JSON of ``session.json``; :class:`SessionError` names the field."""
    if not isinstance(data, dict):
        raise SessionError(f"{path}: a session must be a JSON object, got {type(data).__name__}")
    kwargs = {}
    for key, kind in _FIELDS.items():
        if key not in data:
            if key in ("participant", "index", "seed", "orders"):
                raise SessionError(f"{path}: field '{key}' is missing")
            continue
        value = data[key]
        if isinstance(value, bool) or not isinstance(value, kind):
            raise SessionError(
                f"{path}: field '{key}' must be {_KIND_NAMES[kind]}, got {_short(value)}"
            )
        kwargs[key] = value
    try:
        check_participant(kwargs["participant"])
    except ValueError as exc:
        raise SessionError(f"{path}: field {exc}") from None
    if kwargs["index"] < 0 or kwargs["seed"] < 0:
        raise SessionError(f"{path}: fields 'index' and 'seed' must be >= 0")
    for name, order in kwargs["orders"].items():
        letters = [chr(ord("A") + i) for i in range(len(order))] if isinstance(order, str) else []
        if name not in _SALT or not 2 <= len(letters) <= 8 or sorted(order) != letters:
            raise SessionError(
                f"{path}: field 'orders' must map experiments to orders of A-D (A-H for a "
                f"method set), got "
                f"{_short({name: order})}"
            )
    if "pipeline" in kwargs:
        try:
            Pipeline.from_dict(kwargs["pipeline"], source="pipeline")
        except ValueError as exc:
            raise SessionError(f"{path}: field {exc}") from None
    for name, record in kwargs.get("runs", {}).items():
        if name not in _SALT or not isinstance(record, dict):
            raise SessionError(f"{path}: field 'runs' holds a bad entry {_short({name: record})}")
    return Session(**kwargs)


_KIND_NAMES = {str: "a string", int: "an integer", dict: "an object"}


def open_session(
    results_dir,
    participant: str,
    *,
    index: int | None = None,
    seed: int = 0,
    device_profile: str = "palm-5x6",
    notes: str = "",
    pipeline: Pipeline | None = None,
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
    device_profile : str
        Name of the device profile (recorded; each run records the profile it used in full).
    notes : str
    pipeline : Pipeline, optional
        How scenes become levels; the paper's pipeline (point sampling, plain rounding) by
        default. A resumed session keeps its own and refuses a different one.

    Raises
    ------
    SessionError
        When an existing ``session.json`` is malformed, or disagrees with ``pipeline``.
    """
    participant = check_participant(participant)
    seed = _validate.integer("seed", seed, 0)
    root = Path(results_dir)
    folder = root / f"participant-{participant}"
    path = folder / SESSION_FILE
    if path.exists():
        session = session_from_dict(read_json(path, SessionError), path)
        session.folder = str(folder)
        if pipeline is not None and pipeline.to_dict() != session.pipeline:
            raise SessionError(
                f"{path}: the session runs pipeline {session.pipeline}, not {pipeline.to_dict()}"
            )
        return session
    root.mkdir(parents=True, exist_ok=True)
    if index is None:
        index = len([p for p in root.glob("participant-*") if (p / SESSION_FILE).exists()])
    folder.mkdir(exist_ok=True)
    session = Session(
        participant=participant,
        index=_validate.integer("index", index, 0),
        seed=seed,
        created=dt.datetime.now().isoformat(timespec="seconds"),
        device_profile=device_profile,
        notes=notes,
        pipeline=(pipeline or PAPER_PIPELINE).to_dict(),
        folder=str(folder),
    )
    session.save()
    return session


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
        for _ in range(3):
            try:
                fd = os.open(self.path, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644)
            except FileExistsError:
                holder = self._holder()
                if holder is not None and not self._stale(holder):
                    raise SessionError(
                        f"{self.path.parent}: this participant is being recorded by PID "
                        f"{holder.get('pid')} on {holder.get('host')} since "
                        f"{holder.get('since')}; a second copy may not write to it. If that "
                        f"program is gone, remove {self.path}"
                    ) from None
                self.path.unlink(missing_ok=True)  # stale or unreadable: take it over
                continue
            with os.fdopen(fd, "w", encoding="utf-8") as f:
                json.dump(self._record(), f)
                f.flush()
                os.fsync(f.fileno())
            self.held = True
            return
        raise SessionError(f"{self.path}: could not take the participant's lock")

    def _holder(self) -> dict | None:
        try:
            data = json.loads(self.path.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            return None  # half-written by a process killed while creating it: stale
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
    """Rows of a results CSV as dictionaries (an empty list if it does not exist).

    Lines are read as the runner writes them: a last line without its line end (a torn row) is
    left out.
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
    """Timestamp for a results row."""
    return dt.datetime.now().isoformat(timespec="milliseconds")
