"""Ctrl-C, SIGTERM and SIGHUP stop a command or close the tuner, and nothing they do in their
handler may wait for a lock: a handler runs in the main thread between two bytecodes, maybe
while that thread holds the very lock.

The CLI's handlers used to set a ``threading.Event``. Beside a busy stream thread, a signal
that came while the main loop's ``Event.wait`` re-took the event's lock deadlocked the command
with the stream still playing: once in CI-like load, 2 in 300 Ctrl-C's of a small script, and 5
of 6 runs of the stress below (500 signals each)."""

import signal
import subprocess
import sys
import textwrap
import threading
import time

import pytest

from tactile_core.cli._common import StopRequest

STRESS = textwrap.dedent("""
    import os, signal, subprocess, sys, threading, time
    from tactile_core.cli._common import _install_stop_handlers

    n = int(sys.argv[1])
    sys.setswitchinterval(0.0005)  # as the streamer sets it

    def busy():  # the stream thread: the main thread often waits for the GIL
        x = 0
        while True:
            x += 1
            if x % 1000 == 0:
                time.sleep(0.0001)

    threading.Thread(target=busy, daemon=True).start()
    killer = subprocess.Popen([sys.executable, "-c",
        "import os, random, signal, sys, time\\n"
        "pid, n = int(sys.argv[1]), int(sys.argv[2]); rng = random.Random(1)\\n"
        "for _ in range(n):\\n"
        "    time.sleep(rng.uniform(0.002, 0.006)); os.kill(pid, signal.SIGINT)\\n",
        str(os.getpid()), str(n)])
    stops = 0
    while killer.poll() is None:
        stop = _install_stop_handlers()
        while not stop.wait(0.0005) and killer.poll() is None:
            pass
        stops += stop.is_set()
    print(stops)
""")


def test_signals_at_any_moment_never_deadlock_the_stop_request():
    n = 800
    proc = subprocess.Popen([sys.executable, "-c", STRESS, str(n)], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)  # fmt: skip
    try:
        out, err = proc.communicate(timeout=120)
    except subprocess.TimeoutExpired:
        proc.kill()  # a deadlocked handler would ignore SIGTERM too
        proc.communicate()
        pytest.fail("a signal deadlocked the stop request")
    assert proc.returncode == 0, err
    assert 0 < int(out.split()[-1]) <= n  # signals in one wait count once


def test_a_stop_request_wakes_its_waiter_and_times_out():
    stop = StopRequest()
    assert stop.wait(0.0) is False and stop.wait(-1.0) is False and not stop.is_set()
    started = time.monotonic()
    assert stop.wait(0.05) is False
    assert time.monotonic() - started >= 0.05
    threading.Timer(0.05, stop.set).start()
    assert stop.wait(60.0) is True and stop.is_set()  # woken, not after the minute
    assert stop.wait(60.0) is True  # stays set


@pytest.mark.usefixtures("qt_settings")
@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGINT, signal.SIGHUP])
def test_the_tuner_closes_on_a_signal_after_the_handler_all_off(qtbot, signum):
    from tactile_tuner.main import close_on_signals
    from tactile_tuner.window import MainWindow

    saved = {s: signal.getsignal(s) for s in (signal.SIGTERM, signal.SIGINT, signal.SIGHUP)}
    win = MainWindow(restore=False, process=False)
    qtbot.addWidget(win)
    win.show()
    qtbot.waitExposed(win)
    try:
        win.state.update(mu=1.0, pause_s=0.0)
        qtbot.waitUntil(lambda: win.device.sent_levels().any(), timeout=5000)
        close_on_signals(win)
        signal.raise_signal(signum)  # the handler runs at once, in this thread
        assert win.isVisible()  # it only posted the close: it took no lock
        qtbot.waitUntil(lambda: not win.isVisible(), timeout=5000)
        assert not win.device.streamer.running
        assert not win.device.sent_levels().any()  # all off on the way out
    finally:
        for s, handler in saved.items():
            signal.signal(s, handler)


@pytest.mark.parametrize("terminal", [True, False], ids=["terminal", "pipe"])
def test_ctrl_c_at_a_key_prompt_stops_tune_correction_at_once(tmp_path, terminal):
    # The handler only sets the stop request; a read of standard input went on waiting through
    # it, so Ctrl-C at "Press a key" did nothing until a key came.
    import os

    if terminal:
        controller, stdin = os.openpty()
    else:
        stdin, controller = os.pipe()  # kept open and silent: no key ever comes
    proc = subprocess.Popen(
        [sys.executable, "-m", "tactile_core.cli", "tune-correction", "--device", "sim",
         "--participant", "P1", "--results", str(tmp_path), "--interval-ms", "100"],
        stdin=stdin, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
    )  # fmt: skip
    os.close(stdin)
    try:
        import select

        seen, deadline = b"", time.monotonic() + 60
        while b"(Enter or Space)" not in seen:  # the first question is asked (no newline)
            assert time.monotonic() < deadline and proc.poll() is None, seen
            if select.select([proc.stderr], [], [], 0.1)[0]:
                seen += os.read(proc.stderr.fileno(), 4096)
        proc.send_signal(signal.SIGINT)
        _, err = proc.communicate(timeout=30)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()
        os.close(controller)
    err = (seen + err).decode()
    assert proc.returncode == 1, err  # stopped before the end, as 'q' does
    assert "stopped at 0 of" in err and "stopped: all off" in err
    assert "Traceback" not in err
