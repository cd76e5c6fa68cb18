"""Experiment 3 (paper 3.4.4): circle or square, with each method."""

from __future__ import annotations

from typing import ClassVar

from ..._shared import validate as _validate
from ...rendering.shapes import Circle, Square
from ._conditions import GAMMA, METHODS, MU, SHAPES, _ordered, method_set
from ._runner import HEALTH_FIELDS, Runner, Trial, _continue


class Experiment3(Runner):
    """Experiment 3 (paper 3.4.4): circle or square, with each method.

    For each method (in the participant's counterbalanced order), 10 questions, 5 circles and
    5 squares in random order: a square of edge 4 or a circle of diameter 4.1 ("just over 4"),
    centred on the centre column and the fourth row (2.5, 3.5), retraced continuously
    counter-clockwise at 2 s per trace, mu = 0.33, gamma = 0.7; 20 s to answer (C or S);
    feedback. ``emphasis`` (beyond the paper) slows the point near corners.

    Parameters
    ----------
    session : Session
    emphasis : float, optional
        In [0, 0.9]; recorded in the session (default: the session's, else 0).
    methods : sequence of str, optional
        The methods compared (2 to 8; :func:`method_set`); the paper's four by default.
    write, profile
        As for every :class:`Runner`.
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
        answered = session.answered(self.experiment)  # (before an answer it may change)
        if answered and session.parameters.get("exp3_emphasis", self.emphasis) != self.emphasis:
            raise ValueError(
                f"emphasis {self.emphasis:g} differs from the session's "
                f"{session.parameters['exp3_emphasis']:g}"
            )
        session.parameters["exp3_emphasis"] = self.emphasis  # (written under the lock)
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
