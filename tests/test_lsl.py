"""Lab Streaming Layer outlets resolved on this machine: each marker is stamped with its
presentation's first frame's send time (from a recording tap) within 1 ms, on LSL's clock; the
levels stream carries every frame. pylsl is a dependency: these tests never skip."""

import json
import math
import subprocess
import sys
import time
import uuid

import numpy as np
import pylsl
import pytest

import tactile_core as tc
from tactile_core.device.host_clock import VirtualClock
from tactile_core.device.link import SimulatedArray
from tactile_core.device.profile import default_profile
from tactile_core.rendering.scene import Scene
from tactile_core.serve import LslOutlets, lsl_offset_s
from tactile_core.stream import Streamer, StreamOptions

from .serve_support import Taps, wait_for

CLI = [sys.executable, "-m", "tactile_core.cli"]


def own_offset():
    """LSL's clock minus perf_counter, measured here independently of the module."""
    best = (math.inf, 0.0)
    for _ in range(200):
        a = time.perf_counter()
        lsl = pylsl.local_clock()
        b = time.perf_counter()
        best = min(best, (b - a, lsl - (a + b) / 2))
    return best[1]


def inlet_for(predicate, timeout_s=20.0):
    found = pylsl.resolve_bypred(predicate, 1, timeout_s)
    assert found, f"no LSL stream {predicate} on this machine"
    inlet = pylsl.StreamInlet(found[0], max_buflen=60)
    inlet.open_stream(timeout_s)
    return inlet, found[0]


def first_frame_after(taps, index, seq):
    """``(time, levels)`` of the first frame from tap index ``index`` on with ``seq``."""
    for time_s, s, levels in taps.frames[index:]:
        if s == seq:
            return time_s, levels
    raise AssertionError(f"no frame with seq {seq} after frame {index}")


def first_levels(scene, profile):
    """Channel-ordered levels of frame 0 of ``scene``."""
    cells = np.zeros(profile.channels)
    for i, v in scene.live(profile.layout, 300).entries(0):
        cells[i] = v
    return bytes(tc.quantize(cells, profile.levels)[profile.array.channel_index].tolist())


@pytest.mark.parametrize("lead_s", [0.0, 0.02])
def test_lsl_markers_stamped_with_the_first_frames_send_time(lead_s):
    profile = default_profile()
    taps = Taps()
    sid = f"test-{uuid.uuid4().hex}"
    streamer = Streamer(
        SimulatedArray(profile), profile, taps=[taps], options=StreamOptions(lead_ms=lead_s * 1e3)
    )
    outlets = LslOutlets(profile, source_id=sid).attach(streamer)
    inlet, info = inlet_for(f"source_id='{sid}-markers'")
    assert (info.name(), info.type(), info.channel_format()) == (
        "tactile-markers", "Markers", pylsl.cf_string
    )  # fmt: skip
    streamer.start()
    try:
        scenes = [
            Scene(tc.Circle((2.5, 3), 2), "IM", 0.33, 0.7, marker="trial", repeat=False,
                  duration_s=0.2, epoch=1),
            Scene(tc.Line((0.5, 0.5), (4.5, 5.5)), "AS", 0.2, 0.5, marker="ab", epoch=2),
            Scene(tc.Square((2.5, 3), 2), "CT", marker="interval", epoch=3),
        ]  # fmt: skip
        errors = []
        offset = own_offset()
        for scene in scenes:
            start = len(taps.frames)
            streamer.set_scene(scene)
            sample, stamp = inlet.pull_sample(timeout=20)
            assert sample is not None, "no marker"
            marker = json.loads(sample[0])
            assert (marker["kind"], marker["method"], marker["shape"], marker["cycle"]) == (
                scene.marker, scene.method, scene.shape.spec, 0
            )  # fmt: skip
            assert (marker["mu"], marker["gamma"], marker["timed"]) == (
                scene.mu, scene.gamma, lead_s > 0
            )  # fmt: skip
            sent, levels = first_frame_after(taps, start, marker["seq"])
            assert levels == first_levels(scene, profile)  # the scene's own first frame
            errors.append(stamp - (sent + offset))
        assert max(abs(e) for e in errors) < 1e-3, errors
        print(
            f"LSL marker error (lead {lead_s * 1e3:g} ms): max {max(map(abs, errors)) * 1e6:.3f} us"
        )
        assert outlets.offset_s == pytest.approx(offset, abs=1e-4)
    finally:
        streamer.stop()
        outlets.close()


