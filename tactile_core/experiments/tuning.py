"""Tuning the correction by feel: measure mu and gamma for this array and this hand.

The paper sets the threshold mu and the gamma of ``(1 - mu) I^gamma + mu`` by its authors'
judgement. This procedure measures them.

**The model.** A participant feels one tactor driven at ``d`` (the fraction of full drive the
array gets) with magnitude ``m(d) = ((d - TH) / (1 - TH))^K`` above a threshold ``TH`` and nothing
below, and adds several tactors by energy, ``M = sqrt(sum m_i^2)``. With ``mu = TH`` and
``gamma = 1 / (2K)`` the correction gives ``m_i = I_i^(1/2)``, so ``M = sqrt(sum I_i)``: wherever
the raw intensities sum to 1 (AS inside the hull, IM everywhere) a point between tactors feels
exactly as strong as a point on one, and the paper's correction becomes Tactile Brush's energy
law. Hence:

- **mu is the drive at which one tactor is just felt.** Two-interval forced choice (which of two
  intervals held the vibration?) over the device's own levels, one 3-down/1-up track per tactor
  for several tactors across the array, interleaved at random. A forced choice does not depend on
  the participant's criterion, as yes/no answers do. Each tactor's threshold is the drive at which
  it is felt half the time (75% correct), from a maximum-likelihood fit of a cumulative normal to
  all its trials; mu is their median, with a 95% interval from a parametric bootstrap of the
  median over the fits' profile-likelihood intervals.
- **gamma makes a point between tactors feel as strong as a point on a tactor.** Which of two
  intervals felt stronger: a point held midway between two tactors (raw 0.5 each, corrected with
  the candidate gamma and the measured mu) or a point on a tactor (raw 1, full drive)? gamma
  follows a 1-up/1-down track in log steps (x 1.4, then x 1.2 after two reversals) to the point
  of subjective equality, at two places on the array (one pair side by side, one above each
  other; their tracks start below and above the usual values). gamma is the PSE of one fit to
  both places' trials, with its profile-likelihood interval. A cell corner (four tactors at raw
  0.25 each) is tracked the same way, as the validation: under the model it has the same PSE.
  The constancy stimuli are dithered in time, so that the drive of a candidate gamma is not
  rounded to a level (one level, 1/22 of full drive, moves gamma by up to 12%).

A participant who never feels the array, or answers at random, ends the procedure with a
message and no correction; it never yields a mu or gamma outside [0, 0.95] and [0.1, 10].

The procedure is a :class:`~tactile_core.experiments.runners.Runner` like the experiments: one
CSV row per answer, flushed before it moves on, resumable, one participant at a time.
:func:`save_correction` writes the result as the participant's ``correction.json`` and a preset.
"""

from __future__ import annotations

import math
import random
import statistics
from dataclasses import dataclass, field
from pathlib import Path
from typing import ClassVar

import numpy as np

from .._shared import validate as _validate
from .._shared.jsonfile import read_json, write_json_atomic
from ..rendering.correction import Dither, quantize
from ..rendering.percept import felt_magnitude
from ..rendering.shapes import Line
from ..rendering.trace import render_frames
from .results import Session, now
from .runners import HEALTH_FIELDS, INTERVAL_S, Runner, Trial

EXPERIMENT = "correction"
CORRECTION_FILE = "correction.json"
FORMAT = "tactile-correction"
VERSION = 1
MU_MAX = 0.95
GAMMA_MIN, GAMMA_MAX = 0.1, 10.0
CHI2_95 = 1.920729410347062  # chi2(1 df) 95% quantile / 2: the profile-likelihood drop


# --- the model ---------------------------------------------------------------------------------


def felt_total(drive, threshold: float, exponent: float) -> float:
    """Felt magnitude of a whole frame: the tactors added by energy, ``sqrt(sum m_i^2)``."""
    m = felt_magnitude(drive, threshold, exponent)
    return float(np.sqrt(np.sum(m * m)))


def interval_drive(scene, profile) -> np.ndarray:
    """What the array's motors get over one interval: the mean drive per tactor.

    The scene is rendered at its frame rate for its duration, calibrated, and quantised (or
    dithered, if the scene dithers) to the profile's levels, exactly as the streamer sends it;
    a motor, far slower than the 300 Hz frames, feels the mean.

    Parameters
    ----------
    scene : Scene or None
        None (or a paused scene) is silence.
    profile : DeviceProfile

    Returns
    -------
    ndarray of float64, shape (rows, cols)
        Mean level / (levels - 1), in [0, 1].
    """
    grid = profile.grid
    if scene is None or not scene.active:
        return np.zeros(grid.shape)
    n = max(1, round(scene.duration_s * scene.rate_hz))
    _, frames = render_frames(
        scene.trace(), scene.method, sampling=scene.sampling(), mu=scene.mu, gamma=scene.gamma,
        grid=grid, n_frames=n, gain=scene.gain,
    )  # fmt: skip
    flat = frames.reshape(n, grid.size)
    if scene.felt_domain:
        flat = profile.drive_for(flat)
    flat = profile.calibrate(flat)
    if scene.dither:
        levels = Dither(grid.size, profile.levels).frames(flat)
    else:
        levels = quantize(flat, profile.levels)
    return (levels.mean(axis=0) / (profile.levels - 1)).reshape(grid.shape)


