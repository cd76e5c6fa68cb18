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

import random
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
        self.path = Path(session.folder) / f"{self.experiment}.csv"
        self._lock = ParticipantLock(session.folder) if write else None
        try:
            if write:
                session.record_run(self.experiment, self.run_record())
            self._file = ResultsFile(self.path, self.fields) if write else None
            rows = self._file.load() if write else []
            self._rows: list[dict] = []
            self._start()
            self._replay(rows)
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
            If the answer is not valid for the trial (nothing is recorded), or the runner has
            finished.
        """
        trial = self.current
        if trial is None:
            raise ValueError("answer: the experiment has finished")
        value = self.check_answer(trial, answer)
        feedback = self._feedback(trial, value)
        self._after = {}
        try:
            nxt = self._gen.send(value)
        except StopIteration:
            nxt = None
        row = self._row(trial, value)
        row.update(
            participant=self.session.participant,
            stage=trial.stage,
            trial=trial.index,
            rt_s="" if rt_s is None else f"{rt_s:.3f}",
            time=now(),
        )
        for key in HEALTH_FIELDS:
            row[key] = "" if health is None or key not in health else int(health[key])
        if self._file is not None:
            try:
                self._file.append(row)  # durable before the runner moves on
            except OSError:
                self._rewind()  # back to this very trial: the answer was not recorded
                raise
        self._rows.append({k: str(row.get(k, "")) for k in self.fields})
        self.current = nxt
        self.done += 1
        return feedback

    def _rewind(self) -> None:
        """Rebuild the state from the rows on record (after a failed write): the generator
        advanced past a trial whose row is not on disk, so deal the trials again up to it."""
        rows = list(self._rows)
        self._rows = []
        self._start()
        self._replay(rows)

    def _replay(self, rows: list[dict]) -> None:
        """Feed recorded answers back in (resuming); check they fit this session.

        A last row that does not fit (written by a process that died while writing it) is moved
        aside to the ``.torn`` file and its trial is presented again; any other row that does
        not fit is refused, naming the file, the row and the problem.
        """
        for i, row in enumerate(rows):
            try:
                self._replay_row(i, row)
            except (ValueError, TypeError, KeyError) as exc:
                if i == len(rows) - 1 and self._file is not None:
                    self._file.drop_last_row()
                    self.recovered = f"{self.path.name} row {i + 2} was incomplete: {exc}"
                    return
                raise SessionError(f"{self.path}:{i + 2}: {exc}") from None
            self._rows.append(row)

    recovered = ""
    """What resuming had to repair (a torn last row moved aside), for the user; empty if none."""

    def _replay_row(self, i: int, row: dict) -> None:
        trial = self.current
        if trial is None:
            raise ValueError("a row beyond the last trial")
        if row.get("stage") != trial.stage or row.get("trial") != str(trial.index):
            raise ValueError(
                f"stage {_validate.shown(row.get('stage'))}, trial "
                f"{_validate.shown(row.get('trial'))} is not this session's next trial "
                f"({trial.stage} {trial.index}): another seed, or rows out of order"
            )
        self._check_recorded(trial, row)
        value = self.check_answer(trial, self._recorded_answer(trial, row))
        self._after = {}
        try:
            self.current = self._gen.send(value)
        except StopIteration:
            self.current = None
        self.done += 1

    def _recorded_answer(self, trial: Trial, row: dict):
        answer = row.get("answer", "")
        if trial.kind == "rating":
            return int(answer)
        if trial.kind in ("continue", "prepare"):
            return "continue"
        return None if answer in ("", "None") else answer

    def _check_recorded(self, trial: Trial, row: dict) -> None:
        for key, value in trial.info.items():
            if key in row and row[key] not in ("", str(value)):
                raise ValueError(
                    f"{self.experiment}.csv: recorded {key} {_validate.shown(row[key])} "
                    "differs from the "
                    f"session's {_validate.shown(value)}: different seed or software?"
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


def _continue(experiment, stage, index, prompt) -> Trial:
    """An instruction or rest screen: any key goes on."""
    return Trial(experiment, stage, index, "continue", prompt)
