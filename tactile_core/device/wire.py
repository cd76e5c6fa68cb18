"""Wire format 2 between host and array: COBS-framed payloads sealed with a CRC-16.

Every message, in either direction, is a payload encoded with COBS (Consistent Overhead Byte
Stuffing) and followed by one ``0x00`` byte, so a receiver is back in step at the next zero after
any corruption. Every payload ends with the CRC-16/CCITT-FALSE of the bytes before it
(polynomial 0x1021, initial value 0xFFFF, no reflection, no final xor; ``crc16(b"123456789")
== 0x29B1``), high byte first. Multi-byte integers are big-endian.

Host to array:

=====  ========================================  ==============================================
type   payload before the CRC                    meaning
=====  ========================================  ==============================================
frame  ``'F'`` (0x46), seq, N, N levels          one level per channel, 0 .. levels - 1
hello  ``'H'`` (0x48), seq                       ask the array who it is
query  ``'Q'`` (0x51), seq                       ask for the array's counters
=====  ========================================  ==============================================

Array to host:

======  =================================================  ===========================
type    payload before the CRC                             meaning
======  =================================================  ===========================
info    ``'I'``, seq, version (2), cols, rows, levels,     the answer to a hello
        watchdog ms (u16), PWM Hz (u16), name length, name
status  ``'S'``, seq, frames applied (u32), messages        the answer to a query
        dropped (u32), watchdog trips (u16)
======  =================================================  ===========================

A frame for the 5 x 6 array is 35 payload bytes, 36 after COBS, 37 on the wire, so 115200 baud
(8N1, 11,520 bytes a second) carries 311 frames a second. A receiver drops a message whose CRC,
length, type or values are wrong, and counts it. These functions are pure: no I/O.

**Scheduled frames** (an extension an array announces in its info; format 2 arrays without it
keep working with plain frames): the host keeps the array's clock from clock exchanges and sends
each frame ahead of time with the moment it is to be played, so the array's own timer, not the
host's scheduler, decides when a frame reaches the motors.

============  ============================================  ====================================
type          payload before the CRC                        meaning
============  ============================================  ====================================
timed frame   ``'T'`` (0x54), seq, time (u32), N, N levels  play at ``time`` on the array's clock
clock         ``'C'`` (0x43), seq                           ask for the array's clock
clock reply   ``'c'`` (0x63), seq, arrival (u32), sent      the array's clock when the request's
              (u32), late (u32), full (u32), queued (u8)    delimiter arrived and when the reply
                                                            went out; its scheduling counters
============  ============================================  ====================================

The array's clock counts microseconds in a ``u32`` that wraps every 71.6 minutes; a time is
read as the nearest one to the array's own (a signed 32-bit difference). An array with the
extension appends two bytes to its info after the name: features (bit 0: scheduled frames) and
the number of timed frames it queues. A timed frame whose time has passed when it arrives is
played at once and counted *late*; one that finds the queue full is dropped and counted *full*;
a plain frame plays at once and drops the timed frames still waiting; the watchdog counts from
the last valid frame's arrival and drops the waiting ones too. A timed frame of 30 channels is
41 bytes on the wire: 281 frames a second at 115200 baud.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

from cobs import cobs

PROTOCOL_VERSION = 2
FRAME, HELLO, QUERY, INFO, STATUS = 0x46, 0x48, 0x51, 0x49, 0x53
TIMED, CLOCK, CLOCK_REPLY = 0x54, 0x43, 0x63
FEATURE_SCHEDULED = 0x01
"""Bit 0 of an info's feature byte: the array plays timed frames at their time."""
CLOCK_WRAP = 1 << 32
"""The array's clock counts microseconds modulo this (71.6 minutes)."""
DELIMITER = b"\x00"
WATCHDOG_S = 0.25
"""The array turns every tactor off when no valid frame has arrived for this long."""
KEEPALIVE_S = 0.1
"""While connected the host sends a frame at least this often, whatever the requested rate."""
HELLO_TIMEOUT_S = 0.5
"""An array that has not answered a hello within this long does not identify itself."""
MAX_MESSAGE = 300
"""Longest encoded message a receiver buffers (a frame of 255 channels is 262 bytes); a longer
run of bytes without a delimiter is dropped as one ``"length"`` error (as the firmware does)."""