@dataclass
class SimulatedObserver:
    """The simulated participant of the contract: a power law above a threshold, energy
    summation, noisy answers.

    On each trial the threshold varies around ``threshold`` (normal, ``threshold_sd``); each
    interval's felt magnitude (:func:`felt_total` of :func:`interval_drive`) is perturbed in log
    units by ``weber`` (normal), and the stronger interval is chosen (an interval felt as nothing
    loses; two of them are a guess). With probability ``lapse`` the answer is a coin toss.

    Parameters
    ----------
    threshold : float
        ``TH`` in [0, 0.95].
    exponent : float
        ``K`` in [0.1, 10].
    seed : int
    threshold_sd : float
        Trial-to-trial spread of the threshold (drive units): the detection slope.
    weber : float
        Spread of felt magnitude in log units: the discrimination slope.
    lapse : float
        Probability of a random answer, in [0, 0.5].
    profile : DeviceProfile, optional
        The array the stimuli play on (the palm array by default).
    """

    threshold: float = 0.25
    exponent: float = 1.0
    seed: int = 0
    threshold_sd: float = 0.02
    weber: float = 0.15
    lapse: float = 0.03
    profile: object = None
    _cache: dict = field(default_factory=dict, repr=False)

    def __post_init__(self):
        from ..device.profile import default_profile

        self.threshold = _validate.in_range("threshold", self.threshold, 0.0, MU_MAX)
        self.exponent = _validate.in_range("exponent", self.exponent, 0.1, 10.0)
        self.threshold_sd = _validate.in_range("threshold_sd", self.threshold_sd, 0.0, 0.5)
        self.weber = _validate.in_range("weber", self.weber, 0.0, 5.0)
        self.lapse = _validate.in_range("lapse", self.lapse, 0.0, 0.5)
        self.rng = random.Random(self.seed)
        if self.profile is None:
            self.profile = default_profile()

    @property
    def mu(self) -> float:
        """The right threshold for this observer, ``TH``."""
        return self.threshold

    @property
    def gamma(self) -> float:
        """The right gamma for this observer, ``1 / (2K)``."""
        return 1.0 / (2.0 * self.exponent)

    def drive(self, scene) -> np.ndarray:
        """:func:`interval_drive` of ``scene``, remembered (threshold stimuli repeat)."""
        if scene is None:
            return np.zeros(self.profile.grid.shape)
        hit = self._cache.get(scene)
        if hit is None:
            hit = self._cache[scene] = interval_drive(scene, self.profile)
            if len(self._cache) > 4096:
                self._cache.clear()
        return hit

    def respond(self, trial):
        """The answer to ``trial``: ``"continue"`` to instructions, ``"1"`` or ``"2"`` to a
        two-interval trial."""
        if trial.kind == "continue":
            return "continue"
        if trial.kind != "interval":
            raise ValueError(f"the simulated observer answers interval trials, not {trial.kind!r}")
        rng = self.rng
        if rng.random() < self.lapse:
            return rng.choice(("1", "2"))
        th = min(max(rng.gauss(self.threshold, self.threshold_sd), 0.0), 0.999)
        felt = []
        for scene in trial.intervals:
            m = felt_total(self.drive(scene), th, self.exponent)
            felt.append(math.log(m) + rng.gauss(0.0, self.weber) if m > 0.0 else -math.inf)
        if felt[0] == felt[1]:
            return rng.choice(("1", "2"))
        return "1" if felt[0] > felt[1] else "2"

    def run(self, runner) -> None:
        """Answer every remaining trial of ``runner``."""
        while not runner.finished:
            runner.answer(self.respond(runner.current), rt_s=1.0)


# --- fitting -------------------------------------------------------------------------------------


@dataclass(frozen=True)
class CumulativeFit:
    """Maximum-likelihood fit of a cumulative normal to binary answers (see
    :func:`fit_cumulative`).

    Attributes
    ----------
    location : float
        Where the underlying function crosses one half (the threshold, or the PSE).
    ci : tuple of float
        95% profile-likelihood interval of ``location``; an end the data do not bound is NaN.
    scale : float
        Standard deviation of the cumulative normal (the inverse slope), in units of ``x``.
    lapse : float
        Fitted lapse rate.
    log_likelihood : float
    trials : int
    p_flat : float
        p of the likelihood-ratio test against answers that do not depend on ``x`` (2 df):
        large when the answers look random.
    """

    location: float
    ci: tuple
    scale: float
    lapse: float
    log_likelihood: float
    trials: int
    p_flat: float

    @property
    def bounded(self) -> bool:
        """True when both ends of the interval are finite."""
        return all(math.isfinite(v) for v in self.ci)


LAPSES = (0.0, 0.02, 0.05)


