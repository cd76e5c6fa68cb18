"""The paper's experiments (section 3.4) and a per-tactor calibration, as runners without Qt.

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

from .._shared import validate as _validate
from .._version import __version__
from ..rendering.scene import Scene
from ..rendering.shapes import Circle, Line, Square
from .results import ParticipantLock, ResultsFile, Session, SessionError, now
from .staircase import Staircase
from .stats import apply_order

METHODS = ("CT", "MM", "AS", "IM")
DIRECTIONS = ("up", "down", "left", "right")
SHAPES = ("circle", "square")
MU, GAMMA = 0.33, 0.7
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
        from ..device.profile import default_profile

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
            from .tuning import load_correction

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


MAX_SET = 8
"""Most methods an experiment compares (number keys 1-8 in Experiment 1's preparation)."""


def method_set(session: Session, experiment: str, methods=None) -> list[str]:
    """The methods ``experiment`` compares for this session: ``methods`` (specs, validated and
    made canonical), else the set the session recorded, else the paper's four.

    The set is kept in ``session.json`` (``parameters[experiment + "_methods"]``) so that a
    resumed run compares the same methods; another set is refused.

    Raises
    ------
    ValueError
        Naming the method or the set when a method is unknown, the set has fewer than 2 or
        more than 8 methods or one twice, or differs from the session's.
    """
    from ..rendering.methods import get_method

    key = f"{experiment}_methods"
    recorded = session.parameters.get(key)
    if recorded is not None and (
        not isinstance(recorded, list) or not all(isinstance(m, str) for m in recorded)
    ):
        raise ValueError(f"session parameter {key} must be a list of method names, got "
                         f"{_validate.shown(recorded)}")  # fmt: skip
    chosen = methods if methods is not None else recorded if recorded is not None else METHODS
    if isinstance(chosen, str) or not hasattr(chosen, "__iter__"):
        raise ValueError(f"methods must be a list of method names, got {_validate.shown(chosen)}")
    chosen = [get_method(m).spec for m in chosen]
    if not 2 <= len(chosen) <= MAX_SET or len(set(chosen)) != len(chosen):
        raise ValueError(
            f"methods must be 2 to {MAX_SET} different methods, got {' '.join(chosen) or 'none'}"
        )
    if recorded is not None and [get_method(m).spec for m in recorded] != chosen:
        raise ValueError(
            f"methods {' '.join(chosen)} differ from the session's {' '.join(recorded)} for "
            f"{experiment}: resume with the same set, or use another participant id"
        )
    if recorded is None:
        session.parameters[key] = chosen
        session.save()
    return chosen


def _ordered(session: Session, experiment: str, methods: list) -> list:
    """``methods`` in the participant's counterbalanced order: one of the paper's 12 orders
    for the paper's four (in the paper's order), a balanced Latin square row for any other
    set."""
    paper = list(methods) == list(METHODS)
    order = session.order(experiment, len(methods), paper=paper)
    try:
        return apply_order(order, methods)
    except ValueError:
        raise ValueError(
            f"{session.path}: the order {order!r} of {experiment} does not fit its "
            f"{len(methods)} methods"
        ) from None


def _continue(experiment, stage, index, prompt) -> Trial:
    return Trial(experiment, stage, index, "continue", prompt)


class Experiment1(Runner):
    """Experiment 1 (paper 3.4.2): subjective ratings of the four methods.

    A preparation stage (the Experiment 1 line, slope 0.58 left to right, 2 s per trace; keys
    1-4 switch freely between the methods under a shuffled mapping; a letter key goes on), then
    0-100 ratings of quality, then smoothness, then thickness for each method in the
    participant's counterbalanced order, on the line and then on the circle (radius 2,
    centred, counter-clockwise), traced repeatedly with a 0.5 s pause; mu = 0.33, gamma = 0.7.
    """

    experiment = "exp1"
    fields = ("participant", "stage", "trial", "property", "method", "mapping", "switches",
              "answer", "rt_s", "time", *HEALTH_FIELDS)  # fmt: skip
    conditions: ClassVar[dict] = {method: {"mu": MU, "gamma": GAMMA} for method in METHODS}
    """The paper's four; a run with another method set has its own (see ``methods``)."""
    LINE = Line((0.5, 1.84), (4.5, 4.16))
    CIRCLE = Circle((2.5, 3.0), 2.0)
    PROPERTIES = ("quality", "smoothness", "thickness")
    total = 1 + 2 * 3 * 4

    def __init__(self, session, methods=None, **kwargs):
        self.methods = method_set(session, self.experiment, methods)
        self.conditions = {m: {"mu": MU, "gamma": GAMMA} for m in self.methods}
        self.total = 1 + 2 * 3 * len(self.methods)
        self.mapping: list[str] = []
        self.key = 1
        self.switches = 0
        super().__init__(session, **kwargs)

    def scene(self, shape, method) -> Scene:
        """The scene of a rating trial."""
        return self.make_scene(shape, method, MU, GAMMA, duration_s=2.0, pause_s=0.5)

    def select(self, key: int) -> Scene:
        """Preparation stage: the scene of the method behind number key ``key`` (1-N)."""
        n = len(self.methods)
        key = _validate.integer("key", key, 1, n)
        if self.current is None or self.current.kind != "prepare":
            raise ValueError(f"select: keys 1-{n} switch methods only in the preparation stage")
        if key != self.key:
            self.switches += 1
        self.key = key
        return self.scene(self.LINE, self.mapping[key - 1])

    def _trials(self):
        order = _ordered(self.session, self.experiment, self.methods)
        self.mapping = list(self.methods)
        self.rng.shuffle(self.mapping)
        n = len(self.methods)
        keys = tuple(str(k + 1) for k in range(n))
        yield Trial(
            "exp1", "prepare", 0, "prepare",
            ("Press 1, 2, 3 and 4 as often as you like to feel four renderings of a line. "
             if n == 4 else
             f"Press the keys 1 to {n} as often as you like to feel {n} renderings of a line. ")
            + "Press a letter key when you are ready to rate them.",
            scene=self.scene(self.LINE, self.mapping[0]),
            options=keys,
            info={"mapping": "".join(m[0] for m in self.mapping)},
        )  # fmt: skip
        for stage, shape, noun in (("line", self.LINE, "line"), ("circle", self.CIRCLE, "circle")):
            index = 0
            for prop in self.PROPERTIES:
                for method in order:
                    yield Trial(
                        "exp1", stage, index, "rating",
                        f"Rate the {prop} of this {noun} from 0 to 100 (type the number, Enter).",
                        scene=self.scene(shape, method),
                        info={"property": prop, "method": method},
                    )  # fmt: skip
                    index += 1

    def _row(self, trial, answer):
        if trial.kind == "prepare":
            return {"mapping": " ".join(self.mapping), "switches": self.switches, "answer": ""}
        return {**trial.info, "answer": answer}

    def _check_recorded(self, trial, row):
        if trial.kind == "prepare":
            if row.get("mapping") and row["mapping"] != " ".join(self.mapping):
                raise ValueError("exp1.csv: the recorded key mapping differs from the session's")
            return
        super()._check_recorded(trial, row)


CONDITIONS_EXP2 = {
    "L1": ((2.0, 3.0), 0.33, 0.7),  # midpoint at a cell corner
    "L2": ((2.0, 3.0), 0.0, 1.4),
    "L3": ((2.5, 3.5), 0.33, 0.7),  # midpoint at a tactor centre
    "L4": ((2.5, 3.5), 0.0, 1.4),
}
"""Experiment 2's conditions: line midpoint, mu, gamma. The paper does not say which corner or
tactor; these are next to the array's centre (the tactor is Experiment 3's centre)."""


def direction_line(midpoint, length: float, direction: str) -> Line:
    """A line of ``length`` through ``midpoint`` traced in ``direction`` (up/down/left/right)."""
    x, y = midpoint
    h = length / 2.0
    ends = {
        "right": ((x - h, y), (x + h, y)),
        "left": ((x + h, y), (x - h, y)),
        "up": ((x, y - h), (x, y + h)),
        "down": ((x, y + h), (x, y - h)),
    }
    return Line(*ends[direction])


class Experiment2(Runner):
    """Experiment 2 (paper 3.4.3): the shortest line whose direction can be told (AS only).

    Four stages (L1-L4 in the participant's counterbalanced order) of 30 four-alternative
    questions: a line through the stage's midpoint, traced repeatedly (2 s, 0.5 s pause) up,
    down, left or right at random; answered with the arrow keys; text feedback, with the right
    answer when wrong. The length starts at 2.0 units, x 0.685 after two correct answers in a
    row, x 1.46 after each wrong one (capped at 4 units, the longest line the array can hold
    around these midpoints). The estimate per stage is the mean of the last two peaks and two
    valleys.
    """

    experiment = "exp2"
    fields = ("participant", "stage", "trial", "midpoint", "mu", "gamma", "length", "direction",
              "answer", "correct", "next_length", "reversal", "rt_s", "time",
              *HEALTH_FIELDS)  # fmt: skip
    conditions: ClassVar[dict] = {
        c: {"mu": mu, "gamma": gamma} for c, (_, mu, gamma) in CONDITIONS_EXP2.items()
    }
    QUESTIONS = 30
    total = 4 * (QUESTIONS + 1)

    def __init__(self, session, **kwargs):
        self.staircases: dict[str, Staircase] = {}
        super().__init__(session, **kwargs)

    def _trials(self):
        order = apply_order(self.session.order(self.experiment), list(CONDITIONS_EXP2))
        for s, stage in enumerate(order):
            yield _continue(
                "exp2", f"rest-{stage}", 0,
                "Remove your hand from the array and rest. Press a key to start the next stage."
                if s else "Experiment 2: which way does a short line move? Press a key to start.",
            )  # fmt: skip
            midpoint, mu, gamma = CONDITIONS_EXP2[stage]
            sc = Staircase(2.0, 0.685, 1.46, 2, 1, min_level=0.01, max_level=4.0)
            self.staircases[stage] = sc
            for i in range(self.QUESTIONS):
                direction = self.rng.choice(DIRECTIONS)
                length = sc.level
                scene = self.make_scene(
                    direction_line(midpoint, length, direction), "AS", mu, gamma,
                    duration_s=2.0, pause_s=0.5,
                )  # fmt: skip
                answer = yield Trial(
                    "exp2", stage, i, "direction",
                    "Which way does the line move? Arrow keys.",
                    scene=scene, options=DIRECTIONS,
                    info={"midpoint": f"{midpoint[0]:g} {midpoint[1]:g}", "mu": mu, "gamma": gamma,
                          "length": f"{length:.6g}", "direction": direction},
                )  # fmt: skip
                reversals = len(sc.reversal_levels)
                sc.update(answer == direction)
                self._after = {
                    "correct": int(answer == direction),
                    "next_length": f"{sc.level:.6g}",
                    "reversal": int(len(sc.reversal_levels) > reversals),
                }

    def _feedback(self, trial, answer):
        if trial.kind != "direction":
            return ""
        right = trial.info["direction"]
        return "Correct." if answer == right else f"Wrong: the line moved {right}."

    def _row(self, trial, answer):
        if trial.kind == "continue":
            return {"answer": ""}
        return {**trial.info, "answer": answer, **self._after}

    def estimate(self, stage: str) -> float:
        """The stage's 70.7% length: mean of its last two peaks and two valleys."""
        return self.staircases[stage].estimate(4)


class Experiment3(Runner):
    """Experiment 3 (paper 3.4.4): circle or square, with each method.

    For each method (in the participant's counterbalanced order), 10 questions, 5 circles and
    5 squares in random order: a square of edge 4 or a circle of diameter 4.1 ("just over 4"),
    centred on the centre column and the fourth row (2.5, 3.5), retraced continuously
    counter-clockwise at 2 s per trace, mu = 0.33, gamma = 0.7; 20 s to answer (C or S);
    feedback. ``emphasis`` (beyond the paper) slows the point near corners.
    """

    experiment = "exp3"
    fields = ("participant", "stage", "trial", "method", "shape", "emphasis", "answer",
              "correct", "timeout", "rt_s", "time", *HEALTH_FIELDS)  # fmt: skip
    conditions: ClassVar[dict] = {method: {"mu": MU, "gamma": GAMMA} for method in METHODS}
    SQUARE = Square((2.5, 3.5), 4.0)
    CIRCLE = Circle((2.5, 3.5), 2.05)
    QUESTIONS = 10
    TIME_LIMIT_S = 20.0
    total = 4 * (QUESTIONS + 1)

    def __init__(self, session, emphasis: float | None = None, methods=None, **kwargs):
        self.methods = method_set(session, self.experiment, methods)
        self.conditions = {m: {"mu": MU, "gamma": GAMMA} for m in self.methods}
        self.total = len(self.methods) * (self.QUESTIONS + 1)
        if emphasis is None:
            emphasis = float(session.parameters.get("exp3_emphasis", 0.0))
        self.emphasis = _validate.in_range("emphasis", emphasis, 0.0, 0.9)
        if session.parameters.get("exp3_emphasis", self.emphasis) != self.emphasis:
            raise ValueError(
                f"emphasis {self.emphasis:g} differs from the session's "
                f"{session.parameters['exp3_emphasis']:g}"
            )
        session.parameters["exp3_emphasis"] = self.emphasis
        session.save()
        super().__init__(session, **kwargs)

    def _trials(self):
        order = _ordered(self.session, self.experiment, self.methods)
        for s, method in enumerate(order):
            yield _continue(
                "exp3", f"rest-{method}", 0,
                "Rest. Press a key when ready for the next set." if s
                else "Experiment 3: is it a circle or a square? Press a key to start.",
            )  # fmt: skip
            shapes = list(SHAPES) * (self.QUESTIONS // 2)
            self.rng.shuffle(shapes)
            for i, name in enumerate(shapes):
                shape = self.CIRCLE if name == "circle" else self.SQUARE
                scene = self.make_scene(shape, method, MU, GAMMA, duration_s=2.0, pause_s=0.0,
                                        emphasis=self.emphasis)  # fmt: skip
                answer = yield Trial(
                    "exp3", method, i, "shape",
                    "Circle or square? Press C or S (20 s).",
                    scene=scene, options=SHAPES, time_limit_s=self.TIME_LIMIT_S,
                    info={"method": method, "shape": name, "emphasis": f"{self.emphasis:g}"},
                )  # fmt: skip
                self._after = {"correct": int(answer == name), "timeout": int(answer is None)}

    def _feedback(self, trial, answer):
        if trial.kind != "shape":
            return ""
        right = trial.info["shape"]
        if answer is None:
            return f"Time is up: it was a {right}."
        return "Correct." if answer == right else f"Wrong: it was a {right}."

    def _row(self, trial, answer):
        if trial.kind == "continue":
            return {"answer": ""}
        return {**trial.info, "answer": "" if answer is None else answer, **self._after}


class Calibration(Runner):
    """Per-tactor detection thresholds (beyond the paper; its section 4.2 calls for them).

    Each tactor in turn (in random order) vibrates alone for 0.5 s at a drive level set by a
    1-up/1-down staircase (start 0.5 of full drive, x 0.7 down after "felt", / 0.7 up after "not
    felt"), converging on the level felt half the time; a tactor's threshold is the mean of its
    last 6 reversals (after at most 24 trials). :meth:`calibration` turns the thresholds into
    the device profile's per-tactor offset and gain, so that the median tactor is left as it is
    and every other tactor's drive is mapped to feel like it.
    """

    experiment = "calibration"
    fields = ("participant", "stage", "trial", "tactor", "level", "answer", "next_level",
              "rt_s", "time", *HEALTH_FIELDS)  # fmt: skip
    conditions: ClassVar[dict] = {"all": {"mu": 0.0, "gamma": 1.0}}
    MAX_TRIALS = 24
    REVERSALS = 8

    def __init__(self, session, grid=None, **kwargs):
        from ..rendering.geometry import Grid

        self.grid = grid or Grid()
        self.total = self.grid.size * self.MAX_TRIALS
        self.thresholds: dict[tuple, float] = {}
        super().__init__(session, **kwargs)

    def _trials(self):
        cells = [(c, r) for r in range(self.grid.rows) for c in range(self.grid.cols)]
        self.rng.shuffle(cells)
        for col, row in cells:
            sc = Staircase(0.5, 0.7, 1 / 0.7, 1, 1, min_level=0.02, max_level=1.0)
            centre = (col + 0.5, row + 0.5)
            for i in range(self.MAX_TRIALS):
                level = sc.level
                scene = self.make_scene(Line(centre, centre), "CT", 0.0, 1.0, duration_s=0.5,
                                        pause_s=0.0, repeat=False, gain=level)  # fmt: skip
                answer = yield Trial(
                    "calibration", f"c{col}r{row}", i, "detect",
                    "Did you feel a vibration? Y or N (R to feel it again).",
                    scene=scene, options=("yes", "no"),
                    info={"tactor": f"{col} {row}", "level": f"{level:.6g}"},
                )  # fmt: skip
                sc.update(answer == "yes")
                self._after = {"next_level": f"{sc.level:.6g}"}
                if len(sc.reversal_levels) >= self.REVERSALS:
                    break
            n = min(6, len(sc.reversal_levels))
            self.thresholds[(col, row)] = sc.estimate(n) if n else sc.level

    def _row(self, trial, answer):
        return {**trial.info, "answer": answer, **self._after}

    def calibration(self) -> tuple[list[float], list[float], list[float]]:
        """Per-tactor ``(offset, gain, threshold)`` in flat cell order from the measurements
        (:func:`calibration_from_thresholds`; every tactor must have been measured)."""
        if len(self.thresholds) < self.grid.size:
            raise ValueError(
                f"calibration needs all {self.grid.size} thresholds, has {len(self.thresholds)}"
            )
        return calibration_from_thresholds(self.thresholds, self.grid)


def calibration_from_thresholds(thresholds: dict, grid) -> tuple[list, list, list]:
    """Per-tactor ``(offset, gain, threshold)`` in flat cell order from detection thresholds.

    With a tactor's threshold ``th`` and the median threshold ``t_ref``, perceived intensity is
    modelled as linear in drive above threshold, ``(d - th) / (1 - th)``. Matching the median
    tactor at every corrected intensity ``I`` gives
    ``d = th + (1 - th) / (1 - t_ref) * (I - t_ref)``: gain ``(1 - th) / (1 - t_ref)`` and offset
    ``th - t_ref * gain``. ``I = t_ref`` maps to the tactor's own threshold and ``I = 1`` to full
    drive. A tactor without a threshold is left as it is (offset 0, gain 1) and given ``t_ref``.

    Parameters
    ----------
    thresholds : dict
        ``{(col, row): threshold}`` (drive fractions in [0, 1]); at least one.
    grid : Grid

    Returns
    -------
    offset, gain, threshold : list of float, each of length ``grid.size``
    """
    import statistics

    if not thresholds:
        raise ValueError("calibration needs at least one threshold")
    t_ref = statistics.median(thresholds.values())
    offset, gain, threshold = [], [], []
    for i in range(grid.size):
        cell = grid.cell(i)
        if cell not in thresholds:
            offset.append(0.0)
            gain.append(1.0)
            threshold.append(t_ref)
            continue
        th = thresholds[cell]
        g = (1.0 - th) / (1.0 - t_ref) if t_ref < 1.0 else 1.0
        offset.append(min(max(th - t_ref * g, -1.0), 1.0))
        gain.append(min(max(g, 1e-3), 10.0))
        threshold.append(th)
    return offset, gain, threshold


RUNNERS = {
    "exp1": Experiment1,
    "exp2": Experiment2,
    "exp3": Experiment3,
    "calibration": Calibration,
}
"""Runner classes by experiment name (``"correction"``, the tuning procedure, is added by
:mod:`tactile_core.experiments.tuning`)."""
