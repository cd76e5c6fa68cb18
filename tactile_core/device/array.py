"""The array side of wire format 2, in Python: what the reference firmware does.

:class:`ArrayModel` receives the host's bytes and behaves as ``firmware/`` does on the
ATmega2560: it applies valid frames, answers a hello with its info and a query with its counters,
drops (and counts) every malformed message without changing its levels, and turns every tactor
off when no valid frame has arrived for 250 ms (a watchdog trip, counted when something was on).
It speaks the scheduled-frame extension too: timed frames wait in a queue of
:data:`QUEUE` until their time on the array's clock, a clock request is answered with the
clock's reading, and a timed frame that arrives after its time plays at once and is counted late.

The simulated array (:class:`~.link.SimulatedArray`) and ``tactile emulate`` are built
on it; the same test vectors run against it and against the firmware's C parser.
"""

from __future__ import annotations

from collections import deque

from .profile import DeviceProfile, default_profile
from .wire import (
    CLOCK_WRAP,
    FEATURE_SCHEDULED,
    PROTOCOL_VERSION,
    WATCHDOG_S,
    Clock,
    ClockReply,
    Frame,
    Hello,
    Info,
    MessageReader,
    Query,
    Status,
    Timed,
    clock_diff,
    encode_clock_reply,
    encode_info,
    encode_status,
)

PWM_HZ = 303
"""The reference firmware's PWM frequency: a 6,666.7 Hz timer interrupt (16 MHz / 8 / 300)
steps through 22 slots per period for 23 levels: 303 Hz."""
ONSETS_KEPT = 4096
"""Onsets of timed frames an :class:`ArrayModel` keeps for its reader (13.7 s at 300 Hz)."""
QUEUE = 24
"""Timed frames the reference firmware holds (``TP_QUEUE``)."""
QUEUE_CHANNELS = 30
"""Channels a queued frame has room for (``TP_QUEUE_CHANNELS``): an array with more channels
does not announce the extension."""