def _loglik_grid(x, answers, guess, locations, scales, decreasing, lapses, relative=False):
    """``(log-likelihood, lapse)`` grids over ``locations x scales``, the lapse maximised."""
    from scipy.special import ndtr

    xs = np.asarray(x, dtype=np.float64)
    ys = np.asarray(answers, dtype=bool)
    if xs.ndim != 1 or xs.shape != ys.shape or xs.size < 2 or not np.isfinite(xs).all():
        raise ValueError(f"a psychometric fit needs at least 2 finite trials, got {xs.size}")
    loc = np.asarray(locations, dtype=np.float64)
    sc = np.asarray(scales, dtype=np.float64)
    spread = sc[None, :, None] * (loc[:, None, None] if relative else 1.0)
    z = (xs[None, None, :] - loc[:, None, None]) / spread
    f = ndtr(-z if decreasing else z)
    best = np.full((loc.size, sc.size), -np.inf)
    best_lapse = np.zeros((loc.size, sc.size))
    for lapse in lapses:
        p = lapse / 2 + (1.0 - lapse) * (guess + (1.0 - guess) * f)
        p = np.clip(p, 1e-12, 1.0 - 1e-12)
        ll = np.where(ys, np.log(p), np.log1p(-p)).sum(axis=-1)
        better = ll > best
        best = np.where(better, ll, best)
        best_lapse = np.where(better, lapse, best_lapse)
    return best, best_lapse


def _fit_from_grid(ll, lapse, answers, locations, scales, scale_index=None) -> CumulativeFit:
    """The fit at the grid's maximum (over every scale, or at ``scale_index``), its profile
    interval, and the test against flat answers."""
    loc = np.asarray(locations, dtype=np.float64)
    if scale_index is None:
        profile = ll.max(axis=1)
        i, j = np.unravel_index(np.argmax(ll), ll.shape)
    else:
        j = scale_index
        profile = ll[:, j]
        i = int(np.argmax(profile))
    top = ll[i, j]
    inside = profile >= top - CHI2_95
    lo_i = i
    while lo_i > 0 and inside[lo_i - 1]:
        lo_i -= 1
    hi_i = i
    while hi_i < loc.size - 1 and inside[hi_i + 1]:
        hi_i += 1
    lo = math.nan if lo_i == 0 else float(loc[lo_i])
    hi = math.nan if hi_i == loc.size - 1 else float(loc[hi_i])
    ys = np.asarray(answers, dtype=bool)
    k, n = int(ys.sum()), int(ys.size)
    flat = sum(c * math.log(c / n) for c in (k, n - k) if c)
    p_flat = math.exp(-max(top - flat, 0.0))  # chi-square with 2 df: sf(x) = exp(-x / 2)
    return CumulativeFit(float(loc[i]), (lo, hi), float(scales[j]), float(lapse[i, j]),
                         float(top), n, p_flat)  # fmt: skip


def fit_cumulative(x, answers, *, guess: float, locations, scales, decreasing: bool = False,
                   lapses=LAPSES, relative: bool = False) -> CumulativeFit:  # fmt: skip
    """Fit ``p(x) = lapse/2 + (1 - lapse) (guess + (1 - guess) Phi(+-(x - location) / scale))``.

    A grid search (vectorised; exact to the grid's step) over ``locations`` x ``scales`` x
    ``lapses``: robust on the short, clustered tracks a staircase leaves, where a local
    optimiser can run off. ``guess`` is 0.5 for a two-interval detection (the chance of picking
    the right interval without feeling anything) and 0 for "which was stronger"; a lapse is a
    coin toss.

    Parameters
    ----------
    x : array_like of float, shape (n,)
        The stimulus value of each trial.
    answers : array_like of bool, shape (n,)
        Correct (detection) or "the test was stronger" (constancy).
    guess : float
        In [0, 1).
    locations, scales : array_like of float
        The grids searched (ascending; scales > 0).
    decreasing : bool
        True when ``p`` falls as ``x`` grows (the test weakens as gamma grows).
    lapses : sequence of float
    relative : bool
        The scale is a fraction of the location (``Phi((x - location) / (scale location))``),
        for a spread that grows with the location (gamma).

    Returns
    -------
    CumulativeFit
    """
    ll, lapse = _loglik_grid(x, answers, guess, locations, scales, decreasing, lapses, relative)
    return _fit_from_grid(ll, lapse, answers, locations, scales)


def fit_shared_scale(tracks, *, guess: float, locations, scales, decreasing: bool = False,
                     lapses=LAPSES) -> list[CumulativeFit]:  # fmt: skip
    """Fit several tracks with one common scale (slope) and a location each.

    The tactors of one participant share a slope; a short staircase track alone cannot tell a
    shallow function far away from a steep one nearby, and a lucky guess at a low level can
    then pull its location to the bottom of the grid. The common scale maximises the summed
    profile likelihood of the tracks; each location (and its interval) is then fitted at it.

    Parameters
    ----------
    tracks : sequence of (x, answers)
        One pair of arrays per track, as for :func:`fit_cumulative`.
    guess, locations, scales, decreasing, lapses
        As for :func:`fit_cumulative`.

    Returns
    -------
    list of CumulativeFit
        One per track, in order, all with the same ``scale``.
    """
    grids = [_loglik_grid(x, a, guess, locations, scales, decreasing, lapses) for x, a in tracks]
    total = sum(ll.max(axis=0) for ll, _ in grids)
    j = int(np.argmax(total))
    return [_fit_from_grid(ll, lapse, a, locations, scales, scale_index=j)
            for (ll, lapse), (_, a) in zip(grids, tracks)]  # fmt: skip


