"""How a stream ends when it is not asked to: a hang-up, a bug in its output thread, Ctrl-C in
the terminal of a stream process. Each ends with the array all off and says so in one line,
never a traceback."""

import os
import signal
import subprocess
import sys

import tactile_core as tc
from tactile_core.device.link import SimulatedArray
from tactile_core.rendering.scene import Scene
from tactile_core.stream.process import StreamerProcess
from tactile_core.stream.streamer import Streamer

from .emulator_support import wait_streaming
from .serve_support import wait_for

CLI = [sys.executable, "-m", "tactile_core.cli"]
CIRCLE = tc.Circle((2.5, 3), 2)


def test_sighup_ends_tactile_stream_quietly_all_off():
    # a closed terminal hangs up on the stream: it ends as Ctrl-C ends it, all off
    proc = subprocess.Popen(
        [*CLI, "stream", "--device", "sim", "--shape", "circle:2.5,3,2", "--method", "AS"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )  # fmt: skip
    wait_streaming(proc)  # its handlers are in place (a hang-up before them ends it with 129)
    proc.send_signal(signal.SIGHUP)
    out, err = proc.communicate(timeout=10)
    assert proc.returncode == 0, err
    assert "stopped: all off" in out and "Traceback" not in err


def test_an_internal_error_in_the_output_thread_is_told_and_ends_all_off(monkeypatch):
    array = SimulatedArray()
    streamer = Streamer(array, scene=Scene(CIRCLE))

    def broken(*args):
        raise RuntimeError("boom")

    monkeypatch.setattr(streamer, "_levels", broken)
    streamer.start()
    wait_for(lambda: not streamer.running, timeout_s=20, what="the error ending the thread")
    stats = streamer.stop()
    assert stats.state == "failed" and "internal error: RuntimeError: boom" in stats.status
    assert "all off" in stats.status and "RuntimeError" in streamer.failure_traceback
    assert not array.levels().any()


def test_ctrl_c_in_the_terminal_leaves_the_stream_process_to_its_parent(capfd):
    # Ctrl-C reaches the whole process group: the child printed a KeyboardInterrupt traceback
    # and died, and the tuner lost its stream
    stream = StreamerProcess(None, scene=Scene(CIRCLE)).start()
    try:
        os.kill(stream._proc.pid, signal.SIGINT)  # what Ctrl-C in the terminal sends it
        # The child obeys a command sent after the signal (its command loop is the main
        # thread, where Python raises KeyboardInterrupt): the signal has been dealt with.
        after = Scene(CIRCLE, mu=0.5)
        stream.set_scene(after)
        wait_for(lambda: stream.last_frame[0] is after, timeout_s=20, what="a frame of the scene")
        assert stream.running  # the parent decides when the child stops
    finally:
        stats = stream.stop()
    assert stats.state == "stopped" and stream._proc.returncode == 0
    assert "KeyboardInterrupt" not in capfd.readouterr().err
