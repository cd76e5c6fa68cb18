"""Scheduled frames end to end: ``tactile stream --lead-ms`` into ``tactile emulate`` (real
processes, a real pseudo-terminal), and the streamer against the simulated array.

The array's clock is the emulator's own (microseconds since it opened); the stream keeps it from
clock exchanges. These tests check what is played and in which order, that every frame sent is
accounted for, and that the host's reading of the array's clock agrees with the array; the
precision of the firmware's onsets is measured in simavr (test_firmware_schedule.py).
"""

import time

import numpy as np
import pytest

import tactile_core as tc
from tactile_core.device import SimulatedArray
from tactile_core.device.host_clock import VirtualClock
from tactile_core.device.link import SerialLink
from tactile_core.device.wire import ClockReply, MessageReader, encode_clock, encode_hello
from tactile_core.rendering import Scene
from tactile_core.stream import Streamer, StreamOptions

from .emulator_support import stream


def test_timed_frames_are_played_in_order_and_every_frame_is_accounted_for(emulator, tmp_path):
    emu = emulator("--rate", "100")
    record = tmp_path / "sent.npz"
    proc = stream(
        emu.path, "--shape", "circle:2.5,3,2", "--method", "AS", "--rate", "100",
        "--seconds", "1.5", "--lead-ms", "30", "--record", str(record),
    )  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    assert "timed frames 30 ms ahead on the array's clock" in proc.stdout
    report, log = emu.finish()
    with np.load(record) as data:
        sent_levels, sent_times = data["levels"].reshape(len(data["seq"]), -1), data["time"]
    assert report["dropped"] == 0 and report["timed_full"] == 0
    # Stopping sends all-off for now, which drops the frames still waiting (up to 30 ms worth):
    # every frame sent was either played or dropped unplayed, and the played ones in order.
    played = report["frames"]
    assert played + report["timed_flushed"] == len(sent_levels)
    assert report["timed_flushed"] <= 4  # 30 ms at 100 Hz, and the one being written
    assert report["seq_gaps"] == 0  # received, then dropped unplayed: not lost on the way
    expected = np.vstack([sent_levels[: played - 1], sent_levels[-1:]])
    assert np.array_equal(log[:, 2:].astype(np.uint8), expected)
    assert not log[-1, 2:].any()
    # The stream's reading of the emulator's clock: each on-time frame was to be played at the
    # host time the recorder stamped (deadline + lead), the emulator logs when its own clock
    # said; from the first frame on, the two time lines agree to far less than a frame.
    on_time = played - 1 - report["timed_late"]
    emulator_s = log[:on_time, 0] - log[0, 0]
    error_ms = np.abs(emulator_s - (sent_times[:on_time] - sent_times[0])) * 1e3
    assert on_time > 100 and np.median(error_ms) < 1.0, np.median(error_ms)


def test_a_format_2_array_without_the_extension_gets_frames_for_now(emulator):
    emu = emulator("--plain")
    proc = stream(
        emu.path, "--shape", "line:0.5,1.84,4.5,4.16", "--method", "IM", "--seconds", "0.5",
        "--lead-ms", "20",
    )  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    assert "frames for now: the array does not announce scheduled frames" in proc.stdout
    report, _ = emu.finish()
    sent = int(proc.stdout.split("frames:")[1].split()[0])
    assert report["frames"] == sent and report["dropped"] == 0  # nothing it cannot read


def test_the_emulator_answers_clock_requests_with_its_own_clock(emulator):
    emu = emulator()
    link = SerialLink(emu.path)
    reader = MessageReader(accept=(ClockReply,))
    exchanges = []
    try:
        link.write(encode_hello(0))
        for seq in range(3):
            t0 = time.monotonic()
            link.write(encode_clock(seq))
            got = []
            deadline = time.monotonic() + 10.0
            while not got and time.monotonic() < deadline:
                got = [m for m in reader.feed(link.read()) if m.seq == seq]
                time.sleep(0.001)
            exchanges.append((t0, time.monotonic(), got[0]))
    finally:
        link.close()
    report, _ = emu.finish()
    origin = report["started_monotonic"]  # the emulated array's clock reads 0 here
    for t0, t3, reply in exchanges:
        arrival_s = origin + reply.rx_us * 1e-6
        assert t0 - 1e-3 <= arrival_s <= t3 + 1e-3  # between sending and reading the reply
        assert reply.tx_us >= reply.rx_us and (reply.late, reply.full, reply.queued) == (0, 0, 0)


