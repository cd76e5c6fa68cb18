"""Links to an array: a serial port (or any pyserial URL), the simulated array, and (in
:mod:`.audio`) a multichannel audio interface.

A link is anything with ``write(data)``, ``read()`` (the bytes the array has sent, without
waiting), ``close()``, ``reopen()`` and a ``description``. ``write`` and ``read`` raise
:class:`LinkError` whose message is a one-line status for the user ("port busy: /dev/ttyUSB0 is
open in another program"); no other exception escapes a link.
"""

from __future__ import annotations

import errno
import os
import select
import socket
import threading
import time

import numpy as np
import serial

from .._shared import validate as _validate
from ._link_error import LinkError
from .array import ArrayModel
from .profile import DeviceProfile, default_profile
from .wire import HELLO_TIMEOUT_S, Info, MessageReader, encode_hello

SIMULATED_URLS = ("sim", "sim://", "simulated")
MAX_URL_CHARS = 1024
"""Longest device URL taken (a port name, a pyserial URL, ``audio:NAME?...``): messages name
the URL, some of them twice, and a 100,000-character one made a 300 KB error line."""


_RESET_TEXTS = ("socket disconnected", os.strerror(errno.ECONNRESET),
                os.strerror(errno.ECONNABORTED))  # fmt: skip
"""How a connection the array closed reads when it comes without an errno: pyserial wraps a
socket's reset in a ``SerialException`` ("read failed: [Errno 104] Connection reset by peer"),
and which of the two a refused second client sees is a race."""


_GONE_TEXTS = ("write failed", "read failed", "returned no data")
"""How pyserial says a device went away when it gives no errno: a failed write or read, and a
port that "reports readiness to read but returned no data" (a pseudo-terminal whose other end
closed, an unplugged adapter)."""


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
    if code == errno.ECONNREFUSED or "Connection refused" in text:
        return f"no device at {url}: connection refused (is the device or emulator running?)"
    if code in (errno.ECONNRESET, errno.ECONNABORTED) or any(r in text for r in _RESET_TEXTS):
        return (f"device disconnected: {url} closed the connection (an array serves one host "
                f"at a time: is another program connected to it?)")  # fmt: skip
    if code in (errno.EIO, errno.ENXIO, errno.ENODEV, errno.EPIPE) or any(
        words in text for words in _GONE_TEXTS
    ):
        return f"device disconnected: {url} ({text})"
    if isinstance(exc, ValueError):
        return f"invalid device URL {url!r}: {text}"
    return f"link error on {url}: {text or type(exc).__name__}"


READ_CHUNK_BYTES = 4096
"""Bytes asked of the port at a time by :meth:`SerialLink.read`."""
READ_MAX_BYTES = 1 << 16
"""The most :meth:`SerialLink.read` returns at once (a device that sends without end cannot
keep the output thread reading)."""


def _how_writes_wait(port) -> str:
    """How a port's writes wait for room: ``"own"`` (:meth:`SerialLink._write_all` waits on
    the descriptor: a serial port, ``spy://``, ``socket://``), ``"rfc2217"`` (pyserial's RFC 2217
    client, which takes no write timeout) or ``"pyserial"`` (``loop://``, Windows ports)."""
    module = type(port).__module__
    if module.endswith("protocol_socket"):
        return "own"
    if module.endswith("rfc2217"):
        return "rfc2217"
    if os.name == "posix" and isinstance(port, serial.serialposix.Serial):
        return "own"
    return "pyserial"