def _crc16_table() -> tuple[int, ...]:
    table = []
    for byte in range(256):
        crc = byte << 8
        for _ in range(8):
            crc = ((crc << 1) ^ 0x1021) & 0xFFFF if crc & 0x8000 else (crc << 1) & 0xFFFF
        table.append(crc)
    return tuple(table)


_CRC16 = _crc16_table()


def crc16(data: bytes) -> int:
    """CRC-16/CCITT-FALSE: polynomial 0x1021, initial 0xFFFF, no reflection, no final xor.

    Examples
    --------
    >>> hex(crc16(b"123456789"))
    '0x29b1'
    """
    crc = 0xFFFF
    for byte in data:
        crc = ((crc << 8) & 0xFFFF) ^ _CRC16[(crc >> 8) ^ byte]
    return crc


def seal(body: bytes) -> bytes:
    """A payload's wire form: ``cobs(body + crc16(body)) + 0x00``."""
    body = bytes(body)
    return cobs.encode(body + crc16(body).to_bytes(2, "big")) + DELIMITER


def frame_length(channels: int, *, timed: bool = False) -> int:
    """Bytes on the wire for one frame of ``channels`` channels: 37 for 30, or 41 for a timed
    frame."""
    payload = channels + (9 if timed else 5)
    return payload + 1 + payload // 254 + 1


def clock_diff(a_us: int, b_us: int) -> int:
    """``a - b`` on the array's wrapping microsecond clock: the signed 32-bit difference.

    Examples
    --------
    >>> clock_diff(5, 2**32 - 5)
    10
    """
    d = (a_us - b_us) % CLOCK_WRAP
    return d - CLOCK_WRAP if d >= CLOCK_WRAP // 2 else d


# --- messages ---------------------------------------------------------------------------------


@dataclass(frozen=True)
class Frame:
    """Host to array: levels in channel order."""

    seq: int
    levels: bytes


@dataclass(frozen=True)
class Hello:
    """Host to array: who are you?"""

    seq: int


@dataclass(frozen=True)
class Query:
    """Host to array: your counters?"""

    seq: int


@dataclass(frozen=True)
class Timed:
    """Host to array: levels in channel order, to be played at ``at_us`` on the array's clock."""

    seq: int
    at_us: int
    levels: bytes


@dataclass(frozen=True)
class Clock:
    """Host to array: what time is it on your clock?"""

    seq: int


@dataclass(frozen=True)
class ClockReply:
    """Array to host: the answer to a :class:`Clock`.

    ``rx_us`` is the array's clock when the request's delimiter arrived, ``tx_us`` when the
    reply's first byte went out; ``late``, ``full`` and ``queued`` are its scheduling counters
    (timed frames played after their time, dropped for a full queue, waiting now)."""

    seq: int
    rx_us: int
    tx_us: int
    late: int
    full: int
    queued: int


@dataclass(frozen=True)
class Info:
    """Array to host: the answer to a :class:`Hello`.

    ``features`` and ``queue`` come from the scheduled-frame extension (0 for an array without
    it): bit 0 of ``features`` says the array plays timed frames, ``queue`` how many it holds.
    """

    seq: int
    version: int
    cols: int
    rows: int
    levels: int
    watchdog_ms: int
    pwm_hz: int
    name: str
    features: int = 0
    queue: int = 0

    @property
    def scheduled(self) -> bool:
        """True when the array plays timed frames at their time."""
        return bool(self.features & FEATURE_SCHEDULED) and self.queue > 0

    def describe(self) -> str:
        """One line, e.g. ``"palm-5x6: 5 x 6, 23 levels, PWM 303 Hz, watchdog 250 ms, protocol
        2, scheduled frames (24)"``."""
        extension = f", scheduled frames ({self.queue})" if self.scheduled else ""
        return (
            f"{self.name or '(unnamed)'}: {self.cols} x {self.rows}, {self.levels} levels, "
            f"PWM {self.pwm_hz} Hz, watchdog {self.watchdog_ms} ms, protocol {self.version}"
            f"{extension}"
        )


