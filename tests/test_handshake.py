"""Wire format 2 from the host's side: hello and info on connecting, a refused mismatch, an
unidentified array, queries and counters, and the 100 ms keep-alive at any rate."""

import dataclasses
import itertools
import sys
import threading
import time

import pytest

import tactile_core as tc
from tactile_core.device.emulator import Emulator
from tactile_core.device.host_clock import VirtualClock
from tactile_core.device.link import SerialLink, SimulatedArray, identify
from tactile_core.device.profile import default_profile, profile_from_dict
from tactile_core.device.wire import KEEPALIVE_S
from tactile_core.rendering.scene import Scene
from tactile_core.stream.streamer import Streamer

from .serve_support import wait_for

pytestmark = pytest.mark.skipif(sys.platform == "win32", reason="pseudo-terminals are POSIX")

CIRCLE = tc.Circle((2.5, 3.0), 2.0)


def running_emulator(profile=None):
    emulator = Emulator(profile)
    path = emulator.open()
    stop = threading.Event()
    thread = threading.Thread(target=emulator.run, args=(stop.is_set,), daemon=True)
    thread.start()

    def finish():
        stop.set()
        thread.join(2)
        emulator.close()

    return emulator, path, finish


def test_identify_reads_the_emulators_info():
    _, path, finish = running_emulator()
    link = SerialLink(path)
    try:
        info, problem = identify(link, default_profile(), timeout_s=5.0)  # a loaded host
    finally:
        link.close()
        finish()
    assert problem == ""
    assert (info.cols, info.rows, info.levels, info.watchdog_ms) == (5, 6, 23, 250)
    assert info.name == "palm-5x6" and info.version == 2


def test_a_mismatched_array_is_refused_with_a_status(monkeypatch):
    import functools

    from tactile_core.stream import _talk as _stream_talk

    # the emulator thread may answer the hello late on a loaded host: it is not what is tested
    monkeypatch.setattr(_stream_talk, "identify", functools.partial(identify, timeout_s=5.0))
    data = default_profile().to_dict()
    data.update(name="strip-6x5", columns=6, rows=5)
    other = profile_from_dict(data)
    emulator, path, finish = running_emulator(other)
    link = SerialLink(path)
    streamer = Streamer(link, default_profile(), scene=Scene(CIRCLE))
    try:
        streamer.start()
        deadline = time.monotonic() + 3
        while streamer.running and time.monotonic() < deadline:
            time.sleep(0.02)
        stats = streamer.stop()
    finally:
        link.close()
        finish()
    assert stats.state == "refused"
    assert "6 x 5" in stats.status and "expects 5 x 6" in stats.status
    assert emulator.model.frames_applied <= 1  # at most the final all-off frame, never a scene


def test_cli_refuses_a_mismatched_array_with_a_nonzero_exit(tmp_path):
    import json
    import subprocess

    data = default_profile().to_dict()
    data.update(name="coarse", levels=16)
    (tmp_path / "coarse.json").write_text(json.dumps(data))
    emulator = subprocess.Popen(
        [sys.executable, "-m", "tactile_core.cli", "emulate", "--profile",
         str(tmp_path / "coarse.json"), "--seconds", "20"],
        stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True,
    )  # fmt: skip
    try:
        path = emulator.stdout.readline().strip()
        proc = subprocess.run(
            [sys.executable, "-m", "tactile_core.cli", "stream", "--device", path, "--shape",
             "circle:2.5,3,2", "--method", "AS", "--seconds", "1"],
            capture_output=True, text=True, timeout=30,
        )  # fmt: skip
    finally:
        emulator.kill()
        emulator.communicate()
    assert proc.returncode != 0
    assert "array mismatch" in proc.stdout + proc.stderr and "16 levels" in proc.stdout


def test_an_array_that_does_not_answer_is_driven_and_reported_unidentified():
    link = SerialLink("loop://")  # echoes what is sent: a hello comes back, never an info
    streamer = Streamer(link, default_profile(), scene=Scene(CIRCLE))
    try:
        with streamer:
            deadline = time.monotonic() + 60.0  # generous: a loaded machine is only slower
            while streamer.stats.frames <= 50 and time.monotonic() < deadline:
                time.sleep(0.01)
        stats = streamer.stats
    finally:
        link.close()
    assert stats.array.startswith("unidentified: no answer to hello within 0.5 s")
    assert stats.frames > 50  # it streamed anyway


