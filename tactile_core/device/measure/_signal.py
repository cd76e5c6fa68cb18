"""From a sensor's samples to what the fit reads: the vibration's power envelope, spectral peaks,
the noise floor and mains hum.

The envelope is the squared magnitude of the analytic signal (Hilbert transform) of the
band-passed signal, averaged over blocks of ``1 / rate_hz`` s: for a vibration ``A(t) sin(phi)``
whose amplitude changes slowly against its period it is ``A(t)^2``, without the ripple at twice
the carrier that squaring and low-passing leave. Noise adds its power, which is measured in the
silence before anything moves and subtracted.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import fft, signal

BAND_HZ = (20.0, 1000.0)
"""The band a vibrotactile actuator's vibration lies in (an ERM's 30-300 Hz, an LRA's
150-250 Hz, a voice coil's up to ~1 kHz); below it an accelerometer's offset and gravity."""
ENVELOPE_RATE_HZ = 1000.0
"""Samples per second of the envelope the fit reads (1 ms apart)."""
MAINS_HZ = (50.0, 60.0)


def bandpass(x, samplerate: float, band=BAND_HZ) -> np.ndarray:
    """Zero-phase 4th-order Butterworth band-pass of ``x`` (float64, same shape), the upper
    edge kept below 0.45 of the samplerate."""
    lo, hi = band[0], min(band[1], 0.45 * samplerate)
    sos = signal.butter(4, [lo, hi], btype="bandpass", fs=samplerate, output="sos")
    x = np.asarray(x, dtype=np.float64)
    if x.size < 64:
        return x - x.mean()
    return signal.sosfiltfilt(sos, x)


@dataclass(frozen=True)
class Envelope:
    """The power envelope of a band-passed signal.

    Attributes
    ----------
    t_s : ndarray of float64, shape (n,)
        The centre of each block, seconds from the signal's first sample.
    power : ndarray of float64, shape (n,)
        Mean squared magnitude of the analytic signal over each block (sensor units squared).
    """

    t_s: np.ndarray
    power: np.ndarray

    def window(self, start_s: float, end_s: float) -> np.ndarray:
        """Boolean mask of the blocks within ``[start_s, end_s)``."""
        return (self.t_s >= start_s) & (self.t_s < end_s)

    def mean(self, start_s: float, end_s: float) -> float:
        """Mean power within ``[start_s, end_s)`` (NaN if no block lies there)."""
        inside = self.window(start_s, end_s)
        return float(self.power[inside].mean()) if inside.any() else float("nan")


def envelope(x, samplerate: float, rate_hz: float = ENVELOPE_RATE_HZ) -> Envelope:
    """The power envelope of ``x`` (already band-passed) at about ``rate_hz``.

    Parameters
    ----------
    x : array_like of float, shape (n,)
    samplerate : float
        Samples per second of ``x``.
    rate_hz : float
        Blocks per second (each ``round(samplerate / rate_hz)`` samples, at least one).
    """
    x = np.asarray(x, dtype=np.float64)
    block = max(round(samplerate / rate_hz), 1)
    analytic = signal.hilbert(x, N=fft.next_fast_len(x.size)) if x.size else x
    p = np.abs(analytic[: x.size]) ** 2
    n = p.size // block
    power = p[: n * block].reshape(n, block).mean(axis=1)
    t = (np.arange(n) * block + (block - 1) / 2.0) / samplerate
    return Envelope(t, power)


def spectrum(x, samplerate: float, pad: int = 8) -> tuple[np.ndarray, np.ndarray]:
    """Amplitude spectrum of ``x`` with a Hann window: ``(frequency_hz, amplitude)``, the
    amplitude of a sinusoid read at its peak (``pad`` times zero-padded)."""
    x = np.asarray(x, dtype=np.float64)
    w = np.hanning(x.size)
    n = fft.next_fast_len(pad * x.size)
    mag = np.abs(np.fft.rfft((x - x.mean()) * w, n)) * 2.0 / max(w.sum(), 1e-12)
    return np.fft.rfftfreq(n, 1.0 / samplerate), mag


def peaks(x, samplerate: float, band=BAND_HZ, count: int = 4) -> list[tuple[float, float]]:
    """The strongest spectral peaks of ``x`` within ``band``: ``[(hz, amplitude), ...]``,
    strongest first, each refined by a parabola through its bin and neighbours; peaks closer
    than two resolution widths (``2 samplerate / len(x)``) to a stronger one are left out."""
    hz, mag = spectrum(x, samplerate)
    inside = (hz >= band[0]) & (hz <= min(band[1], 0.45 * samplerate))
    found, _ = signal.find_peaks(np.where(inside, mag, 0.0))
    found = found[np.argsort(mag[found])[::-1]]
    width = 2.0 * samplerate / max(np.size(x), 1)
    out: list[tuple[float, float]] = []
    step = hz[1] - hz[0] if hz.size > 1 else 1.0
    for i in found:
        if 0 < i < mag.size - 1:
            a, b, c = np.log(mag[i - 1 : i + 2] + 1e-300)
            shift = 0.5 * (a - c) / (a - 2 * b + c) if (a - 2 * b + c) < 0 else 0.0
        else:
            shift = 0.0
        f = hz[i] + shift * step
        if all(abs(f - g) > width for g, _ in out):
            out.append((float(f), float(mag[i])))
        if len(out) >= count:
            break
    return out


def hum(x, samplerate: float) -> tuple[float, float]:
    """Mains hum in a quiet stretch ``x``: ``(hz, amplitude)`` of the stronger of 50 and 60 Hz
    (with its odd harmonics' amplitudes added), amplitude 0 for a stretch too short (< 0.1 s)."""
    x = np.asarray(x, dtype=np.float64)
    if x.size < 0.1 * samplerate:
        return 50.0, 0.0
    hz, mag = spectrum(x, samplerate)
    best = (50.0, 0.0)
    for mains in MAINS_HZ:
        total = 0.0
        for k in (1, 3, 5):
            near = np.abs(hz - k * mains) <= 2.0
            if near.any() and k * mains < 0.45 * samplerate:
                total += float(mag[near].max())
        if total > best[1]:
            best = (mains, total)
    return best


def crossing_s(t_s, values, level: float) -> float:
    """When ``values`` first rises to ``level``, interpolated between samples (NaN never)."""
    values = np.asarray(values, dtype=np.float64)
    above = np.flatnonzero(values >= level)
    if above.size == 0:
        return float("nan")
    i = int(above[0])
    if i == 0:
        return float(t_s[0])
    v0, v1 = values[i - 1], values[i]
    return float(t_s[i - 1] + (level - v0) / (v1 - v0) * (t_s[i] - t_s[i - 1]))


HUM_HARMONICS = (1, 2, 3, 4, 5, 6, 7)
"""Harmonics of the mains frequency taken off with the hum (rectifiers make the odd and even)."""


def remove_hum(x, samplerate: float, quiet, hz: float) -> np.ndarray:
    """``x`` without its mains hum: the harmonics of ``hz`` (its frequency refined within
    +-0.5 %), fitted by least squares to the samples where nothing moves, subtracted
    everywhere.

    Hum is stationary (the mains' frequency and the ground loop's coupling hold for
    minutes), so stretches of silence spread over the recording pin its frequency and phase
    far better than the vibration lets a notch filter do without cutting the motor's own
    line where it crosses a harmonic.

    Parameters
    ----------
    x : array_like of float, shape (n,)
    samplerate : float
    quiet : array_like of bool, shape (n,)
        The samples where no motor vibrates.
    hz : float
        The mains frequency (50 or 60).
    """
    from scipy import optimize

    x = np.asarray(x, dtype=np.float64)
    quiet = np.flatnonzero(np.asarray(quiet, dtype=bool))
    if quiet.size < 0.2 * samplerate:
        return x
    t_all = np.arange(x.size) / samplerate
    harmonics = [k for k in HUM_HARMONICS if k * hz < 0.45 * samplerate]

    def basis(f, t):
        w = 2.0 * np.pi * f * np.outer(t, harmonics)
        return np.hstack([np.sin(w), np.cos(w)])

    def misfit(f):
        b = basis(f, t_all[quiet])
        coef = np.linalg.lstsq(b, x[quiet], rcond=None)[0]
        return float(np.sum((b @ coef - x[quiet]) ** 2))

    # the misfit ripples every 1 / span Hz: a grid finer than that, then the best cell refined
    span = (quiet[-1] - quiet[0]) / samplerate
    step = min(0.25 / max(span, 1e-3), 0.05)
    grid = np.arange(hz * 0.995, hz * 1.005 + step, step)
    f0 = grid[int(np.argmin([misfit(f) for f in grid]))]
    best = optimize.minimize_scalar(misfit, bounds=(f0 - step, f0 + step), method="bounded",
                                    options={"xatol": 1e-6})  # fmt: skip
    b = basis(best.x, t_all[quiet])
    coef = np.linalg.lstsq(b, x[quiet], rcond=None)[0]
    return x - basis(best.x, t_all) @ coef
