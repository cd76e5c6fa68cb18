"""Predicted percept: what a method should feel like, before anyone feels it.

**The model.** A participant feels one tactor at effective drive ``d`` with magnitude
``m(d) = ((d - TH) / (1 - TH))^K`` above a threshold ``TH`` and nothing below, and adds several
tactors by energy, ``M = sqrt(sum m_i^2)`` (the model of the correction tuning,
:mod:`tactile_core.experiments.tuning`). For each frame of a trace this module gives

- the **felt intensity** ``M``, and its **ripple** along the trace, ``max M / min M`` over the
  frames in which something is felt (1 is perfectly even);
- the **centroid**, the tactor centres weighted by their felt *energies* ``m_i^2`` (the
  location rule of the energy model: two tactors at energies ``A_1^2`` and ``A_2^2`` are felt at
  ``beta = A_2^2 / (A_1^2 + A_2^2)`` of the way from the first to the second, Tactile Brush's
  rule), and its distance from the true point ``f(t)``, in millimetres.

**Which participant.** A prediction is for a stated participant (``threshold``, ``exponent``);
by default :data:`REFERENCE` (TH 0.2, K 1: the palm array's motors start near drive 0.2, paper
section 4.2, and felt magnitude linear in drive above it), never the one a correction is
tailored to. :func:`predict_range` gives the spread over :func:`participant_grid` (TH 0-0.45 x
K 0.36-1.4), which is what the tables report: for the participant a correction is tailored to
(``TH = mu``, ``K = 1 / (2 gamma)``) AS and IM are even *by construction*, and any other
participant feels them unevenly.

**What is sent.** By default the prediction is in continuous time (``samples`` points). With
``rate_hz`` the trace is point-sampled at that frame rate (the paper's 300 Hz), with ``levels``
rounded to the device's levels (the paper's 23), and with ``motor`` (a
:class:`~tactile_core.rendering.motor.MotorResponse`) low-passed by the motors before it is
felt: the prediction then starts from motors at rest and leaves the first ``3 tau_up`` of the
trace, while they spin up (alike for every method), out of the ripple and the error. With
``compensate`` the frames are sent as motor-aware drive for those motors
(:mod:`~tactile_core.rendering.motor_drive`), which ``motor`` then feels.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np

from .._shared import validate as _validate
from .correction import correct, quantize
from .geometry import Grid
from .methods import get_method
from .motor_drive import motor_drive
from .rasterize import render
from .trace import Sampling, Trace, render_frames

PITCH_MM = 18.0
"""The palm array's tactor pitch."""


@dataclass(frozen=True)
class Participant:
    """A participant of the model: threshold ``TH`` (drive fraction) and exponent ``K``."""

    threshold: float
    exponent: float

    def __post_init__(self):
        _validate.in_range("threshold", self.threshold, 0.0, 0.99)
        _validate.in_range("exponent", self.exponent, 0.01, 100.0)

    @property
    def label(self) -> str:
        """``"TH 0.2, K 1"``."""
        return f"TH {self.threshold:g}, K {self.exponent:g}"


REFERENCE = Participant(0.2, 1.0)
"""The participant of a single prediction unless one is given."""
LINEAR_ENERGY = Participant(0.0, 1.0)
"""No threshold, felt magnitude equal to drive: the participant EN is designed for."""
THRESHOLDS = (0.0, 0.1, 0.2, 0.33, 0.45)
"""Thresholds of :func:`participant_grid`: none, to well above the paper's mu 0.33."""
EXPONENTS = (0.36, 0.5, 0.71, 1.0, 1.4)
"""Exponents of :func:`participant_grid`: from the participant the paper's mu 0 / gamma 1.4 is
tailored to (K 0.36) through its mu 0.33 / gamma 0.7 (K 0.71) to an accelerating 1.4."""


def participant_grid(thresholds=THRESHOLDS, exponents=EXPONENTS) -> tuple[Participant, ...]:
    """Every ``(threshold, exponent)`` pair, thresholds outermost (25 by default)."""
    return tuple(Participant(th, k) for th, k in itertools.product(thresholds, exponents))


def tailored(mu: float, gamma: float) -> Participant:
    """The participant the correction ``mu``/``gamma`` is right for: ``TH = mu``,
    ``K = 1 / (2 gamma)``."""
    return Participant(mu, 1.0 / (2.0 * _validate.positive("gamma", gamma)))