def test_lsl_levels_stream_carries_every_frame_at_its_time():
    profile = default_profile()
    taps = Taps()
    sid = f"test-{uuid.uuid4().hex}"
    streamer = Streamer(SimulatedArray(profile), profile, taps=[taps])
    outlets = LslOutlets(profile, source_id=sid, markers=False, levels=True).attach(streamer)
    inlet, info = inlet_for(f"source_id='{sid}-levels'")
    assert (info.name(), info.channel_count(), info.nominal_srate()) == ("tactile-levels", 30, 300)
    full = inlet.info(20)  # a resolved info has no description; the inlet's has
    labels = full.desc().child("channels").child("channel").child_value("label")
    assert labels == profile.layout.names[int(profile.array.channel_index[0])]
    streamer.start()
    try:
        streamer.set_scene(Scene(tc.Circle((2.5, 3), 2), "AS", duration_s=0.3))
        got, stamps = [], []
        wait_for(lambda: len(taps.frames) > 100, what="100 frames")
        deadline = time.monotonic() + 20
        while len(got) < 60 and time.monotonic() < deadline:
            chunk, ts = inlet.pull_chunk(timeout=1.0)
            got.extend(chunk)
            stamps.extend(ts)
        assert len(got) >= 60
    finally:
        streamer.stop()
        outlets.close()
    sent = {round(t + outlets.offset_s, 9): levels for t, _, levels in taps.frames}
    for sample, stamp in zip(got, stamps):
        assert bytes(sample) == sent[round(stamp, 9)]
    assert any(any(s) for s in got)


def test_lsl_repeating_trace_gets_a_marker_per_cycle():
    """Each cycle of a repeating trace is marked at its own first frame, and a change that keeps
    the trace running (mu) goes on counting cycles. On a virtual clock: on the host clock a
    stream thread held back longer than the first tactor's ~23 ms skips the cycle's first
    frames, and its first frame written is rightly a later one, dark on that tactor."""
    profile = default_profile()
    clock = VirtualClock()
    taps = Taps()
    sid = f"test-{uuid.uuid4().hex}"
    streamer = Streamer(SimulatedArray(profile, clock=clock), profile, taps=[taps], clock=clock,
                        identify=False, spin_s=0.0)  # fmt: skip
    outlets = LslOutlets(profile, source_id=sid).attach(streamer)
    scene = Scene(tc.Line((0.5, 0.5), (4.5, 0.5)), "CT", duration_s=0.2, pause_s=0.05)
    changed = scene.replace(mu=0.5)
    onsets = []

    def on_onset(onset):  # in the output thread: the change lands inside cycle 3, every run
        onsets.append(onset)
        if len(onsets) == 4:
            streamer.set_scene(changed)

    streamer.on_onset.append(on_onset)
    streamer.set_scene(scene)
    streamer.start()
    try:
        wait_for(lambda: len(onsets) >= 6, what="six cycles")
    finally:
        streamer.stop()
        outlets.close()
    onsets = onsets[:6]
    assert [o.cycle for o in onsets] == [0, 1, 2, 3, 4, 5]
    assert [o.scene for o in onsets] == [scene] * 4 + [changed] * 2
    period_s = 0.2 + 0.05  # 75 frames a cycle at 300 Hz
    for onset in onsets:
        assert onset.time_s - onsets[0].time_s == pytest.approx(onset.cycle * period_s, abs=1e-9)
    frames = {t: levels for t, _, levels in taps.frames}
    for onset in onsets:  # each cycle begins lit on the line's first tactor
        assert frames[onset.time_s][0] == 22
    assert outlets.markers_sent >= 6


