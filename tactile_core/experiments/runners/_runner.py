"""The machinery every runner shares: the trial, and the runner that deals trials, records each
answer as a durable CSV row and resumes a session from its rows.

A runner is a state machine that a user interface drives: :attr:`Runner.current` is the trial
to present (what the array plays, what to ask, which answers are valid); :meth:`Runner.answer`
records the answer as one CSV row, flushed to disk before it returns, and moves on. The tuner
drives runners from the keyboard; tests and study planning drive them with simulated
participants (:mod:`tactile_core.experiments.participants`). Starting a runner again on the
same session folder resumes it: the recorded answers are replayed and checked against what the
session's seed generates.
"""

from __future__ import annotations

import datetime as dt
import random
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import ClassVar

from ..._shared import validate as _validate
from ..._version import __version__
from ...rendering.scene import Scene
from .._correction_record import load_correction
from ..results import ParticipantLock, ResultsFile, Session, SessionError, now

HEALTH_FIELDS = ("late_frames", "skipped_frames", "link_errors", "presentations")
"""Per trial, the stream's health while it was presented: frames sent more than 1 ms late,
deadlines skipped after a stall, link errors (empty when no stream was watched), and how many
times the trial was presented (more than 1 after a pause or a lost link presented it again)."""


@dataclass(frozen=True)
class Trial:
    """One question: what the array plays and what the participant is asked.

    Attributes
    ----------
    experiment, stage : str
        E.g. ``"exp2"`` and ``"L3"``.
    index : int
        Trial number within the stage (0-based).
    kind : str
        The answer expected: ``"continue"`` (any key; instructions or rest), ``"prepare"``
        (free switching with keys 1-4, then continue), ``"rating"`` (0-100), ``"direction"``
        (up/down/left/right), ``"shape"`` (circle/square), ``"detect"`` (yes/no),
        ``"interval"`` (a two-interval forced choice: ``"1"`` or ``"2"``).
    prompt : str
        What the screen says.
    scene : Scene or None
        What the array plays (None: all off).
    options : tuple of str
        Valid answers for the choice kinds.
    time_limit_s : float or None
        After this long without an answer, the UI answers None (a timeout).
    info : dict
        The condition, recorded with the answer.
    intervals : tuple of (Scene or None)
        For ``"interval"`` trials: what the array plays in interval 1 and in interval 2, each
        :data:`INTERVAL_S` long with :data:`INTERVAL_GAP_S` of silence between (``scene`` is
        None); the answer is the interval chosen.
    """

    experiment: str
    stage: str
    index: int
    kind: str
    prompt: str
    scene: Scene | None = None
    options: tuple = ()
    time_limit_s: float | None = None
    info: dict = field(default_factory=dict, compare=False)
    intervals: tuple = ()


INTERVAL_S = 0.5
"""Length of each interval of a two-interval trial, seconds."""
INTERVAL_GAP_S = 0.5
"""Silence between the two intervals of a two-interval trial, seconds."""