@dataclass(frozen=True)
class Percept:
    """The predicted percept of one trace.

    Attributes
    ----------
    t : ndarray, shape (n,)
        Trace parameters (of the middle of each frame, for frames).
    felt : ndarray, shape (n,)
        Felt intensity ``M`` per sample or frame (1 = one tactor at full drive).
    centroid : ndarray, shape (n, 2)
        Felt-energy-weighted centroid in grid units (NaN where nothing is felt).
    point : ndarray, shape (n, 2)
        The true point ``f(t)`` in grid units.
    error_mm : ndarray, shape (n,)
        Distance from the centroid to the point, in mm (NaN where nothing is felt).
    valid : ndarray of bool, shape (n,), optional
        The samples the summaries use (all by default; with a motor, those after spin-up).
    """

    t: np.ndarray
    felt: np.ndarray
    centroid: np.ndarray
    point: np.ndarray
    error_mm: np.ndarray
    valid: np.ndarray | None = None

    def _use(self, values):
        return values if self.valid is None else values[self.valid]

    @property
    def ripple(self) -> float:
        """``max / min`` of the felt intensity over the samples used (inf if one of them is
        felt as nothing)."""
        felt = self._use(self.felt)
        if felt.size == 0 or not (felt > 0).all():
            return float("inf")
        return float(felt.max() / felt.min())

    @property
    def mean_error_mm(self) -> float:
        """Mean centroid error over the felt samples used, in mm."""
        e = self._use(self.error_mm)
        e = e[np.isfinite(e)]
        return float(e.mean()) if e.size else float("nan")

    @property
    def max_error_mm(self) -> float:
        """Largest centroid error over the felt samples used, in mm."""
        e = self._use(self.error_mm)
        e = e[np.isfinite(e)]
        return float(e.max()) if e.size else float("nan")


def felt_magnitude(drive, threshold: float, exponent: float) -> np.ndarray:
    """Per-tactor felt magnitude ``((d - TH) / (1 - TH))^K`` above ``TH``, 0 at or below.

    Parameters
    ----------
    drive : array_like, any shape
        Drive fractions in [0, 1].
    threshold : float
        ``TH`` in [0, 1).
    exponent : float
        ``K`` > 0.
    """
    d = np.asarray(drive, dtype=np.float64)
    x = np.clip((d - threshold) / (1.0 - threshold), 0.0, None)
    return np.where(d > threshold, x**exponent, 0.0)


@dataclass(frozen=True)
class Drive:
    """What the motors get (or, with a motor model, the effective drive) along one trace.

    Attributes
    ----------
    t : ndarray, shape (n,)
    point : ndarray, shape (n, 2)
        The true point, grid units.
    drive : ndarray, shape (n, rows, cols)
        Drive fractions in [0, 1].
    valid : ndarray of bool, shape (n,) or None
    """

    t: np.ndarray
    point: np.ndarray
    drive: np.ndarray
    valid: np.ndarray | None = None


