"""How a script's presentations and arrays end: a presentation cut short (replaced, turned off,
its device lost) ends its ``wait()`` at once and says which; a closed array refuses what would
light it; SIGTERM turns every open array off, and closing arrays gives the script its own
SIGTERM handler back only after the last."""

import signal
import subprocess
import sys
import textwrap
import time

import pytest

import tactile_core as tc
from tactile_core import script

from .helpers import stop_with

#: script.START_TIMEOUT_S while a test shows something ends "at once": a wait for the start
#: timeout would take this long, which no load makes the right answer take.
LONG_START_TIMEOUT_S = 120.0


@pytest.mark.parametrize("cut", ["all_off", "play"])
def test_waiting_for_a_presentation_cut_short_before_its_first_frame_returns_at_once(
    cut, monkeypatch
):
    """wait() waited for the start timeout, then raised 'no frame went out' with the stream's
    status, for a presentation that was only replaced or turned off before its first frame."""
    monkeypatch.setattr(script, "START_TIMEOUT_S", LONG_START_TIMEOUT_S)
    with tc.open_array("sim") as array:
        shown = array.play("circle:2.5,3,2", duration_s=1.0, wait=False)
        if cut == "all_off":
            array.all_off()
        else:
            array.play("line:0.5,0.5,4.5,5.5", duration_s=0.05, wait=False)
        start = time.monotonic()
        assert shown.wait() is shown
        assert time.monotonic() - start < LONG_START_TIMEOUT_S / 2  # not the start timeout
        assert shown.interrupted and shown.done.is_set()


def test_a_device_lost_while_a_presentation_plays_fails_its_wait_and_the_next_play(monkeypatch):
    """wait() returned as if the stimulus had played when the device went away under it (a
    trial recorded as presented), and the next play() waited the start timeout before saying
    why."""
    from tactile_core.device.link import LinkError

    monkeypatch.setattr(script, "START_TIMEOUT_S", LONG_START_TIMEOUT_S)
    with tc.open_array("sim") as array:
        shown = array.play("circle:2.5,3,2", duration_s=30.0, wait=False)
        assert shown.started.wait(20)

        def unplugged(data):
            raise LinkError("device disconnected: sim (unplugged in a test)")

        array.link.write = unplugged
        start = time.monotonic()
        with pytest.raises(RuntimeError, match=r"stopped before the stimulus had played.*unplug"):
            shown.wait()
        assert shown.interrupted and "unplugged" in shown.failed
        with pytest.raises(RuntimeError, match=r"the stream has stopped: .*unplugged"):
            array.play("line:0.5,0.5,4.5,5.5", duration_s=0.1)
        with pytest.raises(RuntimeError, match="the stream has stopped"):
            array.point(2.5, 3.0)
        assert time.monotonic() - start < LONG_START_TIMEOUT_S / 2  # not the start timeout


def test_a_closed_array_refuses_points_as_it_refuses_play():
    """point() after close() did nothing and said nothing: the script believed a point on."""
    array = tc.open_array("sim")
    array.close()
    # its threads are gone when close() returns (the keeper used to linger: under load the
    # next test found it still running)
    assert not array._keeper.is_alive() and not array.streamer.running
    array.close()  # twice: nothing happens
    for call in (lambda: array.point(2.5, 3.0), lambda: array.play("circle:2.5,3,2"),
                 array.__enter__):  # fmt: skip
        with pytest.raises(ValueError, match="the array is closed"):
            call()
    array.release()  # harmless: all is off already
    array.all_off()
    assert not array.streamer.running


SIGTERM_SCRIPT = textwrap.dedent("""
    import signal
    import tactile_core as tc
    first, second = tc.open_array("sim"), tc.open_array("sim")
    first.close()
    try:
        with second:
            shown = second.play("circle:2.5,3,2", method="AS", duration_s=60, wait=False)
            shown.started.wait(10)
            print("playing", flush=True)
            shown.wait()
    except SystemExit:
        print("off" if not second.link.levels().any() else "ON", flush=True)
        raise
""")


def test_sigterm_still_turns_the_array_off_after_another_array_closed():
    # Closing the first of two arrays put SIGTERM back to its default while the second was
    # still open: SIGTERM then killed the script outright, no `with` block ran, and the array
    # stayed on until its watchdog.
    proc = subprocess.Popen([sys.executable, "-c", SIGTERM_SCRIPT], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)  # fmt: skip
    try:
        assert proc.stdout.readline().strip() == "playing", proc.stderr.read()
    except BaseException:
        stop_with(proc, signal.SIGKILL)
        raise
    out, err = stop_with(proc, signal.SIGTERM)
    assert out.split() == ["off"], err
    assert proc.returncode == 128 + signal.SIGTERM


HANDLER_SCRIPT = textwrap.dedent("""
    import signal
    import tactile_core as tc
    from tactile_core import script
    def mine(signum, frame):
        pass
    first, second = tc.open_array("sim"), tc.open_array("sim")
    first.close()
    print(signal.getsignal(signal.SIGTERM) is script._terminate)
    second.close()
    print(signal.getsignal(signal.SIGTERM) == signal.SIG_DFL)
    array = tc.open_array("sim")
    signal.signal(signal.SIGTERM, mine)  # the script's own, put in while the array is open
    array.close()
    print(signal.getsignal(signal.SIGTERM) is mine)
""")


def test_closing_arrays_restores_sigterm_only_after_the_last_and_keeps_the_scripts_handler():
    out = subprocess.run([sys.executable, "-c", HANDLER_SCRIPT], capture_output=True, text=True,
                         timeout=60)  # fmt: skip
    assert out.returncode == 0, out.stderr
    assert out.stdout.split() == ["True", "True", "True"]
