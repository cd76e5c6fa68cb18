"""The streamer in a child process: scenes in, frames out, all off whichever side dies."""

import signal
import subprocess
import sys
import time

import numpy as np
import pytest

import tactile_core as tc
from tactile_core.device.link import LinkError
from tactile_core.rendering.scene import Scene
from tactile_core.stream.process import StreamerProcess, open_stream

CIRCLE = tc.Circle((2.5, 3.0), 2.0)


def wait(predicate, timeout=60.0):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if predicate():
            return
        time.sleep(0.01)
    raise AssertionError("condition not met in time")


def test_child_streams_scenes_and_turns_off_on_stop(emulator_thread):
    emu, path = emulator_thread
    stream = open_stream(path, scene=Scene(tc.Line((1.5, 2.5), (1.5, 2.5)), "CT", pause_s=0.0))
    try:
        wait(lambda: len(emu.log) > 20)
        assert emu.log.last()[2 * 5 + 1] == 22  # cell (1, 2)
        wait(lambda: stream.last_levels[2, 1] == 22)  # published back to the parent
        scene, trace_time = stream.last_frame
        assert scene is stream.scene and trace_time is not None
        stream.set_scene(stream.scene.replace(shape=tc.Line((3.5, 4.5), (3.5, 4.5))))
        wait(lambda: emu.log.last()[4 * 5 + 3] == 22 and emu.log.last()[2 * 5 + 1] == 0)
        stream.all_off()
        wait(lambda: not any(emu.log.last()))
        wait(lambda: stream.stats.state == "paused")  # the parent hears it through a pipe
    finally:
        stats = stream.stop()
    assert not stream.running
    assert stats.state == "stopped" and stats.frames > 20
    assert not any(emu.log.last()) and not stream.last_levels.any()


def test_a_bad_port_is_reported_by_start_and_nothing_keeps_running():
    stream = StreamerProcess("/dev/ttyNOPE3")
    with pytest.raises(LinkError, match="no such port: /dev/ttyNOPE3"):
        stream.start()
    assert not stream.running


def test_killing_the_parent_turns_the_array_off_without_the_watchdog(emulator_thread):
    emu, path = emulator_thread
    script = (
        "import signal, tactile_core as tc\n"
        "from tactile_core.stream.process import open_stream\n"
        "from tactile_core.rendering.scene import Scene\n"
        f"s = open_stream({path!r}, scene=Scene(tc.Circle((2.5, 3), 2), mu=1.0, pause_s=0.0))\n"
        "print('streaming', s._proc.pid, flush=True)\n"
        "signal.pause()  # until killed\n"
    )
    parent = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True)
    try:
        said, child = parent.stdout.readline().split()
        assert said == "streaming"
        wait(lambda: len(emu.log) > 30 and any(emu.log.last()))
        parent.send_signal(signal.SIGKILL)
        parent.wait(10)
        wait(lambda: not any(emu.log.last()))
    finally:
        if parent.poll() is None:
            parent.kill()
        parent.stdout.close()
    assert emu.watchdog_trips == 0  # the child noticed and sent all-off itself
    wait(lambda: ended(int(child)))  # and it has stopped streaming: it is gone


def ended(pid):
    """True once process ``pid`` has exited (gone, or a zombie its new parent has not reaped)."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] == "Z"
    except FileNotFoundError:
        return True


def test_local_stream_has_the_same_interface():
    stream = open_stream(None, scene=Scene(CIRCLE, mu=1.0), process=False)
    try:
        wait(lambda: stream.last_levels.any())
        stream.all_off()
        wait(lambda: not stream.last_levels.any())
    finally:
        stats = stream.stop()
    assert stats.state == "stopped" and not np.asarray(stream.last_levels).any()


def test_starting_the_stream_process_prints_no_runpy_warning():
    # The child ran as ``python -m tactile_core.stream.process``, a module the package had
    # already imported: runpy warned on stderr at every stream start ("found in sys.modules").
    code = (
        "from tactile_core.stream import open_stream\n"
        "stream = open_stream(None)\n"
        "assert stream.running\n"
        "stream.stop()\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert out.returncode == 0, out.stderr
    assert "Warning" not in out.stderr, out.stderr