def trace_drive(shape, method, mu: float = 0.33, gamma: float = 0.7, *,
                grid: Grid | None = None, samples: int = 2001, rate_hz: float | None = None,
                levels: int | None = None, motor=None, duration_s: float = 2.0,
                own_correction: bool = False, compensate=None) -> Drive:  # fmt: skip
    """The drive of one trace, in continuous time or as sent (see the module notes).

    Parameters
    ----------
    shape : Shape
    method : str
        Any registered method or spec.
    mu, gamma : float
        The correction set.
    grid : Grid, optional
        The palm array's 5 x 6 by default.
    samples : int
        Points along the trace in continuous time (without ``rate_hz``).
    rate_hz : float, optional
        Frame rate: point sampling at this rate over one trace of ``duration_s``.
    levels : int, optional
        Round the frames to this many device levels (needs ``rate_hz``).
    motor : MotorResponse, optional
        Low-pass the frames through the motors (needs ``rate_hz``).
    duration_s : float
        Seconds per trace (the paper's 2 s).
    own_correction : bool
        Drive the method with its own correction
        (:meth:`~tactile_core.rendering.methods.Method.own_correction`: none for EN) instead of
        ``mu``/``gamma`` as given.
    compensate : MotorResponse, optional
        Send motor-aware drive (:mod:`~tactile_core.rendering.motor_drive`) pre-compensated for
        these motors, before the levels (needs ``rate_hz``); ``motor`` stays the motors that
        feel it, so a mismatch between the two can be predicted.

    Returns
    -------
    Drive
    """
    grid = grid or Grid()
    m = get_method(method).on_clock(duration_s)  # TB times its onsets by the trace
    if own_correction:
        mu, gamma = m.own_correction(mu, gamma)
    if rate_hz is None:
        if levels is not None or motor is not None or compensate is not None:
            raise ValueError("levels, motor and compensate need rate_hz: they act on frames")
        samples = _validate.integer("samples", samples, 2, 1_000_000)
        t = np.linspace(0.0, 1.0, samples)
        drive = correct(render(shape, m, t, grid=grid), mu, gamma)
        return Drive(t, np.stack(shape.xy(t), axis=1), drive)
    rate_hz = _validate.rate("rate_hz", rate_hz, 1.0, 10_000.0)
    trace = Trace(shape, _validate.duration("duration_s", duration_s), 0.0, repeat=False)
    n = max(2, round(trace.duration_s * rate_hz))
    start, frames = render_frames(trace, m, sampling=Sampling(rate_hz, "point"), mu=mu,
                                  gamma=gamma, grid=grid, n_frames=n)  # fmt: skip
    if compensate is not None:
        frames, _ = motor_drive(frames, compensate, rate_hz)
    if levels is not None:
        levels = _validate.integer("levels", levels, 2, 256)
        frames = quantize(frames, levels) / (levels - 1)
    valid = None
    if motor is not None:
        flat, _ = motor.effective(frames.reshape(n, grid.size), rate_hz)
        frames = flat.reshape(frames.shape)
        settle_s = 3.0 * float(np.max(motor.taus(grid.size)[0]))
        valid = start >= settle_s - 1e-12
    mid, _ = trace.parameter(np.minimum(start + 0.5 / rate_hz, trace.duration_s))
    return Drive(mid, np.stack(shape.xy(mid), axis=1), frames, valid)


def percept_of(drive: Drive, threshold: float, exponent: float, *, grid: Grid | None = None,
               pitch_mm: float = PITCH_MM) -> Percept:  # fmt: skip
    """The percept of ``drive`` for the participant ``threshold``/``exponent``."""
    grid = grid or Grid()
    m = felt_magnitude(drive.drive, threshold, exponent)
    energy = m * m
    felt = np.sqrt(energy.sum(axis=(1, 2)))
    weight = energy.sum(axis=(1, 2))
    cx = np.arange(grid.cols) + 0.5
    cy = np.arange(grid.rows) + 0.5
    with np.errstate(invalid="ignore", divide="ignore"):
        centroid = np.stack([np.einsum("nij,j->n", energy, cx) / weight,
                             np.einsum("nij,i->n", energy, cy) / weight], axis=1)  # fmt: skip
    centroid[weight <= 0] = np.nan
    error_mm = np.hypot(*(centroid - drive.point).T) * pitch_mm
    return Percept(drive.t, felt, centroid, drive.point, error_mm, drive.valid)


def predict(shape, method, mu: float = 0.33, gamma: float = 0.7, *,
            threshold: float | None = None, exponent: float | None = None,
            grid: Grid | None = None, samples: int = 2001, rate_hz: float | None = None,
            levels: int | None = None, motor=None, duration_s: float = 2.0,
            own_correction: bool = False, pitch_mm: float = PITCH_MM,
            compensate=None) -> Percept:  # fmt: skip
    """The predicted percept of ``shape`` rendered by ``method`` for one participant.

    Parameters
    ----------
    shape : Shape
    method : str
        Any registered method or spec (``"AS"``, ``"RO:r=1.5"``, a plug-in).
    mu, gamma : float
        The correction the frames are played with.
    threshold, exponent : float, optional
        The participant's ``TH`` and ``K``; by default those of :data:`REFERENCE`. Pass
        ``tailored(mu, gamma)``'s to see the participant the correction is right for.
    grid, samples, rate_hz, levels, motor, duration_s, own_correction, compensate
        As for :func:`trace_drive`: continuous time by default; ``rate_hz=300, levels=23`` is
        what the paper's array was sent.
    pitch_mm : float
        Tactor pitch, for the centroid error.

    Returns
    -------
    Percept
    """
    grid = grid or Grid()
    pitch_mm = _validate.positive("pitch_mm", pitch_mm)
    th = REFERENCE.threshold if threshold is None else threshold
    k = REFERENCE.exponent if exponent is None else exponent
    who = Participant(th, k)
    drive = trace_drive(shape, method, mu, gamma, grid=grid, samples=samples, rate_hz=rate_hz,
                        levels=levels, motor=motor, duration_s=duration_s,
                        own_correction=own_correction, compensate=compensate)  # fmt: skip
    return percept_of(drive, who.threshold, who.exponent, grid=grid, pitch_mm=pitch_mm)


