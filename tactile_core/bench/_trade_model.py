"""The speed/accuracy trade in felt terms: what the skin gets of one pipeline setting.

A *setting* is what a user chooses between the trace and the motors: frame rate, temporal
filter, device levels, dithering, lead and motor-aware drive (:class:`Setting`). For one
setting, one method and one shape, :func:`felt_runs` sends a 2 s trace (the paper's Experiment
traces, each method with its own correction) at several random phases of the trace's start
against the frame clock, and gives per phase:

- **felt ripple** and **felt centroid lag** (the reference participant, TH 0.2, K 1:
  :func:`~tactile_core.rendering.percept.percept_of`) of the motors' effective drive, sampled
  every :data:`EVAL_STEP_S` (1/3 ms) rather than once a frame, so that what the motors do
  *within* a long frame counts too; the first ``3 tau_up`` left out as the motors spin up;
- **onset error at the skin**: ``|felt onset + delay - intended onset|`` per tactor's first
  activation, the intended onset from the corrected trace every 50 us, the felt one where the
  motor's effective drive crosses TH (solved exactly within the frame, as
  :meth:`~tactile_core.rendering.motor.MotorResponse.onsets_s` does);
- **drive error**: each lit tactor's drive energy sent (its levels over the trace) against the
  continuous corrected drive's, in % (the accuracy table's drive column, with the levels).

**When frames play.** A lead ``L > 0`` (timed frames) plays every frame exactly ``L`` after its
deadline (or after its transmission, if that is longer): the whole trace is ``L`` late and the
host's scheduler no longer reaches the skin (docs/benchmarks.md, the lead against latency: 20 ms
kept every frame on time with both cores busy). Frames for now (``L = 0``) play when they
arrive: after their transmission (the link's bytes at its baud) plus the host's jitter, drawn
per frame from a log-normal with the lead table's measured p50 and p99 (idle: 0.8 / 2.35 ms;
both cores busy: 14.2 / 43.9 ms), and on an audio interface up to one block later (the block
they land in). The constant part of the delay (the lead, the transmission, the jitter's median)
only moves the trace in time, so it enters the onset and not the ripple or the lag (measured
against the trace as played); the jitter about its median changes when each frame starts and so
enters all three.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from .._shared import validate as _validate
from ..rendering.correction import Dither, quantize
from ..rendering.geometry import Grid
from ..rendering.methods import get_method
from ..rendering.motor import MotorResponse
from ..rendering.motor_drive import motor_drive
from ..rendering.percept import PITCH_MM, REFERENCE, Drive, percept_of
from ..rendering.trace import Sampling, Trace, render_frames
from ..stream import check_lead_ms
from ._common import GAMMA, MU
from ._motor_drive import _first_activation

EVAL_STEP_S = 1.0 / 3000.0
"""Where the felt percept is evaluated: every 1/3 ms of the trace (a whole number of steps per
frame at 25, 50, 100, 200, 300 and 1000 Hz)."""
REF_STEP_S = 50e-6
"""The continuous reference: the corrected trace every 50 us."""
BOX_SUBSAMPLES = 4
"""Sub-samples of the box filter in the trade."""
JITTER_S = {"idle": (0.8e-3, 2.351e-3), "busy": (14.2e-3, 43.86e-3)}
"""The host's jitter for frames for now, p50 and p99 in s (docs/benchmarks.md, the lead against
latency, frames for now into the reference firmware: an idle host, and both cores busy)."""


@dataclass(frozen=True)
class Setting:
    """One pipeline setting: what is sent, and when it plays.

    Parameters
    ----------
    rate_hz : float
        Frames per second.
    filter : {"point", "box"}
        Temporal filter.
    levels : int
        Device levels, 2..256.
    dither : bool
        Temporal dithering instead of plain rounding.
    lead_ms : float
        Timed frames this far ahead (0: frames for now).
    host : {"idle", "busy"}
        The host's jitter for frames for now (ignored with a lead).
    compensate : bool
        Motor-aware drive for the motors felt.
    subsamples : int
        Sub-samples of the box filter.
    """

    rate_hz: float = 300.0
    filter: str = "point"
    levels: int = 23
    dither: bool = False
    lead_ms: float = 0.0
    host: str = "idle"
    compensate: bool = False
    subsamples: int = BOX_SUBSAMPLES

    def __post_init__(self):
        object.__setattr__(self, "rate_hz", _validate.rate("rate_hz", self.rate_hz, 1.0, 10_000.0))
        _validate.choice("filter", self.filter, ("point", "box"))
        object.__setattr__(self, "levels", _validate.integer("levels", self.levels, 2, 256))
        object.__setattr__(self, "lead_ms", check_lead_ms(self.lead_ms))
        _validate.choice("host", self.host, tuple(JITTER_S))
        for name in ("dither", "compensate"):
            object.__setattr__(self, name, _validate.boolean(name, getattr(self, name)))
        object.__setattr__(self, "subsamples",
                           _validate.integer("subsamples", self.subsamples, 1, 1024))  # fmt: skip

    @property
    def sampling(self) -> Sampling:
        """The :class:`~tactile_core.rendering.trace.Sampling` of the setting."""
        return Sampling(self.rate_hz, self.filter, self.subsamples)

    @property
    def label(self) -> str:
        """``"300 Hz, point, 23 lv, round, lead 0, plain"``."""
        lead = f"lead {self.lead_ms:g}" + (" (busy host)" if self.host == "busy" and
                                           self.lead_ms == 0 else "")  # fmt: skip
        return (f"{self.rate_hz:g} Hz, {self.sampling.label}, {self.levels} lv, "
                f"{'dither' if self.dither else 'round'}, {lead}, "
                f"{'motor-aware' if self.compensate else 'plain'}")  # fmt: skip

    def replace(self, **changes) -> Setting:
        """A copy with ``changes`` (validated)."""
        return replace(self, **changes)


PAPER = Setting()
"""The paper's pipeline: 300 Hz, point sampling, 23 levels, plain rounding, frames for now, plain
drive."""


@dataclass(frozen=True)
class Link:
    """What a frame for now waits for on its way to the motors.

    Parameters
    ----------
    transmit_s : float
        Its transmission (bytes x 10 / baud on a serial link; 0 for an audio interface).
    block_s : float
        An audio interface's block: a frame for now starts with the next one (0 for serial).
    """

    transmit_s: float = 37 * 10 / 115200
    block_s: float = 0.0


@dataclass(frozen=True)
class Runs:
    """Felt figures of one setting, method and shape: one value per phase (arrays ``(P,)``).

    Attributes
    ----------
    ripple : ndarray
        Felt ripple, max / min of the felt intensity (inf where something went unfelt).
    lag_mm : ndarray
        Felt centroid's mean distance from the point, mm (18 mm pitch).
    onset_ms : ndarray
        Mean ``|felt onset at the skin - intended onset|`` over the tactors felt in time, ms.
    drive_pct : ndarray
        Mean relative error of the drive energy of the lit tactors, %.
    missed : ndarray of int
        Tactors whose first activation was never felt.
    """

    ripple: np.ndarray
    lag_mm: np.ndarray
    onset_ms: np.ndarray
    drive_pct: np.ndarray
    missed: np.ndarray


def shared_motor(motor: MotorResponse | None) -> MotorResponse:
    """One pair of time constants for every tactor: a per-tactor motor's medians (the trade
    runs on the paper's grid, whatever the profile's actuators)."""
    if motor is None:
        raise ValueError("motor must be a MotorResponse, got None")
    up, down = (np.median(np.atleast_1d(v)) for v in (motor.tau_up_s, motor.tau_down_s))
    return MotorResponse(float(up), float(down), motor.note)


class References:
    """The continuous references of (shape, method) pairs, computed once per run."""

    def __init__(self):
        self._cache: dict = {}

    def get(self, shape, method: str, grid: Grid, mu: float, gamma: float, duration_s: float):
        """``(energy, on_s, off_s)`` per tactor: the corrected drive's time integral over the
        trace, and the start and end of its first stretch above the reference participant's
        threshold (inf if none)."""
        key = (repr(shape), method, grid.cols, grid.rows, mu, gamma, duration_s)
        if key not in self._cache:
            m = get_method(method)
            trace = Trace(shape, duration_s, 0.0, repeat=False)
            n = round(duration_s / REF_STEP_S)
            start, frames = render_frames(trace, m, sampling=Sampling(1.0 / REF_STEP_S, "point"),
                                          mu=mu, gamma=gamma, grid=grid, n_frames=n)  # fmt: skip
            flat = frames.reshape(n, grid.size)
            on, off = _first_activation(flat, start, REFERENCE.threshold)
            self._cache[key] = (flat.sum(axis=0) * REF_STEP_S, on, off)
        return self._cache[key]


def phase_fractions(phases: int, seed: int = 0) -> np.ndarray:
    """Where frame 0 starts, as fractions of a frame before the trace (the same for every
    setting of a run: common random numbers, so settings differ by the setting, not by luck)."""
    return np.random.default_rng(seed).uniform(0.0, 1.0, phases)


def _jitter_s(setting: Setting, link: Link, n: int, rng) -> np.ndarray:
    """Per frame, how much later than its share of the constant delay it plays (s)."""
    if setting.lead_ms > 0:
        return np.zeros(n)
    p50, p99 = JITTER_S[setting.host]
    sigma = math.log(p99 / p50) / 2.3263478740408408  # the 99th percentile's z
    late = rng.lognormal(math.log(p50), sigma, n)
    if link.block_s > 0:
        late += rng.uniform(0.0, link.block_s, n)
    return late


def _levels(frames: np.ndarray, setting: Setting) -> np.ndarray:
    """Frames ``(n, C)`` in [0, 1] as the levels sent, back in [0, 1]."""
    top = setting.levels - 1
    if setting.dither:
        return Dither(frames.shape[1], setting.levels).frames(frames) / top
    return quantize(frames, setting.levels) / top


def _motor_states(sent, durations, motor: MotorResponse):
    """Effective drive of every column at the start of each frame ``(n, C)``, and whether the
    motor rises during it, for frames held ``durations`` ``(n, C)`` s each, from rest."""
    up, down = motor.tau_up_s, motor.tau_down_s
    with np.errstate(divide="ignore", over="ignore"):
        e_up = np.exp(-durations / up) if up > 0 else np.zeros_like(durations)
        e_down = np.exp(-durations / down) if down > 0 else np.zeros_like(durations)
    start = np.empty_like(sent)
    s = np.zeros(sent.shape[1])
    for k in range(len(sent)):
        start[k] = s
        d = sent[k]
        s = d + (s - d) * np.where(d > s, e_up[k], e_down[k])
    return start, sent > start


def felt_runs(setting: Setting, shape, method: str, motor: MotorResponse, *, phases: int = 8,
              seed: int = 0, link: Link = Link(), refs: References | None = None,
              duration_s: float = 2.0, correction: tuple | None = None, grid: Grid | None = None,
              pitch_mm: float = PITCH_MM) -> Runs:  # fmt: skip
    """The felt figures of ``setting`` for ``method`` on ``shape`` through ``motor``.

    Parameters
    ----------
    setting : Setting
    shape : Shape
        In grid units.
    method : str
        Any registered method or spec, driven with its own correction of the paper's mu 0.33,
        gamma 0.7.
    motor : MotorResponse
        The motors felt (shared constants: :func:`shared_motor`); motor-aware drive
        compensates these.
    phases : int
        Random phases of the trace's start against the frame clock (:func:`phase_fractions`).
    seed : int
        Seeds the phases and the jitter.
    link : Link
        What frames for now wait for.
    refs : References, optional
        The continuous references, shared between calls.
    duration_s : float
        Seconds per trace (the paper's 2 s).
    correction : (float, float), optional
        ``(mu, gamma)`` to drive the method with (default: its own correction of the paper's).
    grid : Grid, optional
        The palm array's 5 x 6 by default.
    pitch_mm : float
        Tactor pitch, for the centroid lag.

    Returns
    -------
    Runs
        One value per phase of each figure (see the module notes).
    """
    grid = grid or Grid()
    phases = _validate.integer("phases", phases, 1, 1000)
    motor = shared_motor(motor)
    refs = refs or References()
    m = get_method(method)
    mu, gamma = m.own_correction(MU, GAMMA) if correction is None else correction
    trace = Trace(shape, duration_s, 0.0, repeat=False)
    ref_energy, on_s, off_s = refs.get(shape, m.spec, grid, mu, gamma, duration_s)
    rate, size = setting.rate_hz, grid.size
    n = math.ceil(duration_s * rate) + 2
    fractions = phase_fractions(phases, seed)
    rng = np.random.default_rng([seed, 1])
    cols = []
    for f in fractions:
        _, frames = render_frames(trace, m, sampling=setting.sampling, mu=mu, gamma=gamma,
                                  grid=grid, n_frames=n, phase_s=-f / rate)  # fmt: skip
        cols.append(frames.reshape(n, size))
    frames = np.hstack(cols)  # (n, phases * size), phase-major
    if setting.compensate:
        frames, _ = motor_drive(frames, motor, rate)
    sent = _levels(frames, setting)
    # Drive energy against the continuous reference, per phase (the frames outside the trace
    # are dark, or running a motor down with drive 0).
    energy = sent.sum(axis=0).reshape(phases, size) / rate
    lit = ref_energy > 0
    drive_pct = (np.abs(energy[:, lit] - ref_energy[lit]) / ref_energy[lit]).mean(axis=1) * 100
    # When each frame plays: its slot on the frame clock, plus the jitter, never before the one
    # before it (the link keeps their order).
    slots = (np.arange(n)[None, :] - fractions[:, None]) / rate
    arrive = np.maximum.accumulate(slots + _jitter_s(setting, link, n * phases, rng)
                                   .reshape(phases, n), axis=1)  # fmt: skip
    # The typical delay moves the trace as a whole: measure the percept against the trace as
    # played (shifted by it) and add it to the onsets.
    typical_s = np.median(arrive - slots, axis=1)
    arrive -= typical_s[:, None]
    samples = slots[:, :, None] + setting.sampling.offsets_s()[None, None, :]
    on_trace = trace.parameter(samples)[1].any(axis=2)  # (phases, n): frames sampled on it
    durations = np.diff(arrive, axis=1, append=arrive[:, -1:] + 1.0 / rate)
    start, rising = _motor_states(sent, np.repeat(durations.T, size, axis=1), motor)
    # A timed frame plays at its time, or when it has arrived if the lead is shorter than its
    # transmission (a slow link: 23 bytes at 9600 baud take 24 ms).
    delay_s = max(setting.lead_ms / 1e3, link.transmit_s)
    t = (np.arange(round(duration_s / EVAL_STEP_S)) + 0.5) * EVAL_STEP_S
    param, _ = trace.parameter(t)
    point = np.stack(shape.xy(param), axis=1)
    settle_s = 3.0 * motor.tau_up_s
    out = {k: np.zeros(phases) for k in ("ripple", "lag", "onset", "missed")}
    th = REFERENCE.threshold
    wanted = np.isfinite(on_s)
    for p in range(phases):
        c = slice(p * size, (p + 1) * size)
        d, s0, up = sent[:, c], start[:, c], rising[:, c]
        k = np.searchsorted(arrive[p], t, side="right") - 1
        played = k >= 0
        k = np.maximum(k, 0)
        u = (t - arrive[p, k])[:, None]
        tau = np.where(up[k], motor.tau_up_s, motor.tau_down_s)
        with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
            left = np.where(tau > 0, np.exp(-u / np.where(tau > 0, tau, 1.0)), 0.0)
        s = np.where(played[:, None], d[k] + (s0[k] - d[k]) * left, 0.0)
        # Left out: frames sampled before the trace starts or after it ends (dark: the trace's
        # edges against the frame clock), and the motors' spin-up from rest, counted from when
        # the first frame of the trace plays.
        first = arrive[p, np.argmax(on_trace[p])]
        valid = played & on_trace[p][k] & (t >= first + settle_s - 1e-12)
        drive = Drive(param, point, s.reshape(len(t), grid.rows, grid.cols), valid)
        felt = percept_of(drive, th, REFERENCE.exponent, grid=grid, pitch_mm=pitch_mm)
        out["ripple"][p], out["lag"][p] = felt.ripple, felt.mean_error_mm
        onset = _felt_onsets(d, s0, arrive[p], motor.tau_up_s, th)
        in_time = wanted & (onset <= off_s + 1.0 / rate)
        error = np.abs(onset[in_time] + delay_s + typical_s[p] - on_s[in_time]) * 1e3
        out["onset"][p] = error.mean() if error.size else np.nan
        out["missed"][p] = int((wanted & ~in_time).sum())
    return Runs(out["ripple"], out["lag"], out["onset"], drive_pct, out["missed"].astype(int))


def _felt_onsets(drive, start, arrive, tau_up: float, level: float) -> np.ndarray:
    """Per column, when the effective drive first rises above ``level`` (s on the trace's
    clock; inf if never): ``arrive_k + tau_up ln((d - s0) / (d - level))`` into the first frame
    that ends above it."""
    size = drive.shape[1]
    end = np.vstack([start[1:], np.full((1, size), -1.0)])  # the last frame is never finished
    above = end > level
    seen = above.any(axis=0)
    onset = np.full(size, np.inf)
    k = np.argmax(above, axis=0)[seen]
    cols = np.flatnonzero(seen)
    d, s0 = drive[k, cols], start[k, cols]
    with np.errstate(divide="ignore", invalid="ignore"):
        into = np.where(s0 > level, 0.0, tau_up * np.log((d - s0) / (d - level)))
    onset[cols] = arrive[k] + np.nan_to_num(into, posinf=0.0)
    return onset


FIGURES = ("ripple", "lag_mm", "onset_ms", "drive_pct")
"""The figures of :class:`Runs` a table pools."""


def pool(runs, figure: str, how: str = "median") -> np.ndarray:
    """Per phase, the median (or mean) of ``figure`` over several :class:`Runs` (methods,
    shapes): shape ``(P,)``. The median by default, so that one method far off the others
    (RO's ripple, uncorrected, is 3.5) does not stand for all; NaN onsets (nothing felt in
    time) are left out."""
    values = np.array([getattr(r, figure) for r in runs], dtype=float)
    out = np.full(values.shape[1], np.nan)
    for p in range(values.shape[1]):
        known = values[~np.isnan(values[:, p]), p]
        if known.size:
            out[p] = np.median(known) if how == "median" else known.mean()
    return out


def spread(values, digits: int) -> str:
    """``"1.144 ± 0.002"``: the mean and standard deviation of per-phase values (``inf`` when
    one is infinite: something went unfelt)."""
    v = np.asarray(values, dtype=float)
    if not np.isfinite(v).all():
        return "inf" if np.isinf(v).any() else "n/a"
    sd = v.std(ddof=1) if v.size > 1 else 0.0
    return f"{v.mean():.{digits}f} ± {sd:.{digits}f}"
