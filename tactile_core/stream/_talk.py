"""What the streamer says to the array besides frames: who it is, its counters, its clock.

:class:`ArrayTalk` runs on the streamer's output thread. It sends the hello and checks the info
against the profile, sends status queries when asked and hands the answers to whoever waits,
and, for an array that plays timed frames, keeps the array's clock (:class:`~.clock.ArrayClock`)
with a burst of clock exchanges before the first frame and one every :data:`SYNC_EVERY_S` after,
each written just before a frame, when the line is idle (a request queued behind a frame
would carry that frame's transmission in its delay).
"""

from __future__ import annotations

import threading

from ..device.clock import ArrayClock
from ..device.link import identify
from ..device.wire import (
    ClockReply,
    Info,
    MessageReader,
    Status,
    encode_clock,
    encode_query,
    frame_length,
    level_bits,
)

SYNC_BURST = 8
"""Clock exchanges before the first timed frame."""
SYNC_EVERY_S = 0.25
"""Seconds between clock exchanges while streaming."""
SYNC_TIMEOUT_S = 0.1
"""An exchange of the burst not answered within this is given up."""


class ArrayTalk:
    """The streamer's conversation with its array (everything but frames).

    Parameters
    ----------
    link
        The link frames go to (``write``, ``read``, ``description``).
    profile : DeviceProfile
        What the array should be.
    lead_s : float
        How far ahead timed frames are sent; 0 sends frames for now.
    update : callable
        ``update(**stats)``: the streamer's statistics setter.
    clock : HostClock, optional
        The streamer's clock.
    """

    def __init__(self, link, profile, *, lead_s: float, update, clock=None):
        from ..device.host_clock import HostClock

        self.link = link
        self._clock = clock or HostClock()
        self.profile = profile
        self.lead_s = lead_s
        self._update = update
        self.info: Info | None = None
        self.status: Status | None = None
        # A link may say how long a byte takes on it (an in-process one: none); else 8N1.
        self.clock = ArrayClock(byte_s=getattr(link, "byte_s", 10.0 / profile.baud))
        self.scheduled = False
        """True while frames go out timed (the array announced the extension and answers the
        clock)."""
        self.query_wanted = threading.Event()
        self.status_arrived = threading.Condition()
        self._reader = MessageReader(accept=(Info, Status, ClockReply))
        self._query_seq = 0
        self._clock_seq = 0
        self._clock_sent: dict[int, float] = {}
        self._next_sync = 0.0

    # --- who the array is --------------------------------------------------------------------

    def hello(self) -> bool:
        """Hello and check; False (state refused) when the array is not the profile's."""
        self._update(state="starting", status=f"identifying the array on {self.link.description}")
        info, problem = identify(self.link, self.profile)
        self.info = info
        if problem:
            self._update(state="refused", status=problem, array=info.describe())
            return False
        if info is None:
            cols, rows = self.profile.layout.wire_shape
            self._update(
                array=(
                    "unidentified: no answer to hello within 0.5 s; driven as "
                    f"{self.profile.name} ({cols} x {rows}, {self.profile.levels} "
                    "levels)"
                )
            )
        else:
            self._update(array=info.describe())
        return True

    def start_schedule(self) -> None:
        """With a lead, and an array that plays timed frames: learn its clock (a burst of
        exchanges) and go timed; else frames for now, and the status says why."""
        self.scheduled = False
        if self.lead_s <= 0:
            self._update(scheduled=False, lead_ms=0.0, schedule="frames for now (no lead)")
            return
        if self.info is None or not self.info.scheduled:
            self._update(
                scheduled=False,
                lead_ms=0.0,
                schedule="frames for now: the array does not announce scheduled frames",
            )
            return
        for _ in range(SYNC_BURST):
            seq = self._ask_clock()
            deadline = self._clock.now() + SYNC_TIMEOUT_S
            while seq in self._clock_sent and self._clock.now() < deadline:
                self.poll()
                self._clock.sleep(0.0005)
            self._clock_sent.pop(seq, None)
        if not self.clock.synced:
            self._update(
                scheduled=False,
                lead_ms=0.0,
                schedule="frames for now: the array did not answer clock requests",
            )
            return
        self.scheduled = True
        self._next_sync = self._clock.now() + SYNC_EVERY_S
        self._report_clock()

    @property
    def max_rate_hz(self) -> float:
        """Frames a second the link carries, timed or not (a link with a limit of its own, such
        as an audio interface, says so in its ``max_rate_hz``)."""
        own = getattr(self.link, "max_rate_hz", None)
        if own is not None:
            return own
        bits = level_bits(self.profile.levels)
        wire_bytes = frame_length(self.profile.channels, timed=self.scheduled, bits=bits)
        return self.profile.baud / 10.0 / wire_bytes

    # --- on the output thread, per frame -------------------------------------------------------

    def before_frame(self, now_s: float) -> None:
        """Just before a frame goes out: a clock exchange if one is due (the line is idle)."""
        if self.scheduled and now_s >= self._next_sync:
            self._next_sync = now_s + SYNC_EVERY_S
            self._ask_clock()
            # an exchange never answered (a reply lost to noise) is forgotten after a while
            for seq, t0 in list(self._clock_sent.items()):
                if now_s - t0 > 2.0:
                    del self._clock_sent[seq]

    def at_us(self, host_s: float) -> int:
        """The array's clock at host time ``host_s`` (wrapped microseconds)."""
        return self.clock.to_array_us(host_s)

    def after_frame(self) -> None:
        """Just after a frame: a status query if one was asked for, then read the answers."""
        if self.query_wanted.is_set():
            self.query_wanted.clear()
            self.send_query()
        self.poll()

    def send_query(self) -> None:
        """Ask the array for its counters."""
        self._query_seq = (self._query_seq + 1) & 0xFF
        self.link.write(encode_query(self._query_seq))

    def poll(self) -> None:
        """Read what the array sent (info, status and clock answers) without waiting."""
        data = self.link.read()
        if not data:
            return
        now = self._clock.now()
        for msg in self._reader.feed(data):
            if isinstance(msg, Status):
                with self.status_arrived:
                    self.status = msg
                    self.status_arrived.notify_all()
                self._update(
                    array_frames=msg.frames_applied,
                    array_dropped=msg.dropped,
                    array_watchdog_trips=msg.watchdog_trips,
                )
            elif isinstance(msg, ClockReply):
                t0 = self._clock_sent.pop(msg.seq, None)
                if t0 is not None:
                    self.clock.add(t0, now, msg)
                    self._update(array_late=msg.late, array_full=msg.full)
                    if self.scheduled:
                        self._report_clock()

    def _ask_clock(self) -> int:
        self._clock_seq = (self._clock_seq + 1) & 0xFF
        self._clock_sent[self._clock_seq] = self._clock.now()  # the request leaves now
        self.link.write(encode_clock(self._clock_seq))
        return self._clock_seq

    def _report_clock(self) -> None:
        self._update(
            scheduled=True,
            lead_ms=self.lead_s * 1e3,
            clock_error_ms=self.clock.error_s * 1e3,
            schedule=(
                f"timed frames {self.lead_s * 1e3:g} ms ahead on the array's clock "
                f"(known to {self.clock.error_s * 1e3:.2f} ms, drift "
                f"{self.clock.drift_ppm:+.0f} ppm)"
            ),
        )


__all__ = ["SYNC_BURST", "SYNC_EVERY_S", "ArrayTalk"]
