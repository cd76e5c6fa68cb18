"""A host that stops running the stream for a while (SIGSTOP, a VM pause, a swap storm): the
stream goes on where its clock says, reports how long it was held up, and its frames keep
counting, so the array sees no frames lost that were not."""

import signal
import time

import tactile_core as tc
from tactile_core.device.host_clock import VirtualClock
from tactile_core.device.link import LinkError, SimulatedArray
from tactile_core.rendering import Scene
from tactile_core.stream import Streamer
from tactile_core.stream._stats import PAUSE_S

from .emulator_support import CLI, wait_streaming

RATE_HZ = 100.0
STEADY = Scene(tc.Line((2.5, 3.5), (2.5, 3.5)), "CT", mu=1.0, pause_s=0.0, rate_hz=RATE_HZ)


class PausingLink:
    """A simulated array behind a link whose host stops for ``pause_s`` in the write at
    ``pause_at`` (virtual seconds), and whose write at ``fail_at`` goes out and then fails, as
    pyserial's write timeout did after a pause."""

    description = "a pausing link"

    def __init__(self, clock, *, pause_at=None, pause_s=0.0, fail_at=None):
        self.clock = clock
        self.array = SimulatedArray(clock=clock)
        self.pause_at, self.pause_s, self.fail_at = pause_at, pause_s, fail_at

    def write(self, data):
        self.array.write(data)  # the bytes went out
        now = self.clock.now()
        if self.pause_at is not None and now >= self.pause_at:
            self.pause_at = None
            self.clock.advance(self.pause_s)  # the host stood still; the array's time ran on
        if self.fail_at is not None and now >= self.fail_at:
            self.fail_at = None
            raise LinkError("write timeout: a pausing link is not taking data")

    def read(self):
        return self.array.read()

    def reopen(self):
        pass

    def close(self):
        pass


def run_until(link, end_s, **kwargs):
    streamer = Streamer(link, scene=STEADY, clock=link.clock, spin_s=0.0, **kwargs)
    statuses = []
    streamer.on_status = lambda stats: statuses.append(stats.status)
    with streamer:
        deadline = time.monotonic() + 60.0  # a bound for a loaded machine, not a duration
        while link.clock.now() < end_s and streamer.running:
            assert time.monotonic() < deadline, "the virtual stream did not get there"
            time.sleep(0.005)
    return streamer.stats, statuses


def test_a_host_pause_is_survived_and_reported_with_its_length():
    clock = VirtualClock()
    start = clock.now()
    link = PausingLink(clock, pause_at=start + 1.0, pause_s=1.5)
    stats, statuses = run_until(link, start + 4.0)
    assert stats.state == "stopped" and stats.errors == 0
    # held up from one frame to the next: the 1.5 s pause and nothing else (a frame is 10 ms)
    assert stats.pauses == 1
    assert abs(stats.longest_pause_s - 1.5) <= 1 / RATE_HZ
    assert stats.paused_s == stats.longest_pause_s
    assert stats.skipped >= 1.5 * RATE_HZ - 1  # the missed deadlines, skipped
    said = [s for s in statuses if s.startswith("resumed after the host paused 1.5")]
    assert said and "watchdog had turned it off" in said[0]  # 1.5 s > the array's 250 ms
    assert "host paused:     1 times, longest 1.5" in stats.summary()
    assert link.array.model.frames_applied > 2.5 * RATE_HZ - 5  # frames after it, too


def test_stalls_shorter_than_the_pause_threshold_are_not_pauses():
    clock = VirtualClock()
    start = clock.now()
    link = PausingLink(clock, pause_at=start + 1.0, pause_s=PAUSE_S * 0.8)
    stats, _ = run_until(link, start + 2.0)
    assert stats.pauses == 0 and stats.skipped >= 1
    assert "host paused:     never" in stats.summary()


def test_the_last_frame_after_a_failed_write_continues_the_sequence():
    # A write that went out and then failed kept its sequence number, and the final all-off
    # frame reused it: the array counted 255 frames lost that never were.
    clock = VirtualClock()
    start = clock.now()
    link = PausingLink(clock, fail_at=start + 1.0)
    stats, _ = run_until(link, start + 3.0)
    assert stats.state == "stopped" and stats.errors == 1
    model = link.array.model
    assert model.seq_gaps == 0
    assert model.frames_applied == stats.frames + 1  # the failed frame went out too
    assert not any(model.levels)


def test_tactile_stream_survives_a_sigstop_and_says_how_long(emulator):
    import subprocess

    emu = emulator()
    proc = subprocess.Popen(
        [*CLI, "stream", "--device", emu.path, "--shape", "circle:2.5,3,2", "--method", "IM",
         "--seconds", "3", "--lead-ms", "20"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )  # fmt: skip
    try:
        wait_streaming(proc)
        proc.send_signal(signal.SIGSTOP)
        time.sleep(0.6)  # the pause made here; what is checked is what the stream reports
        proc.send_signal(signal.SIGCONT)
        out, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()
    assert proc.returncode == 0, err
    assert "resumed after the host paused" in err, out
    paused = next(line for line in out.splitlines() if line.startswith("host paused:"))
    assert paused.split()[2] == "1", out
    report, _ = emu.finish()
    assert report["seq_gaps"] == 0 and report["dropped"] == 0
