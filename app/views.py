"""Plot views: the live heatmap, the activation curves, the correction curve.

Each view builds its plot items once and updates them in place (``setImage``/``setData``) on
every refresh; images have fixed levels (0, 1) and row-major axis order, so nothing flickers or
re-estimates its range.
"""

from __future__ import annotations

import numpy as np
import pyqtgraph as pg
from PySide6 import QtCore, QtGui, QtWidgets

from tactile_core.correction import correct, quantize

pg.setConfigOptions(antialias=True, imageAxisOrder="row-major")

# Qualitative colours for the tactors of a trace, in order of activation.
PALETTE = [
    "#4e79a7", "#f28e2b", "#e15759", "#76b7b2", "#59a14f", "#edc948", "#b07aa1", "#ff9da7",
    "#9c755f", "#bab0ac", "#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b",
    "#e377c2", "#7f7f7f", "#bcbd22", "#17becf",
]  # fmt: skip


def cell_colors(cells) -> dict:
    """``{(col, row): colour}`` for tactors in order of activation."""
    return {cell: PALETTE[i % len(PALETTE)] for i, cell in enumerate(cells)}


class _DrawableImage(pg.ImageItem):
    """An image that reports drags in grid coordinates when drawing is enabled."""

    def __init__(self, view):
        super().__init__(axisOrder="row-major")
        self._view = view

    def mouseClickEvent(self, ev):
        if self._view.drawing and ev.button() == QtCore.Qt.MouseButton.LeftButton:
            pos = self.mapToParent(ev.pos())
            self._view.point_drawn.emit(pos.x(), pos.y())
            self._view.draw_released.emit()
            ev.accept()
        else:
            ev.ignore()

    def mouseDragEvent(self, ev):
        if not self._view.drawing or ev.button() != QtCore.Qt.MouseButton.LeftButton:
            ev.ignore()
            return
        ev.accept()
        pos = self.mapToParent(ev.pos())
        self._view.point_drawn.emit(pos.x(), pos.y())
        if ev.isFinish():
            self._view.draw_released.emit()