class Runner:
    """Base of the experiment runners: trial generation, answers, results rows, resuming.

    Parameters
    ----------
    session : Session
        Where results go, what seeds the random choices, and the pipeline the scenes run.
    write : bool
        Write results (False for dry runs).
    profile : DeviceProfile, optional
        The array the run plays on (the palm array by default); recorded in the session with
        its SHA-256 and calibration, and checked when the run is resumed.
    """

    experiment = ""
    fields: tuple = ()

    def __init__(self, session: Session, *, write: bool = True, profile=None):
        from ...device.profile import default_profile

        self.session = session
        self.pipeline = session.get_pipeline()
        self.profile = profile or default_profile()
        if not self.profile.layout.is_grid:
            raise ValueError(
                f"profile {self.profile.name} is a layout ({self.profile.layout.describe()}): the "
                f"paper's experiments compare its grid methods (CT, MM, AS, IM) and need a grid "
                f"profile such as palm-5x6"
            )
        self.path = Path(session.folder) / f"{self.experiment}.csv"
        self._lock = ParticipantLock(session.folder) if write else None
        try:
            if write:
                # the parameters a subclass chose (a method set, Exp. 3's emphasis) only now,
                # holding the participant: a copy refused the lock rewrote them before
                session.save()
                session.record_run(self.experiment, self.run_record())
            self._file = ResultsFile(self.path, self.fields) if write else None
            self._rows: list[dict] = []
            self._start()
            if write:
                self._replay(self._file.rows())  # streamed: a surplus row stops the reading
                self.recovered = self._file.recovered
        except BaseException:
            self.close()
            raise

    def _start(self) -> None:
        """The trial generator from its beginning (seeded: it always deals the same trials)."""
        seed = f"{self.session.seed}:{self.session.participant}:{self.experiment}"
        self.rng = random.Random(seed)
        self._after: dict = {}
        self._gen = self._trials()
        self.current: Trial | None = next(self._gen, None)
        self.done = 0

    # --- for subclasses ----------------------------------------------------------------------

    conditions: ClassVar[dict] = {}
    """``{condition: {"mu": mu, "gamma": gamma}}`` as the session records them."""

    def run_record(self) -> dict:
        """What ``session.json`` records of this run: the whole pipeline it plays, and the
        participant's measured correction if there is one (recorded, not applied: each
        condition sets its own mu and gamma)."""
        record = {
            "pipeline": self.pipeline.to_dict(),
            "levels": self.profile.levels,
            "conditions": self.conditions,
            "device_profile": self.profile.record(),
            "software_version": __version__,
            "started": now(),
        }
        if self.session.folder and self.experiment != "correction":
            measured = load_correction(self.session.folder)
            if measured is not None:
                record["participant_correction"] = {
                    key: measured.get(key)
                    for key in ("mu", "mu_ci", "gamma", "gamma_ci", "trials", "measured")
                }
        return record

    def make_scene(self, shape, method, mu, gamma, **kwargs) -> Scene:
        """A trial's scene, on the session's pipeline."""
        return self.pipeline.apply(Scene(shape, method, mu, gamma, **kwargs))

    def _trials(self):
        """Generator: yield trials, receive each answer."""
        raise NotImplementedError

    def _row(self, trial: Trial, answer) -> dict:
        """The results row of ``trial`` answered ``answer`` (after :attr:`_after` is set)."""
        raise NotImplementedError

    def _feedback(self, trial: Trial, answer) -> str:
        return ""

    # --- driving -----------------------------------------------------------------------------

    @property
    def finished(self) -> bool:
        """True once every trial is answered."""
        return self.current is None

    def check_answer(self, trial: Trial, answer):
        """Validate an answer for ``trial``; return it normalised."""
        kind = trial.kind
        if kind in ("continue", "prepare"):
            return "continue"
        if kind == "rating":
            value = _validate.real("answer", answer)
            if not (0 <= value <= 100 and float(value).is_integer()):
                raise ValueError(
                    f"answer must be a whole number from 0 to 100, got {_validate.shown(answer)}"
                )
            return int(value)
        if answer is None and trial.time_limit_s is not None:
            return None  # timed out
        if answer not in trial.options:
            raise ValueError(
                f"answer must be one of {', '.join(trial.options)}, got {_validate.shown(answer)}"
            )
        return answer

    def answer(self, answer, rt_s: float | None = None, health: dict | None = None) -> str:
        """Record the answer to the current trial, advance, and return the feedback text.

        ``health`` holds the stream's ``late_frames``, ``skipped_frames`` and ``link_errors``
        while the trial was presented, and its number of ``presentations`` (see
        :data:`HEALTH_FIELDS`).

        Raises
        ------
        ValueError
            If the answer is not valid for the trial, ``rt_s`` is not a time >= 0 or a health
            count not a whole number >= 0 (nothing is recorded), or the runner has finished.
        """
        trial = self.current
        if trial is None:
            raise ValueError("answer: the experiment has finished")
        value = self.check_answer(trial, answer)
        measured = {"rt_s": "" if rt_s is None else f"{_validate.non_negative('rt_s', rt_s):.3f}"}
        for key in HEALTH_FIELDS:  # what a resume accepts in these fields: checked before
            has = health is not None and key in health
            measured[key] = str(_validate.integer(key, health[key], 0)) if has else ""
        feedback = self._feedback(trial, value)
        nxt = self._advance(value)
        row = self._full_row(trial, value)
        row.update(measured, time=now())
        if self._file is not None:
            try:
                self._file.append(row)  # durable before the runner moves on
            except OSError:
                self._rewind()  # back to this very trial: the answer was not recorded
                raise
        self._rows.append(row)
        self.current = nxt
        self.done += 1
        return feedback

    def _advance(self, value):
        """Send ``value`` to the trial generator; the next trial (None at the end)."""
        self._after = {}
        try:
            return self._gen.send(value)
        except StopIteration:
            return None

    def _full_row(self, trial: Trial, value) -> dict:
        """Every field of ``trial``'s row as text (``rt_s``, ``time`` and the health empty);
        after :meth:`_advance` (the row notes what the answer did)."""
        row = self._row(trial, value)
        row.update(participant=self.session.participant, stage=trial.stage, trial=trial.index)
        return {k: str(row.get(k, "")) for k in self.fields}

    def measured(self, trial: Trial) -> set:
        """The fields of ``trial``'s row that record what happened rather than what the session
        deals (the response time, the clock, the stream's health): a replay checks their form,
        not their value."""
        return {"rt_s", "time", *HEALTH_FIELDS}

    def _rewind(self) -> None:
        """Rebuild the state from the rows on record (after a failed write): the generator
        advanced past a trial whose row is not on disk, so deal the trials again up to it."""
        rows = list(self._rows)
        self._rows = []
        self._start()
        self._replay(enumerate(rows, start=2))

    def _replay(self, rows) -> None:
        """Feed recorded rows back in (resuming), replaying the procedure from them.

        Each row must be exactly what this session's procedure writes for its trial given the
        recorded answer (the trial, the condition, what the answer did: ``correct``, the next
        level, the reversals), and its measured fields (:meth:`measured`) must have the form
        the runner writes. Anything else is refused, naming the file, the row and the field:
        a row the replay does not reproduce was changed after it was written, and building on
        it would carry the change into every later trial.

        Parameters
        ----------
        rows : iterable of (int, dict)
            ``(line, row)`` in file order, the header as line 1.
        """
        for line, row in rows:
            try:
                self._replay_row(row)
            except (ValueError, TypeError, KeyError) as exc:
                raise SessionError(f"{self.path}:{line}: {exc}") from None
            self._rows.append(row)

    recovered = ""
    """What resuming had to repair (a torn last row moved aside), for the user; empty if none."""

    def _replay_row(self, row: dict) -> None:
        trial = self.current
        if trial is None:
            raise ValueError("a row beyond the last trial")
        for key, value in (("stage", trial.stage), ("trial", str(trial.index))):
            if row.get(key) != value:
                raise ValueError(
                    f"field {key} is {_validate.shown(row.get(key))}, but this session's next "
                    f"trial is {trial.stage} {trial.index}: another seed, or rows out of order"
                )
        self._check_recorded(trial, row)
        try:
            value = self.check_answer(trial, self._recorded_answer(trial, row))
        except ValueError as exc:
            raise ValueError(
                f"field answer is {_validate.shown(row.get('answer'))}: {exc}"
            ) from None
        nxt = self._advance(value)
        expected = self._full_row(trial, value)
        measured = self.measured(trial)
        for key in self.fields:
            if key in measured:
                _check_measured(key, row.get(key, ""))
            elif row.get(key) != expected[key]:
                raise ValueError(
                    f"field {key} is {_validate.shown(row.get(key))}, but replaying the session "
                    f"gives {_validate.shown(expected[key])}: the row was changed after it was "
                    "written (or written by other software); restore it, or start a new "
                    "participant"
                )
        self.current = nxt
        self.done += 1

    def _recorded_answer(self, trial: Trial, row: dict):
        answer = row.get("answer", "")
        if trial.kind == "rating":
            if not answer.isascii() or not answer.isdigit():
                raise ValueError("not a rating 0-100")
            return int(answer)
        if trial.kind in ("continue", "prepare"):
            return "continue"
        return None if answer == "" else answer

    def _check_recorded(self, trial: Trial, row: dict) -> None:
        for key, value in trial.info.items():
            if key in row and row[key] != str(value):
                raise ValueError(
                    f"field {key} is {_validate.shown(row[key])}, but the session deals "
                    f"{_validate.shown(str(value))} for this trial: a different seed or software, "
                    "or the row was changed after it was written"
                )

    def progress(self) -> tuple[int, int]:
        """``(answered, total)`` trials."""
        return self.done, self.total

    total = 0

    def close(self) -> None:
        """Close the results file and release the participant (idempotent)."""
        file = getattr(self, "_file", None)
        if file is not None:
            file.close()
        lock = getattr(self, "_lock", None)
        if lock is not None:
            lock.release()

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def _check_measured(key: str, value: str) -> None:
    """A measured field has the form the runner writes: empty, or a whole number >= 0 (the
    stream's health, Experiment 1's key switches), a time >= 0 in seconds (``rt_s``), or a
    local ISO 8601 time (``time``)."""
    if value == "" and key != "time":
        return
    try:
        if key == "time":
            dt.datetime.fromisoformat(value)
            ok = len(value) <= 40
        elif key == "rt_s":
            ok = _DECIMAL.fullmatch(value) is not None
        else:
            ok = value.isascii() and value.isdigit() and len(value) <= 40
    except ValueError:
        ok = False
    if not ok:
        raise ValueError(f"field {key} is {_validate.shown(value)}, which the runner never writes")


_DECIMAL = re.compile(r"[0-9]{1,40}(\.[0-9]{1,6})?")


def _continue(experiment, stage, index, prompt) -> Trial:
    """An instruction or rest screen: any key goes on."""
    return Trial(experiment, stage, index, "continue", prompt)