THRESHOLD_LOCATIONS = np.linspace(0.0, 1.0, 401)
THRESHOLD_SCALES = np.geomspace(0.004, 0.4, 24)
GAMMA_LOCATIONS = np.geomspace(GAMMA_MIN, GAMMA_MAX, 601)
GAMMA_SCALES = np.geomspace(0.02, 3.0, 24)


def fit_thresholds(tracks) -> list[CumulativeFit]:
    """Each tactor's threshold, the drive felt half the time (75% correct in two intervals),
    with a slope common to the tactors (:func:`fit_shared_scale`).

    Parameters
    ----------
    tracks : sequence of (drives, correct)
    """
    return fit_shared_scale(tracks, guess=0.5, locations=THRESHOLD_LOCATIONS,
                            scales=THRESHOLD_SCALES)  # fmt: skip


def fit_gamma(gammas, test_stronger) -> CumulativeFit:
    """The gamma of subjective equality.

    Fitted in gamma itself, with a spread proportional to it: under the model the felt
    difference between the test point and the tactor is linear in gamma (``ln M_test -
    ln M_tactor = ln(n) / 2 - K gamma ln(n)`` for ``n`` tactors at ``1 / n``), so the
    psychometric function is symmetric in gamma, not in ``ln gamma``; a fit in ``ln gamma``
    lands ~5% low on such data. The track still steps in log units.
    """
    return fit_cumulative(gammas, test_stronger, guess=0.0, locations=GAMMA_LOCATIONS,
                          scales=GAMMA_SCALES, decreasing=True, relative=True)  # fmt: skip


def median_interval(fits, seed: int = 0, draws: int = 4000) -> tuple[float, float]:
    """95% interval of the median of several fitted locations.

    A parametric bootstrap: each location is drawn from a normal whose standard deviation is its
    profile interval's width / 3.92 (an open end counts as the grid's end), the median taken, and
    the 2.5th and 97.5th percentiles of the medians reported. It carries the measurement error
    of each tactor's threshold into mu.
    """
    rng = np.random.default_rng(seed)
    loc = np.array([f.location for f in fits])
    lo = np.array([f.ci[0] if math.isfinite(f.ci[0]) else THRESHOLD_LOCATIONS[0] for f in fits])
    hi = np.array([f.ci[1] if math.isfinite(f.ci[1]) else THRESHOLD_LOCATIONS[-1] for f in fits])
    se = np.maximum(hi - lo, 1e-6) / 3.92
    samples = np.median(rng.normal(loc, se, size=(draws, loc.size)), axis=1)
    return float(np.percentile(samples, 2.5)), float(np.percentile(samples, 97.5))


# --- the procedure -------------------------------------------------------------------------------


@dataclass(frozen=True)
class TuningPlan:
    """How many trials each part of the procedure gets.

    Attributes
    ----------
    threshold_trials : int
        Per tactor (2..200).
    gamma_trials : int
        Per place (2..400), at each of the two places.
    corner_trials : int
        At the cell corner, the validation (0..400; 0 skips it).
    tactors : tuple of (col, row), optional
        The tactors whose thresholds are measured; default: five across the array
        (:func:`default_layout`).
    """

    threshold_trials: int = 20
    gamma_trials: int = 40
    corner_trials: int = 12
    tactors: tuple | None = None

    def __post_init__(self):
        _validate.integer("threshold_trials", self.threshold_trials, 2, 200)
        _validate.integer("gamma_trials", self.gamma_trials, 2, 400)
        _validate.integer("corner_trials", self.corner_trials, 0, 400)

    def to_dict(self) -> dict:
        """The JSON form (recorded in ``session.json``)."""
        return {
            "threshold_trials": self.threshold_trials,
            "gamma_trials": self.gamma_trials,
            "corner_trials": self.corner_trials,
            "tactors": None if self.tactors is None else [list(c) for c in self.tactors],
        }