def _write_fileno(port) -> int | None:
    """The descriptor to wait on for room to write (the port is open)."""
    sock = getattr(port, "_socket", None)
    return sock.fileno() if sock is not None else port.fd


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
        A write that makes no progress for this long (the port takes no byte: a device that
        stopped reading) fails with "write timeout". A write that completed never does, however
        long the host was paused during it.

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
        self._write_fd = None
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
            port = serial.serial_for_url(self.url, baudrate=self.baud, timeout=0,
                                         do_not_open=True)  # fmt: skip
            waits = _how_writes_wait(port)
            # Our own waiting: each write takes what fits. rfc2217:// refuses any write
            # timeout (its writes wait in the socket's own, 5 s); loop:// keeps pyserial's.
            port.write_timeout = {"own": 0, "rfc2217": None}.get(waits, self.write_timeout_s)
            if hasattr(port, "exclusive") and not self.url.startswith(("loop://", "socket://")):
                try:
                    port.exclusive = True  # fail on a port another program holds (POSIX)
                except (ValueError, serial.SerialException):
                    pass
            port.open()
            sock = getattr(port, "_socket", None)  # socket:// URLs
            if sock is not None:
                # Frames are small and due now: no waiting for the last one's acknowledgement.
                sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
            self._write_fd = _write_fileno(port) if waits == "own" else None
        except (serial.SerialException, OSError, ValueError, NotImplementedError) as exc:
            raise LinkError(_explain(exc, self.url)) from None
        self._port = port

    def write(self, data: bytes) -> None:
        """Write all of ``data``; :class:`LinkError` on any failure."""
        with self._lock:
            port = self._port
            if port is None:
                raise LinkError(f"not connected: {self.url}")
            try:
                if self._write_fd is None:
                    port.write(data)  # loop://, rfc2217://: pyserial waits
                else:
                    self._write_all(port, data)
            except (serial.SerialException, OSError, ValueError) as exc:
                raise LinkError(_explain(exc, self.url)) from None

    def _write_all(self, port, data: bytes) -> None:
        """Write ``data`` in the pieces the port takes, waiting for room between them; a
        timeout only after ``write_timeout_s`` without room for a byte.

        pyserial's own write (3.5) starts its timer before writing and looks at it after: a
        host paused between the two (SIGSTOP, a VM pause, a swap storm) turned a write that had
        completed into "write timeout" and ended the stream, though the device read all along.
        Here only a device that takes nothing for the whole timeout is one, and that is judged
        by ``select`` on the port, asked twice: a host that was paused through the first wait
        finds the room the device made meanwhile on the second look.
        """
        view = memoryview(data)
        while view:
            _, ready, _ = select.select([], [self._write_fd], [], self.write_timeout_s)
            if not ready:
                _, ready, _ = select.select([], [self._write_fd], [], 0)
            if not ready:
                raise serial.SerialTimeoutException("Write timeout")
            view = view[port.write(view) or 0 :]

    def read(self) -> bytes:
        """The bytes received so far (without waiting); :class:`LinkError` on failure.

        Everything that has arrived, on every transport: pyserial's ``in_waiting`` is a byte
        count only on a serial port (``socket://`` answers 1 when anything is there, and an
        ``rfc2217://`` read without waiting returns one byte), so the port is read until it has
        nothing more, up to :data:`READ_MAX_BYTES` a call.
        """
        port = self._port
        if port is None:
            raise LinkError(f"not connected: {self.url}")
        data = bytearray()
        try:
            while len(data) < READ_MAX_BYTES:
                chunk = port.read(READ_CHUNK_BYTES)
                if not chunk:
                    break
                data += chunk
        except (serial.SerialException, OSError, ValueError) as exc:
            raise LinkError(_explain(exc, self.url)) from None
        return bytes(data)

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
    """The built-in array: the bytes that would go on the wire, received by
    :class:`~tactile_core.device.array.ArrayModel` (what the reference firmware does).

    It keeps the last valid levels, answers hello and query, enforces the 250 ms watchdog,
    counts dropped messages, and, when the profile has a motor response curve, reports what the
    motors would do ("felt") beside what was sent.

    Parameters
    ----------
    profile : DeviceProfile, optional
        The array simulated; the palm array by default.
    clock : HostClock, optional
        The host's clock the array's time follows (``time.perf_counter``; a streamer on a
        :class:`~.host_clock.VirtualClock` passes the same one here).
    """

    def __init__(self, profile: DeviceProfile | None = None, *, clock=None):
        from .host_clock import HostClock

        self.profile = profile or default_profile()
        self._now = (clock or HostClock()).now
        self.model = ArrayModel(self.profile, epoch=self._now())
        self._lock = threading.Lock()
        self._replies = bytearray()
        self.closed = False
        self.listeners: list = []
        """Called as ``listener(time_s, levels)`` for every frame the array applies (its host
        time, and its levels in channel order): what a simulated sensor on the array feels."""

    description = "simulated array"

    def reopen(self) -> None:
        """Nothing to reopen; clears the closed flag."""
        self.closed = False

    def write(self, data: bytes) -> None:
        """Receive bytes as the array would."""
        if self.closed:
            raise LinkError("simulated array closed")
        with self._lock:
            now = self._now()
            replies, frames = self.model.receive(data, now)
            self._replies += replies
            if self.listeners and frames:
                self._tell(frames, now)

    def _tell(self, frames, now: float) -> None:
        """(Under the lock.) The listeners get each frame applied: a timed one at the time it
        was to play."""
        times = {id(msg): t for t, msg, _ in self.model.onsets}
        for frame in frames:
            for listener in list(self.listeners):
                listener(times.get(id(frame), now), frame.levels)

    def read(self) -> bytes:
        """What the array answered since the last read."""
        if self.closed:
            raise LinkError("simulated array closed")
        with self._lock:
            data, self._replies = bytes(self._replies), bytearray()
        return data

    def close(self) -> None:
        """Stop receiving (the array then times out to all-off)."""
        self.closed = True

    @property
    def frames(self) -> int:
        """Frames applied."""
        return self.model.frames_applied

    @property
    def watchdog_trips(self) -> int:
        """Watchdog trips (brought up to date)."""
        with self._lock:
            now = self._now()
            self.model.advance(now)
            self.model.watchdog(now)
            return self.model.watchdog_trips

    @property
    def last_seq(self):
        """Sequence number of the last frame applied."""
        return self.model.last_seq

    @property
    def bad_frames(self) -> dict:
        """Dropped messages by reason."""
        return dict(self.model.reader.errors)

    def levels(self, now: float | None = None) -> np.ndarray:
        """Current levels as a ``(rows, cols)`` uint8 frame (``(size,)`` on a layout that is not
        a grid), zero after the watchdog."""
        now = self._now() if now is None else now
        with self._lock:
            played = self.model.advance(now)
            if self.listeners and played:
                self._tell(played, now)
            self.model.watchdog(now)
            channel_levels = np.frombuffer(self.model.levels, dtype=np.uint8)
        flat = np.zeros(self.profile.channels, dtype=np.uint8)
        flat[self.profile.array.channel_index] = channel_levels
        return flat.reshape(self.profile.layout.frame_shape)

    def sent(self, now: float | None = None) -> np.ndarray:
        """Levels as fractions of full drive, ``(rows, cols)`` float64."""
        return self.levels(now) / (self.profile.levels - 1)

    def felt(self, now: float | None = None) -> np.ndarray:
        """What the motors would do (response curve applied), ``(rows, cols)`` float64."""
        return self.profile.felt(self.sent(now))


