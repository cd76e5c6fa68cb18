"""Reading the simavr harness's log: pin edges and UART bytes, stamped in simulated cycles.

Used by the end-to-end tests (tests/test_firmware_sim.py) and by ``report.py``, which prints the
README's firmware table. Numbers follow the firmware: 16 MHz, a timer tick every 2400 cycles
(16 MHz / 8 / 300), 22 ticks a PWM period (52,800 cycles, 303 Hz); channel k on port k // 8, bit
k % 8 (PORTA, PORTC, PORTL, PORTK).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

CPU_HZ = 16_000_000
TICK = 2400
SLOTS = 22
PERIOD = TICK * SLOTS
CHANNELS = 30
BYTE_CYCLES = 1496  # simavr's UART: 11 bit times at 117,647 baud


@dataclass
class PinLog:
    """The parsed log.

    Attributes
    ----------
    edges : list of (cycle, port, value)
    received : list of (cycle, byte)
        Bytes put on the line to the firmware (the cycle the byte's transfer started).
    sent : list of (cycle, byte)
        Bytes the firmware transmitted.
    end : int
        Cycle at which the run ended.
    """

    edges: list
    received: list
    sent: list
    end: int

    @classmethod
    def read(cls, path) -> PinLog:
        edges, received, sent, end = [], [], [], 0
        with open(path, encoding="ascii") as f:
            for line in f:
                kind, *rest = line.split()
                if kind == "P":
                    edges.append((int(rest[0]), int(rest[1]), int(rest[2])))
                elif kind == "R":
                    received.append((int(rest[0]), int(rest[1], 16)))
                elif kind == "T":
                    sent.append((int(rest[0]), int(rest[1], 16)))
                elif kind == "E":
                    end = int(rest[0])
        return cls(edges, received, sent, end)

    def channel_edges(self) -> list[list[tuple[int, int]]]:
        """Per channel, its ``(cycle, state)`` changes in order."""
        ports = [0, 0, 0, 0]
        out = [[] for _ in range(CHANNELS)]
        for cycle, port, value in self.edges:
            changed = ports[port] ^ value
            ports[port] = value
            for bit in range(8):
                ch = port * 8 + bit
                if changed >> bit & 1 and ch < CHANNELS:
                    out[ch].append((cycle, value >> bit & 1))
        return out

    def period_starts(self) -> np.ndarray:
        """Cycles at which PWM periods start (the timer writes slot 0), from the rising edges:
        a channel only rises at slot 0. Periods before the first rise are not counted."""
        rises = np.sort(
            np.array([c for ch in self.channel_edges() for c, s in ch if s == 1], dtype=np.int64)
        )
        if len(rises) == 0:
            return np.zeros(0, dtype=np.int64)
        offsets = (rises - rises[0] + PERIOD // 2) % PERIOD - PERIOD // 2  # interrupt jitter
        anchor = int(rises[0] + np.median(offsets))
        return np.arange(anchor, self.end - PERIOD, PERIOD, dtype=np.int64)

    def duties(self, starts: np.ndarray) -> np.ndarray:
        """On-cycles of every channel in each period: ``(len(starts), 30)``."""
        on = np.zeros((len(starts), CHANNELS), dtype=np.int64)
        for ch, changes in enumerate(self.channel_edges()):
            state, since = 0, 0
            for cycle, new in [*changes, (self.end, 0)]:
                if state:  # on from `since` to `cycle`: spread over the periods it covers
                    lo = np.clip(starts, since, cycle)
                    hi = np.clip(starts + PERIOD, since, cycle)
                    on[:, ch] += hi - lo
                state, since = new, cycle
        return on

    def frame_ends(self) -> list[int]:
        """Cycle at which each received message's delimiter had fully arrived."""
        return [c + BYTE_CYCLES for c, b in self.received if b == 0]

    def all_off_since(self) -> int | None:
        """The cycle from which every pin stays off to the end (None if one is on at the end)."""
        ports = [0, 0, 0, 0]
        since = 0
        for cycle, port, value in self.edges:
            was_off = not any(ports)
            ports[port] = value
            if not any(ports) and not was_off:
                since = cycle
        return None if any(ports) else since


def levels_per_period(log: PinLog):
    """``(starts, levels)``: each whole period's measured level of every channel (on-time in
    ticks, rounded) and the on-cycles themselves."""
    starts = log.period_starts()
    on = log.duties(starts)
    return starts, np.rint(on / TICK).astype(int), on


def match_frames(measured: np.ndarray, frames: list) -> tuple[int, list[int]]:
    """Walk the measured periods against the frames sent, in order.

    Returns the number of periods that match no frame at or after the one matched before, and
    the index of the frame each period matched (-1 for none).
    """
    k, misses, which = 0, 0, []
    for levels in measured:
        j = k
        while j < len(frames) and not np.array_equal(levels, frames[j]):
            j += 1
        if j == len(frames):
            misses += 1
            which.append(-1)
        else:
            k = j
            which.append(j)
    return misses, which


def received_frames(log: PinLog, channels: int = CHANNELS) -> list[tuple[int, np.ndarray]]:
    """The valid frames the firmware received: ``(cycle its last byte arrived, levels)``.

    Decoded from the logged line bytes (COBS, CRC-16), so corrupted messages are left out just
    as the firmware leaves them out.
    """
    from cobs import cobs

    out, buf = [], bytearray()
    for cycle, byte in log.received:
        if byte:
            buf.append(byte)
            continue
        try:
            p = cobs.decode(bytes(buf))
        except cobs.DecodeError:
            p = b""
        buf.clear()
        if len(p) != channels + 5 or p[0] != 0x46 or p[2] != channels:
            continue
        if _crc16(p[:-2]) != int.from_bytes(p[-2:], "big"):
            continue
        out.append((cycle + BYTE_CYCLES, np.frombuffer(p[3:-2], dtype=np.uint8).astype(int)))
    return out


def _crc16(data: bytes) -> int:
    crc = 0xFFFF
    for byte in data:
        crc ^= byte << 8
        for _ in range(8):
            crc = ((crc << 1) ^ 0x1021) & 0xFFFF if crc & 0x8000 else (crc << 1) & 0xFFFF
    return crc


@dataclass
class Check:
    """What the pins did against what the line carried."""

    periods: int  # whole PWM periods measured after the first frame
    mismatched: int  # periods whose levels are not the newest frame applied by then
    frames: int  # frames whose levels differ from the frame before
    shown: int  # ... of them seen on the pins
    superseded: int  # ... replaced by a newer frame before a period boundary came
    latency_cycles: np.ndarray  # last byte of a frame -> first period showing it
    duty_error_cycles: int  # worst |on-time - level * tick| of a channel in a period
    pwm_hz: float


PROCESSING = 16_000
"""Cycles (1 ms) the firmware may take from a frame's last byte to a table ready for the next
period: parsing, the CRC and building the PWM table take about 11,000 (0.7 ms)."""


def check(log: PinLog) -> Check:
    """Compare each PWM period's measured levels with the frames received before it.

    A period shows the newest frame whose last byte arrived at least :data:`PROCESSING` cycles
    before the period started, or one that arrived since (the firmware may have been quick).
    """
    starts, measured, on = levels_per_period(log)
    frames = received_frames(log)
    ends = np.array([e for e, _ in frames])
    # When a frame is surely built: the firmware takes the bytes in order, so a frame right
    # behind another (a burst after the host stalled) waits for the one before it.
    ready = np.zeros(len(ends), dtype=np.int64)
    for k, end in enumerate(ends):
        ready[k] = max(end, ready[k - 1] if k else end) + PROCESSING
    mismatched = 0
    checked = 0
    for s, levels in zip(starts, measured):
        # The firmware swaps in a new table at a period boundary: the newest frame built before
        # s, or one that arrived since (if the firmware was quicker than the bound).
        i = np.searchsorted(ready, s, side="right") - 1
        if i < 0:
            continue
        checked += 1
        j = np.searchsorted(ends, s, side="right") - 1  # a frame just before s may be in too
        if not any(np.array_equal(levels, frames[k][1]) for k in range(max(i, 0), j + 1)):
            mismatched += 1
    distinct, shown, superseded, latency = 0, 0, 0, []
    previous = None
    for k, (end, levels) in enumerate(frames):
        if previous is not None and np.array_equal(levels, previous):
            continue
        previous = levels
        earliest = np.searchsorted(starts, end)  # first period it may show in
        latest = np.searchsorted(starts, end + PROCESSING)  # first period it must show in
        if latest >= len(starts):
            continue
        distinct += 1
        seen = [m for m in range(earliest, latest + 1) if np.array_equal(measured[m], levels)]
        if seen:
            shown += 1
            latency.append(starts[seen[0]] - end)
        elif k + 1 < len(frames) and frames[k + 1][0] < starts[latest]:
            superseded += 1  # a newer frame came before this one's period began
    err = np.abs(on - measured * TICK)
    period = np.diff(starts).mean() if len(starts) > 1 else float("nan")
    return Check(
        periods=checked,
        mismatched=mismatched,
        frames=distinct,
        shown=shown,
        superseded=superseded,
        latency_cycles=np.array(latency),
        duty_error_cycles=int(err.max()) if err.size else 0,
        pwm_hz=CPU_HZ / period,
    )


# --- the firmware's own latencies, counted from its machine code ----------------------------

INTERRUPT_RESPONSE = 5 + 3
"""Cycles from an interrupt's flag to the first instruction of its handler on the ATmega2560:
5 to push the 3-byte return address, 3 for the ``jmp`` in the vector table."""
_CYCLES = {"push": 2, "pop": 2, "lds": 2, "sts": 2, "ld": 2, "ldd": 2, "st": 2, "std": 2,
           "mul": 2, "adiw": 2, "sbiw": 2, "call": 5, "rcall": 4, "ret": 5, "reti": 5}  # fmt: skip


def handler_cycles(elf, vector: int, until: str) -> int:
    """Cycles from interrupt ``vector``'s flag to the instruction whose disassembly contains
    ``until`` (e.g. ``"0x0084"``, the load of TCNT1, or ``"out\\t0x02"``, the write of PORTA),
    counted on the handler's machine code (``avr-objdump -d``): the interrupt response plus each
    instruction before it (1 cycle unless listed in ``_CYCLES``). The handler must reach it
    without a branch, as the firmware's do."""
    import subprocess

    text = subprocess.run(["avr-objdump", "-d", str(elf)], capture_output=True, text=True,
                          check=True).stdout  # fmt: skip
    lines = text.split(f"<__vector_{vector}>:\n", 1)[1].splitlines()
    cycles = INTERRUPT_RESPONSE
    for line in lines:
        if until in line:
            return cycles
        parts = line.split("\t")
        if len(parts) < 3:
            raise ValueError(f"{until!r} not found in vector {vector}")
        cycles += _CYCLES.get(parts[2].split()[0], 1)
    raise ValueError(f"{until!r} not found in vector {vector}")


RX_VECTOR, COMPB_VECTOR = 25, 18  # USART0_RX, TIMER1_COMPB on the ATmega2560


# --- timed frames and the clock exchange -------------------------------------------------------


def messages(events) -> list[tuple[int, bytes]]:
    """Valid messages in a logged byte stream (``log.received`` or ``log.sent``): ``(cycle the
    delimiter's transfer started, payload without the CRC)``, CRC-checked; others left out."""
    from cobs import cobs

    out, buf = [], bytearray()
    for cycle, byte in events:
        if byte:
            buf.append(byte)
            continue
        try:
            p = cobs.decode(bytes(buf))
        except cobs.DecodeError:
            p = b""
        buf.clear()
        if len(p) >= 4 and _crc16(p[:-2]) == int.from_bytes(p[-2:], "big"):
            out.append((cycle, bytes(p[:-2])))
    return out


def _unpack(data: bytes, n: int, bits: int) -> np.ndarray:
    text = "".join(format(b, "08b") for b in data)
    return np.array([int(text[i * bits : (i + 1) * bits], 2) for i in range(n)])


@dataclass
class TimedFrame:
    """A timed frame as the firmware received it."""

    arrived: int  # cycle its delimiter had fully arrived
    seq: int
    at_us: int  # when it was to play, on the array's clock
    levels: np.ndarray  # channel order


def timed_frames(log: PinLog, channels: int = CHANNELS, bits: int = 5) -> list[TimedFrame]:
    """The valid timed frames the firmware received, in order."""
    out = []
    for cycle, body in messages(log.received):
        if body[0] == 0x54 and len(body) == 7 + (channels * bits + 7) // 8 and body[6] == channels:
            at = int.from_bytes(body[2:6], "big")
            out.append(
                TimedFrame(cycle + BYTE_CYCLES, body[1], at, _unpack(body[7:], channels, bits))
            )
    return out


def clock_origin(log: PinLog, rx_entry_cycles: int) -> tuple[float, int]:
    """The cycle at which the firmware's microsecond clock read 0, from its clock replies: each
    reply's arrival stamp was read ``rx_entry_cycles`` after the request's delimiter arrived.
    Returns the median estimate and the number of exchanges it rests on."""
    asked = {}
    for cycle, body in messages(log.received):
        if body[0] == 0x43 and len(body) == 2:
            asked.setdefault(body[1], []).append(cycle + BYTE_CYCLES)
    estimates = []
    for _, body in messages(log.sent):
        if body[0] == 0x63 and len(body) == 19 and asked.get(body[1]):
            arrived = asked[body[1]].pop(0)
            rx_us = int.from_bytes(body[2:6], "big")
            estimates.append(arrived + rx_entry_cycles - rx_us * 16)
    if not estimates:
        raise ValueError("no clock exchange in the log")
    return float(np.median(estimates)), len(estimates)


def last_clock_reply(log: PinLog) -> dict | None:
    """The firmware's scheduling counters from its last clock reply."""
    replies = [b for _, b in messages(log.sent) if b[0] == 0x63 and len(b) == 19]
    if not replies:
        return None
    b = replies[-1]
    return {"late": int.from_bytes(b[10:14], "big"), "full": int.from_bytes(b[14:18], "big"),
            "queued": b[18]}  # fmt: skip


def port_rows(levels, slot: int) -> tuple[int, ...]:
    """What the four ports hold in PWM slot ``slot`` for channel levels ``levels`` (channel k on
    port k // 8, bit k % 8; on in the slots below its level)."""
    rows = [0, 0, 0, 0]
    for ch, level in enumerate(levels):
        if level > slot:
            rows[ch // 8] |= 1 << (ch % 8)
    return tuple(rows)


def onset_errors(log: PinLog, frames: list[TimedFrame], origin: float, *, window_us=300.0,
                 tick_guard_us=8.0):  # fmt: skip
    """Per timed frame, when the pins changed against when it was to play (microseconds).

    At its time a timed frame's table takes over in the PWM slot being played. The pins show it
    when that slot's row differs from the row of the frame before; the change is the port write
    nearest to the frame's time (within ``window_us``, else NaN: it did not show). Frames whose
    time falls within ``tick_guard_us`` of a slot boundary (where the slot interrupt writes too)
    and frames whose onset changes no pin are reported as None.
    """
    edges = np.array([c for c, _, _ in log.edges], dtype=np.float64)
    out = []
    previous = np.zeros(CHANNELS, dtype=int)
    for frame in frames:
        target = origin + frame.at_us * 16
        counts = (target - origin) / 8  # Timer1 counts (2 MHz) since it started
        tick = int(counts // 300)
        from_tick_us = (counts - tick * 300) / 2
        slot = (tick - 1) % SLOTS
        visible = port_rows(frame.levels, slot) != port_rows(previous, slot)
        previous = frame.levels
        if not visible or min(from_tick_us, 150 - from_tick_us) < tick_guard_us:
            out.append(None)
            continue
        i = np.searchsorted(edges, target)
        near = [e for e in edges[max(i - 1, 0) : i + 1] if abs(e - target) <= window_us * 16]
        if not near:
            out.append(float("nan"))  # it should have shown and did not
            continue
        out.append((min(near, key=lambda e: abs(e - target)) - target) / 16)
    return out