@pytest.fixture
def sim_streamer():
    streamers = []

    def start(lead_s, scene):
        sim = SimulatedArray()
        streamer = Streamer(sim, scene=scene, options=StreamOptions(lead_ms=lead_s * 1e3)).start()
        streamers.append(streamer)
        return sim, streamer

    yield start
    for streamer in streamers:
        streamer.stop()


def wait_until(predicate, timeout_s=20.0):
    deadline = time.monotonic() + timeout_s
    while not predicate():
        assert time.monotonic() < deadline, "timed out"
        time.sleep(0.002)


def test_all_off_is_for_now_even_with_a_lead():
    # On a virtual clock (the stream's and the array's): the absence below is over 0.25 s of
    # the array's time, however the host schedules the test.
    scene = Scene(tc.Line((2.5, 3.5), (2.5, 3.5)), "CT", mu=1.0, pause_s=0.0, rate_hz=100.0)
    clock = VirtualClock()
    sim = SimulatedArray(clock=clock)
    options = StreamOptions(lead_ms=200.0)  # a long lead: 20 frames waiting at any time
    with Streamer(sim, scene=scene, options=options, clock=clock, spin_s=0.0) as streamer:
        wait_until(lambda: sim.levels().any() and len(sim.model.queue) > 5)
        streamer.all_off()
        wait_until(lambda: not sim.levels().any())
        assert len(sim.model.queue) == 0  # the plain all-off frame dropped what was scheduled
        assert streamer.stats.scheduled  # still timed; paused frames simply are for now
        off_s = clock.now()
        wait_until(lambda: clock.now() > off_s + 0.25)  # longer than the lead: nothing
        assert not sim.levels().any()  # scheduled comes back on


def test_stopping_turns_the_array_off_at_once(sim_streamer):
    scene = Scene(tc.Line((2.5, 3.5), (2.5, 3.5)), "CT", mu=1.0, pause_s=0.0, rate_hz=100.0)
    sim, streamer = sim_streamer(0.2, scene)
    wait_until(lambda: sim.levels().any() and len(sim.model.queue) >= 5)
    streamer.stop()
    assert not sim.levels().any() and len(sim.model.queue) == 0
    assert sim.model.flushed >= 5


def test_a_lead_changes_when_a_frame_plays_not_what_it_plays(sim_streamer):
    scene = Scene(tc.Circle((2.5, 3.0), 2.0), "IM", rate_hz=100.0, dither=False)
    sim, streamer = sim_streamer(0.05, scene)
    wait_until(lambda: sim.model.frames_applied > 60)
    stats = streamer.stats
    assert stats.scheduled and stats.lead_ms == 50.0 and stats.clock_error_ms < 5.0
    # a copy first (list() of a deque is one step): the stream thread appends meanwhile
    onsets = [(t, msg) for t, msg, late in list(sim.model.onsets) if not late]
    assert len(onsets) > 50
    times = np.array([t for t, _ in onsets])
    # Scheduled at the frame period on the array's clock: intervals of 10 ms, to the few tens of
    # microseconds by which a clock exchange can move the host's estimate of the offset. A
    # stream thread that a loaded host holds back past a deadline skips it (or its frame comes
    # late and is left out above): then an interval is a whole number of periods, still exact.
    intervals = np.diff(times)
    periods = np.round(intervals / 0.01)
    assert np.median(np.abs(intervals - 0.01)) < 5e-6
    assert (periods >= 1).all() and np.allclose(intervals, periods * 0.01, atol=1e-4)


def test_a_preset_keeps_its_lead_and_refuses_a_bad_one(tmp_path):
    from tactile_core.files.presets import Preset, PresetError, load_preset, save_preset

    preset = Preset(Scene(tc.Circle((2.5, 3.0), 2.0), "IM"), name="with a lead", lead_ms=35.0)
    path = save_preset(preset, tmp_path / "lead.json")
    assert load_preset(path).lead_ms == 35.0
    data = preset.to_dict()
    del data["lead_ms"]  # a preset of 0.1: the default
    (tmp_path / "old.json").write_text(__import__("json").dumps(data))
    assert load_preset(tmp_path / "old.json").lead_ms == 20.0
    for bad, says in ((-1, "lead_ms"), (501, "lead_ms"), ("20", "lead_ms"), (None, "lead_ms"),
                      (True, "lead_ms"), (float("nan"), "NaN")):  # fmt: skip
        data["lead_ms"] = bad
        (tmp_path / "bad.json").write_text(__import__("json").dumps(data, allow_nan=True))
        with pytest.raises(PresetError, match=says):
            load_preset(tmp_path / "bad.json")


