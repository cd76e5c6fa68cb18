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
timed frame   ``'T'`` (0x54), seq, time (u32), N, levels    play at ``time`` on the array's clock;
                                                            the levels packed, see below
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
the last valid frame's arrival and drops the waiting ones too. A timed frame's levels are packed
into as few bits as the array's levels need (5 for 23: :func:`level_bits`), most significant bit
first in channel order, zero-padded to a byte: a timed frame of 30 channels is 30 bytes on the
wire, 384 frames a second at 115200 baud, so timing costs no bandwidth.

The messages and their encoders are in ``_wire_messages``, the decoders in ``_wire_read``; this
module is their public face.
"""

from ._wire_messages import (
    CLOCK,
    CLOCK_REPLY,
    CLOCK_WRAP,
    DELIMITER,
    FEATURE_SCHEDULED,
    FRAME,
    HELLO,
    HELLO_TIMEOUT_S,
    INFO,
    KEEPALIVE_S,
    MAX_MESSAGE,
    PROTOCOL_VERSION,
    QUERY,
    STATUS,
    TIMED,
    WATCHDOG_S,
    Clock,
    ClockReply,
    Frame,
    Hello,
    Info,
    Query,
    Status,
    Timed,
    clock_diff,
    crc16,
    encode_clock,
    encode_clock_reply,
    encode_frame,
    encode_hello,
    encode_info,
    encode_query,
    encode_status,
    encode_timed,
    frame_length,
    level_bits,
    pack_levels,
    seal,
    unpack_levels,
)
from ._wire_read import (
    REASONS,
    FrameError,
    FrameReader,
    MessageError,
    MessageReader,
    decode_frame,
    decode_message,
)

__all__ = [
    "CLOCK",
    "CLOCK_REPLY",
    "CLOCK_WRAP",
    "DELIMITER",
    "FEATURE_SCHEDULED",
    "FRAME",
    "HELLO",
    "HELLO_TIMEOUT_S",
    "INFO",
    "KEEPALIVE_S",
    "MAX_MESSAGE",
    "PROTOCOL_VERSION",
    "QUERY",
    "REASONS",
    "STATUS",
    "TIMED",
    "WATCHDOG_S",
    "Clock",
    "ClockReply",
    "Frame",
    "FrameError",
    "FrameReader",
    "Hello",
    "Info",
    "MessageError",
    "MessageReader",
    "Query",
    "Status",
    "Timed",
    "clock_diff",
    "crc16",
    "decode_frame",
    "decode_message",
    "encode_clock",
    "encode_clock_reply",
    "encode_frame",
    "encode_hello",
    "encode_info",
    "encode_query",
    "encode_status",
    "encode_timed",
    "frame_length",
    "level_bits",
    "pack_levels",
    "seal",
    "unpack_levels",
]