@dataclass(frozen=True)
class Status:
    """Array to host: the answer to a :class:`Query`."""

    seq: int
    frames_applied: int
    dropped: int
    watchdog_trips: int


def encode_frame(seq: int, levels: Iterable[int]) -> bytes:
    """Encode one frame for the wire, delimiter included.

    Parameters
    ----------
    seq : int
        Sequence number; reduced modulo 256.
    levels : iterable of int
        One level per channel in channel order, each 0..255 (the device's ``levels - 1`` at
        most; not checked here), at most 255 channels.

    Returns
    -------
    bytes

    Examples
    --------
    >>> encode_frame(0, [0, 22]).hex(" ")
    '02 46 02 02 04 16 d1 76 00'
    """
    levels = bytes(levels)
    if len(levels) > 255:
        raise ValueError(f"levels must hold at most 255 channels, got {len(levels)}")
    return seal(bytes((FRAME, seq & 0xFF, len(levels))) + levels)


def encode_timed(seq: int, at_us: int, levels: Iterable[int]) -> bytes:
    """Encode one timed frame for the wire, delimiter included.

    Parameters
    ----------
    seq : int
        Sequence number; reduced modulo 256.
    at_us : int
        When to play it, on the array's clock in microseconds; reduced modulo 2**32.
    levels : iterable of int
        One level per channel in channel order, at most 255 channels.

    Returns
    -------
    bytes

    Examples
    --------
    >>> encode_timed(1, 5000, [0, 22]).hex(" ")
    '03 54 01 01 04 13 88 02 04 16 61 8d 00'
    """
    levels = bytes(levels)
    if len(levels) > 255:
        raise ValueError(f"levels must hold at most 255 channels, got {len(levels)}")
    body = bytes((TIMED, seq & 0xFF)) + (at_us % CLOCK_WRAP).to_bytes(4, "big")
    return seal(body + bytes((len(levels),)) + levels)


def encode_clock(seq: int) -> bytes:
    """A clock request (wire form)."""
    return seal(bytes((CLOCK, seq & 0xFF)))


def encode_clock_reply(reply: ClockReply) -> bytes:
    """A clock reply (wire form); counters wrap at their widths."""
    body = bytes((CLOCK_REPLY, reply.seq & 0xFF))
    for value in (reply.rx_us, reply.tx_us, reply.late, reply.full):
        body += (value % CLOCK_WRAP).to_bytes(4, "big")
    return seal(body + bytes((reply.queued & 0xFF,)))


def encode_hello(seq: int) -> bytes:
    """A hello message (wire form)."""
    return seal(bytes((HELLO, seq & 0xFF)))


def encode_query(seq: int) -> bytes:
    """A query message (wire form)."""
    return seal(bytes((QUERY, seq & 0xFF)))


def encode_info(info: Info) -> bytes:
    """An info message (wire form); the name is ASCII, at most 64 characters."""
    name = info.name.encode("ascii")
    if len(name) > 64:
        raise ValueError(f"name must be at most 64 ASCII characters, got {len(name)}")
    body = bytes((INFO, info.seq & 0xFF, info.version, info.cols, info.rows, info.levels))
    body += info.watchdog_ms.to_bytes(2, "big") + info.pwm_hz.to_bytes(2, "big")
    body += bytes((len(name),)) + name
    if info.features or info.queue:  # the extension's two bytes; none for a plain format 2 array
        body += bytes((info.features & 0xFF, info.queue & 0xFF))
    return seal(body)


def encode_status(status: Status) -> bytes:
    """A status message (wire form); counters wrap at their widths (u32, u32, u16)."""
    body = bytes((STATUS, status.seq & 0xFF))
    body += (status.frames_applied & 0xFFFFFFFF).to_bytes(4, "big")
    body += (status.dropped & 0xFFFFFFFF).to_bytes(4, "big")
    body += (status.watchdog_trips & 0xFFFF).to_bytes(2, "big")
    return seal(body)


