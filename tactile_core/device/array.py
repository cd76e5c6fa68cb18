"""The array side of wire format 2, in Python: what the reference firmware does.

:class:`ArrayModel` receives the host's bytes and behaves as ``firmware/`` does on the
ATmega2560: it applies valid frames, answers a hello with its info and a query with its counters,
drops (and counts) every malformed message without changing its levels, and turns every tactor
off when no valid frame has arrived for 250 ms (a watchdog trip, counted when something was on).
The simulated array (:class:`~.link.SimulatedArray`) and ``tactile emulate`` are built
on it; the same test vectors run against it and against the firmware's C parser.
"""

from __future__ import annotations

from .profile import DeviceProfile, default_profile
from .wire import (
    PROTOCOL_VERSION,
    WATCHDOG_S,
    Frame,
    Hello,
    Info,
    MessageReader,
    Query,
    Status,
    encode_info,
    encode_status,
)

PWM_HZ = 303
"""The reference firmware's PWM frequency: a 6,666.7 Hz timer interrupt (16 MHz / 8 / 300)
steps through 22 slots per period for 23 levels: 303 Hz."""


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
    """

    def __init__(self, profile: DeviceProfile | None = None, *, pwm_hz: int = PWM_HZ,
                 watchdog_s: float = WATCHDOG_S):  # fmt: skip
        self.profile = profile or default_profile()
        self.channels = self.profile.channels
        self.watchdog_s = watchdog_s
        self.reader = MessageReader(
            channels=self.channels, levels=self.profile.levels, accept=(Frame, Hello, Query)
        )
        self.levels = bytes(self.channels)  # channel order
        self.frames_applied = 0
        self.watchdog_trips = 0
        self.last_valid: float | None = None
        self.last_seq: int | None = None
        grid = self.profile.grid
        name = self.profile.name.encode("ascii", "replace")[:64].decode("ascii")
        self.info = Info(0, PROTOCOL_VERSION, grid.cols, grid.rows, self.profile.levels,
                         round(watchdog_s * 1000), pwm_hz, name)  # fmt: skip

    @property
    def dropped(self) -> int:
        """Messages dropped so far (all reasons)."""
        return self.reader.bad

    def status(self, seq: int = 0) -> Status:
        """The counters as a status message would report them."""
        return Status(seq, self.frames_applied, self.dropped, self.watchdog_trips)

    def receive(self, data: bytes, now: float) -> tuple[bytes, list[Frame]]:
        """Take received bytes at monotonic time ``now``.

        Returns
        -------
        replies : bytes
            What the array sends back (info and status messages, wire form).
        frames : list of Frame
            The frames applied, in order.
        """
        self.watchdog(now)
        replies = bytearray()
        frames = []
        for msg in self.reader.feed(data):
            if isinstance(msg, Frame):
                self.levels = msg.levels
                self.frames_applied += 1
                self.last_valid = now
                self.last_seq = msg.seq
                frames.append(msg)
            elif isinstance(msg, Hello):
                replies += encode_info(
                    Info(msg.seq, *(getattr(self.info, k) for k in _INFO_FIELDS))
                )
            else:
                replies += encode_status(self.status(msg.seq))
        return bytes(replies), frames

    def watchdog(self, now: float) -> bool:
        """Turn everything off once more than ``watchdog_s`` passed without a valid frame (as the
        firmware's millisecond counter does); True if it tripped with something on."""
        if self.last_valid is None or now - self.last_valid <= self.watchdog_s:
            return False
        tripped = any(self.levels)
        if tripped:
            self.watchdog_trips += 1
        self.levels = bytes(self.channels)
        self.last_valid = None
        return tripped

    def due(self) -> float | None:
        """Monotonic time at which the watchdog will trip (None when it is not armed)."""
        return None if self.last_valid is None else self.last_valid + self.watchdog_s


_INFO_FIELDS = ("version", "cols", "rows", "levels", "watchdog_ms", "pwm_hz", "name")
