"""The reference firmware end to end: its ELF runs in simavr (a cycle-accurate ATmega2560),
UART0 bridged to a pseudo-terminal and paced to the wall clock; ``tactile stream`` drives it; the
harness logs every pin edge in simulated cycles, and the tests read what the motors got."""

import os
import signal
import subprocess
import sys
import time

import numpy as np

from tactile_core.device.link import SerialLink, identify
from tactile_core.device.profile import default_profile
from tactile_core.device.wire import encode_frame

from .emulator_support import wait_streaming
from .firmware_support import pinlog, wait_logged
from .helpers import array_status

CLI = [sys.executable, "-m", "tactile_core.cli"]
MS = 16_000  # cycles


def test_firmware_answers_hello_with_the_profiles_array(sim):
    link = SerialLink(sim.path)
    try:
        info, problem = identify(link, default_profile(), timeout_s=10.0)
    finally:
        link.close()
    assert problem == "" and info is not None
    assert (info.cols, info.rows, info.levels) == (5, 6, 23)
    assert info.name == "palm-5x6" and info.watchdog_ms == 250 and info.version == 2
    assert info.pwm_hz >= 300
    sim.finish()


def test_firmware_plays_every_frame_tactile_stream_sends(sim, tmp_path):
    # 250 frames a second: simavr's UART counts 11 bits a byte (a parity bit 8N1 does not
    # have), so the simulated line carries 289 palm frames a second rather than 318.
    proc = subprocess.run(
        [*CLI, "stream", "--device", sim.path, "--shape", "circle:2.5,3,2", "--method", "AS",
         "--mu", "0.33", "--gamma", "0.7", "--rate", "250", "--seconds", "2.0", "--lead-ms", "0"],
        capture_output=True, text=True, timeout=60,
    )  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    sent = int(proc.stdout.split("frames:")[1].split()[0])
    assert f"array counters:  frames applied {sent}, messages dropped 0" in proc.stdout
    log = sim.finish()
    result = pinlog.check(log)
    assert result.periods > 500
    assert result.mismatched == 0  # every period shows a frame that was sent, in order
    assert result.shown + result.superseded == result.frames  # none lost on the way
    assert result.shown >= 0.95 * result.frames
    assert result.duty_error_cycles < pinlog.TICK // 8  # duty = level / 22 within 0.6 %
    assert result.pwm_hz >= 300.0
    latency_ms = result.latency_cycles / MS
    assert latency_ms.max() <= 1000 * pinlog.PERIOD / pinlog.CPU_HZ + 1.0  # a period + 1 ms
    assert log.all_off_since() is not None  # the stream's last frame was all off


def test_firmware_never_applies_a_corrupted_frame_and_counts_it(sim):
    link = SerialLink(sim.path)
    try:
        identify(link, default_profile(), timeout_s=10.0)
        rng = np.random.default_rng(3)
        good = [5] * 30
        link.write(encode_frame(1, good))
        corrupted = 0
        for seq in range(2, 62):  # 60 frames of full drive, each with one or two bits flipped
            data = bytearray(encode_frame(seq, [22] * 30))
            for _ in range(rng.integers(1, 3)):
                i = int(rng.integers(0, len(data) - 1))  # not the delimiter
                data[i] ^= 1 << int(rng.integers(0, 8))
            link.write(bytes(data))
            corrupted += 1
            if seq % 20 == 0:
                link.write(encode_frame(seq, good))  # keep the watchdog fed
    finally:
        link.close()
    # The firmware reads its line in order: it answers the query after the frames before it.
    status = array_status(sim.path)
    assert status.frames_applied == 4  # the four good frames
    assert status.dropped >= corrupted  # a flipped bit may also split a message in two
    log = sim.finish()
    starts, levels, _ = pinlog.levels_per_period(log)
    assert len(starts) > 0
    assert levels.max() <= 5  # full drive never reached a pin
    assert (levels[:, :30] == 5).all(axis=1).any()  # the good frame did


def test_firmware_watchdog_turns_everything_off_after_250_ms(sim):
    # A stream killed without a word (SIGKILL): no all-off frame; the array's watchdog acts.
    proc = subprocess.Popen(
        [*CLI, "stream", "--device", sim.path, "--shape", "line:2.5,3.5,2.5,3.5", "--method",
         "CT", "--pause", "0", "--rate", "100", "--seconds", "30", "--lead-ms", "0"],
        stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
    )  # fmt: skip
    wait_streaming(proc)
    wait_logged(sim, r"^P \d+ \d+ [1-9]\d*$")  # a pin went on: lit frames reach the firmware
    os.kill(proc.pid, signal.SIGKILL)
    proc.communicate(timeout=10)
    deadline = time.monotonic() + 30
    while array_status(sim.path).watchdog_trips == 0:  # the firmware's own count of its act
        assert time.monotonic() < deadline, "the watchdog did not act"
    log = sim.finish()
    frames = pinlog.received_frames(log)
    assert frames and frames[-1][1].any()  # the last frame it got was lit
    off = log.all_off_since()
    assert off is not None
    after_ms = (off - frames[-1][0]) / MS
    period_ms = 1000 * pinlog.PERIOD / pinlog.CPU_HZ
    # more than 250 ms on the firmware's millisecond counter (250-251 ms), then off at once
    # (within a tick and the main loop's wake-up): within 250 ms + one PWM period
    assert 250.0 <= after_ms <= 250.0 + period_ms, after_ms
