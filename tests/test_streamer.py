"""The streamer in-process: what it sends, when it turns off, how it copes with failure.

These tests assert what is sent and in which order, not how fast: rates and latencies are
measured by ``tactile bench``, not asserted here.
"""

import itertools
import socket
import threading
import time

import numpy as np
import pytest

import tactile_core as tc
from tactile_core.device.host_clock import VirtualClock
from tactile_core.device.link import SerialLink, SimulatedArray
from tactile_core.device.profile import default_profile
from tactile_core.device.wire import FrameReader
from tactile_core.files.frames import Recorder
from tactile_core.rendering.scene import Scene
from tactile_core.stream import Streamer, StreamOptions

from .helpers import align

CIRCLE = tc.Circle((2.5, 3.0), 2.0)


class Taps:
    """Collects what the streamer wrote."""

    def __init__(self):
        self.frames = []
        self.lock = threading.Lock()

    def __call__(self, time_s, seq, levels):
        with self.lock:
            self.frames.append((time_s, seq, np.frombuffer(levels, dtype=np.uint8).copy()))

    def wait_for(self, n, timeout=60.0):  # generous: a loaded machine only makes it slower
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            with self.lock:
                if len(self.frames) >= n:
                    return
            time.sleep(0.005)
        raise AssertionError(f"only {len(self.frames)} of {n} frames within {timeout} s")


def virtual(sim=None, *args, **kwargs):
    """A streamer on a virtual clock (its timing exact and instant, whatever the load) into a
    simulated array on the same clock."""
    clock = VirtualClock()
    if sim is None:
        sim = SimulatedArray(clock=clock)
    else:
        sim._now = clock.now  # a profile's own simulated array, on the same clock
    return Streamer(sim, *args, clock=clock, spin_s=0.0, **kwargs)


def run(scene, n, **kwargs):
    taps = Taps()
    streamer = virtual(scene=scene, taps=[taps], **kwargs)
    with streamer:
        taps.wait_for(n)
    return taps.frames, streamer


@pytest.mark.parametrize("method", tc.METHOD_NAMES)
def test_sent_levels_are_the_cores_frames_quantised(method):
    scene = Scene(CIRCLE, method, mu=0.33, gamma=0.7, rate_hz=100.0, dither=False)
    frames, _ = run(scene, 120)
    trace = scene.trace()
    _, expected = tc.render_frames(
        trace, method, sampling=scene.sampling(), mu=0.33, gamma=0.7, n_frames=250
    )
    expected = tc.quantize(expected, 23).reshape(250, 30)
    lit = [f for f in frames[:-1]]  # the last one is the all-off frame
    assert align([f[2] for f in lit], expected) >= len(lit) - 1
    assert any(f[2].any() for f in lit)


def test_sequence_numbers_are_consecutive_and_wrap():
    frames, _ = run(Scene(CIRCLE, rate_hz=300.0), 300)
    seqs = [s for _, s, _ in frames]
    assert all((b - a) % 256 == 1 for a, b in itertools.pairwise(seqs))
    assert 255 in seqs and seqs[seqs.index(255) + 1] == 0


def test_stop_sends_all_off_and_the_array_is_off():
    taps = Taps()
    streamer = virtual(scene=Scene(CIRCLE, mu=1.0), taps=[taps])
    sim = streamer.link
    with streamer:
        taps.wait_for(20)
        assert sim.levels().any()
    assert not taps.frames[-1][2].any()
    assert not sim.levels().any()


def test_pause_is_all_off_with_keep_alive_frames():
    taps = Taps()
    streamer = virtual(scene=Scene(CIRCLE, mu=1.0, rate_hz=100.0), taps=[taps])
    with streamer:
        taps.wait_for(10)
        streamer.set_scene(streamer.scene.replace(playing=False))
        n = len(taps.frames)
        taps.wait_for(n + 6)  # keep-alive frames keep coming while paused
        assert streamer.stats.state == "paused"
        assert streamer.stats.rate_hz >= 10.0
    paused = taps.frames[n + 1 :]
    assert paused and all(not f[2].any() for f in paused)


def test_all_off_takes_effect_on_the_next_frame():
    taps = Taps()
    streamer = virtual(scene=Scene(CIRCLE, mu=1.0, rate_hz=100.0), taps=[taps])
    with streamer:
        taps.wait_for(10)
        streamer.all_off()
        n = len(taps.frames)
        taps.wait_for(n + 3)
    # at most the frame already being written when all_off() ran is still lit
    assert all(not f[2].any() for f in taps.frames[n + 1 :])


