"""Waits on what the tuner's window does, for the tests of what it shows and does (the window
itself, 1280 x 720 with its stream a thread of this process, is the ``window`` fixture of
conftest.py)."""

#: pytest-qt's bound on a wait for the window (ms): generous, for a loaded machine.
WAIT_MS = 5000


def frames_shown(qtbot, window, n=3):
    """Wait until the tune tab's display timer has shown ``n`` more frames: what it shows then
    is what it shows from now on (an absence checked over display ticks, not over a time)."""
    for _ in range(n):
        with qtbot.waitSignal(window.tune.display.frame_shown, timeout=WAIT_MS):
            pass


def frames_sent(qtbot, sent, n):
    """Wait until ``n`` more frames have gone to the array (``sent``: from ``record_sent``)."""
    start = len(sent)
    qtbot.waitUntil(lambda: len(sent) >= start + n, timeout=WAIT_MS)


def settle():
    """Deliver what Qt has posted (layout requests, resizes, zero-time timers): the window's
    geometry is then the one its layouts give, with no time waited."""
    from PySide6 import QtWidgets

    for _ in range(2):  # what the first pass posts (a layout after a resize) goes in the second
        QtWidgets.QApplication.processEvents()
