"""A sensor's recording and its clock: which host time each sample was taken at.

An audio interface counts samples on its own crystal; the host sees them in blocks, each handed
over some time after its last sample was taken. The host time of sample ``n`` is estimated from
the blocks' arrival times (:func:`fit_sample_clock`): every block gives an upper bound on when
its samples were taken (they cannot arrive before they exist), so the line under the lowest
arrivals, fitted over the recording, is the sample clock with the interface's rate (its drift
against the host clock, some parts per million) and without the host's scheduling delays. What
the interface adds before the host could see the samples at all (its converter and transfer,
a millisecond or two on a USB interface) is not in the arrival times: the ``latency_ms`` of an
``audio:`` input URL takes it off when it is known.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

CLOCK_WINDOW_S = 1.0
"""The sample clock takes the earliest arrival in each stretch of this many seconds."""


@dataclass(frozen=True)
class Recording:
    """Samples of a sensor's input, with the host time of each.

    Attributes
    ----------
    samples : ndarray of float32, shape (n, channels)
        Full scale 1.
    samplerate : float
        Nominal samples per second.
    start_s : float
        Host time (``time.perf_counter`` seconds) of ``samples[0]``.
    ratio : float
        Host seconds per nominal sample period, over ``1 / samplerate`` (1 without drift).
    channel : int
        The column of ``samples`` the sensor is on (0 first: input 1 of the interface).
    description : str
        The sensor and its input, for the profile.
    """

    samples: np.ndarray
    samplerate: float
    start_s: float
    ratio: float = 1.0
    channel: int = 0
    description: str = ""

    @property
    def sensor(self) -> np.ndarray:
        """The sensor's channel, ``(n,)`` float32."""
        return self.samples[:, self.channel]

    @property
    def others(self) -> dict:
        """The other inputs, ``{input number: samples (n,)}``, numbered from 1 as on the
        interface (the sensor's is ``channel + 1``)."""
        return {k + 1: self.samples[:, k] for k in range(self.samples.shape[1])
                if k != self.channel}  # fmt: skip

    @property
    def duration_s(self) -> float:
        """Nominal seconds recorded."""
        return len(self.samples) / self.samplerate

    def to_recording_s(self, host_s) -> np.ndarray:
        """Host times as recording seconds (sample index over the samplerate)."""
        return (np.asarray(host_s, dtype=np.float64) - self.start_s) / self.ratio

    def host_s(self, recording_s) -> np.ndarray:
        """Recording seconds as host times."""
        return self.start_s + np.asarray(recording_s, dtype=np.float64) * self.ratio


def fit_sample_clock(end_index, arrival_s, samplerate: float, *,
                     window_s: float = CLOCK_WINDOW_S) -> tuple[float, float]:  # fmt: skip
    """The host time of sample 0 and the clock ratio, from when blocks of samples arrived.

    Parameters
    ----------
    end_index : array_like of int, shape (k,)
        Samples recorded when each block had arrived (the index after its last sample).
    arrival_s : array_like of float, shape (k,)
        Host time at which each block arrived.
    samplerate : float
        Nominal samples per second.
    window_s : float
        Each stretch this long contributes its earliest block (relative to the nominal clock).

    Returns
    -------
    start_s : float
        Host time of sample 0.
    ratio : float
        Host seconds per nominal sample period over ``1 / samplerate``: 1 with fewer than two
        stretches; otherwise the slope of the line through the earliest arrivals.

    Notes
    -----
    Each block gives ``offset_i = arrival_i - end_i / samplerate``, an upper bound on the host
    time of sample 0 (a block arrives no earlier than its last sample). The least of them in
    each stretch of ``window_s`` seconds is nearly free of scheduling delay; a line through
    those minima, shifted down to lie under all of them, follows the interface's clock.
    """
    end = np.asarray(end_index, dtype=np.float64)
    arrival = np.asarray(arrival_s, dtype=np.float64)
    if end.size == 0:
        raise ValueError("fit_sample_clock needs at least one block")
    nominal = end / samplerate
    offset = arrival - nominal
    stretch = np.floor(nominal / window_s).astype(np.int64)
    keep_x, keep_y = [], []
    for k in np.unique(stretch):
        mine = np.flatnonzero(stretch == k)
        i = mine[np.argmin(offset[mine])]
        keep_x.append(nominal[i])
        keep_y.append(offset[i])
    x, y = np.asarray(keep_x), np.asarray(keep_y)
    if x.size < 3 or np.ptp(x) < 2 * window_s:
        return float(offset.min()), 1.0
    slope, intercept = np.polyfit(x, y, 1)
    intercept += float(np.min(y - (intercept + slope * x)))  # under every minimum
    return float(intercept), float(1.0 + slope)
