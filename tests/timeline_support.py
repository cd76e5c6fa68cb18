"""The pattern editor in the tuner's window, for tests/test_timeline_*.py: the window of
tuner_support (1280 x 720, its stream a thread), the editor's dock shown, and the mouse on its
time line and on the heatmap."""

import numpy as np
from PySide6 import QtCore

from .tuner_support import WAIT_MS, settle

LEFT = QtCore.Qt.MouseButton.LeftButton


def editor_of(window):
    """The window's pattern editor, its dock shown (as File > Pattern editor shows it)."""
    from tactile_tuner.timeline import show_editor

    editor = window.timeline
    show_editor(editor)
    settle()
    return editor


def block_point(view, index, x_fraction=0.5) -> QtCore.QPoint:
    """The viewport's point at ``x_fraction`` of effect ``index``'s block, half-way down."""
    rect = view.block(index).rect()
    scene = QtCore.QPointF(rect.left() + rect.width() * x_fraction, rect.center().y())
    return view.mapFromScene(scene)


def drag(qtbot, widget, start: QtCore.QPoint, end: QtCore.QPoint, steps: int = 4) -> None:
    """Press at ``start``, move to ``end`` in ``steps``, release there (real mouse events)."""
    qtbot.mousePress(widget, LEFT, pos=start)
    for k in range(1, steps + 1):
        qtbot.mouseMove(widget, start + (end - start) * (k / steps))
    qtbot.mouseRelease(widget, LEFT, pos=end)


def click_tactor(qtbot, heatmap, x: float, y: float) -> None:
    """A real click on the heatmap at ``(x, y)`` in layout units."""
    scene = heatmap.plot.vb.mapViewToScene(QtCore.QPointF(x, y))
    point = heatmap.mapFromScene(scene)
    qtbot.mouseClick(heatmap.viewport(), LEFT, pos=point)


def shown_values(window):
    """A copy of what the heatmap shows now."""
    return np.array(window.tune.heatmap.values, copy=True)


def wait_shown(qtbot, window, expected, atol=1e-9) -> None:
    """Wait until the heatmap shows ``expected`` (to ``atol``)."""
    qtbot.waitUntil(
        lambda: np.allclose(window.tune.heatmap.values, expected, atol=atol), timeout=WAIT_MS
    )
