"""Simulated participants, for testing the runners and for planning studies.

A :class:`SimulatedParticipant` answers any runner's trials:

- Experiment 1: ratings drawn around a mean per method and property.
- Experiment 2: a psychometric function of line length, a logistic in log length with a guess
  rate of 0.25 (four alternatives) and a small lapse rate (:class:`Psychometric`).
- Experiment 3: right with a probability per method.
- Calibration: "felt" with a logistic probability around each tactor's true threshold.

The defaults follow the paper's findings qualitatively (anti-aliased methods rated higher;
sub-tactor line lengths detectable; IM best at telling circles from squares); they are a model
for exercising the software, not data.
"""

from __future__ import annotations

import math
import random
from dataclasses import dataclass, field


@dataclass(frozen=True)
class Psychometric:
    """P(correct) for a four-alternative direction task as a function of line length.

    ``p(L) = guess + (1 - guess - lapse) / (1 + exp(-slope * (ln L - ln midpoint)))``

    Attributes
    ----------
    midpoint : float
        Length (grid units) at the logistic's centre.
    slope : float
        Steepness in log length.
    guess, lapse : float
        Chance rate (0.25 for four alternatives) and lapse rate.
    """

    midpoint: float
    slope: float = 4.0
    guess: float = 0.25
    lapse: float = 0.02

    def p_correct(self, length: float) -> float:
        """Probability of a correct answer at ``length``."""
        if length <= 0:
            return self.guess
        z = self.slope * (math.log(length) - math.log(self.midpoint))
        return self.guess + (1.0 - self.guess - self.lapse) / (1.0 + math.exp(-z))

    def length_at(self, p: float) -> float:
        """The length answered correctly with probability ``p`` (e.g. 0.707)."""
        span = 1.0 - self.guess - self.lapse
        if not self.guess < p < self.guess + span:
            raise ValueError(f"p must be within ({self.guess}, {self.guess + span}), got {p!r}")
        q = (p - self.guess) / span
        return self.midpoint * math.exp(math.log(q / (1.0 - q)) / self.slope)


DEFAULT_RATINGS = {
    # mean rating (0-100) per method for quality, smoothness, thickness
    "CT": (30.0, 25.0, 50.0),
    "MM": (32.0, 28.0, 50.0),
    "AS": (65.0, 70.0, 55.0),
    "IM": (66.0, 72.0, 50.0),
}
DEFAULT_EXP2 = {"L1": 0.9, "L2": 0.35, "L3": 0.55, "L4": 0.4}  # 70.7% lengths
DEFAULT_EXP3 = {"CT": 0.55, "MM": 0.55, "AS": 0.62, "IM": 0.85}  # P(correct)


@dataclass
class SimulatedParticipant:
    """Answers runner trials from a model of a participant.

    Parameters
    ----------
    seed : int
        Seeds the answers.
    ratings : dict
        ``{method: (quality, smoothness, thickness)}`` mean ratings; a method not listed
        (a peer method, a plug-in) gets 50 for each.
    rating_sd : float
        Spread of ratings around the means.
    exp2_lengths : dict
        ``{condition: length}`` answered correctly 70.7% of the time.
    exp2_slope : float
        Slope of the psychometric functions (in log length).
    exp3_accuracy : dict
        ``{method: P(correct)}`` for circle/square; 0.75 for a method not listed.
    timeout_rate : float
        Chance of not answering within the time limit.
    tactor_thresholds : dict
        ``{(col, row): threshold}`` for the calibration; 0.25 for every tactor if empty.
    detection_spread : float
        Width of the detection logistic (drive units).
    correction : (float, float)
        ``(TH, K)`` of the contract's simulated participant
        (:class:`~tactile_core.experiments.tuning.SimulatedObserver`), who answers the
        correction tuning's two-interval trials.
    """

    seed: int = 0
    ratings: dict = field(default_factory=lambda: dict(DEFAULT_RATINGS))
    rating_sd: float = 8.0
    exp2_lengths: dict = field(default_factory=lambda: dict(DEFAULT_EXP2))
    exp2_slope: float = 4.0
    exp3_accuracy: dict = field(default_factory=lambda: dict(DEFAULT_EXP3))
    timeout_rate: float = 0.0
    tactor_thresholds: dict = field(default_factory=dict)
    detection_spread: float = 0.03
    correction: tuple = (0.25, 1.0)

    def __post_init__(self):
        self.rng = random.Random(self.seed)
        self._observer = None

    def psychometric(self, condition: str) -> Psychometric:
        """The Experiment 2 psychometric function of ``condition``, placed so that its 70.7%
        point is ``exp2_lengths[condition]``."""
        base = Psychometric(1.0, self.exp2_slope)
        shift = base.length_at(0.707)
        return Psychometric(self.exp2_lengths[condition] / shift, self.exp2_slope)

    def respond(self, trial):
        """An answer to ``trial`` (any runner's)."""
        kind = trial.kind
        if kind in ("continue", "prepare"):
            return "continue"
        if kind == "rating":
            prop = ("quality", "smoothness", "thickness").index(trial.info["property"])
            mean = self.ratings.get(trial.info["method"], (50, 50, 50))[prop]
            return int(min(max(round(self.rng.gauss(mean, self.rating_sd)), 0), 100))
        if kind == "direction":
            p = self.psychometric(trial.stage).p_correct(float(trial.info["length"]))
            right = trial.info["direction"]
            if self.rng.random() < p:
                return right
            return self.rng.choice([d for d in trial.options if d != right])
        if kind == "shape":
            if self.rng.random() < self.timeout_rate:
                return None
            right = trial.info["shape"]
            if self.rng.random() < self.exp3_accuracy.get(trial.info["method"], 0.75):
                return right
            return next(s for s in trial.options if s != right)
        if kind == "detect":
            col, row = map(int, trial.info["tactor"].split())
            threshold = self.tactor_thresholds.get((col, row), 0.25)
            level = float(trial.info["level"])
            p = 1.0 / (1.0 + math.exp(-(level - threshold) / self.detection_spread))
            return "yes" if self.rng.random() < p else "no"
        if kind == "interval":  # the correction tuning: the contract's simulated participant
            if self._observer is None:
                from .tuning import SimulatedObserver

                threshold, exponent = self.correction
                self._observer = SimulatedObserver(threshold, exponent, seed=self.seed)
            return self._observer.respond(trial)
        raise ValueError(f"trial kind {kind!r} is not known to the simulated participant")

    def run(self, runner, rt_s: float = 1.0):
        """Answer every remaining trial of ``runner``; return the feedback texts."""
        feedback = []
        while not runner.finished:
            if runner.current.kind == "prepare":
                n = len(runner.current.options)
                for key in (*range(1, n + 1), 2, min(3, n)):  # every key, then back
                    runner.select(key)
            feedback.append(runner.answer(self.respond(runner.current), rt_s=rt_s))
        return feedback
