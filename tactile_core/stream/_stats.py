"""The streamer's statistics: the snapshot a reader gets, and the book the thread keeps.

The output thread counts into a :class:`StatsBook` under its lock; any thread asks for a
:class:`StreamStats`, an immutable snapshot (a frozen dataclass), which is what crosses threads
and, pickled, the pipe from the stream process.
"""

from __future__ import annotations

import threading
import time
from dataclasses import dataclass

import numpy as np

from ..device.wire import WATCHDOG_S

PAUSE_S = 0.1
"""A stall of the output thread longer than this beyond a frame counts as a pause of the host:
past the 100 ms within which a frame is promised to the array."""


@dataclass(frozen=True)
class StreamStats:
    """A snapshot of the streamer's statistics.

    Attributes
    ----------
    state : str
        ``"starting"``, ``"streaming"``, ``"paused"``, ``"idle"``, ``"disconnected"``,
        ``"stopped"``, ``"refused"`` (the array is not the profile's) or ``"failed"`` (an
        internal error ended the stream; the array was turned off).
    status : str
        One line for the user (what happened last, e.g. why the stream stopped).
    requested_rate_hz, rate_hz : float
        Rate the scene asks for and rate in use (capped by the link).
    capped : bool
        True when the link cannot carry the requested rate.
    frames, bytes, errors : int
        Frames and bytes written, and link errors.
    late : int
        Frames written more than 1 ms after their deadline.
    skipped : int
        Deadlines passed over after a stall of more than one frame (the trace stays on time).
    achieved_rate_hz : float
        Frames per second over the last second.
    interval_error_p50_ms, interval_error_p99_ms : float
        Median and 99th percentile of ``|interval - period|`` between successive frames at a
        steady rate (last 8192 intervals).
    elapsed_s : float
        Seconds since the thread started.
    realtime : bool
        True when the output thread runs with real-time priority.
    array : str
        What the array said it is (its info), or why not ("unidentified: ...").
    array_frames, array_dropped, array_watchdog_trips : int
        The array's own counters from its last status answer (-1 before any): frames applied,
        messages dropped, watchdog trips.
    scheduled : bool
        True while frames go out timed, to be played ``lead_ms`` after their deadline on the
        array's clock (an array with the scheduled-frame extension, and a lead).
    lead_ms, clock_error_ms : float
        The lead in use (0 for frames played on arrival) and the expected error of the host's
        reading of the array's clock.
    schedule : str
        One line on how frames are timed, or why they are not.
    array_late, array_full : int
        The array's scheduling counters from its last clock answer (-1 before any): timed frames
        played after their time, and dropped for a full queue.
    clock_relearned : int
        Times the array's clock was learned afresh while streaming because it jumped (the array
        restarted while the line stayed up).
    pauses : int
        Times the output thread was held up more than :data:`PAUSE_S` beyond a frame: the host
        paused the stream (a SIGSTOP, a VM pause, a suspend, a swap storm) or the link took no
        data for that long. The stream resumes on time after each.
    longest_pause_s, paused_s : float
        The longest of those pauses, and all of them together (seconds).
    """

    state: str = "stopped"
    status: str = ""
    requested_rate_hz: float = 0.0
    rate_hz: float = 0.0
    capped: bool = False
    frames: int = 0
    bytes: int = 0
    errors: int = 0
    late: int = 0
    skipped: int = 0
    achieved_rate_hz: float = 0.0
    interval_error_p50_ms: float = 0.0
    interval_error_p99_ms: float = 0.0
    elapsed_s: float = 0.0
    realtime: bool = False
    array: str = ""
    array_frames: int = -1
    array_dropped: int = -1
    array_watchdog_trips: int = -1
    scheduled: bool = False
    lead_ms: float = 0.0
    clock_error_ms: float = float("inf")
    schedule: str = ""
    array_late: int = -1
    array_full: int = -1
    clock_relearned: int = 0
    pauses: int = 0
    longest_pause_s: float = 0.0
    paused_s: float = 0.0

    def summary(self) -> str:
        """Multi-line human summary (what ``tactile stream`` prints at the end)."""
        cap = " (capped by the link)" if self.capped else ""
        return "\n".join(
            [
                f"state:           {self.state} - {self.status}",
                f"rate:            {self.rate_hz:.1f} Hz "
                f"(requested {self.requested_rate_hz:g} Hz){cap}",
                f"achieved:        {self.achieved_rate_hz:.1f} Hz over the last second",
                f"frames:          {self.frames} ({self.bytes} bytes) in {self.elapsed_s:.2f} s",
                f"interval error:  p50 {self.interval_error_p50_ms:.3f} ms, "
                f"p99 {self.interval_error_p99_ms:.3f} ms",
                f"late (>1 ms):    {self.late}, skipped deadlines: {self.skipped}",
                (
                    f"host paused:     {self.pauses} times, longest {self.longest_pause_s:.2f} s, "
                    f"{self.paused_s:.2f} s in all"
                    if self.pauses
                    else f"host paused:     never (no stall over {PAUSE_S * 1e3:g} ms)"
                ),
                f"link errors:     {self.errors}",
                f"priority:        {'real-time' if self.realtime else 'normal'}",
                f"array:           {self.array or '-'}",
                (
                    f"array counters:  frames applied {self.array_frames}, messages dropped "
                    f"{self.array_dropped}, watchdog trips {self.array_watchdog_trips}"
                    if self.array_frames >= 0
                    else "array counters:  not reported"
                ),
                f"timing:          {self.schedule or '-'}"
                + (
                    f"; clock learned again {self.clock_relearned}x" if self.clock_relearned else ""
                ),
                (
                    f"array schedule:  late {self.array_late}, queue full {self.array_full}"
                    if self.array_late >= 0
                    else "array schedule:  not reported"
                ),
            ]
        )


