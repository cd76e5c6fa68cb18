"""The array's clock as the host sees it: offset and drift from clock exchanges, NTP-style.

Each exchange is four times: the host writes a clock request at ``t0`` (its own clock,
``time.perf_counter``), the array stamps the request's arrival ``rx`` and its reply's departure
``tx`` on its clock, and the host reads the whole reply at ``t3``. Both directions cost the
transmission of the bytes on the line (``request_bytes`` and ``reply_bytes`` at ``byte_s`` each)
plus latencies the host cannot see (the USB adapter, the operating system). Assuming those
latencies equal both ways, the array's clock is ahead of the host's by

    offset = ((rx - t0 - s_request) + (tx + s_reply - t3)) / 2

with a round-trip delay ``delay = (t3 - t0) - (tx - rx) - s_request - s_reply``; the offset is
then wrong by at most half the delay (all of it one way). So the exchanges with the least delay
are the ones to trust: :class:`ArrayClock` keeps the last ``window`` exchanges, uses those within
``slack_s`` of the least delay among them, and fits offset against time over them (least
squares) once they span ``drift_after_s``: the slope is the drift of the array's crystal against
the host's clock (a 16 MHz crystal is good to ~50 ppm: 3 ms a minute). :attr:`error_s` states
the expected error of a conversion now: half the least delay kept plus the fit's residual.

Times on the array are microseconds in a ``u32`` that wraps every 71.6 minutes; offsets here
are unwrapped floats (the nearest reading to the previous one), and :meth:`to_array_us` wraps.
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass

from .wire import CLOCK_WRAP, ClockReply, clock_diff

JUMP_MARGIN_S = 0.005
"""What :meth:`ArrayClock.jump_s` allows beyond the errors an exchange and the fit state: more
than a 100 ppm crystal drifts over the 16 s of a fit's window, and than the bias of a link
whose bytes take no line time (a clock exchange's 29 bytes at 115200 baud are 2.5 ms)."""


@dataclass(frozen=True)
class ClockSample:
    """One clock exchange.

    Attributes
    ----------
    host_s : float
        Host time of the exchange's midpoint, ``(t0 + t3) / 2`` (seconds).
    offset_s : float
        Array clock minus host clock (seconds, unwrapped).
    delay_s : float
        Round-trip delay beyond the bytes' transmission (seconds).
    """

    host_s: float
    offset_s: float
    delay_s: float


class ArrayClock:
    """Offset and drift of an array's clock against the host's, from clock exchanges.

    Parameters
    ----------
    byte_s : float
        Seconds one byte takes on the line (10 bits at the link's baud for 8N1).
    request_bytes, reply_bytes : int
        A clock request's and reply's bytes on the wire (6 and 23 in wire format 2).
    window : int
        Exchanges remembered.
    slack_s : float
        Exchanges whose delay is within this of the least delay in the window are used.
    drift_after_s : float
        The used exchanges must span this long before drift is estimated (else 0).
    """

    def __init__(self, *, byte_s: float = 10 / 115200, request_bytes: int = 6,
                 reply_bytes: int = 23, window: int = 64, slack_s: float = 200e-6,
                 drift_after_s: float = 2.0):  # fmt: skip
        self.s_request = request_bytes * byte_s
        self.s_reply = reply_bytes * byte_s
        self.samples: deque[ClockSample] = deque(maxlen=window)
        self.slack_s = slack_s
        self.drift_after_s = drift_after_s
        self._fit = (0.0, 0.0, 0.0, math.inf)  # offset at t_ref, drift, t_ref, error

    def measure(self, t0: float, t3: float, reply: ClockReply) -> ClockSample:
        """One exchange's offset and delay, without recording it: request written at host time
        ``t0``, reply read at ``t3``; the offset unwrapped to the reading nearest the last one
        recorded."""
        rx_s, tx_s = reply.rx_us * 1e-6, reply.tx_us * 1e-6
        offset = ((rx_s - t0 - self.s_request) + (tx_s + self.s_reply - t3)) / 2
        delay = (t3 - t0) - ((reply.tx_us - reply.rx_us) % CLOCK_WRAP) * 1e-6
        delay -= self.s_request + self.s_reply
        if self.samples:  # unwrap: the reading nearest to the last offset
            last = self.samples[-1].offset_s
            offset = last + clock_diff(round(offset * 1e6), round(last * 1e6)) * 1e-6
        return ClockSample((t0 + t3) / 2, offset, max(delay, 0.0))

    def add(self, t0: float, t3: float, reply: ClockReply) -> ClockSample:
        """Record one exchange: request written at host time ``t0``, reply read at ``t3``."""
        sample = self.measure(t0, t3, reply)
        self.samples.append(sample)
        self._refit()
        return sample

    def jump_s(self, sample: ClockSample) -> float:
        """How far ``sample`` (from :meth:`measure`) puts the array's clock from where the
        exchanges so far put it, when no error allows that (seconds; 0 when it agrees).

        The true offset lies within half an exchange's delay of the offset it measured, and
        the fit's within :attr:`error_s` of it; beyond both, and :data:`JUMP_MARGIN_S` for the
        drift since, the array's clock itself moved: the array restarted (its clock counts from
        its start), or the host's clock stood still while the array's ran on (a suspend). An
        exchange spanning a host pause has a delay as long, so a pause is never a jump.
        Negative: the array's clock went back.
        """
        if not self.samples:
            return 0.0
        moved = sample.offset_s - self.offset_at(sample.host_s)
        allowed = sample.delay_s / 2 + self.error_s + JUMP_MARGIN_S
        return moved if abs(moved) > allowed else 0.0

    @property
    def synced(self) -> bool:
        """True once there is an exchange to go by."""
        return bool(self.samples)

    @property
    def drift_ppm(self) -> float:
        """The array's clock runs fast by this many parts per million (0 until estimated)."""
        return self._fit[1] * 1e6

    @property
    def error_s(self) -> float:
        """Expected error of a conversion (seconds): half the least delay used plus the fit's
        residual; infinite before the first exchange."""
        return self._fit[3]

    def offset_at(self, host_s: float) -> float:
        """Array clock minus host clock at host time ``host_s`` (seconds)."""
        offset, drift, t_ref, _ = self._fit
        return offset + drift * (host_s - t_ref)

    def to_array_us(self, host_s: float) -> int:
        """The array's clock reading (microseconds, wrapped) at host time ``host_s``."""
        return round((host_s + self.offset_at(host_s)) * 1e6) % CLOCK_WRAP

    def to_host(self, at_us: int, near_host_s: float) -> float:
        """Host time of array time ``at_us``, the nearest such time to ``near_host_s``."""
        return near_host_s + clock_diff(at_us, self.to_array_us(near_host_s)) * 1e-6

    def _refit(self) -> None:
        least = min(s.delay_s for s in self.samples)
        used = [s for s in self.samples if s.delay_s <= least + self.slack_s]
        n = len(used)
        t_ref = sum(s.host_s for s in used) / n
        mean = sum(s.offset_s for s in used) / n
        span = max(s.host_s for s in used) - min(s.host_s for s in used)
        drift = 0.0
        if n >= 4 and span >= self.drift_after_s:
            sxx = sum((s.host_s - t_ref) ** 2 for s in used)
            drift = sum((s.host_s - t_ref) * (s.offset_s - mean) for s in used) / sxx
        residual = 0.0
        if n > 1:
            residual = math.sqrt(
                sum((s.offset_s - mean - drift * (s.host_s - t_ref)) ** 2 for s in used) / n
            )
        self._fit = (mean, drift, t_ref, least / 2 + residual)
