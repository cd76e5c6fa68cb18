"""The heatmap's picture of a grid: one image cell per tactor, the cell lines, the numbers and
the frames of the tactors a trace lights (as the tuner has always drawn the palm array)."""

from __future__ import annotations

import numpy as np
import pyqtgraph as pg
from PySide6 import QtCore, QtGui, QtWidgets

from ._common import cell_label


class GridCells:
    """The items that draw a grid on a :class:`~.heatmap.HeatmapView`, built once per grid.

    The view's image item shows the values (fixed levels (0, 1), row-major); keys are
    ``(col, row)``. :meth:`remove` takes every item of this grid off the plot.
    """

    axis_label = "x (grid units)"

    def __init__(self, view, grid):
        self.grid = grid
        self.plot = view.plot
        self.image = view.image
        cols, rows = grid.cols, grid.rows
        self.range = (0.0, float(cols), 0.0, float(rows))
        self.pad_rect = QtCore.QRectF(0, 0, cols, rows)
        self.values = np.zeros((rows, cols))
        self.image.setImage(self.values, levels=(0.0, 1.0), autoLevels=False)
        self.image.setRect(QtCore.QRectF(0, 0, cols, rows))
        self.image.setVisible(True)
        self._items = []
        grid_pen = pg.mkPen((255, 255, 255, 90), width=1)
        for c in range(1, cols):
            self._add(pg.InfiniteLine(c, angle=90, pen=grid_pen))
        for r in range(1, rows):
            self._add(pg.InfiniteLine(r, angle=0, pen=grid_pen))
        self.highlight_item = QtWidgets.QGraphicsRectItem(0, 0, 1, 1)
        self.highlight_item.setVisible(False)
        self.highlight_item.setZValue(20)
        self._add(self.highlight_item)
        self.texts = []
        for r in range(rows):
            for c in range(cols):
                item = pg.TextItem("", color="w", anchor=(0.5, 0.5))
                item.setPos(c + 0.5, r + 0.5)
                item.setVisible(False)
                self._add(item)
                self.texts.append(item)
        self._text_values = [None] * (rows * cols)
        self.frames: dict = {}

    def _add(self, item) -> None:
        self.plot.addItem(item)
        self._items.append(item)

    def ticks(self) -> tuple[list, list]:
        """Ticks of the x and y axes: the cells' edges."""
        return ([(i, str(i)) for i in range(self.grid.cols + 1)],
                [(i, str(i)) for i in range(self.grid.rows + 1)])  # fmt: skip

    def remove(self) -> None:
        """Take this grid's items off the plot."""
        for item in [*self._items, *self.frames.values()]:
            self.plot.removeItem(item)
        self._items, self.frames = [], {}

    def set_palette(self, colors) -> None:
        """The highlight in the palette's foreground colour."""
        pen = QtGui.QPen(colors["foreground"])
        pen.setWidthF(4)
        pen.setCosmetic(True)
        self.highlight_item.setPen(pen)

    def key_at(self, x: float, y: float):
        """``(col, row)`` of the cell at ``(x, y)``, or None outside the grid."""
        col, row = int(np.floor(x)), int(np.floor(y))
        return (col, row) if 0 <= col < self.grid.cols and 0 <= row < self.grid.rows else None

    def describe(self, key) -> str:
        """The readout's words for a cell: ``tactor (1,3), 0.42``."""
        return f"tactor {cell_label(key)}, {self.values[key[1], key[0]]:.2f}"

    def clamp(self, x: float, y: float) -> tuple[float, float]:
        """A drawn point kept on the grid."""
        return min(max(x, 0.0), float(self.grid.cols)), min(max(y, 0.0), float(self.grid.rows))

    def canonical(self, x: float, y: float) -> tuple[float, float]:
        """Where a point is drawn (a grid does not wrap)."""
        return x, y

    def path(self, points) -> tuple[np.ndarray, np.ndarray]:
        """A path's x and y as drawn."""
        pts = np.asarray(points, dtype=float)
        return pts[:, 0], pts[:, 1]

    def set_values(self, values) -> None:
        """Show intensities ``(rows, cols)``; repainted only when they change."""
        values = np.asarray(values, dtype=np.float64)
        if values.shape != self.values.shape:
            self.values = values.copy()
            self.image.setImage(self.values, levels=(0.0, 1.0), autoLevels=False)
        elif not np.array_equal(values, self.values):  # unchanged (off, paused): no repaint
            np.copyto(self.values, values)
            self.image.setImage(self.values, levels=(0.0, 1.0), autoLevels=False)

    def set_texts(self, labels) -> None:
        """Write ``labels`` (one per cell) in the cells, changed ones only."""
        flat = np.asarray(labels).reshape(-1)
        values = self.values.reshape(-1)
        for i, text in enumerate(flat.tolist()):
            if text != self._text_values[i]:
                self._text_values[i] = text
                self.texts[i].setText(str(text))
                self.texts[i].setColor("k" if values[i] > 0.6 else "w")

    def show_texts(self, show: bool) -> None:
        """Show or hide the numbers in the cells."""
        for item in self.texts:
            item.setVisible(show)
        self._text_values = [None] * len(self.texts)

    def highlight(self, key) -> None:
        """Outline a cell (None: none)."""
        if key is None:
            self.highlight_item.setVisible(False)
        else:
            self.highlight_item.setRect(key[0], key[1], 1.0, 1.0)
            self.highlight_item.setVisible(True)

    def set_frames(self, colors: dict) -> None:
        """Frame cells ``{(col, row): colour}`` (the activation curves' colours)."""
        for cell, item in list(self.frames.items()):
            if cell not in colors:
                self.plot.removeItem(item)
                del self.frames[cell]
        for cell, color in colors.items():
            item = self.frames.get(cell)
            if item is None:
                col, row = cell
                item = QtWidgets.QGraphicsRectItem(col + 0.06, row + 0.06, 0.88, 0.88)
                self.plot.addItem(item)
                self.frames[cell] = item
            pen = QtGui.QPen(QtGui.QColor(color))
            pen.setWidthF(3)
            pen.setCosmetic(True)
            item.setPen(pen)
            item.setToolTip(cell_label(cell))

    def fit_labels(self) -> None:
        """Nothing to fit: a grid's cells have no names drawn."""
