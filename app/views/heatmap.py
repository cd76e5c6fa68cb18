"""The live heatmap: the array as the device profile lays it out, the shape, the point, and what
the trace lights.

A grid is drawn as one image cell per tactor (:mod:`._cells`); actuators anywhere as discs at
their positions (:mod:`._discs`). This module holds what both share: the plot, the shape's
outline, the moving point, the readout, the banner, clicks and drags.
"""

from __future__ import annotations

import numpy as np
import pyqtgraph as pg
from PySide6 import QtCore, QtGui

from tactile_core.rendering.geometry import Grid
from tactile_core.rendering.layout import Layout

from ..theme import plot_colors
from ._cells import GridCells
from ._common import PaletteMixin, style_plot
from ._discs import Discs

_GAP = np.array([np.nan])
"""Between two outlines: no line joins them."""


class _Pad(pg.GraphicsObject):
    """An invisible item over the array that takes clicks (a tactor to pulse, or a point in
    draw mode) and drags (draw mode)."""

    def __init__(self, view):
        super().__init__()
        self._view = view
        self._rect = QtCore.QRectF()
        self.setZValue(25)

    def set_rect(self, rect: QtCore.QRectF) -> None:
        self.prepareGeometryChange()
        self._rect = QtCore.QRectF(rect)

    def boundingRect(self) -> QtCore.QRectF:  # Qt override
        return self._rect

    def paint(self, *args) -> None:  # Qt override: nothing to draw
        pass

    def mouseClickEvent(self, ev):
        if ev.button() != QtCore.Qt.MouseButton.LeftButton:
            ev.ignore()
            return
        pos = self.mapToParent(ev.pos())
        ev.accept()
        shift = bool(ev.modifiers() & QtCore.Qt.KeyboardModifier.ShiftModifier)
        self._view._clicked(pos.x(), pos.y(), shift)

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
    """The array as a live heatmap, in layout units (pitches; grid units on a grid).

    On a grid, one cell per tactor, row 0 at the bottom; on any other layout, a disc per
    actuator at its position, named, a wrap unrolled into one turn with its seam marked
    (:meth:`set_layout` switches between them). Shows the shape's outline and the moving point
    over them, optionally each tactor's value, a coloured frame around every tactor the trace
    activates (the colours of the activation curves), the pointer's coordinates, and "not
    streaming" over the array when it is not being driven. Hovering a tactor emits
    :attr:`cell_hovered`; clicking one emits :attr:`cell_clicked` on a grid and
    :attr:`actuator_clicked` on a layout (the window pulses that tactor); in draw mode,
    dragging emits :attr:`point_drawn`.

    Parameters
    ----------
    cols, rows : int
        The grid drawn when no ``layout`` is given.
    layout : Layout, optional
        The layout to draw (a grid's layout draws that grid).
    """

    point_drawn = QtCore.Signal(float, float)
    draw_released = QtCore.Signal()
    cell_hovered = QtCore.Signal(object)
    """``(col, row)`` (an actuator's index on a layout) under the pointer, or None."""
    cell_clicked = QtCore.Signal(int, int, bool)
    """``col, row, shift`` (grids)."""
    actuator_clicked = QtCore.Signal(int, bool)
    """``index, shift`` (layouts that are not grids)."""

    def __init__(self, cols: int = 5, rows: int = 6, *, title: str = "", colorbar: bool = True,
                 layout: Layout | None = None, parent=None):  # fmt: skip
        super().__init__(parent=parent)
        self.drawing = False
        self.readout = self.addLabel("", row=0, col=0, justify="left")
        self.plot = self.addPlot(row=1, col=0, title=title or None)
        # Below the plot, in the room a layout's strip does not need (see _fit_height): what
        # the profile says of its layout (which way x runs, where the seam is). In the view's
        # layout only while it has words: a grid fills the view as it always has.
        self.caption = pg.LabelItem("", justify="left")
        self._tallest = self.plot.maximumHeight()
        self.plot.setAspectLocked(True)
        self.plot.setMenuEnabled(False)
        self.plot.setMouseEnabled(False, False)
        self.plot.hideButtons()
        self.plot.setLabel("left", "y")
        # The grid's edges are labelled too: pyqtgraph hides a horizontal axis's labels that
        # stick out of it, and 0 and 5 of the palm array sit on its ends, half out.
        self.plot.getAxis("bottom").setStyle(hideOverlappingLabels=False)
        self.image = pg.ImageItem(axisOrder="row-major")
        self.image.setImage(np.zeros((rows, cols)), levels=(0.0, 1.0))
        self.plot.addItem(self.image)
        self.colorbar = None
        if colorbar:
            self.colorbar = pg.ColorBarItem(
                values=(0, 1), colorMap="viridis", interactive=False, label="intensity", width=14
            )
            self.colorbar.setImageItem(self.image, insert_in=self.plot)
        else:
            self.image.setColorMap(pg.colormap.get("viridis"))
        self.pad = _Pad(self)
        self.plot.addItem(self.pad)
        self.outline = pg.PlotDataItem(
            pen=pg.mkPen("w", width=2, style=QtCore.Qt.PenStyle.DashLine)
        )
        self.outline.setZValue(10)
        self.plot.addItem(self.outline)
        self.path = pg.PlotDataItem(pen=pg.mkPen("#ff9800", width=2))  # the felt centroid
        self.path.setZValue(10)
        self.plot.addItem(self.path)
        self.point = pg.ScatterPlotItem(
            [0.0], [0.0], size=14, brush=pg.mkBrush("#ff3030"), pen=pg.mkPen("w", width=2)
        )
        self.point.setVisible(False)
        self.point.setZValue(12)
        self.point_xy = None
        """Where the moving point is drawn (layout units), or None while hidden."""
        self.plot.addItem(self.point)
        self.banner = pg.TextItem("", color="#ffffff", anchor=(0.5, 0.5), fill=(192, 57, 43, 220))
        self.banner.setZValue(30)
        self.banner.setVisible(False)
        self.plot.addItem(self.banner)
        self._show_texts = False
        self._hovered = None
        self.layout = None
        self.cells = None
        self.set_layout(layout if layout is not None else Grid(cols, rows))
        self.scene().sigMouseMoved.connect(self._on_mouse_moved)
        self.plot.vb.sigResized.connect(self._on_plot_resized)
        self.apply_palette()
        self._ready = True

    # --- the layout ----------------------------------------------------------------------------

    def set_layout(self, layout: Layout) -> None:
        """Draw ``layout``: a grid as cells, any other layout as discs (built once per layout;
        nothing happens for the layout already drawn)."""
        if layout == self.layout:
            return
        self.layout = layout
        if self.cells is not None:
            self.cells.remove()
        self._hovered = None
        self.cells = GridCells(self, layout) if layout.is_grid else Discs(self, layout)
        x0, x1, y0, y1 = self.cells.range
        self.plot.setRange(xRange=(x0, x1), yRange=(y0, y1), padding=0.0)
        bottom, left = self.cells.ticks()
        self.plot.getAxis("bottom").setTicks([bottom, []])
        self.plot.getAxis("left").setTicks([left, []])
        self.plot.setLabel("bottom", self.cells.axis_label)
        self.pad.set_rect(self.cells.pad_rect)
        self.banner.setPos((x0 + x1) / 2, (y0 + y1) / 2)
        self.cells.show_texts(self._show_texts)
        self.point_xy = None
        self.point.setVisible(False)
        self.outline.setData([], [])
        self.path.setData([], [])
        if self._ready:
            self.apply_palette()
            self._fit_height()
        self.updateGeometry()

    @property
    def cols(self) -> int:
        """Columns of the grid drawn (on a layout: its actuators, as one row)."""
        return self.layout.wire_shape[0]

    @property
    def rows(self) -> int:
        """Rows of the grid drawn (1 on a layout)."""
        return self.layout.wire_shape[1]

    @property
    def values(self) -> np.ndarray:
        """The values shown: ``(rows, cols)`` on a grid, ``(size,)`` on a layout."""
        return self.cells.values

    @property
    def highlight_item(self):
        """The outline of the hovered tactor (a rectangle on a grid, a ring on a layout)."""
        return self.cells.highlight_item

    @property
    def _frames(self) -> dict:
        return self.cells.frames

    def centre(self) -> tuple[float, float]:
        """The middle of the array, in layout units (where draw mode starts)."""
        x0, x1, y0, y1 = self.cells.range
        return self.cells.clamp((x0 + x1) / 2, (y0 + y1) / 2)

    def clamp(self, x: float, y: float) -> tuple[float, float]:
        """A drawn point kept on the array (round a wrap: within one turn)."""
        return self.cells.clamp(float(x), float(y))

    # --- palette and size ------------------------------------------------------------------------

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
        for label in (self.readout, self.caption):
            label.setAttr("color", colors["foreground"].name())
            label.setText(label.text)
        self._wrap_caption()
        outline = colors["foreground"] if not self.layout.is_grid else QtGui.QColor("white")
        self.outline.setPen(pg.mkPen(outline, width=2, style=QtCore.Qt.PenStyle.DashLine))
        self.cells.set_palette(colors)

    def _on_plot_resized(self, _vb=None) -> None:
        self._fit_height()
        self.cells.fit_labels()

    def _fit_height(self) -> None:
        """On a layout, the plot no taller than the strip it shows at its width (a belt is a
        row of actuators: the rest of the height goes below it, not into empty plot); a grid
        fills the view as it always has."""
        vb = self.plot.vb
        self._wrap_caption()
        if self.layout.is_grid or vb.width() <= 0:
            self.plot.setMaximumHeight(self._tallest)
            return
        w, h = self.extent()
        extra = self.plot.height() - vb.height()
        self.plot.setMaximumHeight(max(vb.width() * h / w + extra, 160.0))

    def set_caption(self, text: str) -> None:
        """Words under the array (wrapped to its width): the profile's description of a
        layout; "" for none."""
        shown = self.caption in self.ci.items
        if text and not shown:
            self.ci.addItem(self.caption, row=2, col=0)
        elif not text and shown:
            self.ci.removeItem(self.caption)
        self.caption.setText(text)
        self._wrap_caption()

    def _wrap_caption(self) -> None:
        self.caption.item.setTextWidth(max(self.plot.width() - 30, 120.0))
        self.caption.updateMin()
        self.caption.setMinimumWidth(0)  # the caption follows the plot's width, never sets it

    def extent(self) -> tuple[float, float]:
        """Width and height of the view, in layout units."""
        x0, x1, y0, y1 = self.cells.range
        return x1 - x0, y1 - y0

    def heightForWidth(self, width: int) -> int:  # Qt override
        w, h = self.extent()
        return round(width * h / (w + 1.5))

    def preferred_width(self, height: int) -> int:
        """The width at which the array fills ``height`` (axes and colour bar included)."""
        w, h = self.extent()
        extra = 110 if self.colorbar is not None else 60
        return round((height - 70) * w / h) + extra

    def _margins(self) -> tuple[int, int]:
        """Pixels around the array: axes and colour bar across; axis, title and the caption
        under a layout down."""
        caption = self.caption.boundingRect().height() if self.caption in self.ci.items else 0
        return (110 if self.colorbar is not None else 60), 70 + round(caption)

    def preferred_height(self, width: int) -> int:
        """The height at which the array fills ``width``: :meth:`preferred_width` the other
        way round (the caption under a layout included)."""
        w, h = self.extent()
        across, down = self._margins()
        return round((width - across) * h / w) + down

    def scale_in(self, width: int, height: int) -> float:
        """Pixels per layout unit the array gets in a view of ``width`` x ``height``."""
        w, h = self.extent()
        across, down = self._margins()
        return min((width - across) / w, (height - down) / h)

    # --- the pointer -----------------------------------------------------------------------------

    def _on_mouse_moved(self, pos) -> None:
        vb = self.plot.vb
        if not vb.sceneBoundingRect().contains(pos):
            self._hover(None)
            return
        p = vb.mapSceneToView(pos)
        key = self.cells.key_at(p.x(), p.y())
        x, y = self.cells.canonical(p.x(), p.y())
        where = f"  {self.cells.describe(key)}" if key is not None else ""
        self.readout.setText(f"x {x:.2f}, y {y:.2f}{where}")
        self._hover(key)

    def _clicked(self, x: float, y: float, shift: bool) -> None:
        if self.drawing:
            self.point_drawn.emit(x, y)
            self.draw_released.emit()
            return
        key = self.cells.key_at(x, y)
        if key is None:
            return
        if self.layout.is_grid:
            self.cell_clicked.emit(key[0], key[1], shift)
        else:
            self.actuator_clicked.emit(key, shift)

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
        """Outline a tactor (``(col, row)``, an index on a layout; None: none), e.g. when its
        curve is hovered."""
        self.cells.highlight(cell)

    # --- what is shown ---------------------------------------------------------------------------

    def set_streaming(self, streaming: bool, text: str = "not streaming") -> None:
        """Mark the heatmap when the array is not being driven."""
        self.banner.setText(f" {text} ")
        self.banner.setVisible(not streaming)

    def set_frame(self, values, labels=None) -> None:
        """Show intensities in [0, 1], ``(rows, cols)`` on a grid and ``(size,)`` on a layout;
        ``labels`` per tactor when values are shown. Nothing is repainted when they did not
        change."""
        self.cells.set_values(values)
        if self._show_texts and labels is not None:
            self.cells.set_texts(labels)

    def set_show_values(self, show: bool) -> None:
        """Show or hide the per-tactor numbers."""
        self._show_texts = bool(show)
        self.cells.show_texts(self._show_texts)

    def set_outline(self, points) -> None:
        """Draw the shape's outline, ``(n, 2)`` points, or a list of outlines (a pattern's
        paths; an empty list for a pattern of dots alone), None to hide; round a wrap,
        unrolled with a gap at the seam."""
        parts = [] if points is None else points if isinstance(points, list) else [points]
        if not parts:  # no shape, or a pattern of dots alone: nothing left of the last shape
            self.outline.setData([], [])
            return
        xs, ys = [], []
        for part in parts:
            x, y = self.cells.path(part)
            xs += [x, _GAP]
            ys += [y, _GAP]
        self.outline.setData(np.concatenate(xs[:-1]), np.concatenate(ys[:-1]), connect="finite")

    def set_path(self, points) -> None:
        """Draw a path, ``(n, 2)`` points, NaN rows as gaps (None to hide): the predicted
        felt centroid."""
        if points is None:
            self.path.setData([], [])
        else:
            pts = np.asarray(points, dtype=float)
            self.path.setData(pts[:, 0], pts[:, 1], connect="finite")

    def set_point(self, xy) -> None:
        """Draw the moving point at ``(x, y)`` (None to hide); round a wrap, within one turn.

        The point is one spot at the item's origin, moved by its position: a frame changes a
        transform, not the scatter's data.
        """
        if xy is not None:
            xy = self.cells.canonical(float(xy[0]), float(xy[1]))
        if xy == self.point_xy:
            return
        self.point_xy = xy
        if xy is None:
            self.point.setVisible(False)
        else:
            self.point.setPos(*xy)
            self.point.setVisible(True)

    def set_cell_frames(self, colors: dict) -> None:
        """Frame tactors ``{(col, row) or index: colour}`` (the activation curves' colours)."""
        self.cells.set_frames(colors)

    def set_drawing(self, enabled: bool) -> None:
        """Enable or disable draw mode (drag to move the point)."""
        self.drawing = bool(enabled)
        cursor = QtCore.Qt.CursorShape.CrossCursor if enabled else QtCore.Qt.CursorShape.ArrowCursor
        self.setCursor(cursor)
