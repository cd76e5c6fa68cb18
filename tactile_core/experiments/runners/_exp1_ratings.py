"""Experiment 1 (paper 3.4.2): subjective ratings of the methods."""

from __future__ import annotations

from typing import ClassVar

from ..._shared import validate as _validate
from ...rendering.scene import Scene
from ...rendering.shapes import Circle, Line
from ._conditions import GAMMA, METHODS, MU, _ordered, method_set
from ._runner import HEALTH_FIELDS, Runner, Trial


class Experiment1(Runner):
    """Experiment 1 (paper 3.4.2): subjective ratings of the four methods.

    A preparation stage (the Experiment 1 line, slope 0.58 left to right, 2 s per trace; keys
    1-4 switch freely between the methods under a shuffled mapping; a letter key goes on), then
    0-100 ratings of quality, then smoothness, then thickness for each method in the
    participant's counterbalanced order, on the line and then on the circle (radius 2,
    centred, counter-clockwise), traced repeatedly with a 0.5 s pause; mu = 0.33, gamma = 0.7.

    Parameters
    ----------
    session : Session
    methods : sequence of str, optional
        The methods rated (2 to 8; :func:`method_set`); the paper's four by default.
    write, profile
        As for every :class:`Runner`.
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
