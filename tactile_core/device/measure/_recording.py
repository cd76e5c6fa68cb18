"""A sensor's recording and its clock: which host time each sample was taken at.

An audio interface counts samples on its own crystal; the host sees them in blocks, each handed
over some time after its last sample was taken. The host time of sample ``n`` is estimated from
the blocks' arrival times (:func:`fit_sample_clock`): every block gives an upper bound on when
its samples were taken (they cannot arrive before they exist), so the line under all the
arrivals, touching the soonest, is the sample clock with the interface's rate (its drift
against the host clock, some parts per million) and without the host's scheduling delays. What
the interface adds before the host could see the samples at all (its converter and transfer,
a millisecond or two on a USB interface) is not in the arrival times: the ``latency_ms`` of an
``audio:`` input URL takes it off when it is known.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

MIN_SPAN_S = 2.0
"""Blocks spanning less than this give no clock drift (the ratio is 1)."""
BIN_S = 0.05
"""The sample clock's programme takes the earliest block of each stretch this long (1,000
ppm of drift moves the line 50 us across one)."""


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
                     min_span_s: float = MIN_SPAN_S) -> tuple[float, float]:  # fmt: skip
    """The host time of sample 0 and the clock ratio, from when blocks of samples arrived.

    Parameters
    ----------
    end_index : array_like of int, shape (k,)
        Samples recorded when each block had arrived (the index after its last sample).
    arrival_s : array_like of float, shape (k,)
        Host time at which each block arrived.
    samplerate : float
        Nominal samples per second.
    min_span_s : float
        Over a shorter recording the ratio is taken as 1 (drift cannot be told from jitter).

    Returns
    -------
    start_s : float
        Host time of sample 0.
    ratio : float
        Host seconds per nominal sample period over ``1 / samplerate``.

    Notes
    -----
    Each block gives ``offset_i = arrival_i - end_i / samplerate``, an upper bound on the host
    time of sample 0 (a block arrives no earlier than its last sample), on a line whose slope is
    the interface's drift. The line taken lies under every bound with the least mean gap to
    them (a linear programme: it touches the lower hull of the bounds at the blocks that came
    soonest), so neither a late block nor a stretch with few blocks moves it.
    """
    from scipy import optimize

    end = np.asarray(end_index, dtype=np.float64)
    arrival = np.asarray(arrival_s, dtype=np.float64)
    if end.size == 0:
        raise ValueError("fit_sample_clock needs at least one block")
    nominal = end / samplerate
    offset = arrival - nominal
    if np.ptp(nominal) < min_span_s:
        return float(offset.min()), 1.0
    # Only the earliest block of each short stretch can touch the line (the rest lie above
    # it by more than the drift moves it there): the programme is solved on those.
    stretch = np.floor(nominal / BIN_S).astype(np.int64)
    order = np.lexsort((offset, stretch))
    first = order[np.r_[True, np.diff(stretch[order]) != 0]]
    nominal, offset = nominal[first], offset[first]
    x = nominal - nominal.mean()
    y = offset - offset.min()
    bounds = [(None, None), (-1e-3, 1e-3)]  # drift of at most 1000 ppm
    found = optimize.linprog([-x.size, -x.sum()], A_ub=np.column_stack([np.ones_like(x), x]),
                             b_ub=y, bounds=bounds, method="highs")  # fmt: skip
    if not found.success:
        return float(offset.min()), 1.0
    level, slope = found.x
    start = offset.min() + level - slope * nominal.mean()
    return float(start), float(1.0 + slope)
