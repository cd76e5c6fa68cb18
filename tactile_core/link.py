"""Links to an array: a serial port (or any pyserial URL) and the simulated array.

A link is anything with ``write(data)``, ``close()``, ``reopen()`` and a ``description``.
``write`` raises :class:`LinkError` whose message is a one-line status for the user ("port busy:
/dev/ttyUSB0 is open in another program"); no other exception escapes a link.
"""

from __future__ import annotations

import errno
import threading
import time

import numpy as np
import serial

from .device import DeviceProfile, default_profile
from .wire import WATCHDOG_S, FrameReader


class LinkError(Exception):
    """The link failed; the message says what happened in words a user can act on."""


SIMULATED_URLS = ("sim", "sim://", "simulated")


def _explain(exc: BaseException, url: str) -> str:
    """Turn a pyserial/OS error into a short status line."""
    code = getattr(exc, "errno", None)
    text = str(exc)
    if isinstance(exc, serial.SerialTimeoutException):
        return f"write timeout: {url} is not taking data (device stalled or not reading)"
    if code == errno.ENOENT or "No such file" in text:
        return f"no such port: {url} (is the device plugged in?)"
    if code == errno.EACCES or "Permission denied" in text:
        return f"permission denied: {url} (on Linux, add yourself to the 'dialout' group)"
    if code == errno.EBUSY or "exclusively lock" in text or "busy" in text.lower():
        return f"port busy: {url} is open in another program"
    if code in (errno.EIO, errno.ENXIO, errno.ENODEV, errno.EPIPE) or "write failed" in text:
        return f"device disconnected: {url} ({text})"
    if isinstance(exc, ValueError):
        return f"invalid device URL {url!r}: {text}"
    return f"link error on {url}: {text or type(exc).__name__}"


class SerialLink:
    """A device reached through ``serial.serial_for_url``: a port name, ``loop://``,
    ``socket://host:port``, ``rfc2217://...``, ``spy://...``.

    Parameters
    ----------
    url : str
        Anything ``serial.serial_for_url`` accepts.
    baud : int
        Link speed, 8N1.
    write_timeout_s : float
        A write that cannot complete within this time fails with "write timeout".

    Raises
    ------
    LinkError
        On open, when the port is missing, busy, not permitted or the URL is invalid.
    """

    def __init__(self, url: str, baud: int = 115200, write_timeout_s: float = 0.2):
        self.url = url
        self.baud = baud
        self.write_timeout_s = write_timeout_s
        self._port = None
        self._lock = threading.Lock()
        self.reopen()

    @property
    def description(self) -> str:
        """The URL, for status lines."""
        return self.url

    def reopen(self) -> None:
        """(Re)open the port; raises :class:`LinkError` with the reason if it cannot."""
        self.close()
        try:
            port = serial.serial_for_url(
                self.url,
                baudrate=self.baud,
                timeout=0,
                write_timeout=self.write_timeout_s,
                do_not_open=True,
            )
            if hasattr(port, "exclusive") and not self.url.startswith(("loop://", "socket://")):
                try:
                    port.exclusive = True  # fail on a port another program holds (POSIX)
                except (ValueError, serial.SerialException):
                    pass
            port.open()
        except (serial.SerialException, OSError, ValueError) as exc:
            raise LinkError(_explain(exc, self.url)) from None
        self._port = port

    def write(self, data: bytes) -> None:
        """Write all of ``data``; :class:`LinkError` on any failure."""
        with self._lock:
            port = self._port
            if port is None:
                raise LinkError(f"not connected: {self.url}")
            try:
                port.write(data)
            except (serial.SerialException, OSError, ValueError) as exc:
                raise LinkError(_explain(exc, self.url)) from None

    def close(self) -> None:
        """Close the port (idempotent; never raises)."""
        with self._lock:
            port, self._port = self._port, None
        if port is not None:
            sock = getattr(port, "_socket", None)  # socket:// URLs
            try:
                port.close()
            except (serial.SerialException, OSError):
                pass
            if sock is not None:
                # pyserial 3.5 skips close() when shutdown() fails on a socket the peer has
                # already dropped, leaking it; closing twice is harmless.
                sock.close()


class SimulatedArray:
    """The built-in array: decodes exactly the bytes that would go on the wire.

    It keeps the last valid levels, enforces the contract's 250 ms watchdog, counts dropped
    frames, and, when the profile has a motor response curve, reports what the motors would do
    ("felt") beside what was sent.

    Parameters
    ----------
    profile : DeviceProfile, optional
        The array simulated; the palm array by default.
    """

    def __init__(self, profile: DeviceProfile | None = None):
        self.profile = profile or default_profile()
        self._reader = FrameReader(channels=self.profile.channels, levels=self.profile.levels)
        self._lock = threading.Lock()
        self._channel_levels = np.zeros(self.profile.channels, dtype=np.uint8)
        self._last_valid = None
        self.frames = 0
        self.watchdog_trips = 0
        self.last_seq = None
        self.closed = False

    description = "simulated array"

    def reopen(self) -> None:
        """Nothing to reopen; clears the closed flag."""
        self.closed = False

    def write(self, data: bytes) -> None:
        """Receive bytes as the array would."""
        if self.closed:
            raise LinkError("simulated array closed")
        frames = self._reader.feed(data)
        if frames:
            now = time.monotonic()
            with self._lock:
                seq, values = frames[-1]
                self._channel_levels = np.frombuffer(values, dtype=np.uint8).copy()
                self._last_valid = now
                self.frames += len(frames)
                self.last_seq = seq

    def close(self) -> None:
        """Stop receiving (the array then times out to all-off)."""
        self.closed = True

    @property
    def bad_frames(self) -> dict:
        """Dropped frames by reason."""
        return dict(self._reader.errors)

    def levels(self, now: float | None = None) -> np.ndarray:
        """Current levels as a ``(rows, cols)`` uint8 frame, zero after the watchdog."""
        now = time.monotonic() if now is None else now
        with self._lock:
            if self._last_valid is not None and now - self._last_valid > WATCHDOG_S:
                if self._channel_levels.any():
                    self.watchdog_trips += 1
                self._channel_levels[:] = 0
            channel_levels = self._channel_levels.copy()
        flat = np.zeros(self.profile.channels, dtype=np.uint8)
        flat[self.profile.array.channel_index] = channel_levels
        return flat.reshape(self.profile.grid.shape)

    def sent(self, now: float | None = None) -> np.ndarray:
        """Levels as fractions of full drive, ``(rows, cols)`` float64."""
        return self.levels(now) / (self.profile.levels - 1)

    def felt(self, now: float | None = None) -> np.ndarray:
        """What the motors would do (response curve applied), ``(rows, cols)`` float64."""
        return self.profile.felt(self.sent(now))


def open_link(url: str | None, profile: DeviceProfile | None = None, **kwargs):
    """Open a link: the simulated array for None or ``"sim"``, else a :class:`SerialLink`."""
    profile = profile or default_profile()
    if url is None or url in SIMULATED_URLS:
        return SimulatedArray(profile)
    return SerialLink(url, baud=profile.baud, **kwargs)
