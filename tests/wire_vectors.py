"""Test vectors of wire format 2, built without the code under test.

Each vector is a fresh palm array (5 x 6, 23 levels, watchdog 250 ms, the scheduled-frame
extension with a queue of 24) whose clock starts at 0 µs, receiving ``steps``:
``("feed", bytes)`` or ``("advance_ms", n)`` (the clock moves on; timed frames that come due
play, at most one per step here). After the steps it has applied the frames ``applied`` (seq,
levels) in order, holds ``levels``, has answered ``replies`` (the concatenated wire bytes) and
counts ``frames_applied``, ``dropped`` (by reason in ``dropped_by``) and ``watchdog_trips``.
The same vectors run against the Python receiver (:class:`tactile_core.device.array.ArrayModel`)
and the firmware's C parser compiled for the host.

The CRC is computed bit by bit here and COBS by hand, independently of ``tactile_core.device.wire``.
"""

PALM = {
    "cols": 5,
    "rows": 6,
    "levels": 23,
    "watchdog_ms": 250,
    "pwm_hz": 303,
    "name": "palm-5x6",
    "features": 1,
    "queue": 24,
}


def crc16_bitwise(data: bytes) -> int:
    """CRC-16/CCITT-FALSE one bit at a time: poly 0x1021, init 0xFFFF, no reflection/xor."""
    crc = 0xFFFF
    for byte in data:
        crc ^= byte << 8
        for _ in range(8):
            crc = ((crc << 1) ^ 0x1021) & 0xFFFF if crc & 0x8000 else (crc << 1) & 0xFFFF
    return crc


def cobs_encode(data: bytes) -> bytes:
    """COBS by the textbook: each zero-free run of up to 254 bytes after a length code."""
    out, run = bytearray(), bytearray()
    for byte in data:
        if byte == 0:
            out += bytes((len(run) + 1,)) + run
            run.clear()
        else:
            run.append(byte)
            if len(run) == 254:
                out += b"\xff" + run
                run.clear()
    out += bytes((len(run) + 1,)) + run
    return bytes(out)


def wire(body: bytes) -> bytes:
    """A payload sealed with its CRC (high byte first), COBS-encoded, delimited."""
    crc = crc16_bitwise(body)
    return cobs_encode(body + bytes((crc >> 8, crc & 0xFF))) + b"\x00"


def frame(seq, levels):
    return wire(bytes((0x46, seq, len(levels))) + bytes(levels))


def packed(levels, bits=5):
    """Levels as a string of '0'/'1', ``bits`` each, most significant first, zero-padded."""
    text = "".join(format(v, f"0{bits}b") for v in levels)
    text += "0" * (-len(text) % 8)
    return bytes(int(text[i : i + 8], 2) for i in range(0, len(text), 8))


def timed(seq, at_us, levels):
    """A timed frame: played at ``at_us`` on the array's clock (u32, big-endian), its levels
    packed at 5 bits (the palm array's 23 levels)."""
    head = bytes((0x54, seq)) + at_us.to_bytes(4, "big") + bytes((len(levels),))
    return wire(head + packed(levels))


def clock(seq):
    return wire(bytes((0x43, seq)))


def clock_reply(seq, rx_us, tx_us, late, full, queued):
    body = bytes((0x63, seq)) + b"".join(v.to_bytes(4, "big") for v in (rx_us, tx_us, late, full))
    return wire(body + bytes((queued,)))


def hello(seq):
    return wire(bytes((0x48, seq)))


def query(seq):
    return wire(bytes((0x51, seq)))


def info(seq, a=PALM):
    name = a["name"].encode()
    body = bytes((0x49, seq, 2, a["cols"], a["rows"], a["levels"]))
    body += a["watchdog_ms"].to_bytes(2, "big") + a["pwm_hz"].to_bytes(2, "big")
    body += bytes((len(name),)) + name
    if a.get("features"):  # the scheduled-frame extension: features, queue depth
        body += bytes((a["features"], a["queue"]))
    return wire(body)


def status(seq, frames, dropped, trips):
    body = bytes((0x53, seq)) + frames.to_bytes(4, "big") + dropped.to_bytes(4, "big")
    return wire(body + trips.to_bytes(2, "big"))


RAMP = [i % 23 for i in range(30)]  # 0, 1, ..., 22, 0, 1, ..., 6
FULL = [22] * 30
OFF = [0] * 30


def flip(data: bytes, index: int, bit: int) -> bytes:
    """``data`` with one bit flipped."""
    out = bytearray(data)
    out[index] ^= 1 << bit
    return bytes(out)


