"""Plot views: the live heatmap, the activation curves, the correction curve.

Each view builds its plot items once and updates them in place (``setImage``/``setData``) on
every refresh; images have fixed levels (0, 1) and row-major axis order, so nothing flickers or
re-estimates its range. Colours follow the application palette (light or dark, see
:mod:`tactile_tuner.theme`), and each activated tactor has one of 30 distinct colours, the same
on the heatmap's cell frame and on its activation curve.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np
import pyqtgraph as pg
from PySide6 import QtCore, QtGui, QtWidgets

from tactile_core.rendering.correction import correct, quantize

from .theme import TACTOR_COLORS, plot_colors

pg.setConfigOptions(antialias=True, imageAxisOrder="row-major")

PALETTE = TACTOR_COLORS


def cell_colors(cells) -> dict:
    """``{(col, row): colour}`` for tactors in order of activation (30 distinct colours)."""
    return {cell: PALETTE[i % len(PALETTE)] for i, cell in enumerate(cells)}


def cell_label(cell) -> str:
    """``"(col,row)"``: how a tactor is named on the axes and in tooltips."""
    return f"({cell[0]},{cell[1]})"


def _style_plot(plot: pg.PlotItem, colors: dict) -> None:
    fg = colors["foreground"]
    for name in ("left", "bottom", "right", "top"):
        axis = plot.getAxis(name)
        axis.setPen(pg.mkPen(fg))
        axis.setTextPen(pg.mkPen(fg))
    plot.titleLabel.setAttr("color", fg.name())
    plot.titleLabel.setText(plot.titleLabel.text)


class ElidedLabel(QtWidgets.QLabel):
    """A one-line label that shortens its text with an ellipsis instead of widening its panel.

    The full text stays available as the tooltip.
    """

    def __init__(self, text: str, parent=None):
        super().__init__(text, parent)
        self.setToolTip(text)
        self.setSizePolicy(
            QtWidgets.QSizePolicy.Policy.Ignored, QtWidgets.QSizePolicy.Policy.Preferred
        )

    def minimumSizeHint(self) -> QtCore.QSize:  # Qt override
        return QtCore.QSize(0, super().minimumSizeHint().height())

    def paintEvent(self, event) -> None:  # Qt override
        painter = QtGui.QPainter(self)
        text = self.fontMetrics().elidedText(
            self.text(), QtCore.Qt.TextElideMode.ElideRight, self.contentsRect().width()
        )
        painter.drawText(self.contentsRect(), int(self.alignment()), text)


class _PaletteMixin:
    """Restyle when the application palette changes (light <-> dark)."""

    _ready = False  # set once the view's items exist

    def changeEvent(self, event):  # Qt override
        kinds = (QtCore.QEvent.Type.PaletteChange, QtCore.QEvent.Type.ApplicationPaletteChange)
        if self._ready and event.type() in kinds:
            self.apply_palette()
        super().changeEvent(event)


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


class HeatmapView(_PaletteMixin, pg.GraphicsLayoutWidget):
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
            size=14, brush=pg.mkBrush("#ff3030"), pen=pg.mkPen("w", width=2)
        )
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
        _style_plot(self.plot, colors)
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

    def set_path(self, points) -> None:
        """Draw a path, ``(n, 2)`` points, NaN rows as gaps (None to hide): the predicted
        felt centroid."""
        if points is None:
            self.path.setData([], [])
        else:
            pts = np.asarray(points, dtype=float)
            self.path.setData(pts[:, 0], pts[:, 1], connect="finite")

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
            item.setToolTip(cell_label(cell))

    def set_drawing(self, enabled: bool) -> None:
        """Enable or disable draw mode (drag to move the point)."""
        self.drawing = bool(enabled)
        cursor = QtCore.Qt.CursorShape.CrossCursor if enabled else QtCore.Qt.CursorShape.ArrowCursor
        self.setCursor(cursor)


class CurvesView(_PaletteMixin, pg.PlotWidget):
    """Activation curves: each activated tactor's intensity over one trace (Figures 3, 4).

    Two layouts: *overlaid* (every curve on one axis, as the paper's figures) and *lanes* (one
    row per tactor, labelled ``(col,row)``, so that bi-level methods' sequences, whose curves all
    sit at 1, can be read). Corrected intensities are solid, raw ones dashed; the pause after the
    trace is shaded. The time cursor is dashed, in the text colour (no curve's colour); dragging
    it scrubs the trace (:attr:`scrubbed`). Hovering a curve highlights it and emits
    :attr:`curve_hovered` with its tactor.
    """

    scrubbed = QtCore.Signal(float)
    """The cursor was dragged to this time (s)."""
    scrub_finished = QtCore.Signal()
    curve_hovered = QtCore.Signal(object)

    def __init__(self, parent=None, *, title: str = "Activation curves"):
        super().__init__(parent=parent)
        self.plotItem.setTitle(title)
        self.setLabel("bottom", "time", units="s")
        self.setLabel("left", "intensity")
        self.setMouseEnabled(False, False)
        self.plotItem.setMenuEnabled(False)
        self.plotItem.hideButtons()
        self.cursor = pg.InfiniteLine(0, angle=90, movable=True)
        self.cursor.setZValue(30)
        self.cursor.setToolTip("drag to scrub the trace (the array pauses)")
        self.cursor.sigDragged.connect(lambda line: self.scrubbed.emit(float(line.value())))
        self.cursor.sigPositionChangeFinished.connect(lambda _: self.scrub_finished.emit())
        self.addItem(self.cursor)
        self.pause = pg.LinearRegionItem((0, 0), movable=False)
        self.pause.setZValue(-10)
        self.addItem(self.pause)
        self._lines: list = []
        self._solid: dict = {}
        self.curves = None
        self.colors: dict = {}
        self.lanes = False
        self._raw = True
        self._period = 1.0
        self._hovered = None
        self.scene().sigMouseMoved.connect(self._on_mouse_moved)
        self.apply_palette()
        self._ready = True

    @property
    def dragging(self) -> bool:
        """True while the cursor is being dragged."""
        return self.cursor.moving

    def apply_palette(self) -> None:
        """Take the background and text colours from the application palette."""
        colors = plot_colors(self.palette())
        self.setBackground(colors["background"])
        _style_plot(self.plotItem, colors)
        self.cursor.setPen(pg.mkPen(colors["foreground"], width=2,
                                    style=QtCore.Qt.PenStyle.DashLine))  # fmt: skip
        self.cursor.setHoverPen(pg.mkPen(colors["foreground"], width=4))
        self.pause.setBrush(pg.mkBrush(colors["shade"]))

    def set_lanes(self, lanes: bool) -> None:
        """One row per tactor (True) or all curves overlaid (False)."""
        if bool(lanes) != self.lanes:
            self.lanes = bool(lanes)
            if self.curves is not None:
                self._build(self.curves, self.colors, self._period, self._raw)

    def set_curves(self, curves, colors: dict, period_s: float, raw: bool = True) -> None:
        """Show ``curves`` (:class:`tactile_core.rendering.curves.ActivationCurves`).

        When the same tactors are active as before (a change of mu or gamma), the existing
        plot items get new data in place; otherwise they are rebuilt.
        """
        previous = self.curves
        same = (
            previous is not None
            and previous.cells == curves.cells
            and raw == self._raw
            and len(self._lines) == len(curves.cells) * (2 if raw else 1)
        )
        if not same:
            self._build(curves, colors, period_s, raw)
            return
        self.curves, self.colors, self._period = curves, colors, period_s
        step = 2 if raw else 1
        raw_changed = raw and not (
            np.array_equal(previous.time_s, curves.time_s)
            and np.array_equal(previous.raw, curves.raw)
        )
        for i in range(len(curves.cells)):
            self._lines[i * step].setData(curves.time_s, self._y(curves.corrected[:, i], i))
            if raw_changed:
                self._lines[i * step + 1].setData(curves.time_s, self._y(curves.raw[:, i], i))
        self._frame(curves, period_s)

    def _y(self, values, index):
        """A curve's y: the intensity, or in lanes its lane's baseline plus 0.85 of it."""
        if not self.lanes:
            return values
        return (len(self.curves.cells) - 1 - index) + 0.85 * values

    def _build(self, curves, colors, period_s, raw) -> None:
        self.curves, self.colors, self._period, self._raw = curves, colors, period_s, raw
        for item in self._lines:
            self.removeItem(item)
        self._lines, self._solid = [], {}
        for i, cell in enumerate(curves.cells):
            color = colors[cell]
            solid = self.plot(curves.time_s, self._y(curves.corrected[:, i], i),
                              pen=pg.mkPen(color, width=2))  # fmt: skip
            solid.setToolTip(cell_label(cell))
            self._lines.append(solid)
            self._solid[cell] = solid
            if raw:
                dashed = self.plot(
                    curves.time_s,
                    self._y(curves.raw[:, i], i),
                    pen=pg.mkPen(color, width=1, style=QtCore.Qt.PenStyle.DashLine),
                )
                self._lines.append(dashed)
        # Moving the cursor repaints the plot; cached curves are blitted, not redrawn.
        for item in self._lines:
            item.curve.setCacheMode(QtWidgets.QGraphicsItem.CacheMode.DeviceCoordinateCache)
        self._frame(curves, period_s)

    def _frame(self, curves, period_s) -> None:
        n = len(curves.cells)
        left = self.getAxis("left")
        if self.lanes and n:
            self.setYRange(-0.1, n, padding=0)
            left.setTicks([[(n - 1 - i + 0.42, cell_label(c)) for i, c in enumerate(curves.cells)],
                           []])  # fmt: skip
            self.setLabel("left", "tactor (col,row)")
        else:
            self.setYRange(0, 1.05, padding=0)
            left.setTicks(None)
            self.setLabel("left", "intensity")
        duration = float(curves.time_s[-1]) if len(curves.time_s) else 0.0
        self.pause.setRegion((duration, max(duration, period_s)))
        self.setXRange(0, max(period_s, 1e-3), padding=0.01)

    def set_series(self, time_s, values, period_s: float, label: str) -> None:
        """Show one curve instead of the activation curves: the predicted felt intensity."""
        self.clear_curves()
        pen = pg.mkPen(self.palette().color(QtGui.QPalette.ColorRole.Text), width=2)
        line = self.plot(np.asarray(time_s), np.asarray(values), pen=pen)
        line.setToolTip(label)
        self._lines = [line]
        top = float(np.nanmax(values)) if len(values) else 1.0
        self.setYRange(0, max(1.05, 1.05 * top), padding=0)
        self.getAxis("left").setTicks(None)
        self.setLabel("left", label)
        duration = float(time_s[-1]) if len(time_s) else 0.0
        self.pause.setRegion((duration, max(duration, period_s)))
        self.setXRange(0, max(period_s, 1e-3), padding=0.01)

    def clear_curves(self) -> None:
        """No curves (draw mode: a free point has no trace)."""
        for item in self._lines:
            self.removeItem(item)
        self._lines, self._solid, self.curves = [], {}, None
        self.pause.setRegion((0, 0))
        self.cursor.setVisible(False)

    def set_cursor(self, time_s) -> None:
        """Move the cursor to ``time_s`` seconds into the period (None hides it)."""
        if self.cursor.moving:
            return  # the user is dragging it
        if time_s is None:
            self.cursor.setVisible(False)
        else:
            self.cursor.setVisible(True)
            self.cursor.setValue(time_s)

    def _on_mouse_moved(self, pos) -> None:
        if self.curves is None or not self.plotItem.vb.sceneBoundingRect().contains(pos):
            self._hover(None)
            return
        p = self.plotItem.vb.mapSceneToView(pos)
        t, y = p.x(), p.y()
        times = self.curves.time_s
        if len(times) == 0 or not times[0] <= t <= times[-1]:
            self._hover(None)
            return
        k = int(np.clip(np.searchsorted(times, t), 0, len(times) - 1))
        values = [self._y(self.curves.corrected[k, i], i) for i in range(len(self.curves.cells))]
        distances = np.abs(np.asarray(values) - y)
        i = int(np.argmin(distances))
        near = distances[i] < (0.35 if self.lanes else 0.06)
        self._hover(self.curves.cells[i] if near else None)

    def _hover(self, cell) -> None:
        if cell != self._hovered:
            self._hovered = cell
            self.highlight(cell)
            self.curve_hovered.emit(cell)

    def highlight(self, cell) -> None:
        """Draw ``cell``'s curve thick (None: none), e.g. when its cell is hovered."""
        for c, line in self._solid.items():
            line.setPen(pg.mkPen(self.colors[c], width=5 if c == cell else 2))


class CorrectionView(_PaletteMixin, pg.PlotWidget):
    """Adjusted against raw intensity for the current mu and gamma, with the device's level
    steps (the paper's Figure 5) and, if the profile has one, the motor response. The key is in
    the title, in the curves' colours, so it never covers them."""

    COLORS: ClassVar[dict] = {"curve": "#2478b4", "levels": "#de9c00", "felt": "#00c078"}

    def __init__(self, parent=None):
        super().__init__(parent=parent)
        self.setLabel("bottom", "raw intensity I")
        self.setLabel("left", "drive")
        self.setXRange(0, 1, padding=0.02)
        self.setYRange(0, 1, padding=0.02)
        self.setMouseEnabled(False, False)
        self.plotItem.setMenuEnabled(False)
        self.plotItem.hideButtons()
        self.identity = self.plot(
            [0, 1], [0, 1], pen=pg.mkPen((150, 150, 150), style=QtCore.Qt.PenStyle.DotLine)
        )
        self.curve = self.plot(pen=pg.mkPen(self.COLORS["curve"], width=2))
        self.steps = self.plot(pen=pg.mkPen(self.COLORS["levels"], width=1.5), stepMode="center")
        self.felt = self.plot(
            pen=pg.mkPen(self.COLORS["felt"], width=1.5, style=QtCore.Qt.PenStyle.DashLine)
        )
        self._x = np.linspace(0.0, 1.0, 501)
        self._has_felt = False
        self._felt_domain = False
        self._title()
        self.apply_palette()
        self._ready = True

    def _title(self) -> None:
        c = self.COLORS
        wanted = " (felt)" if getattr(self, "_felt_domain", False) else ""
        levels = "drive levels sent" if wanted else "device levels"
        parts = [
            f"<span style='color:{c['curve']}'>&#9473; (1-&mu;) I<sup>&gamma;</sup> + &mu;"
            f"{wanted}</span>",
            f"<span style='color:{c['levels']}'>&#9473; {levels}</span>",
        ]
        if self._has_felt:
            parts.append(f"<span style='color:{c['felt']}'>&#9476; felt (motor response)</span>")
        self.plotItem.setTitle("&nbsp;&nbsp;".join(parts), size="9pt")

    def apply_palette(self) -> None:
        """Take the background and text colours from the application palette."""
        colors = plot_colors(self.palette())
        self.setBackground(colors["background"])
        _style_plot(self.plotItem, colors)
        self._title()

    def set_params(self, mu: float, gamma: float, levels: int = 23, response=None,
                   drive_for=None) -> None:  # fmt: skip
        """Redraw for ``mu``, ``gamma``, the device's ``levels`` and motor ``response``.

        ``drive_for`` (the response's inverse) switches to the felt-amplitude domain: the
        corrected curve is then the motor output wanted, the steps the drive levels sent for it,
        and the dashed curve what the motors make of those levels (on the corrected curve but
        for the level steps)."""
        y = correct(self._x, mu, gamma)
        self.curve.setData(self._x, y)
        drive = y if drive_for is None else drive_for(y)
        q = quantize(drive, levels) / (levels - 1)
        change = np.flatnonzero(np.diff(q)) + 1
        xs = np.concatenate([[0.0], self._x[change], [1.0]])
        ys = np.concatenate([[q[0]], q[change]])
        self.steps.setData(xs, ys)
        if response is None:
            self.felt.setData([], [])
        else:
            self.felt.setData(self._x, np.interp(q, *response))
        felt_domain = drive_for is not None and response is not None
        self.setLabel("left", "felt amplitude / drive" if felt_domain else "drive")
        if (response is not None) != self._has_felt or felt_domain != self._felt_domain:
            self._has_felt = response is not None
            self._felt_domain = felt_domain
            self._title()