def default_layout(grid) -> tuple[tuple, dict]:
    """The tactors measured and the constancy places on ``grid`` (at least 3 x 3).

    On the 5 x 6 palm array: tactors (1,1), (3,1), (2,2), (1,4), (3,4); the pair side by side
    is (1,2)-(2,2) (test point (2.0, 2.5), reference on (1,2)); the pair above each other is
    (3,3)-(3,4) (test point (3.5, 4.0), reference on (3,3)); the corner joins (1,3), (2,3), (1,4)
    and (2,4) (test point (2.0, 4.0), reference on (1,3)).

    Returns
    -------
    tactors : tuple of (col, row)
    places : dict
        ``{name: {"point": (x, y), "reference": (x, y), "start": gamma}}``.
    """
    cols, rows = grid.cols, grid.rows
    if cols < 3 or rows < 3:
        raise ValueError(
            f"tuning the correction needs a grid of at least 3 x 3, got {cols} x {rows}"
        )
    lo_c, lo_r = max(0, round((cols - 1) / 4)), max(0, round((rows - 1) / 4))
    hi_c, hi_r = cols - 1 - lo_c, rows - 1 - lo_r
    mid_c, mid_r = (cols - 1) // 2, (rows - 1) // 2
    tactors = tuple(dict.fromkeys(
        [(lo_c, lo_r), (hi_c, lo_r), (mid_c, mid_r), (lo_c, hi_r), (hi_c, hi_r)]
    ))  # fmt: skip
    h_c = min(lo_c, cols - 2)
    r1 = min(mid_r + 1, rows - 2)
    corner_c = max(mid_c, 1)
    places = {
        "side": {"point": (h_c + 1.0, mid_r + 0.5), "reference": (h_c + 0.5, mid_r + 0.5),
                 "start": 0.35},
        "above": {"point": (hi_c + 0.5, r1 + 1.0), "reference": (hi_c + 0.5, r1 + 0.5),
                  "start": 1.4},
        "corner": {"point": (float(corner_c), r1 + 1.0),
                   "reference": (corner_c - 0.5, r1 + 0.5), "start": 0.7},
    }  # fmt: skip
    return tactors, places


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


@dataclass
class TuningResult:
    """What the procedure found.

    Attributes
    ----------
    ok : bool
        False when it could not find a correction (``message`` says why; ``mu`` and ``gamma`` are
        then None and nothing may be applied).
    message : str
    mu, gamma : float or None
    mu_ci, gamma_ci : tuple of float
        95% intervals (NaN for an end the data did not bound).
    trials : int
        Answers given (instructions not counted).
    thresholds : dict
        ``{"col,row": {"threshold", "ci", "trials", "felt"}}`` per tactor measured.
    places : dict
        ``{place: {"gamma", "ci", "trials"}}`` per constancy place, the corner included.
    corner_agrees : bool or None
        Whether gamma lies within the corner's interval (None without a corner track).
    warnings : list of str
    """

    ok: bool
    message: str
    mu: float | None = None
    gamma: float | None = None
    mu_ci: tuple = (math.nan, math.nan)
    gamma_ci: tuple = (math.nan, math.nan)
    trials: int = 0
    thresholds: dict = field(default_factory=dict)
    places: dict = field(default_factory=dict)
    corner_agrees: bool | None = None
    warnings: list = field(default_factory=list)

    def to_dict(self) -> dict:
        """JSON form (NaN written as null)."""

        def clean(value):
            if isinstance(value, float):
                return value if math.isfinite(value) else None
            if isinstance(value, (list, tuple)):
                return [clean(v) for v in value]
            if isinstance(value, dict):
                return {k: clean(v) for k, v in value.items()}
            return value

        return clean({
            "ok": self.ok, "message": self.message, "mu": self.mu, "mu_ci": list(self.mu_ci),
            "gamma": self.gamma, "gamma_ci": list(self.gamma_ci), "trials": self.trials,
            "thresholds": self.thresholds, "places": self.places,
            "corner_agrees": self.corner_agrees, "warnings": self.warnings,
        })  # fmt: skip

    def summary(self) -> str:
        """A few lines for a terminal or a dialog."""
        if not self.ok:
            return f"No correction: {self.message}"
        lines = [
            f"mu    {self.mu:.3f}  (95% {_interval(self.mu_ci, '.3f')})",
            f"gamma {self.gamma:.3f}  (95% {_interval(self.gamma_ci, '.3f')})",
            f"{self.trials} trials",
        ]
        for cell, t in self.thresholds.items():
            felt = "" if t["felt"] else f"  ({t['problem']}: left out)"
            lines.append(f"  threshold at ({cell}): {t['threshold']:.3f} "
                         f"({_interval(t['ci'], '.3f')}){felt}")  # fmt: skip
        for name, p in self.places.items():
            lines.append(f"  gamma at {name}: {p['gamma']:.3f} ({_interval(p['ci'], '.3f')})")
        lines += [f"note: {w}" for w in self.warnings]
        return "\n".join(lines)


def _interval(ci, fmt: str) -> str:
    return " .. ".join("open" if not math.isfinite(v) else format(v, fmt) for v in ci)


