"""What the streamer says to the array besides frames: who it is, its counters, its clock.

:class:`ArrayTalk` runs on the streamer's output thread. It sends the hello and checks the info
against the profile, sends status queries when asked and hands the answers to whoever waits,
and, for an array that plays timed frames, keeps the array's clock (:class:`~.clock.ArrayClock`)
with a burst of clock exchanges before the first frame and one every :data:`SYNC_EVERY_S` after,
each written just before a frame, when the line is idle (a request queued behind a frame
would carry that frame's transmission in its delay).

The clock is learned afresh on every connection, and whenever an exchange shows the array's
clock jumped or its counters went back (the array restarted while the line stayed up): frames
go for now until :data:`SYNC_BURST` new exchanges are in, one before each frame. Frames go
timed only while the error the clock states is within :data:`LEAD_FRACTION` of the lead; past
it they go for now, and timed again once the error is back within :data:`RESUME_FRACTION`.
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
LEAD_FRACTION = 0.25
"""Frames go for now while the array's clock is known less well than this fraction of the lead:
a frame sent ``lead`` ahead must still arrive before its time when the clock is off by its
stated error, beside the frame's transmission (2.6 ms at 115200 baud) and the host's stalls,
which the other three quarters leave room for (5 ms of a 20 ms lead)."""
RESUME_FRACTION = 0.125
"""Frames go timed again once the stated error is within this fraction of the lead (half of
:data:`LEAD_FRACTION`, so an error near the limit does not switch at every exchange)."""


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
        self._byte_s = getattr(link, "byte_s", 10.0 / profile.baud)
        self.clock = ArrayClock(byte_s=self._byte_s)
        self.timing = False
        """True while the array is one to time frames for: a lead, and an array that announced
        the extension; its clock is kept even while frames go for now."""
        self.scheduled = False
        """True while frames go out timed (the array answers the clock, and its stated error is
        within :data:`LEAD_FRACTION` of the lead)."""
        self._learning = False
        self._counters = (0, 0)  # the array's late and full counters in its last clock answer
        self.relearned = 0
        """Times the array's clock was learned afresh while streaming (it jumped)."""
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

    def connect(self) -> bool:
        """On (re)connecting: :meth:`hello`, then :meth:`start_schedule`; False when refused."""
        if not self.hello():
            return False
        self.start_schedule()
        return True

    def start_schedule(self) -> None:
        """With a lead, and an array that plays timed frames: learn its clock afresh (a burst
        of exchanges) and go timed; else frames for now, and the status says why."""
        self.scheduled = self.timing = self._learning = False
        self.clock = ArrayClock(byte_s=self._byte_s)  # a new connection: maybe a new array
        self._clock_sent.clear()
        self._counters = (0, 0)
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
        for _ in range(SYNC_BURST):  # (decided once, after the burst)
            seq = self._ask_clock()
            deadline = self._clock.now() + SYNC_TIMEOUT_S
            while seq in self._clock_sent and self._clock.now() < deadline:
                self.poll()
                self._clock.sleep(0.0005)
            self._clock_sent.pop(seq, None)
        self.timing = True
        self._learning = not self.clock.synced
        self._next_sync = self._clock.now() + SYNC_EVERY_S
        if self._learning:  # asked on, an exchange a frame: timed once it answers
            self._update(
                scheduled=False,
                lead_ms=0.0,
                schedule="frames for now: the array did not answer clock requests",
            )
            return
        self._decide(fresh=True, announce=False)

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
        """Just before a frame goes out: a clock exchange if one is due (the line is idle):
        every :data:`SYNC_EVERY_S`, or while the clock is learned afresh, one whenever the last
        was answered (or given up after :data:`SYNC_TIMEOUT_S`)."""
        if not self.timing:
            return
        if self._learning:
            if any(now_s - t0 < SYNC_TIMEOUT_S for t0 in self._clock_sent.values()):
                return
        elif now_s < self._next_sync:
            return
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
                    self._clock_answer(t0, now, msg)

    def _clock_answer(self, t0: float, t3: float, reply: ClockReply) -> None:
        """An exchange answered: a jump learns the clock afresh, else it joins the others."""
        sample = self.clock.measure(t0, t3, reply)
        jump = self.clock.jump_s(sample)
        went_back = reply.late < self._counters[0] or reply.full < self._counters[1]
        self._counters = (reply.late, reply.full)
        self._update(array_late=reply.late, array_full=reply.full)
        if jump or went_back:
            why = (f"the array's clock jumped {jump:+.3f} s" if jump else
                   "the array's late and full counters went back")  # fmt: skip
            self._relearn(why)
        self.clock.add(t0, t3, reply)
        if self._learning:
            if len(self.clock.samples) >= SYNC_BURST:
                self._learning = False
                self._decide(fresh=True)
        elif self.timing:
            self._decide(fresh=False)

    def _relearn(self, why: str) -> None:
        """Forget the array's clock and learn it again; frames for now meanwhile."""
        self.clock = ArrayClock(byte_s=self._byte_s)
        self._clock_sent.clear()
        self._learning = True
        self.scheduled = False
        self.relearned += 1
        self._update(
            scheduled=False,
            clock_relearned=self.relearned,
            schedule=f"frames for now: learning the array's clock again ({why})",
            status=f"{why} (did the array restart?): frames for now while its clock is "
            f"learned again",
        )

    def _decide(self, fresh: bool, announce: bool = True) -> None:
        """Timed or for now, by the error the clock states against the lead: a clock just
        learned (``fresh``) or in use goes for now past :data:`LEAD_FRACTION`, frames for now
        go timed again within :data:`RESUME_FRACTION`. ``announce``: a change is said in the
        status line too."""
        error_s = self.clock.error_s
        was = self.scheduled
        limit = LEAD_FRACTION if (was or fresh) else RESUME_FRACTION
        self.scheduled = error_s <= limit * self.lead_s
        if self.scheduled:
            self._report_clock()
            if announce and not was:
                self._update(status=f"timed frames: the array's clock is known to "
                                    f"{error_s * 1e3:.2f} ms")  # fmt: skip
        elif was or fresh:
            schedule = (
                f"frames for now: the array's clock is known only to {error_s * 1e3:.2f} ms, "
                f"more than {LEAD_FRACTION:g} of the {self.lead_s * 1e3:g} ms lead (timed "
                f"again within {RESUME_FRACTION * self.lead_s * 1e3:.2f} ms)"
            )
            self._update(scheduled=False, lead_ms=0.0, clock_error_ms=error_s * 1e3,
                         schedule=schedule,
                         **({"status": schedule} if announce else {}))  # fmt: skip
        else:
            self._update(clock_error_ms=error_s * 1e3)

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


__all__ = ["LEAD_FRACTION", "RESUME_FRACTION", "SYNC_BURST", "SYNC_EVERY_S", "ArrayTalk"]
