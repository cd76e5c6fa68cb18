"""The live heatmap: one cell per tactor, the shape, the point, and what the trace lights."""

from __future__ import annotations

import numpy as np
import pyqtgraph as pg
from PySide6 import QtCore, QtGui, QtWidgets

from ..theme import plot_colors
from ._common import PaletteMixin, cell_label, style_plot


class _DrawableImage(pg.ImageItem):
    """The heatmap's image: clicks (draw mode, or a cell to pulse) and drags (draw mode)."""

    def __init__(self, view):
        super().__init__(axisOrder="row-major")
        self._view = view

    def mouseClickEvent(self, ev):
        if ev.button() != QtCore.Qt.MouseButton.LeftButton:
            ev.ignore()
            return
        pos = self.mapToParent(ev.pos())
        ev.accept()
        if self._view.drawing:
            self._view.point_drawn.emit(pos.x(), pos.y())
            self._view.draw_released.emit()
            return
        col, row = int(np.floor(pos.x())), int(np.floor(pos.y()))
        if 0 <= col < self._view.cols and 0 <= row < self._view.rows:
            shift = bool(ev.modifiers() & QtCore.Qt.KeyboardModifier.ShiftModifier)
            self._view.cell_clicked.emit(col, row, shift)

    def mouseDragEvent(self, ev):
        if not self._view.drawing or ev.button() != QtCore.Qt.MouseButton.LeftButton:
            ev.ignore()
            return
        ev.accept()
        pos = self.mapToParent(ev.pos())
        self._view.point_drawn.emit(pos.x(), pos.y())
        if ev.isFinish():
            self._view.draw_released.emit()