class CorrectionTuning(Runner):
    """The guided procedure that measures mu and gamma (see the module notes).

    Parameters
    ----------
    session : Session
    plan : TuningPlan, optional
        Trial counts (the defaults: 20 per tactor, 40 per place, 12 at the corner: 192 trials,
        about 10 minutes at 3.2 s a trial; the README's benchmark table shows why).
    write, profile
        As for every runner.
    """

    experiment = EXPERIMENT
    fields = ("participant", "stage", "trial", "phase", "tactor", "level", "drive", "place",
              "mu", "gamma", "stimulus", "answer", "correct", "test_stronger", "rt_s", "time",
              *HEALTH_FIELDS)  # fmt: skip
    conditions: ClassVar[dict] = {}

    def __init__(self, session: Session, plan: TuningPlan | None = None, **kwargs):
        from ..device.profile import default_profile

        self.plan = plan or TuningPlan()
        profile = kwargs.get("profile") or default_profile()
        kwargs["profile"] = profile
        tactors, self.places = default_layout(profile.grid)
        if self.plan.tactors is not None:
            tactors = tuple((int(c), int(r)) for c, r in self.plan.tactors)
            for c, r in tactors:
                if not (0 <= c < profile.grid.cols and 0 <= r < profile.grid.rows):
                    raise ValueError(f"tactor ({c},{r}) is not on the {profile.grid.cols} x "
                                     f"{profile.grid.rows} grid")  # fmt: skip
        self.tactors = tactors
        if self.plan.corner_trials == 0:
            self.places = {k: v for k, v in self.places.items() if k != "corner"}
        self.conditions = {
            "plan": self.plan.to_dict(),
            "tactors": [f"{c},{r}" for c, r in tactors],
            "places": {k: {"point": list(v["point"]), "reference": list(v["reference"])}
                       for k, v in self.places.items()},
            "constancy_dither": True,
        }  # fmt: skip
        self.total = (
            2
            + len(tactors) * self.plan.threshold_trials
            + 2 * self.plan.gamma_trials
            + self.plan.corner_trials
        )
        self.failure = ""
        self.mu: float | None = None
        self.threshold_fits: dict = {}
        self.gamma_fits: dict = {}
        self.trials_by_stage: dict = {}
        super().__init__(session, **kwargs)

    # --- trials --------------------------------------------------------------------------------

    def _point_scene(self, point, mu, gamma, **extra):
        return self.make_scene(Line(point, point), "AS", mu, gamma, duration_s=INTERVAL_S,
                               pause_s=0.0, repeat=False, **extra)  # fmt: skip

    def _trials(self):
        self.failure, self.mu = "", None
        self.threshold_fits, self.gamma_fits = {}, {}
        data: dict = {}
        self.trials_by_stage = data
        top = self.profile.levels - 1
        yield Trial(
            EXPERIMENT, "intro-threshold", 0, "continue",
            "Part 1 of 2: two short intervals follow, 1 then 2; one of them holds a weak "
            "vibration. Press 1 or 2 for the one that held it; guess if unsure. Press a key to "
            "start.",
        )  # fmt: skip
        tracks = {cell: _LevelTrack(round(top / 2), top) for cell in self.tactors}
        counts = dict.fromkeys(self.tactors, 0)
        while True:
            open_cells = [c for c in self.tactors if counts[c] < self.plan.threshold_trials]
            if not open_cells:
                break
            cell = self.rng.choice(open_cells)
            track = tracks[cell]
            level = track.level
            centre = (cell[0] + 0.5, cell[1] + 0.5)
            stim = self.make_scene(Line(centre, centre), "CT", 0.0, 1.0, duration_s=INTERVAL_S,
                                   pause_s=0.0, repeat=False, gain=level / top)  # fmt: skip
            first = self.rng.random() < 0.5
            stage = f"threshold-c{cell[0]}r{cell[1]}"
            answer = yield Trial(
                EXPERIMENT, stage, counts[cell], "interval",
                "Which interval held the vibration? 1 or 2 (R: feel both again).",
                intervals=(stim, None) if first else (None, stim), options=("1", "2"),
                info={"phase": "threshold", "tactor": f"{cell[0]} {cell[1]}", "level": level,
                      "drive": f"{level / top:.6g}", "stimulus": "1" if first else "2"},
            )  # fmt: skip
            correct = answer == ("1" if first else "2")
            track.update(correct)
            data.setdefault(stage, []).append((level / top, correct))
            counts[cell] += 1
            self._after = {"correct": int(correct)}
        self._estimate_mu()
        if self.failure:
            return
        mu = self.mu
        yield Trial(
            EXPERIMENT, "intro-constancy", 0, "continue",
            "Part 2 of 2: two intervals again, both vibrating. Press 1 or 2 for the one that "
            "felt stronger; guess if they feel the same. Press a key to start.",
        )  # fmt: skip
        budget = {name: self.plan.corner_trials if name == "corner" else self.plan.gamma_trials
                  for name in self.places}  # fmt: skip
        tracks = {name: _LogTrack(p["start"]) for name, p in self.places.items()}
        counts = dict.fromkeys(self.places, 0)
        while True:
            open_places = [p for p in self.places if counts[p] < budget[p]]
            if not open_places:
                break
            name = self.rng.choice(open_places)
            place, track = self.places[name], tracks[name]
            gamma = round(track.level, 6)
            test = self._point_scene(place["point"], mu, gamma).replace(dither=True)
            reference = self._point_scene(place["reference"], mu, gamma).replace(dither=True)
            first = self.rng.random() < 0.5
            stage = f"gamma-{name}"
            answer = yield Trial(
                EXPERIMENT, stage, counts[name], "interval",
                "Which interval felt stronger? 1 or 2 (R: feel both again).",
                intervals=(test, reference) if first else (reference, test), options=("1", "2"),
                info={"phase": "constancy", "place": name, "mu": f"{mu:.6g}",
                      "gamma": f"{gamma:.6g}", "stimulus": "1" if first else "2"},
            )  # fmt: skip
            stronger = answer == ("1" if first else "2")
            track.update(stronger)
            data.setdefault(stage, []).append((gamma, stronger))
            counts[name] += 1
            self._after = {"test_stronger": int(stronger)}
        self._estimate_gamma()

    def _row(self, trial, answer):
        if trial.kind == "continue":
            return {"phase": trial.stage.removeprefix("intro-"), "answer": ""}
        return {**trial.info, "answer": answer, **self._after}

    # --- estimates -------------------------------------------------------------------------------

    def _estimate_mu(self) -> None:
        tracks = []
        for cell in self.tactors:
            rows = self.trials_by_stage[f"threshold-c{cell[0]}r{cell[1]}"]
            tracks.append(tuple(zip(*rows)))
        felt, problems = [], []
        for cell, fit, (drives, correct) in zip(self.tactors, fit_thresholds(tracks), tracks):
            share = sum(correct) / len(correct)
            problem = ""
            if fit.location >= MU_MAX or math.isnan(fit.ci[1]):
                problem = f"not felt reliably ({share:.0%} right; chance is 50%)"
            elif math.isnan(fit.ci[0]):
                problem = (
                    f"not bounded from below (mostly right down to drive {min(drives):.2f}): "
                    "the track did not reach the threshold"
                )
            self.threshold_fits[cell] = (fit, not problem, problem)
            if problem:
                problems.append(f"({cell[0]},{cell[1]}) {problem}")
            else:
                felt.append(fit)
        if len(felt) * 2 <= len(self.tactors):
            self.failure = (
                f"no threshold: {len(problems)} of {len(self.tactors)} tactors: "
                + "; ".join(problems)
                + ". Check that the hand is on the array and the array is on; a participant who "
                "answers at random looks like this too; more trials per tactor help a track "
                "that did not reach its threshold"
            )
            return
        self.mu = round(statistics.median(f.location for f in felt), 4)

    def _estimate_gamma(self) -> None:
        for name in self.places:
            rows = self.trials_by_stage.get(f"gamma-{name}", [])
            if rows:
                gammas, stronger = zip(*rows)
                self.gamma_fits[name] = fit_gamma(gammas, stronger)
        pooled = [r for n in self.places if n != "corner"
                  for r in self.trials_by_stage.get(f"gamma-{n}", [])]  # fmt: skip
        gammas, stronger = zip(*pooled)
        fit = fit_gamma(gammas, stronger)
        self.gamma_fits["pooled"] = fit
        edge = GAMMA_MIN * 1.05, GAMMA_MAX / 1.05
        if not edge[0] < fit.location < edge[1]:
            self.failure = (
                f"no point of equality between gamma {GAMMA_MIN:g} and {GAMMA_MAX:g}: the test "
                "point felt "
                + ("stronger" if fit.location >= edge[1] else "weaker")
                + " than the tactor at every gamma tried"
            )
        elif math.isnan(fit.ci[0]) and math.isnan(fit.ci[1]):
            # A 1-up/1-down track sits where the answers are 50/50 by design, so random answers
            # are told by where they leave the point of equality: anywhere.
            share = sum(stronger) / len(stronger)
            self.failure = (
                f"no point of equality: the answers did not settle on a gamma (the test point "
                f"was chosen {share:.0%} of the time over gammas {min(gammas):.2f}.."
                f"{max(gammas):.2f}; its 95% interval is {_interval(fit.ci, '.2f')}): "
                "the participant answered at random or could not compare the intervals; more "
                "trials may settle it"
            )

    def result(self) -> TuningResult:
        """The measured correction (only once :attr:`finished`)."""
        if not self.finished:
            raise ValueError("result: the procedure has not finished")
        trials = sum(len(v) for v in self.trials_by_stage.values())
        thresholds = {
            f"{c},{r}": {"threshold": fit.location, "ci": list(fit.ci), "trials": fit.trials,
                         "felt": ok, "problem": problem}
            for (c, r), (fit, ok, problem) in self.threshold_fits.items()
        }  # fmt: skip
        places = {
            name: {"gamma": fit.location, "ci": list(fit.ci), "trials": fit.trials}
            for name, fit in self.gamma_fits.items() if name != "pooled"
        }  # fmt: skip
        if self.failure:
            return TuningResult(False, self.failure, trials=trials, thresholds=thresholds,
                                places=places)  # fmt: skip
        felt = [fit for fit, ok, _ in self.threshold_fits.values() if ok]
        warnings = [
            f"tactor ({c},{r}) {problem}: left out of mu (check its motor if it was not felt)"
            for (c, r), (_, ok, problem) in self.threshold_fits.items() if not ok
        ]  # fmt: skip
        pooled = self.gamma_fits["pooled"]
        gamma = round(pooled.location, 4)
        corner = self.gamma_fits.get("corner")
        agrees = None
        if corner is not None:
            lo, hi = corner.ci
            agrees = (math.isnan(lo) or lo <= gamma) and (math.isnan(hi) or gamma <= hi)
            if not agrees:
                warnings.append(
                    f"at the cell corner gamma {corner.location:.2f} "
                    f"({_interval((lo, hi), '.2f')}) differs from {gamma:.2f}: energy "
                    "summation may not hold for four tactors on this hand"
                )
        return TuningResult(
            True, "measured", mu=self.mu, gamma=gamma,
            mu_ci=median_interval(felt, seed=self.session.seed),
            gamma_ci=tuple(pooled.ci), trials=trials,
            thresholds=thresholds, places=places, corner_agrees=agrees, warnings=warnings,
        )  # fmt: skip

    def calibration(self) -> tuple[list[float], list[float], list[float]]:
        """Per-tactor ``(offset, gain, threshold)`` in flat cell order from the thresholds
        measured, for the device profile (see
        :meth:`~tactile_core.experiments.runners.Calibration.calibration`); tactors not measured
        are left as they are (offset 0, gain 1, the median threshold)."""
        from .runners import calibration_from_thresholds

        measured = {cell: fit.location for cell, (fit, ok, _) in self.threshold_fits.items() if ok}
        if not measured:
            raise ValueError("calibration: no tactor threshold was measured")
        return calibration_from_thresholds(measured, self.profile.grid)


