"""The adaptive tracks: whole device levels for the thresholds, log steps of gamma for the
constancy."""

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