def test_query_answers_agree_with_the_emulators_own_counts(monkeypatch):
    from tactile_core.stream import streamer as streamer_module

    # the final counters must come back for the comparison: a loaded host may answer late
    monkeypatch.setattr(streamer_module, "FINAL_STATUS_WAIT_S", 5.0)
    emulator, path, finish = running_emulator()
    link = SerialLink(path)
    streamer = Streamer(link, default_profile(), scene=Scene(CIRCLE, rate_hz=200.0))
    try:
        streamer.start()
        wait_for(lambda: emulator.model.frames_applied >= 20, what="20 frames at the emulator")
        link.write(b"\x13\x37garbage\x00")  # one malformed message for the dropped count
        status = streamer.query_status(5.0)  # asked after the garbage, so answered after it
        stats = streamer.stop()
    finally:
        link.close()
        finish()
    assert status is not None and status.dropped == 1
    assert 0 < status.frames_applied <= emulator.model.frames_applied
    final = emulator.report()
    assert stats.array_frames == final["frames_applied"] == len(emulator.log)
    assert stats.array_dropped == final["dropped"] == 1
    assert stats.array_watchdog_trips == final["watchdog_trips"] == 0


def run_virtual(scene, seconds, **kwargs):
    """Stream ``scene`` for ``seconds`` of virtual time: the frames and the simulated array."""
    clock = VirtualClock()
    array = SimulatedArray(clock=clock)
    sent = []
    tap = [lambda t, seq, levels: sent.append((t, levels))]
    streamer = Streamer(array, scene=scene, clock=clock, identify=False, spin_s=0.0, taps=tap,
                        **kwargs)  # fmt: skip
    end = clock.now() + seconds
    with streamer:
        deadline = time.monotonic() + 60.0  # generous: virtual time runs as fast as it can
        while clock.now() < end and time.monotonic() < deadline:
            time.sleep(0.001)
    return sent, array


@pytest.mark.parametrize("rate_hz", [1.0, 2.0, 4.0])
def test_slow_rates_keep_the_watchdog_fed(rate_hz):
    scene = Scene(tc.Line((2.5, 3.5), (2.5, 3.5)), "CT", rate_hz=rate_hz, pause_s=0.0)
    sent, array = run_virtual(scene, 3.0)
    gaps = [b - a for (a, _), (b, _) in itertools.pairwise(sent)]
    assert len(sent) > 40
    # A frame at most every 60 ms (KEEPALIVE_S; the period split evenly: 1 s / 17, 0.5 s / 9,
    # 0.25 s / 5): 40 ms of margin on the contract's "at least every 100 ms" for the host's
    # scheduler, the link and the receiver.
    tick = (1 / rate_hz) / {1.0: 17, 2.0: 9, 4.0: 5}[rate_hz]
    assert max(gaps) == pytest.approx(tick, abs=1e-9) and tick <= KEEPALIVE_S
    assert array.watchdog_trips == 0


def test_keepalive_repeats_the_frame_between_trace_frames():
    # 2 Hz on a 4 s trace: trace frames at 0, 0.5, 1.0 s; between them the same levels repeat
    scene = Scene(tc.Line((0.5, 3.5), (4.5, 3.5)), "CT", rate_hz=2.0, duration_s=4.0)
    frames, _ = run_virtual(scene, 1.15)
    t0 = frames[0][0]
    first = [lv for t, lv in frames if t - t0 < 0.5 - 1e-9]
    assert len(first) == 9  # ticks of 0.5 s / 9 = 55.6 ms: 0, 55.6, ..., 444.4 ms
    assert all(lv == first[0] for lv in first)
    assert frames[9][0] - t0 == pytest.approx(0.5) and frames[9][1] != first[0]


def test_simulated_array_answers_hello_and_query():
    array = SimulatedArray(dataclasses.replace(default_profile()))
    info, problem = identify(array, default_profile())
    assert problem == "" and info.describe().startswith("palm-5x6: 5 x 6, 23 levels")
