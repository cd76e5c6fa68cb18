"""``tactile stream`` into ``tactile emulate`` over a pseudo-terminal, as a user runs them.

Real processes, a real pseudo-terminal, pyserial unmocked. Faults: the emulator closing
mid-stream, the streaming process killed with SIGKILL, garbage on the line, Ctrl-C.
"""

import os
import signal
import subprocess
import sys

import numpy as np
import pytest

import tactile_core as tc

from .emulator_support import CLI, Emulator, stream, wait_streaming
from .helpers import align, array_status
from .serve_support import wait_for

pytestmark = pytest.mark.skipif(sys.platform == "win32", reason="pseudo-terminals are POSIX")


def test_stream_into_the_emulator_end_to_end(emulator, tmp_path):
    emu = emulator("--rate", "100")
    proc = stream(
        emu.path, "--shape", "circle:2.5,3,2", "--method", "IM", "--mu", "0.33", "--gamma", "0.7",
        "--rate", "100", "--seconds", "1.5", "--no-dither", "--record", str(tmp_path / "sent.npz"),
        "--lead-ms", "0",  # frames for now: each applied on arrival (timed: test_stream_timed)
    )  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    assert "frames:" in proc.stdout and "interval error:" in proc.stdout
    report, log = emu.finish()
    assert report["bad_frames"] == {k: 0 for k in report["bad_frames"]}
    assert report["seq_gaps"] == 0
    with np.load(tmp_path / "sent.npz") as sent:
        assert report["frames"] == len(sent["seq"]) == len(log)  # every frame decoded
    seqs = log[:, 1].astype(int)
    assert ((np.diff(seqs) % 256) == 1).all()  # no gaps
    levels = log[:, 2:].astype(np.uint8)
    assert not levels[-1].any()  # the last frame is all off
    scene_trace = tc.Trace(tc.Circle((2.5, 3.0), 2.0), 2.0, 0.5)
    _, expected = tc.render_frames(
        scene_trace, "IM", sampling=tc.Sampling(100.0, "point"), mu=0.33, gamma=0.7
    )
    expected = tc.quantize(expected, 23).reshape(-1, 30)  # channel order = row * cols + col
    assert align(levels[:-1], expected) >= len(levels) - 2
    assert levels[:-1].any(axis=1).sum() > 100  # lit frames were really checked


def test_emulator_closing_mid_stream_stops_the_streamer_with_a_message(emulator):
    emu = emulator("--close-after", "0.6")  # 0.6 s after the first frame: mid-stream
    proc = stream(
        emu.path, "--shape", "line:0.5,1.84,4.5,4.16", "--method", "AS", "--seconds", "20"
    )
    assert proc.returncode == 1  # stopped by the failure, well before its 20 s
    assert "device disconnected" in proc.stdout + proc.stderr
    assert "stopped" in proc.stdout
    report, _ = emu.finish(ends_itself=True)
    assert report["frames"] > 0 and report["events"][-1][1] == "closed"


def test_sigkilled_streamer_is_turned_off_by_the_watchdog(emulator_thread):
    # The emulator in a thread of this process, so the test sees the frames arrive: it kills
    # the stream once lit frames came, and waits for the watchdog to act.
    emu, path = emulator_thread
    proc = subprocess.Popen(
        [*CLI, "stream", "--device", path, "--shape", "circle:2.5,3,2", "--method", "CT",
         "--pause", "0", "--seconds", "60", "--lead-ms", "0"],
        stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
    )  # fmt: skip
    try:
        wait_streaming(proc)
        wait_for(lambda: len(emu.log) >= 10, timeout_s=30, what="frames at the emulator")
    finally:
        proc.kill()  # no chance to send all-off
        proc.communicate(timeout=10)
    wait_for(lambda: emu.watchdog_trips > 0, timeout_s=30, what="the watchdog")
    report = emu.report()
    times, _, levels = emu.log.arrays()
    assert report["watchdog_trips"] == 1
    assert levels[-1].any()  # the last frame received had a tactor on
    (trip,) = [t for t, e in report["events"] if e == "watchdog"]
    silence = trip - (times[-1] - report["started_monotonic"])  # the report's, from its start
    # off 250 ms after the last frame (+ a poll); the report rounds its times to 1 µs
    assert 0.25 - 1e-6 <= silence < 0.25 + 0.05
    assert not np.array(report["last_levels"]).any()