STAGES = ("continuous", "sent", "felt")
"""What :func:`predict_range` predicts from: the continuous trace, the frames sent (rate and
levels), and those frames through the motors."""


@dataclass(frozen=True)
class PerceptRange:
    """Ripple and centroid error of one method over a range of participants.

    Attributes
    ----------
    participants : tuple of Participant
    ripple, mean_error_mm : dict
        ``{stage: ndarray of shape (len(participants),)}`` for each stage of :data:`STAGES`
        predicted.
    """

    participants: tuple
    ripple: dict
    mean_error_mm: dict

    def at(self, stage: str, who: Participant) -> tuple[float, float]:
        """``(ripple, mean error mm)`` of participant ``who`` at ``stage``."""
        i = self.participants.index(who)
        return float(self.ripple[stage][i]), float(self.mean_error_mm[stage][i])

    def span(self, stage: str) -> str:
        """``"1.00-1.31"``: the ripple's range over the participants at ``stage``."""
        r = self.ripple[stage]
        return f"{np.min(r):.2f}-{np.max(r):.2f}"


def predict_range(shape, method, mu: float = 0.33, gamma: float = 0.7, *, participants=None,
                  grid: Grid | None = None, samples: int = 2001, rate_hz: float = 300.0,
                  levels: int = 23, motor=None, duration_s: float = 2.0,
                  own_correction: bool = True, pitch_mm: float = PITCH_MM,
                  compensate=None) -> PerceptRange:  # fmt: skip
    """Predict ``method`` for every participant of a range, continuous and as sent.

    Parameters
    ----------
    participants : sequence of Participant, optional
        :func:`participant_grid` by default, plus :data:`REFERENCE` and :data:`LINEAR_ENERGY`
        if they are not in it.
    rate_hz, levels : float, int
        What is sent (the paper's 300 Hz and 23 levels by default).
    motor : MotorResponse, optional
        With it, the ``"felt"`` stage too.
    own_correction : bool
        Drive each method with its own correction (True by default: EN, PK and RO without one).
    compensate : MotorResponse, optional
        Send motor-aware drive for these motors (the ``"sent"`` and ``"felt"`` stages).
    shape, method, mu, gamma, grid, samples, duration_s, pitch_mm
        As for :func:`predict`.

    Returns
    -------
    PerceptRange
    """
    grid = grid or Grid()
    if participants is None:
        participants = participant_grid()
        participants += tuple(p for p in (REFERENCE, LINEAR_ENERGY) if p not in participants)
    participants = tuple(participants)
    kw = dict(grid=grid, duration_s=duration_s, own_correction=own_correction)
    sent = dict(rate_hz=rate_hz, levels=levels, compensate=compensate)
    drives = {
        "continuous": trace_drive(shape, method, mu, gamma, samples=samples, **kw),
        "sent": trace_drive(shape, method, mu, gamma, **sent, **kw),
    }
    if motor is not None:
        drives["felt"] = trace_drive(shape, method, mu, gamma, motor=motor, **sent, **kw)
    ripple, error = {}, {}
    for stage, drive in drives.items():
        got = [percept_of(drive, p.threshold, p.exponent, grid=grid, pitch_mm=pitch_mm)
               for p in participants]  # fmt: skip
        ripple[stage] = np.array([g.ripple for g in got])
        error[stage] = np.array([g.mean_error_mm for g in got])
    return PerceptRange(participants, ripple, error)