def test_the_tuner_sets_the_lead_and_a_preset_carries_it(qtbot, tmp_path):
    from tactile_tuner.window import MainWindow

    window = MainWindow(restore=False, process=False)
    qtbot.addWidget(window)
    panel = window.device_panel
    assert panel.lead_spin.value() == 20.0 and window.device.lead_ms == 20.0
    panel.lead_spin.setValue(35.0)  # as a committed edit does
    qtbot.waitUntil(lambda: window.device.stats.lead_ms == 35.0, timeout=20_000)
    qtbot.waitUntil(lambda: "timed 35 ms ahead" in panel.status_label.text(), timeout=20_000)
    assert "35 ms ahead on the array's clock" in panel.lead_spin.statusTip()
    assert window.files.save_preset_file(tmp_path / "p.json")
    panel.lead_spin.setValue(0.0)
    qtbot.waitUntil(lambda: not window.device.stats.scheduled, timeout=20_000)
    assert window.files.load_preset_file(tmp_path / "p.json")
    assert window.device.lead_ms == 35.0 and panel.lead_spin.value() == 35.0
    window.close()


def test_a_simulated_array_keeps_a_bounded_record_of_onsets():
    # the tuner's default (the simulated array, timed frames) played 300 onsets a second into a
    # list nobody read: bounded now, the latest kept
    from tactile_core.device.array import ONSETS_KEPT, ArrayModel
    from tactile_core.device.wire import encode_timed

    model = ArrayModel()
    for k in range(ONSETS_KEPT + 500):
        model.receive(encode_timed(k & 0xFF, 0, bytes(30), bits=5), now=k * 1e-3)
    assert len(model.onsets) == ONSETS_KEPT


def test_sequence_gaps_count_frames_lost_on_the_way_not_frames_dropped_unplayed():
    # The emulator used to count gaps among the frames it played, so the timed frames that a
    # clean stop's all-off drops (a lead's worth, received) read as "sequence gaps: 6".
    from tactile_core.device.array import ArrayModel
    from tactile_core.device.wire import encode_frame, encode_timed

    model = ArrayModel(epoch=0.0)
    off = [0] * 30
    ahead = b"".join(encode_timed(seq, 50_000 + seq, off, 5) for seq in range(1, 5))
    model.receive(ahead, 0.001)  # four timed frames 50 ms ahead, queued
    model.receive(encode_frame(5, off), 0.002)  # all-off for now drops them
    assert (model.flushed, model.seq_gaps) == (4, 0)
    model.receive(encode_frame(7, off) + encode_frame(8, off), 0.003)  # 6 lost on the way
    frame = bytearray(encode_frame(9, off))
    frame[3] ^= 0x40  # 9 corrupted: dropped by its checksum, then 10 arrives
    model.receive(bytes(frame) + encode_frame(10, off), 0.004)
    assert model.seq_gaps == 2 and model.dropped == 1
    model.receive(encode_frame(1, off), 0.005)  # the counter wraps: 10 -> 1 is 246 missing
    assert model.seq_gaps == 2 + 246


def test_a_new_hosts_hello_starts_the_sequence_count_again():
    # Two streams in turn into one emulator read as 166 sequence gaps: the second one's frames
    # from 0 after the first one's last, 89. A host says hello when it starts.
    from tactile_core.device.array import ArrayModel
    from tactile_core.device.wire import encode_frame, encode_hello

    off = [0] * 30
    model = ArrayModel(epoch=0.0)
    model.receive(b"".join(encode_frame(seq, off) for seq in range(90)), 0.001)
    model.receive(encode_hello(0) + encode_frame(0, off) + encode_frame(1, off), 0.002)
    assert model.seq_gaps == 0
    model.receive(encode_frame(0, off), 0.003)  # without a hello, 1 -> 0 misses 2..255
    assert model.seq_gaps == 254
