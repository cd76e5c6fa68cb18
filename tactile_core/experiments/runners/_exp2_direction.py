"""Experiment 2 (paper 3.4.3): the shortest line whose direction can be told."""

from __future__ import annotations

from typing import ClassVar

from ...rendering.shapes import Line
from ..staircase import Staircase
from ..stats import apply_order
from ._conditions import DIRECTIONS
from ._runner import HEALTH_FIELDS, Runner, Trial, _continue

CONDITIONS_EXP2 = {
    "L1": ((2.0, 3.0), 0.33, 0.7),  # midpoint at a cell corner
    "L2": ((2.0, 3.0), 0.0, 1.4),
    "L3": ((2.5, 3.5), 0.33, 0.7),  # midpoint at a tactor centre
    "L4": ((2.5, 3.5), 0.0, 1.4),
}
"""Experiment 2's conditions: line midpoint, mu, gamma. The paper does not say which corner or
tactor; these are next to the array's centre (the tactor is Experiment 3's centre)."""


def direction_line(midpoint, length: float, direction: str) -> Line:
    """A line of ``length`` through ``midpoint`` traced in ``direction``.

    Parameters
    ----------
    midpoint : (float, float)
        ``(x, y)`` in grid units (tactor pitches; y up).
    length : float
        Grid units.
    direction : {"up", "down", "left", "right"}

    Returns
    -------
    Line
        From its start to its end in ``direction``.
    """
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

    Parameters
    ----------
    session : Session
    write, profile
        As for every :class:`Runner`.
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