class MessageError(ValueError):
    """A message that is not valid; ``reason`` is one of :data:`REASONS`."""

    def __init__(self, reason: str, detail: str):
        super().__init__(f"{reason}: {detail}")
        self.reason = reason


REASONS = ("cobs", "short", "crc", "type", "length", "range")
"""Why a message was dropped: bad COBS encoding, too short for a type byte and a CRC, CRC
mismatch, unknown type, wrong length (or N disagreeing with the array's channels), a value out
of range (a level >= levels, an info with a version other than 2)."""

FrameError = MessageError  # the name the frame-only decoder had


def decode_message(
    message: bytes, *, channels: int | None = None, levels: int = 256, accept: tuple | None = None
):
    """Decode one message (the bytes between two delimiters, without them).

    Parameters
    ----------
    message : bytes
        The COBS-encoded payload.
    channels : int, optional
        Expected number of channels of a frame; a frame with another N is rejected.
    levels : int
        Number of device levels; a frame level ``>= levels`` is rejected.
    accept : tuple of message classes, optional
        The types this receiver takes (the array: frame, hello, query); any other type is
        rejected as ``"type"`` before its contents are looked at.

    Returns
    -------
    Frame, Hello, Query, Info or Status

    Raises
    ------
    MessageError
        With ``reason`` naming why the message is invalid.
    """
    try:
        payload = cobs.decode(bytes(message))
    except cobs.DecodeError as exc:
        raise MessageError("cobs", str(exc)) from None
    if len(payload) < 4:
        raise MessageError("short", f"{len(payload)} payload bytes, a message has at least 4")
    body, crc = payload[:-2], int.from_bytes(payload[-2:], "big")
    expected = crc16(body)
    if crc != expected:
        raise MessageError("crc", f"CRC 0x{crc:04x}, computed 0x{expected:04x}")
    kind, seq = body[0], body[1]
    if accept is not None and _CLASSES.get(kind) not in accept:
        raise MessageError("type", f"type 0x{kind:02x} is not taken here")
    if kind == FRAME:
        n = body[2] if len(body) > 2 else -1
        if len(body) != n + 3:
            raise MessageError("length", f"frame of {len(body)} bytes does not match N = {n}")
        if channels is not None and n != channels:
            raise MessageError("length", f"N = {n}, the array has {channels} channels")
        values = body[3:]
        if values and max(values) >= levels:
            raise MessageError("range", f"level {max(values)} >= {levels} levels")
        return Frame(seq, bytes(values))
    if kind == TIMED:
        n = body[6] if len(body) > 6 else -1
        if len(body) != n + 7:
            raise MessageError("length", f"timed frame of {len(body)} bytes does not match N = {n}")
        if channels is not None and n != channels:
            raise MessageError("length", f"N = {n}, the array has {channels} channels")
        values = body[7:]
        if values and max(values) >= levels:
            raise MessageError("range", f"level {max(values)} >= {levels} levels")
        return Timed(seq, int.from_bytes(body[2:6], "big"), bytes(values))
    if kind in (HELLO, QUERY, CLOCK):
        if len(body) != 2:
            raise MessageError("length", f"{chr(kind)} of {len(body)} bytes, expected 2")
        return {HELLO: Hello, QUERY: Query, CLOCK: Clock}[kind](seq)
    if kind == CLOCK_REPLY:
        if len(body) != 19:
            raise MessageError("length", f"clock reply of {len(body)} bytes, expected 19")
        rx, tx, late, full = (int.from_bytes(body[i : i + 4], "big") for i in (2, 6, 10, 14))
        return ClockReply(seq, rx, tx, late, full, body[18])
    if kind == INFO:
        if len(body) < 11 or len(body) not in (11 + body[10], 13 + body[10]):
            raise MessageError("length", f"info of {len(body)} bytes")
        if body[2] != PROTOCOL_VERSION:
            raise MessageError("range", f"protocol version {body[2]}, this host speaks 2")
        name = bytes(body[11 : 11 + body[10]])
        extension = body[11 + body[10] :]
        if any(b < 0x20 or b > 0x7E for b in name):
            raise MessageError("range", "info name is not printable ASCII")
        return Info(
            seq=seq,
            version=body[2],
            cols=body[3],
            rows=body[4],
            levels=body[5],
            watchdog_ms=int.from_bytes(body[6:8], "big"),
            pwm_hz=int.from_bytes(body[8:10], "big"),
            name=name.decode("ascii"),
            features=extension[0] if extension else 0,
            queue=extension[1] if extension else 0,
        )
    if kind == STATUS:
        if len(body) != 12:
            raise MessageError("length", f"status of {len(body)} bytes, expected 12")
        return Status(
            seq=seq,
            frames_applied=int.from_bytes(body[2:6], "big"),
            dropped=int.from_bytes(body[6:10], "big"),
            watchdog_trips=int.from_bytes(body[10:12], "big"),
        )
    raise MessageError("type", f"type 0x{kind:02x} is not F, T, H, Q, C, I, S or c")