def test_garbage_and_truncated_frames_are_counted_not_fatal(emulator):
    from tactile_core.device.wire import crc16, encode_frame

    emu = emulator()
    fd = os.open(emu.path, os.O_RDWR | os.O_NOCTTY)
    try:
        good = encode_frame(1, [3] * 30)
        bad_crc = bytearray(encode_frame(2, [3] * 30))
        bad_crc[10] ^= 0x01
        from cobs import cobs

        payload = bytes([0x46, 3, 30]) + bytes([30] * 30)
        out_of_range = cobs.encode(payload + crc16(payload).to_bytes(2, "big")) + b"\x00"
        for chunk in [
            b"\xde\xad\xbe\xef\x00",  # garbage
            good[:12] + b"\x00",  # truncated
            bytes(bad_crc),
            encode_frame(4, [3] * 29),  # wrong N
            out_of_range,
            os.urandom(3000).replace(b"\x00", b"\x01") + b"\x00",  # long noise
            good,
        ]:
            os.write(fd, chunk)
    finally:
        os.close(fd)
    # The emulator leaves on Ctrl-C without reading what is still pending: its answer to a
    # query written after the chunks says it has read them.
    array_status(emu.path)
    report, log = emu.finish()
    assert report["frames"] == 1 and len(log) == 1
    bad = report["bad_frames"]
    assert report["crc_errors"] == 1 and bad["range"] == 1
    assert sum(bad.values()) == 6
    assert "received 1 frames" in emu.output


def test_ctrl_c_turns_the_array_off_and_reports(emulator_thread):
    emu, path = emulator_thread  # in this process: the test sees the frames arrive
    proc = subprocess.Popen(
        [*CLI, "stream", "--device", path, "--shape", "square:2.5,3.5,4", "--method", "MM",
         "--mu", "1", "--pause", "0", "--seconds", "60"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
        env={**os.environ, "PYTHONFAULTHANDLER": "1"},  # SIGABRT prints where it hangs
    )  # fmt: skip
    try:
        wait_streaming(proc)
        wait_for(lambda: len(emu.log) >= 10, timeout_s=30, what="frames at the emulator")
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=30)
    except subprocess.TimeoutExpired:  # (a handler deadlocked once: tests/test_stop_signals.py)
        proc.send_signal(signal.SIGABRT)
        out, err = proc.communicate(timeout=10)
        pytest.fail(f"the stream did not stop 30 s after Ctrl-C; where it was:\n{err}")
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()
    assert proc.returncode == 0, err
    assert "stopped: all off" in out
    # the all-off frame, written before the stream exited, read by the emulator's thread
    wait_for(lambda: not any(emu.log.last()), timeout_s=30, what="the all-off frame")
    levels = emu.log.arrays()[2]
    assert levels[:-1].any() and not levels[-1].any()
    assert emu.watchdog_trips == 0


def test_normal_interpreter_exit_sends_all_off(emulator):
    emu = emulator()
    script = (
        "import time, tactile_core as tc\n"
        "from tactile_core.device.link import SerialLink\n"
        "from tactile_core.rendering.scene import Scene\n"
        "from tactile_core.stream.streamer import Streamer\n"
        f"link = SerialLink({emu.path!r})\n"
        "scene = Scene(tc.Circle((2.5, 3), 2), mu=1.0, pause_s=0.0)\n"
        "s = Streamer(link, scene=scene)\n"
        "s.start()\n"
        "while s.stats.frames < 30:  # lit frames went out\n"
        "    time.sleep(0.01)\n"
        "# exits without stop(): atexit must turn the array off\n"
    )
    proc = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, timeout=30
    )
    assert proc.returncode == 0, proc.stderr
    array_status(emu.path)  # answered once the emulator has read what came before
    report, log = emu.finish()
    assert log[:-1, 2:].any() and not log[-1, 2:].any()
    assert report["watchdog_trips"] == 0


