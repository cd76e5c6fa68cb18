"""The wire format from host to array: COBS-framed payloads with a CRC-8.

Every message is a payload encoded with COBS (Consistent Overhead Byte Stuffing) and followed by
one ``0x00`` byte, so a receiver resynchronises at the next zero after any corruption. The frame
payload:

==========  =============================================================================
byte        meaning
==========  =============================================================================
0           ``0x46`` (``'F'``)
1           sequence number, +1 per frame, wrapping 255 -> 0
2           N, the number of channels
3 .. 2+N    one level per channel, 0 .. levels-1, in channel order
3+N         CRC-8 of bytes 0 .. 2+N: polynomial 0x07, initial value 0x00, no reflection,
            no final xor (CRC-8/SMBUS; check value 0xF4 for ``b"123456789"``)
==========  =============================================================================

One frame for the 5 x 6 array is 34 payload bytes, 35 after COBS, 36 on the wire with the
delimiter. A receiver drops (and counts) frames with a bad CRC, a wrong N, or a level out of
range. These functions are pure: no I/O.
"""

from __future__ import annotations

from collections.abc import Iterable

from cobs import cobs

FRAME_TYPE = 0x46  # 'F'
DELIMITER = b"\x00"
WATCHDOG_S = 0.25
"""The array turns every tactor off when no valid frame has arrived for this long."""


def _crc8_table() -> tuple[int, ...]:
    table = []
    for byte in range(256):
        crc = byte
        for _ in range(8):
            crc = ((crc << 1) ^ 0x07) & 0xFF if crc & 0x80 else (crc << 1) & 0xFF
        table.append(crc)
    return tuple(table)


_CRC8 = _crc8_table()


def crc8(data: bytes) -> int:
    """CRC-8 with polynomial 0x07, initial value 0, no reflection, no final xor.

    Examples
    --------
    >>> hex(crc8(b"123456789"))
    '0xf4'
    """
    crc = 0
    for byte in data:
        crc = _CRC8[crc ^ byte]
    return crc


class FrameError(ValueError):
    """A message that is not a valid frame; ``reason`` is one of :data:`REASONS`."""

    def __init__(self, reason: str, detail: str):
        super().__init__(f"{reason}: {detail}")
        self.reason = reason


REASONS = ("cobs", "short", "type", "length", "crc", "range")
"""Why a frame was dropped: bad COBS encoding, too short, not an 'F' frame, N disagreeing with
the expected channel count or the message length, CRC mismatch, level out of range."""


def frame_length(channels: int) -> int:
    """Bytes on the wire for one frame of ``channels`` channels (36 for 30)."""
    payload = channels + 4
    return payload + 1 + payload // 254 + 1


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
        ``cobs(payload) + b"\\x00"``.

    Examples
    --------
    >>> encode_frame(0, [0, 22]).hex(" ")
    '02 46 02 02 03 16 37 00'
    """
    body = bytes((FRAME_TYPE, seq & 0xFF, 0)) + bytes(levels)
    n = len(body) - 3
    if n > 255:
        raise ValueError(f"levels must hold at most 255 channels, got {n}")
    payload = bytearray(body)
    payload[2] = n
    payload.append(crc8(payload))
    return cobs.encode(bytes(payload)) + DELIMITER


def decode_frame(message: bytes, *, channels: int | None = None, levels: int = 256):
    """Decode one message (the bytes between two delimiters, without them).

    Parameters
    ----------
    message : bytes
        The COBS-encoded payload.
    channels : int, optional
        Expected number of channels; a frame with another N is rejected.
    levels : int
        Number of device levels; a level ``>= levels`` is rejected.

    Returns
    -------
    seq : int
    values : bytes
        One level per channel, in channel order.

    Raises
    ------
    FrameError
        With ``reason`` naming why the frame is invalid.
    """
    try:
        payload = cobs.decode(bytes(message))
    except cobs.DecodeError as exc:
        raise FrameError("cobs", str(exc)) from None
    if len(payload) < 4:
        raise FrameError("short", f"{len(payload)} payload bytes, a frame has at least 4")
    if payload[0] != FRAME_TYPE:
        raise FrameError("type", f"first byte 0x{payload[0]:02x}, expected 0x46 ('F')")
    n = payload[2]
    if len(payload) != n + 4:
        raise FrameError("length", f"N = {n} but {len(payload) - 4} level bytes")
    if channels is not None and n != channels:
        raise FrameError("length", f"N = {n}, the array has {channels} channels")
    crc = crc8(payload[:-1])
    if crc != payload[-1]:
        raise FrameError("crc", f"CRC 0x{payload[-1]:02x}, computed 0x{crc:02x}")
    values = payload[3:-1]
    if values and max(values) >= levels:
        raise FrameError("range", f"level {max(values)} >= {levels} levels")
    return payload[1], values


class FrameReader:
    """Split a byte stream into messages at each ``0x00`` and decode them.

    Feed it whatever arrives; it returns the decoded frames and counts the dropped ones by
    reason. Garbage before the first delimiter is one bad message; a message longer than
    ``max_length`` (runaway garbage without zeros) is dropped as ``"length"`` without being
    buffered further.
    """

    def __init__(self, *, channels: int | None = None, levels: int = 256, max_length=512):
        self.channels = channels
        self.levels = levels
        self.max_length = max_length
        self.errors = dict.fromkeys(REASONS, 0)
        self._buffer = bytearray()
        self._overflow = False

    def feed(self, data: bytes) -> list[tuple[int, bytes]]:
        """Add received bytes; return the ``(seq, levels)`` of each complete valid frame."""
        frames = []
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
                    frames.append(
                        decode_frame(
                            bytes(self._buffer), channels=self.channels, levels=self.levels
                        )
                    )
                except FrameError as exc:
                    self.errors[exc.reason] += 1
            self._buffer.clear()
        return frames

    @property
    def bad(self) -> int:
        """Total dropped messages."""
        return sum(self.errors.values())