_CLASSES = {
    FRAME: Frame,
    TIMED: Timed,
    HELLO: Hello,
    QUERY: Query,
    CLOCK: Clock,
    INFO: Info,
    STATUS: Status,
    CLOCK_REPLY: ClockReply,
}


def decode_frame(message: bytes, *, channels: int | None = None, levels: int = 256):
    """Decode a message that must be a frame: ``(seq, levels)``; else :class:`MessageError`."""
    msg = decode_message(message, channels=channels, levels=levels)
    if not isinstance(msg, Frame):
        raise MessageError("type", f"a {type(msg).__name__.lower()}, not a frame")
    return msg.seq, msg.levels


class MessageReader:
    """Split a byte stream into messages at each ``0x00`` and decode them.

    Feed it whatever arrives; it returns the decoded messages and counts the dropped ones by
    reason. Garbage before the first delimiter is one bad message; a message longer than
    ``max_length`` (runaway garbage without zeros) is dropped as ``"length"`` without being
    buffered further. ``accept`` limits the message types (others count as ``"type"``).
    """

    def __init__(
        self,
        *,
        channels: int | None = None,
        levels: int = 256,
        max_length: int = MAX_MESSAGE,
        accept: tuple = (Frame, Timed, Hello, Query, Clock, Info, Status, ClockReply),
    ):
        self.channels = channels
        self.levels = levels
        self.max_length = max_length
        self.accept = accept
        self.errors = dict.fromkeys(REASONS, 0)
        self._buffer = bytearray()
        self._overflow = False

    def feed(self, data: bytes) -> list:
        """Add received bytes; return each complete valid message."""
        out = []
        parts = bytes(data).split(DELIMITER)
        for i, part in enumerate(parts):
            last = i == len(parts) - 1
            if not self._overflow:
                self._buffer += part
                if len(self._buffer) > self.max_length:
                    self._overflow = True
                    self._buffer.clear()
            if last:
                break
            if self._overflow:
                self.errors["length"] += 1
                self._overflow = False
            elif self._buffer:
                try:
                    msg = decode_message(
                        bytes(self._buffer),
                        channels=self.channels,
                        levels=self.levels,
                        accept=self.accept,
                    )
                except MessageError as exc:
                    self.errors[exc.reason] += 1
                else:
                    out.append(msg)
            self._buffer.clear()
        return out

    @property
    def bad(self) -> int:
        """Total dropped messages."""
        return sum(self.errors.values())


class FrameReader(MessageReader):
    """A :class:`MessageReader` for frames only, returning ``(seq, levels)`` pairs."""

    def __init__(self, *, channels: int | None = None, levels: int = 256, max_length=MAX_MESSAGE):
        super().__init__(channels=channels, levels=levels, max_length=max_length, accept=(Frame,))

    def feed(self, data: bytes) -> list[tuple[int, bytes]]:
        """Add received bytes; return ``(seq, levels)`` of each complete valid frame."""
        return [(m.seq, m.levels) for m in super().feed(data)]