def test_emulate_on_a_socket_receives_every_frame_and_the_next_client(emulator, tmp_path):
    emu = emulator("--socket", "--rate", "100")
    assert emu.path.startswith("socket://127.0.0.1:")
    sent = []
    for run in range(2):  # one client after another, as a line replugged
        record = tmp_path / f"sent{run}.npz"
        proc = stream(
            emu.path, "--shape", "line:0.5,1.84,4.5,4.16", "--method", "AS", "--rate", "100",
            "--seconds", "0.5", "--lead-ms", "0", "--record", str(record),
        )  # fmt: skip
        assert proc.returncode == 0, proc.stderr
        with np.load(record) as frames:
            sent.append(len(frames["seq"]))
    report, log = emu.finish()
    assert report["bad_frames"] == {k: 0 for k in report["bad_frames"]}
    assert report["frames"] == sum(sent) == len(log)  # every frame of both clients decoded
    answered = [event for _, event in report["events"] if event.startswith("answered")]
    assert len(answered) >= 2 and not log[-1, 2:].any()  # each client's hello; all off at the end


def test_emulate_realtime_receives_at_real_time_priority_or_says_why(tmp_path):
    emu = Emulator(tmp_path, "--realtime", "--plain")
    try:
        policy = os.sched_getscheduler(emu.proc.pid)  # set before the path was printed
    finally:
        emu.finish()
    if "receiving at real-time priority (SCHED_FIFO 20)" in emu.errors:
        assert policy == os.SCHED_FIFO
    else:
        assert policy != os.SCHED_FIFO
        assert "real-time priority" in emu.errors  # (not permitted / not available: why)


def test_stream_to_a_missing_device_says_so():
    proc = stream("/dev/ttyNOPE9", "--shape", "circle:2.5,3,2", "--method", "AS", "--seconds", "1")
    assert proc.returncode == 1
    assert "no such port: /dev/ttyNOPE9" in proc.stderr


def test_stream_bad_arguments_exit_2():
    proc = stream(
        "sim", "--shape", "circle:2.5,3,2", "--method", "AS", "--mu", "nan", "--seconds", "1"
    )
    assert proc.returncode == 2 and "mu" in proc.stderr
    proc = stream("sim", "--shape", "circle:2.5,3,2", "--method", "AS", "--profile", "/nope.json")
    assert proc.returncode == 2 and "no such file" in proc.stderr


def test_a_second_client_of_a_socket_array_is_refused_not_left_waiting(emulator_socket_thread):
    # An array serves one host, as a serial port held by one program does. The emulator used
    # to leave a second client in the listening socket's backlog: its connection completed,
    # open_array returned, and its presentations counted as played while every frame waited
    # in a kernel buffer. Now the second client is closed at once and told why.
    array, url = emulator_socket_thread
    with tc.open_array(url, lead_ms=0) as first:
        with pytest.raises(RuntimeError, match=r"closed the connection.*another program"):
            tc.open_array(url, lead_ms=0)
        shown = first.play("circle:2.5,3,2", "AS", duration_s=0.2)
        assert shown.first_frame_s is not None and not shown.failed
    with tc.open_array(url, lead_ms=0) as after:  # free again once the first one left
        assert not after.play("circle:2.5,3,2", "AS", duration_s=0.1).failed
    report = array.report()
    assert report["clients_refused"] == 1
    assert report["bad_frames"] == {k: 0 for k in report["bad_frames"]}
    assert "second clients refused: 1" in array.summary()


def test_a_socket_with_nothing_listening_says_so():
    import socket

    from tactile_core.device.link import LinkError, open_link
    from tactile_core.device.profile import load_profile

    with socket.create_server(("127.0.0.1", 0)) as probe:
        port = probe.getsockname()[1]  # (closed again: nothing listens there now)
    with pytest.raises(LinkError, match=r"no device at socket://127\.0\.0\.1:.*connection refused"):
        open_link(f"socket://127.0.0.1:{port}", load_profile(None))