def test_idle_streamer_sends_zeros():
    frames, streamer = run(None, 5)
    assert all(not f[2].any() for f in frames)
    assert streamer.stats.state == "stopped"


def test_parameter_change_reaches_the_next_frames():
    taps = Taps()
    scene = Scene(CIRCLE, "AS", mu=0.0, gamma=1.0, rate_hz=100.0, dither=False)
    streamer = virtual(scene=scene, taps=[taps])
    with streamer:
        taps.wait_for(10)
        streamer.set_scene(scene.replace(mu=1.0))  # every lit tactor at 22
        n = len(taps.frames)
        taps.wait_for(n + 5)
    after = taps.frames[n + 1 : n + 5]
    for _, _, levels in after:
        assert set(levels[levels > 0].tolist()) == {22}
    before = [f[2] for f in taps.frames[2:n]]
    assert any(set(lv[lv > 0].tolist()) != {22} for lv in before)  # it really changed


def test_rate_is_capped_at_what_the_link_carries():
    _, streamer = run(Scene(CIRCLE, rate_hz=1000.0), 5)
    stats = streamer.stats
    assert stats.capped and stats.rate_hz == pytest.approx(115200 / 10 / 37)  # 311 frames/s
    assert "320 frames/s" in stats.status or stats.state == "stopped"


def test_rate_cap_status_names_the_link_limit():
    messages = []
    taps = Taps()
    streamer = virtual(
        scene=Scene(CIRCLE, rate_hz=1000.0),
        taps=[taps],
        on_status=lambda s: messages.append(s.status),
    )
    with streamer:
        taps.wait_for(3)
    assert any("1000 Hz requested, the link carries 311 frames/s" in m for m in messages)


def test_calibration_offsets_and_gains_reach_the_wire():
    offset = np.zeros(30)
    gain = np.ones(30)
    gain[:] = 0.5  # every tactor at half drive
    profile = default_profile().with_calibration(offset, gain)
    taps = Taps()
    scene = Scene(tc.Line((2.5, 3.5), (2.5, 3.5)), "CT", rate_hz=100.0, dither=False)
    with virtual(SimulatedArray(profile), profile, scene=scene, taps=[taps]):
        taps.wait_for(5)
    levels = taps.frames[2][2]
    assert levels[3 * 5 + 2] == 11  # floor(0.5 * 22 + 0.5)
    assert levels.sum() == 11


def test_dithering_carries_finer_averages():
    # AS at (2.2, 3.5): tactor (2, 3) gets 0.7, i.e. 15.4 in level units; (1, 3) gets 6.6.
    scene = Scene(tc.Line((2.2, 3.5), (2.2, 3.5)), "AS", mu=0.0, gamma=1.0, rate_hz=300.0,
                  dither=True)  # fmt: skip
    frames, _ = run(scene, 400)
    levels = np.array([f[2] for f in frames[:-1]])
    assert levels[:, 17].mean() == pytest.approx(15.4, abs=0.05)
    assert levels[:, 16].mean() == pytest.approx(6.6, abs=0.05)
    assert set(levels[:, 17].tolist()) == {15, 16}
    plain, _ = run(scene.replace(dither=False), 50)
    assert {f[2][16] for f in plain[:-1]} == {7}  # rounding: 6.6 -> 7 every frame


def test_recorder_writes_csv_and_npz(tmp_path):
    profile = default_profile()
    recorder = Recorder(profile.array)
    taps = Taps()
    with virtual(scene=Scene(CIRCLE, mu=1.0, rate_hz=100.0), taps=[recorder, taps]):
        taps.wait_for(20)
    recorder.save(tmp_path / "r.npz")
    recorder.save(tmp_path / "r.csv")
    with np.load(tmp_path / "r.npz") as data:
        assert data["levels"].shape == (len(recorder), 6, 5)
        steps = np.diff(data["time"])
        # frames at their (virtual) times; the all-off on stopping may share the last instant
        assert data["time"][0] == 0.0 and (steps[:-1] > 0).all() and steps[-1] >= 0
        np.testing.assert_array_equal(
            data["levels"].reshape(len(recorder), 30), [f[2] for f in taps.frames]
        )
    lines = (tmp_path / "r.csv").read_text().splitlines()
    assert lines[0].startswith("time,seq,r0c0,r0c1") and len(lines) == len(recorder) + 1
    with pytest.raises(ValueError, match=r"csv or \.npz"):
        recorder.save(tmp_path / "r.txt")


