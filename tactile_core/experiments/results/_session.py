"""A participant's session: ``session.json``, what every experiment of theirs was recorded under.

It holds the participant id, their recruitment index and seed (which deal the counterbalanced
orders), the pipeline and the record of each experiment's run, so that a resumed run can be
checked against the one it continues.
"""

from __future__ import annotations

import datetime as dt
import os
import re
import stat
from dataclasses import asdict, dataclass, field
from pathlib import Path

from ..._shared import validate as _validate
from ..._shared.jsonfile import read_json, write_json_atomic
from ..._version import __version__
from ...rendering.scene import PAPER_PIPELINE, Pipeline
from ..stats import order_for, order_for_set

SESSION_FILE = "session.json"
_ID = re.compile(r"^[A-Za-z0-9_.-]{1,64}$")


class SessionError(ValueError):
    """A session file or results file that cannot be used: names the file, the row or field,
    and the problem."""


def check_participant(participant) -> str:
    """A participant id usable as a folder name: letters, digits, ``_.-``, up to 64.

    Parameters
    ----------
    participant : str

    Returns
    -------
    str
        ``participant``, unchanged.

    Raises
    ------
    ValueError
        If it is not such a string (it names a folder: no paths).
    """
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

    def answered(self, experiment: str) -> bool:
        """Whether ``experiment``'s results file holds an answer (a line after its header).
        Only a regular file is read, and only its first 64 KiB: anything else (``/dev/zero``,
        a FIFO that would block) is refused when the run opens it."""
        if not self.folder:
            return False
        path = Path(self.folder) / f"{experiment}.csv"
        try:
            if not stat.S_ISREG(os.lstat(path).st_mode):
                return False
            with open(path, "rb") as f:
                head = f.read(1 << 16)
        except OSError:  # none yet
            return False
        return any(line.strip() for line in head.split(b"\n")[1:])

    def record_run(self, experiment: str, record: dict) -> None:
        """Record what ``experiment`` runs, or check that a resumed run is the same. A run
        started and stopped before its first answer may start again with other settings
        (nothing was recorded under the old ones).

        Raises
        ------
        SessionError
            Naming the file and what differs, when the experiment was started under another
            pipeline, device profile, calibration or correction and has answers.
        """
        old = self.runs.get(experiment)
        if old is None or not self.answered(experiment):
            self.runs[experiment] = record
            self.save()
            return
        for key in ("pipeline", "conditions", "device_profile"):
            if _same(key, old.get(key), record.get(key)):
                continue
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


def _same(key: str, old, new) -> bool:
    """Whether two recorded pipelines are the same: one recorded before ``compensate_motors``
    existed is the same as one without it."""
    if key != "pipeline":
        return False
    try:
        return Pipeline.from_dict(old) == Pipeline.from_dict(new)
    except ValueError:
        return False


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
    """Validate the JSON of ``session.json``.

    Parameters
    ----------
    data : object
        The parsed JSON.
    path : path
        The file, for messages.

    Returns
    -------
    Session
        Without its ``folder`` (the caller sets it).

    Raises
    ------
    SessionError
        Naming the file and the field that is missing or wrong.
    """
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
        try:  # in full: one recorded before a field existed says what it ran
            kwargs["pipeline"] = Pipeline.from_dict(kwargs["pipeline"], source="pipeline").to_dict()
        except ValueError as exc:
            raise SessionError(f"{path}: field {exc}") from None
    for name, record in kwargs.get("runs", {}).items():
        if name not in _SALT or not isinstance(record, dict):
            raise SessionError(f"{path}: field 'runs' holds a bad entry {_short({name: record})}")
    return Session(**kwargs)


_KIND_NAMES = {str: "a string", int: "an integer", dict: "an object"}


def _next_index(root: Path) -> int:
    """One past the highest recruitment index of the sessions in ``root`` (0 for none). The
    number of sessions gave a participant recruited after a deleted one the index, and so the
    counterbalanced orders, of another still there."""
    highest = -1
    for path in root.glob(f"participant-*/{SESSION_FILE}"):
        try:
            index = read_json(path, SessionError, follow_symlinks=False).get("index")
        except (SessionError, AttributeError):
            continue  # (a malformed session is refused when it is opened)
        if type(index) is int:
            highest = max(highest, index)
    return highest + 1


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
        (no two of the first 12 share one). Default: one past the highest index of the
        participants in ``results_dir`` (their number, unless one was deleted).
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
    if os.path.lexists(path):  # a symbolic link, even a dangling one, is refused
        session = session_from_dict(read_json(path, SessionError, follow_symlinks=False), path)
        session.folder = str(folder)
        if pipeline is not None and pipeline.to_dict() != session.pipeline:
            raise SessionError(
                f"{path}: the session runs pipeline {session.pipeline}, not {pipeline.to_dict()}"
            )
        return session
    root.mkdir(parents=True, exist_ok=True)
    if index is None:
        index = _next_index(root)
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
