"""Wire format 2's decoding: one message, or a stream of them (see
:mod:`tactile_core.device.wire`)."""

from __future__ import annotations

from cobs import cobs

from ._wire_messages import (
    CLOCK,
    CLOCK_REPLY,
    DELIMITER,
    FRAME,
    HELLO,
    INFO,
    MAX_MESSAGE,
    PROTOCOL_VERSION,
    QUERY,
    STATUS,
    TIMED,
    Clock,
    ClockReply,
    Frame,
    Hello,
    Info,
    Query,
    Status,
    Timed,
    crc16,
    level_bits,
    unpack_levels,
)


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
        bits = level_bits(levels)
        if len(body) != 7 + (n * bits + 7) // 8:
            raise MessageError("length", f"timed frame of {len(body)} bytes does not match N = {n}")
        if channels is not None and n != channels:
            raise MessageError("length", f"N = {n}, the array has {channels} channels")
        values = unpack_levels(bytes(body[7:]), n, bits)
        if values and max(values) >= levels:
            raise MessageError("range", f"level {max(values)} >= {levels} levels")
        return Timed(seq, int.from_bytes(body[2:6], "big"), values)
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