class StatsBook:
    """The output thread's running statistics, under one lock: written by the output thread,
    read from any.

    Holds the current :class:`StreamStats` fields (state, status, ...), the counters (frames,
    bytes, errors, late, skipped), the write times of the recent frames (for the achieved rate)
    and the last 8192 interval errors (for their percentiles).
    """

    def __init__(self):
        self._lock = threading.Lock()
        self._intervals = np.zeros(8192)
        self._n_intervals = 0
        self._recent: list[float] = []
        self.current = StreamStats(state="starting", status="not started")
        """The fields set with :meth:`update` (the counters and rates are not kept here)."""
        self._counts = {"frames": 0, "bytes": 0, "errors": 0, "late": 0, "skipped": 0}

    def count(self, name: str, n: int = 1) -> None:
        """Add ``n`` to the counter ``name``."""
        with self._lock:
            self._counts[name] += n

    def update(self, **changes) -> StreamStats:
        """Change fields of :attr:`current`; returns the value before."""
        with self._lock:
            old = self.current
            self.current = StreamStats(**{**old.__dict__, **changes})
        return old

    def wrote(self, now_s: float, n_bytes: int) -> None:
        """One frame of ``n_bytes`` bytes went out at ``now_s`` (perf_counter seconds)."""
        with self._lock:
            self._counts["frames"] += 1
            self._counts["bytes"] += n_bytes
            self._recent.append(now_s)
            if len(self._recent) > 4 * 1024:
                del self._recent[: len(self._recent) - 2048]

    def paused(self, held_s: float) -> str:
        """The output thread was held up ``held_s`` seconds beyond a frame (> :data:`PAUSE_S`)
        and now resumes; returns the status line that says so."""
        with self._lock:
            old = self.current
            self.current = StreamStats(**{**old.__dict__, "pauses": old.pauses + 1,
                                          "longest_pause_s": max(old.longest_pause_s, held_s),
                                          "paused_s": old.paused_s + held_s})  # fmt: skip
        off = " (the array's watchdog had turned it off)" if held_s > WATCHDOG_S else ""
        return f"resumed after the host paused {held_s:.2f} s{off}"

    def record_interval(self, error_s: float) -> None:
        """One interval between successive frames, ``error_s`` off the period."""
        with self._lock:
            self._intervals[self._n_intervals % len(self._intervals)] = abs(error_s)
            self._n_intervals += 1

    def snapshot(self, running_since_s: float | None, now_s: float | None = None) -> StreamStats:
        """A :class:`StreamStats` of everything at ``now_s`` (the stream's clock, seconds;
        ``time.perf_counter`` if not given); ``elapsed_s`` counts from ``running_since_s`` while
        the thread runs, else it is the last one set."""
        with self._lock:
            stats = StreamStats(**{**self.current.__dict__, **self._counts})
            n = min(self._n_intervals, len(self._intervals))
            errors = self._intervals[:n].copy()
            recent = list(self._recent)
        now = time.perf_counter() if now_s is None else now_s
        recent = [t for t in recent if now - t <= 1.0]
        p50, p99 = (np.percentile(errors, [50, 99]) * 1e3) if n else (0.0, 0.0)
        elapsed = now - running_since_s if running_since_s else stats.elapsed_s
        if len(recent) > 1:
            achieved = (len(recent) - 1) / (recent[-1] - recent[0])
        else:
            achieved = 0.0
        return StreamStats(
            **{
                **stats.__dict__,
                "achieved_rate_hz": achieved,
                "interval_error_p50_ms": float(p50),
                "interval_error_p99_ms": float(p99),
                "elapsed_s": elapsed,
            }
        )