def exchange(link, request: bytes, want, timeout_s: float, reader: MessageReader | None = None):
    """Send ``request`` and wait up to ``timeout_s`` for a reply of type ``want`` with the
    request's sequence number; return it, or None. :class:`LinkError` if the link fails.

    Replies with another sequence number (late answers to an earlier request) are skipped.
    """
    reader = reader or MessageReader(accept=(want,))
    seq = request_seq(request)
    link.write(request)
    deadline = time.monotonic() + timeout_s
    while True:
        for msg in reader.feed(link.read()):
            if isinstance(msg, want) and msg.seq == seq:
                return msg
        if time.monotonic() >= deadline:
            return None
        time.sleep(0.002)


def request_seq(request: bytes) -> int:
    """The sequence number of an encoded hello or query."""
    from cobs import cobs

    return cobs.decode(request[:-1])[1]


def identify(link, profile: DeviceProfile, seq: int = 0, timeout_s: float = HELLO_TIMEOUT_S):
    """Ask the array who it is and check it against the profile.

    Returns
    -------
    info : Info or None
        The array's answer, or None if it did not answer within ``timeout_s`` (an array that
        does not identify itself).
    problem : str
        Empty if the info agrees with the profile (columns, rows, levels); else one line saying
        how they differ.
    """
    info = exchange(link, encode_hello(seq), Info, timeout_s)
    if info is None:
        return None, ""
    cols, rows = profile.layout.wire_shape
    if (info.cols, info.rows, info.levels) != (cols, rows, profile.levels):
        return info, (
            f"array mismatch: the array reports {info.cols} x {info.rows} with {info.levels} "
            f"levels ({info.name or 'unnamed'}), the profile {profile.name} expects "
            f"{cols} x {rows} with {profile.levels} levels; not streaming"
        )
    return info, ""


def open_link(url: str | None, profile: DeviceProfile | None = None, *,
              open_timeout_s: float | None = None, **kwargs):  # fmt: skip
    """Open a link: the simulated array for None or ``"sim"``, an audio interface for
    ``audio:...`` (:class:`~.audio.AudioLink`, given up after ``open_timeout_s`` seconds if
    set, else its own :data:`~.audio.OPEN_DEVICE_TIMEOUT_S`), else a :class:`SerialLink`
    (``kwargs``: its own)."""
    from ._audio_url import is_audio_url

    profile = profile or default_profile()
    if url is None or url in SIMULATED_URLS:
        return SimulatedArray(profile)
    if isinstance(url, str) and not url.strip():
        raise LinkError("the device URL is empty: give a port (/dev/ttyUSB0, COM3), a pyserial "
                        "URL, 'sim' or 'audio:'")  # fmt: skip
    if isinstance(url, str) and len(url) > MAX_URL_CHARS:  # every message below repeats it
        raise LinkError(f"invalid device URL {_validate.shown(url)}: longer than "
                        f"{MAX_URL_CHARS} characters")  # fmt: skip
    if is_audio_url(url):
        from .audio import AudioLink

        if open_timeout_s is None:
            return AudioLink(url, profile)
        return AudioLink(url, profile, open_timeout_s=open_timeout_s)
    return SerialLink(url, baud=profile.baud, **kwargs)