class ArrayModel:
    """The receiving array, message by message.

    Parameters
    ----------
    profile : DeviceProfile, optional
        Channels, levels and name of the array (the palm array by default).
    pwm_hz : int
        PWM frequency the array reports in its info.
    watchdog_s : float
        Silence after which every tactor goes off.
    epoch : float
        Host time (the ``now`` passed in, seconds) at which the array's clock reads 0; its
        clock counts microseconds from there, wrapping every 2**32.
    scheduled : bool
        Speak the scheduled-frame extension (announced in the info); False is a plain format 2
        array, which drops timed frames and clock requests as an unknown type.
    queue_channels : int
        The most channels a queued frame holds; an array with more does not announce the
        extension (the firmware's :data:`QUEUE_CHANNELS`; an audio interface has no such limit).
    """

    def __init__(self, profile: DeviceProfile | None = None, *, pwm_hz: int = PWM_HZ,
                 watchdog_s: float = WATCHDOG_S, epoch: float = 0.0,
                 scheduled: bool = True, queue_channels: int = QUEUE_CHANNELS):  # fmt: skip
        self.profile = profile or default_profile()
        self.channels = self.profile.channels
        self.watchdog_s = watchdog_s
        self.epoch = epoch
        self.scheduled = scheduled and self.channels <= queue_channels
        accept = (Frame, Hello, Query) + ((Timed, Clock) if self.scheduled else ())
        self.reader = MessageReader(
            channels=self.channels, levels=self.profile.levels, accept=accept
        )
        self.levels = bytes(self.channels)  # channel order
        self.frames_applied = 0
        self.watchdog_trips = 0
        self.late = 0
        self.full = 0
        self.flushed = 0
        """Timed frames dropped unplayed: by a frame for now, or by the watchdog."""
        self.queue: deque[Timed] = deque()
        self.last_valid: float | None = None
        self.last_seq: int | None = None
        self.seq_gaps = 0
        """Sequence numbers missing among the frames received (for now or timed), in arrival
        order: frames lost on the way. Timed frames dropped unplayed were received, and are
        not gaps."""
        self._received_seq: int | None = None
        self.onsets: deque[tuple[float, Timed, bool]] = deque(maxlen=ONSETS_KEPT)
        """Timed frames played: ``(host time, frame, late)``, for emulators that log them (the
        latest :data:`ONSETS_KEPT`: a simulated array nobody reads must not grow)."""
        cols, rows = self.profile.layout.wire_shape
        name = self.profile.name.encode("ascii", "replace")[:64].decode("ascii")
        self.info = Info(0, PROTOCOL_VERSION, cols, rows, self.profile.levels,
                         round(watchdog_s * 1000), pwm_hz, name,
                         FEATURE_SCHEDULED if self.scheduled else 0,
                         QUEUE if self.scheduled else 0)  # fmt: skip

    @property
    def dropped(self) -> int:
        """Messages dropped so far (all reasons)."""
        return self.reader.bad

    def clock_us(self, now: float) -> int:
        """The array's clock at host time ``now``: microseconds since ``epoch``, wrapping."""
        return round((now - self.epoch) * 1e6) % CLOCK_WRAP

    def host_time(self, at_us: int, now: float) -> float:
        """The host time of array time ``at_us``, read as the nearest such time to ``now``."""
        return now + clock_diff(at_us, self.clock_us(now)) / 1e6

    def status(self, seq: int = 0) -> Status:
        """The counters as a status message would report them."""
        return Status(seq, self.frames_applied, self.dropped, self.watchdog_trips)

    def receive(self, data: bytes, now: float) -> tuple[bytes, list]:
        """Take received bytes at host time ``now`` (seconds).

        Timed frames already due by ``now`` play first (at their times), then the messages in
        ``data`` are handled in order.

        Returns
        -------
        replies : bytes
            What the array sends back (info, status and clock messages, wire form).
        frames : list of Frame or Timed
            The frames applied, in order.
        """
        frames = self.advance(now)
        replies = bytearray()
        for msg in self.reader.feed(data):
            if isinstance(msg, (Frame, Timed)):
                if self._received_seq is not None:
                    self.seq_gaps += (msg.seq - self._received_seq - 1) % 256
                self._received_seq = msg.seq
            if isinstance(msg, Frame):
                self.flushed += len(self.queue)
                self.queue.clear()  # a frame for now drops what is scheduled
                self._apply(msg, now)
                frames.append(msg)
            elif isinstance(msg, Timed):
                self.last_valid = now  # feeds the watchdog on arrival
                if len(self.queue) >= QUEUE:
                    self.full += 1
                elif clock_diff(msg.at_us, self.clock_us(now)) < 0 and not self.queue:
                    self._apply(msg, now)  # its time has passed: at once, counted late
                    self.late += 1
                    self.onsets.append((now, msg, True))
                    frames.append(msg)
                else:
                    self.queue.append(msg)
                    frames += self.advance(now)  # due this very moment
            elif isinstance(msg, Hello):
                self._received_seq = None  # a host starts again: its sequence restarts
                replies += encode_info(
                    Info(msg.seq, *(getattr(self.info, k) for k in _INFO_FIELDS))
                )
            elif isinstance(msg, Clock):
                at = self.clock_us(now)
                replies += encode_clock_reply(
                    ClockReply(msg.seq, at, at, self.late, self.full, len(self.queue))
                )
            else:
                replies += encode_status(self.status(msg.seq))
        return bytes(replies), frames

    def advance(self, now: float) -> list[Timed]:
        """Play the timed frames whose time has come by host time ``now``, in order."""
        played = []
        clock = self.clock_us(now)
        while self.queue and clock_diff(self.queue[0].at_us, clock) <= 0:
            msg = self.queue.popleft()
            self._apply(msg, None)
            self.onsets.append((self.host_time(msg.at_us, now), msg, False))
            played.append(msg)
        return played

    def _apply(self, msg, now: float | None) -> None:
        self.levels = msg.levels
        self.frames_applied += 1
        self.last_seq = msg.seq
        if now is not None:
            self.last_valid = now

    def watchdog(self, now: float) -> bool:
        """Turn everything off once more than ``watchdog_s`` passed without a valid frame (and
        drop the timed frames waiting); True if it tripped with something on."""
        if self.last_valid is None or now - self.last_valid <= self.watchdog_s:
            return False
        tripped = any(self.levels)
        if tripped:
            self.watchdog_trips += 1
        self.levels = bytes(self.channels)
        self.last_valid = None
        self.flushed += len(self.queue)
        self.queue.clear()
        return tripped

    def due(self) -> float | None:
        """Host time of the next thing the array does on its own: the watchdog or the next timed
        frame (None when neither is pending)."""
        times = []
        if self.last_valid is not None:
            times.append(self.last_valid + self.watchdog_s)
        if self.queue:
            reference = self.last_valid if self.last_valid is not None else self.epoch
            times.append(self.host_time(self.queue[0].at_us, reference))
        return min(times) if times else None


_INFO_FIELDS = ("version", "cols", "rows", "levels", "watchdog_ms", "pwm_hz", "name",
                "features", "queue")  # fmt: skip