def simulate_tuning(threshold: float, exponent: float, seed: int = 0, plan=None, **observer):
    """Run the procedure against a :class:`SimulatedObserver` in memory.

    Parameters
    ----------
    threshold, exponent : float
        The observer's ``TH`` and ``K``.
    seed : int
        Seeds the observer and the procedure.
    plan : TuningPlan, optional
    **observer
        Further :class:`SimulatedObserver` parameters (``threshold_sd``, ``weber``, ``lapse``,
        ``profile``).

    Returns
    -------
    TuningResult
    """
    seed = _validate.integer("seed", seed, 0, 2**31 - 1)
    sim = SimulatedObserver(threshold, exponent, seed=seed, **observer)
    session = Session(participant="simulated", seed=seed)
    runner = CorrectionTuning(session, plan, write=False, profile=sim.profile)
    sim.run(runner)
    return runner.result()


# --- keeping the result ------------------------------------------------------------------------


def save_correction(runner: CorrectionTuning, result: TuningResult | None = None) -> tuple:
    """Keep a successful result as the participant's correction.

    Writes ``correction.json`` in the participant's folder (the result, the participant, when,
    the device profile and the plan) and a preset ``correction-<participant>.json`` beside it
    (the Experiment 1 line with the measured mu and gamma), both atomically. Later experiment
    sessions of the participant record the correction (``session.json``, ``runs``).

    Returns
    -------
    (Path, Path)
        The correction record and the preset.

    Raises
    ------
    ValueError
        If the result is not a correction (``ok`` false): nothing is written.
    """
    from ..files.presets import Preset, save_preset
    from ..rendering.scene import Scene
    from .runners import Experiment1

    result = result or runner.result()
    if not result.ok:
        raise ValueError(f"nothing to save: {result.message}")
    folder = Path(runner.session.folder)
    pid = runner.session.participant
    record = {
        "format": FORMAT,
        "version": VERSION,
        "participant": pid,
        "measured": now(),
        "device_profile": runner.profile.record(),
        "plan": runner.plan.to_dict(),
        **result.to_dict(),
    }
    path = write_json_atomic(folder / CORRECTION_FILE, record)
    notes = (
        f"Measured for participant {pid} on {record['measured']}: mu {result.mu:.3f} "
        f"(95% {_interval(result.mu_ci, '.3f')}), gamma {result.gamma:.3f} "
        f"(95% {_interval(result.gamma_ci, '.3f')}), {result.trials} trials."
    )
    scene = Scene(Experiment1.LINE, "IM", result.mu, result.gamma)
    preset = save_preset(
        Preset(scene, name=f"correction {pid}", notes=notes, device_profile=runner.profile.name),
        folder / f"correction-{pid}.json",
    )
    return path, preset


def load_correction(folder) -> dict | None:
    """The participant's ``correction.json`` in ``folder`` as a dict, or None if there is none.

    Raises
    ------
    ValueError
        If the file exists but is not a valid correction record (it names the file).
    """
    path = Path(folder) / CORRECTION_FILE
    if not path.exists():
        return None
    data = read_json(path)
    if not isinstance(data, dict) or data.get("format") != FORMAT:
        raise ValueError(f"{path}: not a correction record (format {FORMAT!r})")
    try:
        mu = _validate.in_range("mu", data.get("mu"), 0.0, MU_MAX)
        gamma = _validate.in_range("gamma", data.get("gamma"), GAMMA_MIN, GAMMA_MAX)
    except ValueError as exc:
        raise ValueError(f"{path}: {exc}") from None
    return {**data, "mu": mu, "gamma": gamma}
