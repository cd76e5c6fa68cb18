"""Guard for the PySide6 pin: painting must not leak references to None, True or False.

PySide6 6.12.0 drops a reference to None on every ``QPainter.setRenderHint`` and to True on
every pyqtgraph repaint. On Python < 3.12, where these objects are not immortal, the count
eventually reaches zero and the interpreter aborts ("Fatal Python error: none_dealloc").
"""

import sys

import numpy as np
import pytest
from PySide6 import QtGui

pytestmark = pytest.mark.skipif(
    sys.version_info >= (3, 12), reason="None/True/False are immortal from Python 3.12"
)


def counts():
    return np.array([sys.getrefcount(None), sys.getrefcount(True), sys.getrefcount(False)])


def test_set_render_hint_keeps_none_alive(qapp):
    image = QtGui.QImage(8, 8, QtGui.QImage.Format.Format_ARGB32)
    painter = QtGui.QPainter(image)
    try:
        before = counts()
        for _ in range(2000):
            painter.setRenderHint(QtGui.QPainter.RenderHint.Antialiasing, True)
        drift = counts() - before
    finally:
        painter.end()
    assert np.abs(drift).max() < 100, f"None/True/False refcounts drifted by {drift} in 2000 calls"


def test_plot_repaints_keep_true_alive(qtbot):
    import pyqtgraph as pg

    widget = pg.PlotWidget()
    qtbot.addWidget(widget)
    widget.plot(np.linspace(0, 1, 50), np.linspace(0, 1, 50))
    widget.show()
    before = counts()
    for _ in range(200):
        widget.grab()
    drift = counts() - before
    assert np.abs(drift).max() < 100, f"refcounts drifted by {drift} in 200 repaints"