def test_scene_rejects_bad_values_before_they_reach_the_thread():
    for kwargs, word in [
        ({"mu": float("nan")}, "mu"),
        ({"gamma": 0.0}, "gamma"),
        ({"rate_hz": 0.0}, "rate_hz"),
        ({"duration_s": -1.0}, "duration_s"),
        ({"method": "XY"}, "method"),
        ({"subsamples": 0}, "subsamples"),
    ]:
        with pytest.raises(ValueError, match=word):
            Scene(CIRCLE, **kwargs)
    streamer = Streamer(SimulatedArray())
    with pytest.raises(ValueError, match="scene"):
        streamer.set_scene("circle")


def test_link_failure_stops_the_stream_with_a_status(tmp_path):
    import os
    import tty

    master, slave = os.openpty()
    tty.setraw(master)
    path = os.ttyname(slave)
    reader = FrameReader(channels=30, levels=23)
    link = SerialLink(path)
    streamer = Streamer(link, scene=Scene(CIRCLE, rate_hz=100.0))
    streamer.start()
    try:
        got = []
        end = time.monotonic() + 5
        while len(got) < 10 and time.monotonic() < end:
            time.sleep(0.01)
            got += reader.feed(os.read(master, 4096))
        assert len(got) >= 10
        os.close(master)
        os.close(slave)
        streamer._thread.join(5.0)
        assert not streamer.running
        stats = streamer.stats
        assert stats.state == "stopped" and "disconnected" in stats.status
        assert stats.errors == 1
    finally:
        streamer.stop()
        link.close()


class FlakyServer:
    """A TCP 'device' for socket:// that can drop its client and accept a new one."""

    def __init__(self):
        self.server = socket.socket()
        self.server.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        self.server.bind(("127.0.0.1", 0))
        self.server.listen(1)
        self.port = self.server.getsockname()[1]
        self.reader = FrameReader(channels=30, levels=23)
        self.frames = []
        self.connections = 0
        self.drop = threading.Event()
        self.alive = True
        self.thread = threading.Thread(target=self.serve, daemon=True)
        self.thread.start()

    def serve(self):
        self.server.settimeout(0.1)
        while self.alive:
            try:
                conn, _ = self.server.accept()
            except OSError:
                continue
            self.connections += 1
            conn.settimeout(0.05)
            while self.alive and not self.drop.is_set():
                try:
                    data = conn.recv(4096)
                except OSError:
                    continue
                if not data:
                    break
                self.frames += self.reader.feed(data)
            self.drop.clear()
            conn.shutdown(socket.SHUT_RDWR)
            conn.close()

    def close(self):
        self.alive = False
        self.thread.join(2)
        self.server.close()


def test_reconnects_after_the_device_drops_the_link():
    server = FlakyServer()
    link = SerialLink(f"socket://127.0.0.1:{server.port}")
    statuses = []
    streamer = Streamer(
        link,
        scene=Scene(CIRCLE, rate_hz=100.0),
        options=StreamOptions(reconnect=True),
        reconnect_interval_s=0.05,
        on_status=lambda s: statuses.append(s.status),
    )
    try:
        streamer.start()
        end = time.monotonic() + 5
        while len(server.frames) < 10 and time.monotonic() < end:
            time.sleep(0.01)
        server.drop.set()  # the device goes away
        end = time.monotonic() + 5
        while server.connections < 2 and time.monotonic() < end:
            time.sleep(0.01)
        n = len(server.frames)
        end = time.monotonic() + 5
        while len(server.frames) < n + 10 and time.monotonic() < end:
            time.sleep(0.01)
        assert server.connections >= 2
        assert len(server.frames) >= n + 10  # streaming again
        assert streamer.running
        assert any("reconnected" in s for s in statuses)
        assert streamer.stats.errors >= 1
    finally:
        streamer.stop()
        link.close()
        server.close()


def test_realtime_priority_is_granted_or_the_status_says_why():
    taps = Taps()
    streamer = Streamer(
        SimulatedArray(),
        scene=Scene(CIRCLE, rate_hz=100.0),
        taps=[taps],
        options=StreamOptions(realtime=True),
    )
    with streamer:
        taps.wait_for(5)
        stats = streamer.stats
    assert stats.realtime or "real-time priority" in stats.status
    assert "priority:" in stats.summary()
