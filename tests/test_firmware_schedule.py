"""Scheduled frames on the reference firmware, in simavr (a cycle-accurate ATmega2560): timed
frames reach the pins at their time on the array's clock, whatever the host is doing.

The array's clock is read back from the log: each clock reply carries the moment its request's
delimiter arrived, which the harness logged in cycles, and the receive interrupt's own entry
(counted on the machine code) is taken out. A timed frame's onset shows on the pins when the
slot it starts in differs from the frame before; those onsets are measured to the cycle.
"""

import re
import subprocess
import sys
import time

import numpy as np

from tactile_core.device.link import SerialLink, identify
from tactile_core.device.profile import default_profile
from tactile_core.device.wire import (
    ClockReply,
    MessageReader,
    encode_clock,
    encode_frame,
    encode_timed,
)

from .firmware_support import FIRMWARE, pinlog

CLI = [sys.executable, "-m", "tactile_core.cli"]
RX_VECTOR, COMPB_VECTOR = 25, 18  # USART0_RX, TIMER1_COMPB on the ATmega2560


class CpuHog:
    """Both host cores busy (two spinning processes) for as long as the block runs."""

    def __enter__(self):
        spin = "while True: pass"
        self.procs = [subprocess.Popen([sys.executable, "-c", spin]) for _ in range(2)]
        return self

    def __exit__(self, *exc):
        for proc in self.procs:
            proc.kill()
            proc.wait()


def test_the_onset_lead_matches_the_interrupts_entry_counted_on_the_machine_code(sim):
    config = (FIRMWARE / "src" / "config.h").read_text()
    lead_counts = int(re.search(r"#define ONSET_LEAD_COUNTS (\d+)", config).group(1))
    entry = pinlog.handler_cycles(sim.elf, COMPB_VECTOR, "out\t0x02")  # to PORTA's write
    assert 30 <= entry <= 60
    assert abs(entry - lead_counts * 8) <= 8  # the match fires that early, to half a µs
    sim.finish()


def test_the_firmware_announces_scheduled_frames(sim):
    link = SerialLink(sim.path)
    try:
        info, problem = identify(link, default_profile(), timeout_s=10.0)
    finally:
        link.close()
    assert problem == "" and info.scheduled and info.queue == 24
    sim.finish()


def test_timed_frames_reach_the_pins_at_their_time_with_both_host_cores_busy(sim):
    # CT at full drive on a fast circle: every change of tactor shows on the pins in any slot.
    with CpuHog():
        proc = subprocess.run(
            [*CLI, "stream", "--device", sim.path, "--shape", "circle:2.5,3,2", "--method", "CT",
             "--duration", "0.2", "--pause", "0", "--rate", "200", "--lead-ms", "20",
             "--seconds", "3"],
            capture_output=True, text=True, timeout=60,
        )  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    assert "timed frames 20 ms ahead" in proc.stdout
    log = sim.finish()
    rx_entry = pinlog.handler_cycles(sim.elf, RX_VECTOR, "0x0084")  # to the counter's read
    origin, exchanges = pinlog.clock_origin(log, rx_entry)
    now = [cycle for cycle, _ in pinlog.received_frames(log)]  # frames for now
    stopped = now[-1]  # the all-off frame for now that ended it
    # A frame for now drops what is scheduled and sets the pins itself: a host that stopped
    # scheduling for a while (its clock's error above a quarter of the lead, as a loaded host
    # may) sends some. Onsets are judged within runs of timed frames with none between them,
    # each against the frame before it in the run (the first of a run has no known one).
    timed = [f for f in pinlog.timed_frames(log) if origin + f.at_us * 16 < stopped]
    runs, since = [[]], 0
    for f in timed:
        due = origin + f.at_us * 16
        if any(since < c < due for c in now):
            runs.append([])
        runs[-1].append(f)
        since = due
    frames, errors = [], []
    for run in runs:
        frames += run[1:]
        errors += pinlog.onset_errors(log, run, origin)[1:]
    # How long before its time each frame's last byte was in (ms): the lead, less the bytes'
    # transmission and whatever the busy host added.
    margin_ms = np.array([(origin + f.at_us * 16 - f.arrived) / 16_000 for f in frames])
    on_time = np.array([e for e, m in zip(errors, margin_ms) if e is not None and m > 2.0])
    assert exchanges >= 8 and len(frames) > 500
    assert len(on_time) > 100  # visible onsets of frames that arrived in time
    assert not np.isnan(on_time).any()  # every one of them showed
    assert np.abs(on_time).max() <= 20.0, np.abs(on_time).max()  # µs, the worst one
    # Frames that came after their time were played at once and counted; the firmware may also
    # count one that came less than 2 ms ahead (parsing and building its table take ~1.2 ms).
    counters = pinlog.last_clock_reply(log)
    every_ms = np.array([(origin + f.at_us * 16 - f.arrived) / 16_000 for f in timed])
    after, close = int((every_ms < 0).sum()), int((every_ms < 2.0).sum())
    assert counters is not None and after <= counters["late"] <= close
    assert counters["full"] == 0


def clock_exchange(link, reader, seq, timeout_s=10.0):
    link.write(encode_clock(seq))
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        for msg in reader.feed(link.read()):
            if isinstance(msg, ClockReply) and msg.seq == seq:
                return msg
        time.sleep(0.001)
    raise AssertionError("no clock reply")


def test_a_late_frame_plays_at_once_and_one_dropped_by_a_plain_frame_never_plays(sim):
    link = SerialLink(sim.path)
    reader = MessageReader(accept=(ClockReply,))
    full = [0] * 30
    full[7] = 22
    try:
        identify(link, default_profile(), timeout_s=10.0)
        now_us = clock_exchange(link, reader, 1).tx_us
        link.write(encode_timed(2, now_us - 5_000, full, bits=5))  # 5 ms in the past: late
        # The firmware reads its line in order: it has the late frame when it answers the next
        # clock request, and shows it within 32,000 cycles (2 ms, as asserted below): wait 10 ms
        # on its own clock.
        seq, now_us = 3, clock_exchange(link, reader, 3).tx_us
        shown_us = now_us + 10_000
        while now_us < shown_us:
            seq += 1
            now_us = clock_exchange(link, reader, seq).tx_us
        future = [0] * 30
        future[20] = 22
        link.write(encode_timed(seq + 1, now_us + 10_000_000, future, bits=5))  # 10 s ahead ...
        link.write(encode_frame(seq + 2, [0] * 30))  # ... dropped by a frame for now
        reply = clock_exchange(link, reader, seq + 3)  # answered after both
    finally:
        link.close()
    assert (reply.late, reply.full, reply.queued) == (1, 0, 0)
    log = sim.finish()
    edges = log.channel_edges()
    late_frame = next(f for f in pinlog.timed_frames(log) if f.seq == 2)
    rise = next(c for c, on in edges[7] if on)
    assert 0 < rise - late_frame.arrived < 16 * 2000  # played on arrival: parsed, built, shown
    assert not [c for c, on in edges[20] if on]  # the dropped frame never reached its pin
