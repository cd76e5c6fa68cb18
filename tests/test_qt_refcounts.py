"""Guard for the PySide6 pin: painting must not leak references to None, True or False.

PySide6 6.12.0 drops a reference to None on every ``QPainter.setRenderHint`` and to True on
every pyqtgraph repaint. On Python < 3.12, where these objects are not immortal, the count
eventually reaches zero and the interpreter aborts ("Fatal Python error: none_dealloc").

The counts are taken in a fresh interpreter: in a test worker, garbage and threads left by
earlier tests change them too (a drift of -350 in 200 repaints beside a CPU hog, none of it
from painting).
"""

import json
import os
import subprocess
import sys

import pytest

pytestmark = pytest.mark.skipif(
    sys.version_info >= (3, 12), reason="None/True/False are immortal from Python 3.12"
)

COUNT = """
import gc, json, sys
import numpy as np
import pyqtgraph as pg
from PySide6 import QtGui, QtWidgets

app = QtWidgets.QApplication([])

def counts():
    return [sys.getrefcount(None), sys.getrefcount(True), sys.getrefcount(False)]

def drift(step, n):
    gc.collect()
    gc.disable()
    before = counts()
    for _ in range(n):
        step()
    after = counts()
    gc.enable()
    return [a - b for a, b in zip(after, before)]

image = QtGui.QImage(8, 8, QtGui.QImage.Format.Format_ARGB32)
painter = QtGui.QPainter(image)
hint = drift(lambda: painter.setRenderHint(QtGui.QPainter.RenderHint.Antialiasing, True), 2000)
painter.end()

widget = pg.PlotWidget()
widget.plot(np.linspace(0, 1, 50), np.linspace(0, 1, 50))
widget.show()
widget.grab()
repaint = drift(widget.grab, 200)
print(json.dumps({"hint": hint, "repaint": repaint}))
"""


@pytest.fixture(scope="module")
def drifts():
    env = dict(os.environ, QT_QPA_PLATFORM="offscreen")
    done = subprocess.run(
        [sys.executable, "-c", COUNT], capture_output=True, text=True, timeout=120, env=env
    )
    assert done.returncode == 0, done.stderr[-2000:]
    return json.loads(done.stdout.strip().splitlines()[-1])


def test_set_render_hint_keeps_none_alive(drifts):
    # The bug loses one reference per call: -2000 in 2000 calls.
    assert max(map(abs, drifts["hint"])) < 100, f"drifted by {drifts['hint']} in 2000 calls"


def test_plot_repaints_keep_true_alive(drifts):
    # The bug loses at least one reference to True per repaint: -200 or more in 200.
    assert max(map(abs, drifts["repaint"])) < 50, f"drifted by {drifts['repaint']} in 200 repaints"
