"""Wire format 2's messages and their encoding (see :mod:`tactile_core.device.wire`)."""

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
KEEPALIVE_S = 0.06
"""While connected the host sends a frame at least this often, whatever the requested rate: the
contract promises one at least every 100 ms, and 60 ms leaves 40 ms for the host's scheduler,
the link and the receiver before that promise breaks at the array."""
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


def level_bits(levels: int) -> int:
    """Bits a level takes in a timed frame: enough for ``levels - 1`` (5 for 23 levels).

    Examples
    --------
    >>> level_bits(23), level_bits(2), level_bits(256)
    (5, 1, 8)
    """
    return max(1, (int(levels) - 1).bit_length())


def pack_levels(values: bytes, bits: int) -> bytes:
    """Levels as one bit string: each ``bits`` wide, most significant bit first, in channel
    order, zero-padded to a whole byte at the end.

    Examples
    --------
    >>> pack_levels(bytes([22, 1]), 5).hex(" ")  # 10110 00001 000000
    'b0 40'
    """
    acc = 0
    for value in values:
        if value >> bits:
            raise ValueError(f"level {value} does not fit {bits} bits")
        acc = (acc << bits) | value
    n_bits = len(values) * bits
    pad = -n_bits % 8
    return (acc << pad).to_bytes((n_bits + pad) // 8, "big")


def unpack_levels(data: bytes, n: int, bits: int) -> bytes:
    """The ``n`` levels of a bit string written by :func:`pack_levels`."""
    acc = int.from_bytes(data, "big") >> (len(data) * 8 - n * bits)
    mask = (1 << bits) - 1
    return bytes((acc >> (bits * (n - 1 - i))) & mask for i in range(n))


def frame_length(channels: int, *, timed: bool = False, bits: int = 8) -> int:
    """Bytes on the wire for one frame of ``channels`` channels: 37 for 30; a timed frame with
    levels of ``bits`` bits: 30 for 30 channels of 5 bits."""
    if timed:
        payload = 9 + (channels * bits + 7) // 8
    else:
        payload = channels + 5
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
    """Host to array: levels in channel order, to be played at ``at_us`` on the array's clock
    (on the wire packed at :func:`level_bits` bits a level)."""

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


def encode_timed(seq: int, at_us: int, levels: Iterable[int], bits: int) -> bytes:
    """Encode one timed frame for the wire, delimiter included.

    Parameters
    ----------
    seq : int
        Sequence number; reduced modulo 256.
    at_us : int
        When to play it, on the array's clock in microseconds; reduced modulo 2**32.
    levels : iterable of int
        One level per channel in channel order, at most 255 channels.
    bits : int
        Bits a level takes: :func:`level_bits` of the array's number of levels.

    Returns
    -------
    bytes

    Examples
    --------
    >>> encode_timed(1, 5000, [0, 22], bits=5).hex(" ")  # levels 00000 10110 -> 05 80
    '03 54 01 01 08 13 88 02 05 80 7d 07 00'
    """
    levels = bytes(levels)
    if len(levels) > 255:
        raise ValueError(f"levels must hold at most 255 channels, got {len(levels)}")
    body = bytes((TIMED, seq & 0xFF)) + (at_us % CLOCK_WRAP).to_bytes(4, "big")
    return seal(body + bytes((len(levels),)) + pack_levels(levels, bits))


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