def _vector(
    name,
    steps,
    *,
    applied=(),
    levels=OFF,
    replies=b"",
    dropped_by=None,
    trips=0,
    some_dropped=False,
):
    """``some_dropped``: at least one message is dropped, for whatever reason (a flipped bit
    may fall in a COBS code, the CRC, or make a zero that splits the message in two)."""
    dropped_by = dict(dropped_by or {})
    return {
        "name": name,
        "steps": steps,
        "applied": list(applied),
        "levels": list(levels),
        "replies": replies,
        "frames_applied": len(applied),
        "dropped": None if some_dropped else sum(dropped_by.values()),
        "dropped_by": None if some_dropped else dropped_by,
        "watchdog_trips": trips,
    }


VECTORS = [
    _vector(
        "hello 0 is answered with the palm array's info", [("feed", hello(0))], replies=info(0)
    ),
    _vector(
        "query 5 on a fresh array: all counters zero",
        [("feed", query(5))],
        replies=status(5, 0, 0, 0),
    ),
    _vector("a frame is applied", [("feed", frame(1, RAMP))], applied=[(1, RAMP)], levels=RAMP),
    _vector(
        "two frames in one write: both applied, the last one holds",
        [("feed", frame(254, FULL) + frame(255, RAMP))],
        applied=[(254, FULL), (255, RAMP)],
        levels=RAMP,
    ),
    _vector(
        "counters after a frame and a bad message",
        [("feed", frame(9, RAMP)), ("feed", flip(frame(10, FULL), 12, 0)), ("feed", query(3))],
        applied=[(9, RAMP)],
        levels=RAMP,
        replies=status(3, 1, 1, 0),
        dropped_by={"crc": 1},
    ),
]
# One flipped bit anywhere in a frame's COBS bytes (delimiter excepted) never applies it.
_BASE = frame(7, RAMP)
VECTORS += [
    _vector(
        f"frame with bit {bit} of byte {index} flipped is dropped",
        [("feed", frame(6, FULL)), ("feed", flip(_BASE, index, bit))],
        applied=[(6, FULL)],
        levels=FULL,
        some_dropped=True,
    )
    for index in (0, 1, 3, 17, 34, 35)
    for bit in (0, 7)
]
VECTORS += [
    _vector(
        "garbage glued to a frame loses both: no delimiter between them",
        [("feed", bytes.fromhex("11 22 33") + frame(4, RAMP))],
        dropped_by={"cobs": 1},
    ),
    _vector(
        "a frame of 2 channels is the wrong length",
        [("feed", frame(1, [0, 22]))],
        dropped_by={"length": 1},
    ),
    _vector(
        "a level of 23 is out of range",
        [("feed", frame(1, [*RAMP[:29], 23]))],
        dropped_by={"range": 1},
    ),
    _vector("an unknown type with a good CRC", [("feed", wire(b"X\x01"))], dropped_by={"type": 1}),
    _vector("an info sent to the array is not taken", [("feed", info(1))], dropped_by={"type": 1}),
    _vector(
        "a hello with a byte too many", [("feed", wire(b"H\x01\x00"))], dropped_by={"length": 1}
    ),
    _vector(
        "two bytes are too short for a message",
        [("feed", cobs_encode(b"F\x00") + b"\x00")],
        dropped_by={"short": 1},
    ),
    _vector(
        "a COBS code running past the message",
        [("feed", bytes.fromhex("05 11 22 00"))],
        dropped_by={"cobs": 1},
    ),
    _vector(
        "garbage before a frame: the receiver is back in step at the next delimiter",
        [("feed", bytes.fromhex("11 22 33 00") + frame(4, RAMP))],
        applied=[(4, RAMP)],
        levels=RAMP,
        dropped_by={"cobs": 1},
    ),
    _vector(
        "400 bytes without a delimiter are one over-long message",
        [("feed", b"\x01" * 400 + b"\x00" + frame(2, FULL))],
        applied=[(2, FULL)],
        levels=FULL,
        dropped_by={"length": 1},
    ),
    _vector("delimiters alone are no messages", [("feed", b"\x00\x00\x00")]),
    _vector(
        "the watchdog turns everything off once 250 ms have passed, and counts it",
        [("feed", frame(1, RAMP)), ("advance_ms", 250), ("advance_ms", 1), ("feed", query(8))],
        applied=[(1, RAMP)],
        levels=OFF,
        replies=status(8, 1, 0, 1),
        trips=1,
    ),
    _vector(
        "250 ms of silence is not yet a trip (251 is)",
        [("feed", frame(1, RAMP)), ("advance_ms", 250)],
        applied=[(1, RAMP)],
        levels=RAMP,
    ),
    _vector(
        "an all-off array timing out is no trip",
        [("feed", frame(1, OFF)), ("advance_ms", 300), ("feed", query(2))],
        applied=[(1, OFF)],
        replies=status(2, 1, 0, 0),
    ),
    _vector(
        "hello and query do not feed the watchdog",
        [
            ("feed", frame(1, FULL)),
            ("advance_ms", 200),
            ("feed", hello(1)),
            ("advance_ms", 60),
        ],
        applied=[(1, FULL)],
        replies=info(1),
        trips=1,
    ),
]

