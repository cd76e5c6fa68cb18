"""The adaptive tracks: whole device levels for the thresholds (a 3-down/1-up track or QUEST+),
log steps of gamma for the constancy."""

from __future__ import annotations

from .._correction_record import GAMMA_MAX, GAMMA_MIN


class _LevelTrack:
    """3-down/1-up over whole device levels (79% correct in two intervals).

    The descent from the start (half drive) is quicker until the second wrong answer: two right
    in a row step down 2 levels (two, because a guess is right half the time: one lucky guess
    must not carry the track far below the threshold) and a wrong answer steps up 1. From then
    on 3 right in a row step down 1 level and 1 wrong steps up 1. Waiting for a second wrong
    answer keeps one early lapse from stranding the track above the threshold; it recovered
    low thresholds (TH 0.1) within 0.03 in 98% of simulated runs against 88% when the quick
    phase ended at the first wrong answer.
    """

    FAST_UNTIL_WRONG = 2

    def __init__(self, start: int, top: int):
        self.level, self.top = start, top
        self.run = 0
        self.wrong = 0
        self.trials = 0

    def update(self, correct: bool) -> None:
        self.trials += 1
        fast = self.wrong < self.FAST_UNTIL_WRONG
        step = 0
        if correct:
            self.run += 1
            if self.run == (2 if fast else 3):
                step, self.run = (-2 if fast else -1), 0
        else:
            step = 1
            self.wrong += 1
            self.run = 0
        self.level = min(max(self.level + step, 1), self.top)


class _LogTrack:
    """1-up/1-down in log steps: x 1.4 until two reversals, then x 1.2, within [0.1, 10]."""

    def __init__(self, start: float):
        self.level = start
        self.direction = 0
        self.reversals = 0
        self.trials = 0

    def update(self, test_stronger: bool) -> None:
        self.trials += 1
        step = 1 if test_stronger else -1  # stronger: raise gamma (the test point weakens)
        if self.direction and step != self.direction:
            self.reversals += 1
        self.direction = step
        factor = 1.4 if self.reversals < 2 else 1.2
        self.level = min(max(self.level * factor**step, GAMMA_MIN), GAMMA_MAX)


class _QuestTrack:
    """QUEST+ over whole device levels 1..top (Watson 2017; the ``questplus`` package).

    The model is the threshold fit's: in two intervals ``p = 0.5 + (0.5 - lapse) Phi((d - T) /
    sd)`` at drive ``d = level / top``, with a uniform prior over ``T`` (0 to 1 in steps of
    0.02), ``sd`` (eight values, 0.01 to 0.3) and the lapse (0, 0.02, 0.05); each trial goes to
    the level whose answer is expected to leave the posterior with the least entropy. The
    selection is deterministic, so a resumed run replays the same levels from the same
    answers.
    """

    def __init__(self, top: int):
        import numpy as np
        import questplus

        self.top = top
        self.trials = 0
        self._levels = np.arange(1, top + 1) / top
        self._qp = questplus.QuestPlus(
            stim_domain={"intensity": self._levels},
            param_domain={"mean": np.linspace(0.0, 1.0, 51), "sd": np.geomspace(0.01, 0.3, 8),
                          "lower_asymptote": 0.5, "lapse_rate": [0.0, 0.02, 0.05]},
            outcome_domain={"response": ["Correct", "Incorrect"]},
            func="norm_cdf", stim_scale="linear", stim_selection_method="min_entropy",
        )  # fmt: skip
        self._stim = self._qp.next_stim
        self.level = round(self._stim["intensity"] * top)

    def update(self, correct: bool) -> None:
        self.trials += 1
        self._qp.update(stim=self._stim,
                        outcome={"response": "Correct" if correct else "Incorrect"})  # fmt: skip
        self._stim = self._qp.next_stim
        self.level = min(max(round(self._stim["intensity"] * self.top), 1), self.top)
