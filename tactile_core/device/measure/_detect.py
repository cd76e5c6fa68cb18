"""The first vibration after a commanded time, in a sensor's recording: what the validator
logs beside each presentation's send time.

The rule is the one :func:`~._analysis.analyse` gives a pulse's onset, for a stimulus of
unknown strength: the amplitude (the power envelope less the noise's power, measured just
before the command) first reaching ``ONSET_FRACTION`` of the stimulus's own peak within the
window, and at least ``min_snr`` times the noise's RMS amplitude; the last such crossing before
the vibration reaches half its peak, so that noise poking up earlier does not count.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import signal

from ._analysis import ONSET_FRACTION
from ._signal import Envelope, bandpass, crossing_s, envelope

BEFORE_S = 0.2
"""Seconds before the command the noise is measured over."""
EARLY_S = 0.005
"""A vibration is looked for from this long before the command (clocks are not perfect)."""
EDGE_S = 0.03
"""The band-pass filter and the Hilbert transform ring at a segment's ends: the segment is
tapered (a Tukey window) over this much at each end and the envelope there left out (the
segment reaches that much further where the samples allow)."""
MIN_SNR = 6.0
"""The onset's amplitude is at least this many times the noise's RMS amplitude (16 dB)."""


@dataclass(frozen=True)
class Detection:
    """The sensor's view of one presentation.

    Attributes
    ----------
    onset_s : float
        Recording seconds of the first vibration (NaN when none was found).
    peak : float
        The largest amplitude within the window (sensor units).
    noise : float
        The noise's RMS amplitude before the command.
    """

    onset_s: float
    peak: float
    noise: float

    @property
    def found(self) -> bool:
        """True when a vibration was found."""
        return math.isfinite(self.onset_s)


def detect_onset(x, samplerate: float, command_s: float, window_s: float = 0.5, *,
                 min_snr: float = MIN_SNR,
                 noise_floor: float | None = None) -> Detection:  # fmt: skip
    """The first vibration in ``x`` after ``command_s``.

    Parameters
    ----------
    x : array_like of float, shape (n,)
        The sensor's channel, starting at recording second 0.
    samplerate : float
    command_s : float
        Recording seconds of the command (the presentation's first frame).
    window_s : float
        How long after the command a vibration is looked for (the samples should reach
        :data:`EDGE_S` further).
    min_snr : float
        The onset's amplitude is at least this many times the noise's RMS.
    noise_floor : float, optional
        The quietest noise amplitude seen so far: used instead of the noise before the
        command when that is louder than 4 times it (a vibration still dying away).

    Returns
    -------
    Detection
    """
    x = np.asarray(x, dtype=np.float64)
    lo = max(round((command_s - BEFORE_S - EDGE_S) * samplerate), 0)
    hi = min(round((command_s + window_s + EDGE_S) * samplerate), x.size)
    if hi - lo < 0.05 * samplerate + 2 * EDGE_S * samplerate:
        return Detection(float("nan"), 0.0, float("nan"))
    taper = signal.windows.tukey(hi - lo, min(1.0, 2 * EDGE_S * samplerate / (hi - lo)))
    env = envelope(bandpass(x[lo:hi] * taper, samplerate), samplerate)
    t = env.t_s + lo / samplerate
    inside = (t >= lo / samplerate + EDGE_S) & (t <= hi / samplerate - EDGE_S)
    env = Envelope(t[inside], env.power[inside])
    t = env.t_s
    before = (t >= command_s - BEFORE_S + 0.02) & (t < command_s - 0.002)
    noise_power = float(env.power[before].mean()) if before.any() else float(env.power.min())
    noise = math.sqrt(noise_power)
    if noise_floor is not None and noise > 4.0 * noise_floor:
        noise, noise_power = noise_floor, noise_floor**2
    amplitude = np.sqrt(np.clip(env.power - noise_power, 0.0, None))
    after = t >= command_s - EARLY_S
    t, a = t[after], amplitude[after]
    peak = float(a.max()) if a.size else 0.0
    level = max(ONSET_FRACTION * peak, min_snr * noise)
    if a.size < 3 or peak < level:
        return Detection(float("nan"), peak, noise)
    half = int(np.argmax(a >= max(0.5 * peak, level)))
    below = np.flatnonzero(a[: half + 1] < level)
    if below.size == 0:  # already vibrating at the window's start
        return Detection(float("nan"), peak, noise)
    i = int(below[-1])
    return Detection(crossing_s(t[i : half + 1], a[i : half + 1], level), peak, noise)