class HeatmapView(pg.GraphicsLayoutWidget):
    """The array as a live heatmap: one cell per tactor, row 0 at the bottom.

    Shows the shape's outline and the moving point over the cells, optionally each cell's
    value, and a coloured frame around every tactor the trace activates (the colours of the
    activation curves). In draw mode, dragging over it emits :attr:`point_drawn`.
    """

    point_drawn = QtCore.Signal(float, float)
    draw_released = QtCore.Signal()

    def __init__(
        self, cols: int = 5, rows: int = 6, *, title: str = "", colorbar: bool = True, parent=None
    ):
        super().__init__(parent=parent)
        self.setBackground("w")
        self.cols, self.rows = cols, rows
        self.drawing = False
        self.plot = self.addPlot(title=title or None)
        self.plot.setAspectLocked(True)
        self.plot.setMenuEnabled(False)
        self.plot.setMouseEnabled(False, False)
        self.plot.hideButtons()
        self.plot.setRange(xRange=(0, cols), yRange=(0, rows), padding=0.02)
        for name, n in (("bottom", cols), ("left", rows)):
            axis = self.plot.getAxis(name)
            axis.setTicks([[(i + 0.5, str(i)) for i in range(n)]])
        self.plot.setLabel("bottom", "column")
        self.plot.setLabel("left", "row")
        self.image = _DrawableImage(self)
        self.image.setImage(np.zeros((rows, cols)), levels=(0.0, 1.0))
        self.image.setRect(QtCore.QRectF(0, 0, cols, rows))
        self.plot.addItem(self.image)
        self.colorbar = None
        if colorbar:
            self.colorbar = pg.ColorBarItem(
                values=(0, 1), colorMap="viridis", interactive=False, label="intensity"
            )
            self.colorbar.setImageItem(self.image, insert_in=self.plot)
        else:
            self.image.setColorMap(pg.colormap.get("viridis"))
        grid_pen = pg.mkPen((255, 255, 255, 90), width=1)
        for c in range(1, cols):
            self.plot.addItem(pg.InfiniteLine(c, angle=90, pen=grid_pen))
        for r in range(1, rows):
            self.plot.addItem(pg.InfiniteLine(r, angle=0, pen=grid_pen))
        self._frames: dict = {}
        self.outline = pg.PlotDataItem(
            pen=pg.mkPen("w", width=2, style=QtCore.Qt.PenStyle.DashLine)
        )
        self.plot.addItem(self.outline)
        self.point = pg.ScatterPlotItem(
            size=14, brush=pg.mkBrush("#ff3030"), pen=pg.mkPen("w", width=2)
        )
        self.plot.addItem(self.point)
        self.texts = []
        for r in range(rows):
            for c in range(cols):
                item = pg.TextItem("", color="w", anchor=(0.5, 0.5))
                item.setPos(c + 0.5, r + 0.5)
                item.setVisible(False)
                self.plot.addItem(item)
                self.texts.append(item)
        self._text_values = [None] * (rows * cols)
        self._show_texts = False
        self.values = np.zeros((rows, cols))

    def set_frame(self, values, labels=None) -> None:
        """Show intensities ``(rows, cols)`` in [0, 1]; ``labels`` per cell when shown."""
        values = np.asarray(values, dtype=np.float64)
        self.values = values
        self.image.setImage(values, levels=(0.0, 1.0), autoLevels=False)
        if self._show_texts and labels is not None:
            flat = np.asarray(labels).reshape(-1)
            for i, text in enumerate(flat.tolist()):
                if text != self._text_values[i]:
                    self._text_values[i] = text
                    self.texts[i].setText(str(text))
                    v = values.reshape(-1)[i]
                    self.texts[i].setColor("k" if v > 0.6 else "w")

    def set_show_values(self, show: bool) -> None:
        """Show or hide the per-cell numbers."""
        self._show_texts = bool(show)
        for item in self.texts:
            item.setVisible(self._show_texts)
        self._text_values = [None] * len(self.texts)

    def set_outline(self, points) -> None:
        """Draw the shape's outline, ``(n, 2)`` points (None to hide)."""
        if points is None:
            self.outline.setData([], [])
        else:
            pts = np.asarray(points)
            self.outline.setData(pts[:, 0], pts[:, 1])

    def set_point(self, xy) -> None:
        """Draw the moving point at ``(x, y)`` (None to hide)."""
        if xy is None:
            self.point.setData([], [])
        else:
            self.point.setData([xy[0]], [xy[1]])

    def set_cell_frames(self, colors: dict) -> None:
        """Frame cells ``{(col, row): colour}`` (the activation curves' colours)."""
        for cell, item in list(self._frames.items()):
            if cell not in colors:
                self.plot.removeItem(item)
                del self._frames[cell]
        for cell, color in colors.items():
            item = self._frames.get(cell)
            if item is None:
                col, row = cell
                item = QtWidgets.QGraphicsRectItem(col + 0.06, row + 0.06, 0.88, 0.88)
                self.plot.addItem(item)
                self._frames[cell] = item
            pen = QtGui.QPen(QtGui.QColor(color))
            pen.setWidthF(3)
            pen.setCosmetic(True)
            item.setPen(pen)

    def set_drawing(self, enabled: bool) -> None:
        """Enable or disable draw mode (drag to move the point)."""
        self.drawing = bool(enabled)
        cursor = QtCore.Qt.CursorShape.CrossCursor if enabled else QtCore.Qt.CursorShape.ArrowCursor
        self.setCursor(cursor)