def test_lsl_marker_presentation_counts_on_where_the_wire_seq_wraps():
    from tactile_core.stream import Onset

    sid = f"test-{uuid.uuid4().hex}"
    outlets = LslOutlets(default_profile(), source_id=sid)
    inlet, _ = inlet_for(f"source_id='{sid}-markers'")
    scene = Scene(tc.Circle((2.5, 3), 2), "AS", marker="trial")
    try:
        for k in range(300):  # presentations 75 frames apart: the wire's seq wraps often
            outlets.onset(Onset(scene, 100.0 + k, (75 * k) & 0xFF))
        got = []
        deadline = time.monotonic() + 20
        while len(got) < 300 and time.monotonic() < deadline:
            sample, _ = inlet.pull_sample(timeout=1.0)
            if sample:
                got.append(json.loads(sample[0]))
    finally:
        outlets.close()
    assert [m["presentation"] for m in got] == list(range(1, 301))
    assert [m["seq"] for m in got] == [(75 * k) % 256 for k in range(300)]


def test_lsl_offset_is_measured_not_assumed():
    assert abs(lsl_offset_s() - own_offset()) < 1e-4


def test_tactile_stream_lsl_marks_each_trace_at_its_first_frame(tmp_path):
    record = tmp_path / "frames.npz"
    proc = subprocess.Popen(
        [*CLI, "stream", "--device", "sim", "--shape", "line:0.5,0.5,4.5,0.5", "--method", "CT",
         "--duration", "0.2", "--pause", "0.1", "--seconds", "6", "--lsl", "--lead-ms", "0",
         "--record", str(record)],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )  # fmt: skip
    try:
        inlet, _info = inlet_for(f"name='tactile-markers' and desc/pid='{proc.pid}'")
        markers = []
        while len(markers) < 3:
            sample, stamp = inlet.pull_sample(timeout=20)
            assert sample is not None, "no marker from tactile stream"
            markers.append((json.loads(sample[0]), stamp))
        _out, err = proc.communicate(timeout=30)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()
    assert proc.returncode == 0, err
    with np.load(record) as data:  # times from the first frame; the first trace's marker
        times, seqs = data["time"], data["seq"]  # went out before this test could connect
    per_cycle = 0.3  # duration + pause
    (_first, stamp0), anchor = markers[0], None
    for marker, stamp in markers:
        assert marker["kind"] == "stream" and marker["shape"] == "line:0.5,0.5,4.5,0.5"
        # the recorded frame with the marker's seq (which wraps every 256 frames) nearest the
        # start of its cycle
        candidates = np.flatnonzero(seqs == marker["seq"])
        index = candidates[np.argmin(np.abs(times[candidates] - marker["cycle"] * per_cycle))]
        assert data_levels_lit(record, index)
        if anchor is None:
            anchor = times[index]
        # stamps and recorded send times agree, marker to marker, within 1 ms
        assert abs((stamp - stamp0) - (times[index] - anchor)) < 1e-3
    assert [m["cycle"] for m, _ in markers] == sorted({m["cycle"] for m, _ in markers})


def data_levels_lit(record, index):
    with np.load(record) as data:
        return data["levels"][index].reshape(-1)[0] == 22  # the line's first tactor, at full


def test_lsl_markers_from_the_stream_process_name_the_parents_scenes():
    from tactile_core.stream.process import open_stream

    sid = f"test-{uuid.uuid4().hex}"
    stream = open_stream(None, default_profile(), process=True)
    outlets = LslOutlets(stream.profile, source_id=sid).attach(stream)  # markers only
    onsets = []
    stream.on_onset.append(onsets.append)
    try:
        inlet, _ = inlet_for(f"source_id='{sid}-markers'")
        scene = Scene(tc.Circle((2.5, 3), 2), "AS", marker="ab", repeat=False, duration_s=0.1)
        offset = own_offset()
        before = time.perf_counter()
        stream.set_scene(scene)
        sample, stamp = inlet.pull_sample(timeout=20)
        after = time.perf_counter()
        assert json.loads(sample[0])["kind"] == "ab"
        assert before + offset <= stamp <= after + offset  # written between the two
        wait_for(lambda: onsets, what="the onset hook")
        assert onsets[0].scene is scene and onsets[0].time_s == pytest.approx(stamp - offset)
    finally:
        stream.stop()
        outlets.close()