# The scheduled-frame extension.
_LATE_THEN_ASK = [("advance_ms", 10), ("feed", timed(2, 5000, RAMP)), ("feed", clock(4))]
_WRAP = 2**32
VECTORS += [
    _vector(
        "a timed frame waits for its time on the array's clock",
        [("feed", timed(1, 5000, RAMP)), ("advance_ms", 4), ("feed", query(1))],
        replies=status(1, 0, 0, 0),
    ),
    _vector(
        "a timed frame plays when its time comes",
        [("feed", timed(1, 5000, RAMP)), ("advance_ms", 4), ("advance_ms", 1)],
        applied=[(1, RAMP)],
        levels=RAMP,
    ),
    _vector(
        "timed frames play in order, each at its own time",
        [("feed", timed(1, 2000, RAMP) + timed(2, 4000, FULL)), ("advance_ms", 2)],
        applied=[(1, RAMP)],
        levels=RAMP,
    ),
    _vector(
        "the second timed frame follows at its time",
        [
            ("feed", timed(1, 2000, RAMP) + timed(2, 4000, FULL)),
            ("advance_ms", 2),
            ("advance_ms", 2),
        ],
        applied=[(1, RAMP), (2, FULL)],
        levels=FULL,
    ),
    _vector(
        "a timed frame whose time has passed plays at once and is counted late",
        _LATE_THEN_ASK,
        applied=[(2, RAMP)],
        levels=RAMP,
        replies=clock_reply(4, 10_000, 10_000, 1, 0, 0),
    ),
    _vector(
        "a frame for now drops the timed frames waiting",
        [
            ("feed", timed(1, 5000, FULL)),
            ("feed", frame(2, RAMP)),
            ("advance_ms", 10),
            ("feed", clock(1)),
        ],
        applied=[(2, RAMP)],
        levels=RAMP,
        replies=clock_reply(1, 10_000, 10_000, 0, 0, 0),
    ),
    _vector(
        "the clock request is answered with the clock at its arrival",
        [("advance_ms", 7), ("feed", timed(1, 9000, FULL)), ("feed", clock(3))],
        replies=clock_reply(3, 7000, 7000, 0, 0, 1),
    ),
    _vector(
        "a full queue drops the 25th timed frame and counts it",
        [("feed", b"".join(timed(i, 100_000 + i, RAMP) for i in range(25))), ("feed", clock(9))],
        replies=clock_reply(9, 0, 0, 0, 1, 24),
    ),
    _vector(
        "timed frames feed the watchdog when they arrive, and it drops the ones waiting",
        [
            ("feed", timed(1, 1000, FULL)),
            ("feed", timed(2, 400_000, RAMP)),
            ("advance_ms", 1),
            ("advance_ms", 251),
            ("advance_ms", 200),
            ("feed", clock(5)),
        ],
        applied=[(1, FULL)],
        levels=OFF,
        replies=clock_reply(5, 452_000, 452_000, 0, 0, 0),
        trips=1,
    ),
    _vector(
        "a time just past the clock's wrap is in the future, not 71 minutes ago",
        [("advance_ms", 4_294_967), ("feed", timed(1, 1000, RAMP)), ("advance_ms", 1)],
    ),
    _vector(
        "and it plays once the clock has wrapped past it",
        [
            ("advance_ms", 4_294_967),
            ("feed", timed(1, 1000, RAMP)),
            ("advance_ms", 1),
            ("advance_ms", 1),
        ],
        applied=[(1, RAMP)],
        levels=RAMP,
    ),
    _vector(
        "a timed frame of 2 channels is the wrong length",
        [("feed", timed(1, 0, [0, 22]))],
        dropped_by={"length": 1},
    ),
    _vector(
        "a timed level of 23 is out of range",
        [("feed", timed(1, 0, [*RAMP[:29], 23]))],
        dropped_by={"range": 1},
    ),
    _vector(
        "a timed frame with its levels unpacked (a byte each) is the wrong length",
        [("feed", wire(bytes((0x54, 1, 0, 0, 0, 0, 30)) + bytes(RAMP)))],
        dropped_by={"length": 1},
    ),
    _vector(
        "a clock request with a byte too many",
        [("feed", wire(b"C\x01\x00"))],
        dropped_by={"length": 1},
    ),
    _vector(
        "a clock reply sent to the array is not taken",
        [("feed", clock_reply(1, 0, 0, 0, 0, 0))],
        dropped_by={"type": 1},
    ),
]