class CurvesView(pg.PlotWidget):
    """Activation curves: each activated tactor's intensity over one trace (Figures 3, 4).

    Corrected intensities are solid, raw ones dashed; a vertical cursor marks the current time
    and the pause after the trace is shaded. Each curve has the colour of its tactor's frame on
    the heatmap (a legend of up to 16 tactors would cover the curves).
    """

    def __init__(self, parent=None, *, title: str = "Activation curves"):
        super().__init__(parent=parent)
        self.setBackground("w")
        self.plotItem.setTitle(title)
        self.setLabel("bottom", "time", units="s")
        self.setLabel("left", "intensity")
        self.setYRange(0, 1.05, padding=0)
        self.setMouseEnabled(False, False)
        self.plotItem.setMenuEnabled(False)
        self.plotItem.hideButtons()
        self.cursor = pg.InfiniteLine(0, angle=90, pen=pg.mkPen("#d62728", width=2))
        self.addItem(self.cursor)
        self.pause = pg.LinearRegionItem((0, 0), movable=False, brush=pg.mkBrush(0, 0, 0, 25))
        self.pause.setZValue(-10)
        self.addItem(self.pause)
        self._lines: list = []
        self.curves = None

    def set_curves(self, curves, colors: dict, period_s: float, raw: bool = True) -> None:
        """Show ``curves`` (:class:`tactile_core.curves.ActivationCurves`).

        When the same tactors are active as before (a change of mu or gamma), the existing
        plot items get new data in place; otherwise they are rebuilt.
        """
        previous = self.curves
        same = (
            previous is not None
            and previous.cells == curves.cells
            and len(self._lines) == len(curves.cells) * (2 if raw else 1)
        )
        self.curves = curves
        if same:
            step = 2 if raw else 1
            # A change of mu or gamma leaves the raw curves as they were: skip them.
            raw_changed = raw and not (
                np.array_equal(previous.time_s, curves.time_s)
                and np.array_equal(previous.raw, curves.raw)
            )
            for i in range(len(curves.cells)):
                self._lines[i * step].setData(curves.time_s, curves.corrected[:, i])
                if raw_changed:
                    self._lines[i * step + 1].setData(curves.time_s, curves.raw[:, i])
        else:
            for item in self._lines:
                self.removeItem(item)
            self._lines = []
            for i, cell in enumerate(curves.cells):
                color = colors[cell]
                solid = self.plot(
                    curves.time_s, curves.corrected[:, i], pen=pg.mkPen(color, width=2)
                )
                self._lines.append(solid)
                if raw:
                    dashed = self.plot(
                        curves.time_s,
                        curves.raw[:, i],
                        pen=pg.mkPen(color, width=1, style=QtCore.Qt.PenStyle.DashLine),
                    )
                    self._lines.append(dashed)
            # Moving the cursor repaints the plot; cached curves are blitted, not redrawn.
            for item in self._lines:
                item.curve.setCacheMode(QtWidgets.QGraphicsItem.CacheMode.DeviceCoordinateCache)
        duration = float(curves.time_s[-1]) if len(curves.time_s) else 0.0
        self.pause.setRegion((duration, max(duration, period_s)))
        self.setXRange(0, max(period_s, 1e-3), padding=0.01)

    def set_cursor(self, time_s) -> None:
        """Move the cursor to ``time_s`` seconds into the period (None hides it)."""
        if time_s is None:
            self.cursor.setVisible(False)
        else:
            self.cursor.setVisible(True)
            self.cursor.setValue(time_s)


class CorrectionView(pg.PlotWidget):
    """Adjusted against raw intensity for the current mu and gamma, with the device's level
    steps (the paper's Figure 5) and, if the profile has one, the motor response."""

    def __init__(self, parent=None):
        super().__init__(parent=parent)
        self.setBackground("w")
        self.plotItem.setTitle("Threshold/gamma correction")
        self.setLabel("bottom", "raw intensity I")
        self.setLabel("left", "adjusted")
        self.setXRange(0, 1, padding=0.02)
        self.setYRange(0, 1, padding=0.02)
        self.setMouseEnabled(False, False)
        self.plotItem.setMenuEnabled(False)
        self.plotItem.hideButtons()
        self.addLegend(offset=(10, 10), labelTextSize="8pt")
        self.identity = self.plot(
            [0, 1], [0, 1], pen=pg.mkPen((150, 150, 150), style=QtCore.Qt.PenStyle.DotLine)
        )
        self.curve = self.plot(pen=pg.mkPen("#1f77b4", width=2), name="(1 - mu) I^gamma + mu")
        self.steps = self.plot(
            pen=pg.mkPen("#ff7f0e", width=1.5), name="device levels", stepMode="center"
        )
        self.felt = self.plot(
            pen=pg.mkPen("#2ca02c", width=1.5, style=QtCore.Qt.PenStyle.DashLine), name="felt"
        )
        self._x = np.linspace(0.0, 1.0, 501)

    def set_params(self, mu: float, gamma: float, levels: int = 23, response=None) -> None:
        """Redraw for ``mu``, ``gamma``, the device's ``levels`` and motor ``response``."""
        y = correct(self._x, mu, gamma)
        self.curve.setData(self._x, y)
        q = quantize(y, levels) / (levels - 1)
        change = np.flatnonzero(np.diff(q)) + 1
        xs = np.concatenate([[0.0], self._x[change], [1.0]])
        ys = np.concatenate([[q[0]], q[change]])
        self.steps.setData(xs, ys)
        if response is None:
            self.felt.setData([], [])
        else:
            self.felt.setData(self._x, np.interp(q, *response))
