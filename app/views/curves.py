"""The activation curves: each activated tactor's intensity over one trace."""

from __future__ import annotations

import numpy as np
import pyqtgraph as pg
from PySide6 import QtCore, QtGui, QtWidgets

from ..theme import plot_colors
from ._common import PaletteMixin, cell_label, set_title, style_plot

TITLE_SIZE = "11pt"
"""The curves' title's type size (pyqtgraph's); a choice may ask for a smaller one."""


class CurvesView(PaletteMixin, pg.PlotWidget):
    """Activation curves: each activated tactor's intensity over one trace (Figures 3, 4).

    Two layouts: *overlaid* (every curve on one axis, as the paper's figures) and *lanes* (one
    row per tactor, labelled ``(col,row)`` on a grid and by the actuator's name on a layout
    (:meth:`names`), so that bi-level methods' sequences, whose curves all
    sit at 1, can be read). Corrected intensities are solid, raw ones dashed; the pause after the
    trace is shaded. The time cursor is dashed, in the text colour (no curve's colour); dragging
    it scrubs the trace (:attr:`scrubbed`). Hovering a curve highlights it and emits
    :attr:`curve_hovered` with its tactor. The title is the first of a few wordings that fits
    the plot's width (:meth:`set_titles`), chosen again when the view is resized: never cut off.
    """

    scrubbed = QtCore.Signal(float)
    """The cursor was dragged to this time (s)."""
    scrub_finished = QtCore.Signal()
    curve_hovered = QtCore.Signal(object)

    def __init__(self, parent=None, *, title: str = "Activation curves"):
        super().__init__(parent=parent)
        self._titles: tuple = ()
        self._title_timer = QtCore.QTimer(self)  # a resize: fitted once the plot has its width
        self._title_timer.setSingleShot(True)
        self._title_timer.timeout.connect(self._fit_title)
        # the title's width is the plot box's, settled after the view's own resize
        self.plotItem.titleLabel.geometryChanged.connect(lambda: self._title_timer.start(0))
        self.set_titles(title)
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

    def set_titles(self, *choices) -> None:
        """Title the plot with the first of ``choices`` that fits its width, else the last.

        Parameters
        ----------
        *choices : str or (str, str)
            A text, or ``(text, size)`` with a type size such as ``"9pt"`` (:data:`TITLE_SIZE`
            otherwise); ``<br>`` breaks a text into lines, and a text fits when its widest line
            does. The longest wording first, the shortest last.
        """
        self._titles = tuple((c, TITLE_SIZE) if isinstance(c, str) else tuple(c) for c in choices)
        self._fit_title()

    def _fit_title(self) -> None:
        if not self._titles:
            return
        label = self.plotItem.titleLabel
        # The title spans the plot's box, less its text's margins; wider, it is cut off.
        margins = 2 * label.item.document().documentMargin()
        room = (label.width() if label.width() > 0 else self.width() - 50) - margins
        font = QtGui.QFont(label.item.font())
        for text, size in self._titles:
            font.setPointSizeF(float(size.removesuffix("pt")))
            metrics = QtGui.QFontMetricsF(font)
            if max(metrics.horizontalAdvance(line) for line in text.split("<br>")) <= room:
                break
        if (text, size) != (label.text, label.opts.get("size")):
            set_title(self.plotItem, text, size=size)

    def resizeEvent(self, event) -> None:  # Qt override
        super().resizeEvent(event)
        if self._ready:  # (pyqtgraph resizes the view while it is being made)
            self._title_timer.start(0)

    def apply_palette(self) -> None:
        """Take the background and text colours from the application palette."""
        colors = plot_colors(self.palette())
        self.setBackground(colors["background"])
        style_plot(self.plotItem, colors)
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
            and previous.names == curves.names
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

    def name(self, index: int) -> str:
        """The name of the ``index``-th curve's tactor: ``(col,row)`` on a grid, the
        actuator's name on a layout."""
        curves = self.curves
        return curves.names[index] if curves.names else cell_label(curves.cells[index])

    def names(self) -> list[str]:
        """The tactors whose curves are shown, by name, in order of activation."""
        return [] if self.curves is None else [self.name(i) for i in range(len(self.curves.cells))]

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
            solid.setToolTip(self.name(i))
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
            left.setTicks([[(n - 1 - i + 0.42, self.name(i)) for i in range(n)], []])
            on_grid = isinstance(curves.cells[0], tuple)
            self.setLabel("left", "tactor (col,row)" if on_grid else "actuator")
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

    def leaveEvent(self, event) -> None:  # Qt override
        self._hover(None)  # the mouse left: no highlight stays behind
        super().leaveEvent(event)

    def _hover(self, cell) -> None:
        if cell != self._hovered:
            self._hovered = cell
            self.highlight(cell)
            self.curve_hovered.emit(cell)

    def highlight(self, cell) -> None:
        """Draw ``cell``'s curve thick (None: none), e.g. when its cell is hovered."""
        for c, line in self._solid.items():
            line.setPen(pg.mkPen(self.colors[c], width=5 if c == cell else 2))