class HeatmapView(PaletteMixin, pg.GraphicsLayoutWidget):
    """The array as a live heatmap: one cell per tactor, row 0 at the bottom, in grid units.

    Shows the shape's outline and the moving point over the cells, optionally each cell's
    value, a coloured frame around every tactor the trace activates (the colours of the
    activation curves), the pointer's coordinates, and "not streaming" over the cells when the
    array is not being driven. Hovering a cell emits :attr:`cell_hovered`; clicking one emits
    :attr:`cell_clicked` (the window pulses that tactor); in draw mode, dragging emits
    :attr:`point_drawn`.
    """

    point_drawn = QtCore.Signal(float, float)
    draw_released = QtCore.Signal()
    cell_hovered = QtCore.Signal(object)
    """``(col, row)`` under the pointer, or None."""
    cell_clicked = QtCore.Signal(int, int, bool)
    """``col, row, shift``."""

    def __init__(
        self, cols: int = 5, rows: int = 6, *, title: str = "", colorbar: bool = True, parent=None
    ):
        super().__init__(parent=parent)
        self.cols, self.rows = cols, rows
        self.drawing = False
        self.readout = self.addLabel("", row=0, col=0, justify="left")
        self.plot = self.addPlot(row=1, col=0, title=title or None)
        self.plot.setAspectLocked(True)
        self.plot.setMenuEnabled(False)
        self.plot.setMouseEnabled(False, False)
        self.plot.hideButtons()
        self.plot.setRange(xRange=(0, cols), yRange=(0, rows), padding=0.0)
        for name, n in (("bottom", cols), ("left", rows)):
            axis = self.plot.getAxis(name)
            axis.setTicks([[(i, str(i)) for i in range(n + 1)], []])  # grid units: cell edges
        self.plot.setLabel("bottom", "x (grid units)")
        self.plot.setLabel("left", "y")
        self.image = _DrawableImage(self)
        self.image.setImage(np.zeros((rows, cols)), levels=(0.0, 1.0))
        self.image.setRect(QtCore.QRectF(0, 0, cols, rows))
        self.plot.addItem(self.image)
        self.colorbar = None
        if colorbar:
            self.colorbar = pg.ColorBarItem(
                values=(0, 1), colorMap="viridis", interactive=False, label="intensity", width=14
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
        self.path = pg.PlotDataItem(pen=pg.mkPen("#ff9800", width=2))  # the felt centroid
        self.plot.addItem(self.path)
        self.point = pg.ScatterPlotItem(
            [0.0], [0.0], size=14, brush=pg.mkBrush("#ff3030"), pen=pg.mkPen("w", width=2)
        )
        self.point.setVisible(False)
        self.point_xy = None
        """Where the moving point is drawn (grid units), or None while hidden."""
        self.plot.addItem(self.point)
        self.highlight_item = QtWidgets.QGraphicsRectItem(0, 0, 1, 1)
        self.highlight_item.setVisible(False)
        self.highlight_item.setZValue(20)
        self.plot.addItem(self.highlight_item)
        self.texts = []
        for r in range(rows):
            for c in range(cols):
                item = pg.TextItem("", color="w", anchor=(0.5, 0.5))
                item.setPos(c + 0.5, r + 0.5)
                item.setVisible(False)
                self.plot.addItem(item)
                self.texts.append(item)
        self.banner = pg.TextItem("", color="#ffffff", anchor=(0.5, 0.5), fill=(192, 57, 43, 220))
        self.banner.setPos(cols / 2, rows / 2)
        self.banner.setZValue(30)
        self.banner.setVisible(False)
        self.plot.addItem(self.banner)
        self._text_values = [None] * (rows * cols)
        self._show_texts = False
        self._hovered = None
        self.values = np.zeros((rows, cols))
        self.scene().sigMouseMoved.connect(self._on_mouse_moved)
        self.apply_palette()
        self._ready = True

    def apply_palette(self) -> None:
        """Take the background and text colours from the application palette."""
        colors = plot_colors(self.palette())
        self.setBackground(colors["background"])
        style_plot(self.plot, colors)
        if self.colorbar is not None:
            for name in ("left", "right"):
                axis = self.colorbar.getAxis(name)
                axis.setPen(pg.mkPen(colors["foreground"]))
                axis.setTextPen(pg.mkPen(colors["foreground"]))
        self.readout.setAttr("color", colors["foreground"].name())
        self.readout.setText(self.readout.text)
        pen = QtGui.QPen(colors["foreground"])
        pen.setWidthF(4)
        pen.setCosmetic(True)
        self.highlight_item.setPen(pen)

    def heightForWidth(self, width: int) -> int:  # Qt override
        return round(width * self.rows / (self.cols + 1.5))

    def preferred_width(self, height: int) -> int:
        """The width at which the cells fill ``height`` (axes and colour bar included)."""
        extra = 110 if self.colorbar is not None else 60
        return round((height - 70) * self.cols / self.rows) + extra

    def _on_mouse_moved(self, pos) -> None:
        vb = self.plot.vb
        if not vb.sceneBoundingRect().contains(pos):
            self._hover(None)
            return
        p = vb.mapSceneToView(pos)
        x, y = p.x(), p.y()
        col, row = int(np.floor(x)), int(np.floor(y))
        inside = 0 <= col < self.cols and 0 <= row < self.rows
        cell = (col, row) if inside else None
        value = f", {self.values[row, col]:.2f}" if inside else ""
        self.readout.setText(
            f"x {x:.2f}, y {y:.2f}" + (f"  tactor {cell_label(cell)}{value}" if inside else "")
        )
        self._hover(cell)

    def leaveEvent(self, event) -> None:  # Qt override
        self._hover(None)  # the mouse left: no highlight stays behind
        super().leaveEvent(event)

    def _hover(self, cell) -> None:
        if cell != self._hovered:
            self._hovered = cell
            self.highlight(cell)
            self.cell_hovered.emit(cell)
        if cell is None:
            self.readout.setText("")

    def highlight(self, cell) -> None:
        """Outline ``(col, row)`` (None: no outline), e.g. when its curve is hovered."""
        if cell is None:
            self.highlight_item.setVisible(False)
        else:
            self.highlight_item.setRect(cell[0], cell[1], 1.0, 1.0)
            self.highlight_item.setVisible(True)

    def set_streaming(self, streaming: bool, text: str = "not streaming") -> None:
        """Mark the heatmap when the array is not being driven."""
        self.banner.setText(f" {text} ")
        self.banner.setVisible(not streaming)

    def set_frame(self, values, labels=None) -> None:
        """Show intensities ``(rows, cols)`` in [0, 1]; ``labels`` per cell when shown."""
        values = np.asarray(values, dtype=np.float64)
        if values.shape != self.values.shape:
            self.values = values.copy()
            self.image.setImage(self.values, levels=(0.0, 1.0), autoLevels=False)
        elif not np.array_equal(values, self.values):  # unchanged (off, paused): no repaint
            np.copyto(self.values, values)
            self.image.setImage(self.values, levels=(0.0, 1.0), autoLevels=False)
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

    def set_path(self, points) -> None:
        """Draw a path, ``(n, 2)`` points, NaN rows as gaps (None to hide): the predicted
        felt centroid."""
        if points is None:
            self.path.setData([], [])
        else:
            pts = np.asarray(points, dtype=float)
            self.path.setData(pts[:, 0], pts[:, 1], connect="finite")

    def set_point(self, xy) -> None:
        """Draw the moving point at ``(x, y)`` (None to hide).

        The point is one spot at the item's origin, moved by its position: a frame changes a
        transform, not the scatter's data.
        """
        xy = None if xy is None else (float(xy[0]), float(xy[1]))
        if xy == self.point_xy:
            return
        self.point_xy = xy
        if xy is None:
            self.point.setVisible(False)
        else:
            self.point.setPos(*xy)
            self.point.setVisible(True)

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
            item.setToolTip(cell_label(cell))

    def set_drawing(self, enabled: bool) -> None:
        """Enable or disable draw mode (drag to move the point)."""
        self.drawing = bool(enabled)
        cursor = QtCore.Qt.CursorShape.CrossCursor if enabled else QtCore.Qt.CursorShape.ArrowCursor
        self.setCursor(cursor)
