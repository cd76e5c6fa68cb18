"""Adaptive staircases (Levitt 1971), as in the paper's Experiment 2."""

from __future__ import annotations

import numpy as np

from .._shared import validate as _validate


class Staircase:
    """An up-down staircase with multiplicative steps.

    The level is multiplied by ``down`` after ``n_down`` correct answers in a row and by ``up``
    after ``n_up`` wrong answers in a row. With the paper's 2-down/1-up rule it converges on the
    level answered correctly 70.7% of the time; its steps, x 0.685 (31.5% shorter) and x 1.46
    (46% longer), are equal in log units (0.685 = 1 / 1.46).

    Parameters
    ----------
    start : float
        First level (> 0); 2.0 grid units (36 mm) in the paper.
    down, up : float
        Step factors, ``0 < down < 1 < up``.
    n_down, n_up : int
        Answers in a row needed for a step down / up.
    min_level, max_level : float, optional
        Bounds the level is clipped to (e.g. the largest line the array can show).

    Attributes
    ----------
    levels : list of float
        Level presented at each trial so far.
    answers : list of bool
        The answers given.
    reversal_levels : list of float
        Levels at which the track changed direction, in order: the level presented in the
        trial whose answer turned the track (a peak when it turns down, a valley when it turns
        up). The first step sets a direction and is not a reversal.

    Examples
    --------
    >>> sc = Staircase(start=2.0, down=0.685, up=1.46, n_down=2, n_up=1)
    >>> [round(sc.update(a), 4) for a in (True, True, False, True, True)]
    [2.0, 1.37, 2.0002, 2.0002, 1.3701]
    >>> sc.reversal_levels
    [1.37, 2.0002]
    """

    def __init__(
        self,
        start: float = 2.0,
        down: float = 0.685,
        up: float = 1.46,
        n_down: int = 2,
        n_up: int = 1,
        min_level: float | None = None,
        max_level: float | None = None,
    ):
        self.start = _validate.positive("start", start)
        self.down = _validate.in_range("down", down, 0.0, 1.0)
        self.up = _validate.real("up", up)
        if not 0.0 < self.down < 1.0:
            raise ValueError(f"down must be within (0, 1), got {down!r}")
        if self.up <= 1.0:
            raise ValueError(f"up must be > 1, got {up!r}")
        self.n_down = _validate.integer("n_down", n_down, 1)
        self.n_up = _validate.integer("n_up", n_up, 1)
        self.min_level = None if min_level is None else _validate.positive("min_level", min_level)
        self.max_level = None if max_level is None else _validate.positive("max_level", max_level)
        self.level = self._clip(self.start)
        self.levels: list[float] = []
        self.answers: list[bool] = []
        self.reversal_levels: list[float] = []
        self.reversal_trials: list[int] = []
        self._direction = 0  # -1 going down, +1 going up, 0 not yet moved
        self._run_correct = 0
        self._run_wrong = 0

    def _clip(self, level: float) -> float:
        if self.min_level is not None:
            level = max(level, self.min_level)
        if self.max_level is not None:
            level = min(level, self.max_level)
        return level

    @property
    def trials(self) -> int:
        """Answers recorded so far."""
        return len(self.answers)

    def update(self, correct: bool) -> float:
        """Record the answer to the current level; return the next level to present."""
        if not (
            isinstance(correct, (bool, np.bool_))
            or (isinstance(correct, int) and correct in (0, 1))
        ):
            raise ValueError(f"correct must be True or False, got {correct!r}")
        correct = bool(correct)
        presented = self.level
        self.levels.append(presented)
        self.answers.append(correct)
        step = 0
        if correct:
            self._run_correct += 1
            self._run_wrong = 0
            if self._run_correct >= self.n_down:
                step = -1
                self._run_correct = 0
        else:
            self._run_wrong += 1
            self._run_correct = 0
            if self._run_wrong >= self.n_up:
                step = +1
                self._run_wrong = 0
        if step:
            if self._direction and step != self._direction:
                self.reversal_levels.append(presented)
                self.reversal_trials.append(len(self.answers) - 1)
            self._direction = step
            self.level = self._clip(presented * (self.down if step < 0 else self.up))
        return self.level

    def estimate(self, n: int = 4) -> float:
        """Mean of the last ``n`` reversal levels (the paper: the last two peaks and the last
        two valleys, ``n = 4``).

        Raises
        ------
        ValueError
            If fewer than ``n`` reversals have happened.
        """
        n = _validate.integer("n", n, 1)
        if len(self.reversal_levels) < n:
            raise ValueError(
                f"n = {n} reversals are needed for an estimate, the track has "
                f"{len(self.reversal_levels)}"
            )
        last = self.reversal_levels[-n:]
        return sum(last) / n
