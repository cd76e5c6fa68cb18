"""The heatmap's picture of actuators anywhere: a disc per actuator at its position, named, with
a wrap unrolled into one turn (the seam marked) and the layout's groups outlined."""

from __future__ import annotations

import math

import numpy as np
import pyqtgraph as pg
from PySide6 import QtCore, QtGui, QtWidgets

from tactile_core.rendering.placement import unrolled

WRAP_MARGIN = 0.6
"""How far the strip goes past the seam on each side, in layout units (shaded there)."""
NAME_OFFSET = 1.2
"""A name's distance from its actuator, in disc radii: clear of the ring a lit actuator gets
(1.12 radii)."""
MIN_SPAN = 2.5
"""The smallest extent shown along either axis (a belt is one row of actuators)."""


def _spacing(layout) -> float:
    """The median distance from an actuator to its nearest neighbour (1 for one actuator)."""
    if layout.size < 2:
        return 1.0
    xy = layout.xy
    d = layout.distances(xy[:, 0], xy[:, 1])
    np.fill_diagonal(d, np.inf)
    return float(np.median(d.min(axis=1)))


def _lut() -> list:
    """256 brushes along viridis, the heatmap's colour map (made once per picture)."""
    table = pg.colormap.get("viridis").getLookupTable(0.0, 1.0, 256, alpha=False)
    return [QtGui.QBrush(QtGui.QColor(int(r), int(g), int(b))) for r, g, b in table]


class Discs:
    """The items that draw a layout on a :class:`~.heatmap.HeatmapView`, built once per layout.

    One :class:`pyqtgraph.ScatterPlotItem` holds a disc per actuator (``pxMode=False``: the
    discs are sized in layout units, 0.7 of the actuators' spacing); a new frame changes the
    brushes of the discs whose colour changed, picked from a table of 256 made up front, and
    nothing else. Keys are actuator indices. Round a wrap the strip is one turn,
    ``[0, circumference]``, with a dashed, labelled seam at each end, half a pitch shaded
    beyond it, and there a copy of an actuator that sits on the seam (dashed, filled as the
    actuator). Groups are outlined with their names above them. Actuators' names are written
    under their discs where they fit.
    """

    axis_label = "x (pitches)"

    def __init__(self, view, layout):
        self.layout = layout
        self.plot = view.plot
        view.image.setVisible(False)
        xy = layout.xy
        self.spacing = _spacing(layout)
        self.size = min(0.7 * self.spacing, 1.0)
        r = self.size / 2
        self.values = np.zeros(layout.size)
        self._items = []
        self._lut = _lut()
        self._shown = [0] * layout.size  # the table index each disc shows (0: the brush below)
        self.range = self._range(r)
        x0, x1, y0, y1 = self.range
        self.pad_rect = QtCore.QRectF(x0, y0, x1 - x0, y1 - y0)
        self.seams, self.shades = [], []
        if layout.wrap is not None:
            self._seam()
        self.groups = []
        for name, members in layout.groups:
            self._group(name, members, r)
        self.scatter = pg.ScatterPlotItem(
            x=xy[:, 0], y=xy[:, 1], size=self.size, pxMode=False, symbol="o",
            brush=self._lut[0], data=list(range(layout.size)),
        )  # fmt: skip
        self.scatter.setZValue(5)
        self._add(self.scatter)
        self._spots = list(self.scatter.points())
        self._ghosts, self._ghost_of = self._ghost_copies(xy, r)
        self.names = []
        for i, (x, y) in enumerate(layout.positions):
            item = pg.TextItem(layout.names[i], anchor=(0.5, 0.0))
            item.textItem.document().setDocumentMargin(1)  # its filled box hugs the words
            item.setPos(x, y - NAME_OFFSET * r)
            # over the shape's outline (z 10), on the background's colour: the outline ran
            # through the vest's names; under the moving point (z 12)
            item.setZValue(11)
            self._add(item)
            self.names.append(item)
        self.texts = []
        for x, y in layout.positions:
            item = pg.TextItem("", color="w", anchor=(0.5, 0.5))
            item.setPos(x, y)
            item.setZValue(7)
            item.setVisible(False)
            self._add(item)
            self.texts.append(item)
        self._text_values = [None] * layout.size
        self._show_texts = False
        self.highlight_item = QtWidgets.QGraphicsEllipseItem(-r * 1.3, -r * 1.3, 2.6 * r, 2.6 * r)
        self.highlight_item.setVisible(False)
        self.highlight_item.setZValue(20)
        self._add(self.highlight_item)
        self.frames: dict = {}
        metrics = QtGui.QFontMetrics(self.names[0].textItem.font())
        self._name_px = max(metrics.horizontalAdvance(n) for n in layout.names) + 6
        seam = self.seams[-1][1].textItem.toPlainText() if self.seams else ""
        self._seam_px = metrics.horizontalAdvance(seam)
        # the filled box a name takes (not the font's height alone: with the box's margins
        # the vest's names covered the tops of the discs below at 1280 x 720)
        self._text_px = self.names[0].textItem.boundingRect().height()
        self._label_gap = self._vertical_gap(xy, r)

    def _add(self, item) -> None:
        self.plot.addItem(item)
        self._items.append(item)

    def _range(self, r: float) -> tuple[float, float, float, float]:
        """The view's extent: the actuators and a margin, one turn (and a little more) round a
        wrap, room for the group names, at least :data:`MIN_SPAN` each way."""
        x0, x1, y0, y1 = self.layout.bounds(margin=r + 0.4)
        wrap = self.layout.wrap
        if wrap is not None:
            lo, hi = -WRAP_MARGIN, wrap.circumference + WRAP_MARGIN
            x0, x1 = (lo, hi) if wrap.axis == "x" else (x0, x1)
            y0, y1 = (lo, hi) if wrap.axis == "y" else (y0, y1)
        if self.layout.groups and (wrap is None or wrap.axis == "x"):
            y1 += 0.35  # the group names above their outlines
        if wrap is not None and wrap.axis == "x":
            y1 += 0.5  # a row for the seams' labels, above everything else
        if x1 - x0 < MIN_SPAN:
            x0, x1 = (x0 + x1 - MIN_SPAN) / 2, (x0 + x1 + MIN_SPAN) / 2
        if y1 - y0 < MIN_SPAN:
            y0, y1 = (y0 + y1 - MIN_SPAN) / 2, (y0 + y1 + MIN_SPAN) / 2
        return (x0, x1, y0, y1)

    def _seam(self) -> None:
        wrap = self.layout.wrap
        c = wrap.circumference
        x0, x1, y0, y1 = self.range
        vertical = wrap.axis == "x"
        for at, text, side in ((0.0, " seam", 0.0), (c, f"seam ({c:g} = 0) ", 1.0)):
            ends = ([at, at], [y0, y1]) if vertical else ([x0, x1], [at, at])
            line = pg.PlotDataItem(*ends)
            line.setZValue(3)
            # inside the strip, beside the line: never cut off at the view's edge
            label = pg.TextItem(text, anchor=(side, 0.0) if vertical else (0.0, side))
            label.setPos(at, y1) if vertical else label.setPos(x0, at)
            label.setZValue(8)
            tip = (f"The {wrap.axis} axis wraps: {wrap.axis} = {c:g} is {wrap.axis} = 0, and "
                   "a point crossing here comes back on the other side")  # fmt: skip
            line.setToolTip(tip)
            self._add(line)
            self._add(label)
            self.seams.append((line, label))
        for a, b in ((-WRAP_MARGIN, 0.0), (c, c + WRAP_MARGIN)):
            rect = (a, y0, b - a, y1 - y0) if vertical else (x0, a, x1 - x0, b - a)
            shade = QtWidgets.QGraphicsRectItem(*rect)
            shade.setPen(QtGui.QPen(QtCore.Qt.PenStyle.NoPen))
            shade.setZValue(-5)
            shade.setToolTip("beyond the seam: the other end of the strip, again")
            self._add(shade)
            self.shades.append(shade)

    def _group(self, name: str, members, r: float) -> None:
        pts = self.layout.xy[list(members)]
        lo, hi = pts.min(axis=0) - (r + 0.12), pts.max(axis=0) + (r + 0.12)
        lo[1] -= 0.2  # the names under the lowest discs, inside
        box = QtWidgets.QGraphicsRectItem(lo[0], lo[1], hi[0] - lo[0], hi[1] - lo[1])
        box.setZValue(2)
        box.setToolTip(f"group {name}: {', '.join(self.layout.names[i] for i in members)}")
        label = pg.TextItem(name, anchor=(0.5, 1.0))
        label.setPos((lo[0] + hi[0]) / 2, hi[1])
        label.setZValue(8)
        self._add(box)
        self._add(label)
        self.groups.append((box, label))

    def _ghost_copies(self, xy, r: float):
        """Round a wrap, a copy of each actuator whose disc fits wholly in the margin beyond
        the seam, drawn there."""
        wrap = self.layout.wrap
        if wrap is None:
            return None, []
        c, k = wrap.circumference, wrap.index
        room = WRAP_MARGIN - r
        shifted, sources = [], []
        for i, p in enumerate(xy.tolist()):
            for shift in ((c,) if p[k] <= room else ()) + ((-c,) if p[k] >= c - room else ()):
                q = list(p)
                q[k] += shift
                shifted.append(q)
                sources.append(i)
        if not shifted:
            return None, []
        pts = np.asarray(shifted)
        pen = pg.mkPen((128, 128, 128), width=1.5, style=QtCore.Qt.PenStyle.DashLine)
        ghosts = pg.ScatterPlotItem(x=pts[:, 0], y=pts[:, 1], size=self.size, pxMode=False,
                                    symbol="o", pen=pen, brush=self._lut[0])  # fmt: skip
        ghosts.setZValue(5)
        ghosts.setOpacity(0.75)
        ghosts.setToolTip(", ".join(self.layout.names[i] for i in sources) + " (across the seam)")
        self._add(ghosts)
        return list(ghosts.points()), sources

    def _vertical_gap(self, xy, r: float) -> float:
        """The smallest room under a disc before the next one down (inf: none below)."""
        gap = math.inf
        for i, (x, y) in enumerate(xy.tolist()):
            for j, (u, v) in enumerate(xy.tolist()):
                if j != i and abs(u - x) < 2 * r and v < y:
                    gap = min(gap, (y - v) - (1 + NAME_OFFSET) * r)
        return gap

    def ticks(self) -> tuple[list, list]:
        """Ticks at whole layout units within the view."""
        x0, x1, y0, y1 = self.range
        return ([(i, str(i)) for i in range(math.ceil(x0), math.floor(x1) + 1)],
                [(i, str(i)) for i in range(math.ceil(y0), math.floor(y1) + 1)])  # fmt: skip

    def remove(self) -> None:
        """Take this layout's items off the plot."""
        for item in [*self._items, *self.frames.values()]:
            self.plot.removeItem(item)
        self._items, self.frames = [], {}

    def set_palette(self, colors) -> None:
        """Outlines, names and seams in the palette's foreground colour."""
        fg = colors["foreground"]
        pen = QtGui.QPen(fg)
        pen.setWidthF(4)
        pen.setCosmetic(True)
        self.highlight_item.setPen(pen)
        self.scatter.setPen(pg.mkPen(fg, width=1))
        under = QtGui.QColor(colors["background"])
        under.setAlpha(200)
        for item in self.names:
            item.setColor(fg)
            item.fill = pg.mkBrush(under)
            item.update()
        dashed = pg.mkPen(fg, width=2, style=QtCore.Qt.PenStyle.DashLine)
        for line, label in self.seams:
            line.setPen(dashed)
            label.setColor(fg)
        for shade in self.shades:
            shade.setBrush(pg.mkBrush(colors["shade"]))
        dotted = QtGui.QPen(fg, 1.5, QtCore.Qt.PenStyle.DotLine)
        dotted.setCosmetic(True)
        for box, label in self.groups:
            box.setPen(dotted)
            label.setColor(fg)

    def key_at(self, x: float, y: float):
        """The actuator whose disc holds ``(x, y)`` (round a wrap too), or None."""
        x, y = self.canonical(x, y)
        d = self.layout.distances(x, y)
        i = int(np.argmin(d))
        return i if d[i] <= self.size / 2 * 1.15 else None

    def describe(self, key) -> str:
        """The readout's words for an actuator: ``actuator front-left (1), 0.42``."""
        groups = self.layout.group_of(key)
        where = f" in {', '.join(groups)}" if groups else ""
        return f"actuator {self.layout.names[key]} ({key}){where}, {self.values[key]:.2f}"

    def clamp(self, x: float, y: float) -> tuple[float, float]:
        """A drawn point kept on the layout: round a wrap, taken into one turn (a path may
        cross the seam); otherwise within the view."""
        x0, x1, y0, y1 = self.range
        axis = self.layout.wrap.axis if self.layout.wrap is not None else ""
        x = x if axis == "x" else min(max(x, x0), x1)
        y = y if axis == "y" else min(max(y, y0), y1)
        return self.canonical(x, y)

    def canonical(self, x: float, y: float) -> tuple[float, float]:
        """Where a point is drawn: round a wrap, within one turn."""
        wrap = self.layout.wrap
        if wrap is None:
            return x, y
        c = wrap.circumference
        return (x % c, y) if wrap.axis == "x" else (x, y % c)

    def path(self, points) -> tuple[np.ndarray, np.ndarray]:
        """A path's x and y as drawn on the unrolled strip (a gap where it crosses the seam)."""
        return unrolled(points, self.layout)

    def set_values(self, values) -> None:
        """Show intensities ``(size,)``: the discs whose colour changed get a brush from the
        table; nothing is repainted when nothing changed."""
        values = np.asarray(values, dtype=np.float64).reshape(-1)
        if np.array_equal(values, self.values):
            return
        np.copyto(self.values, values)
        lut, shown, spots = self._lut, self._shown, self._spots
        for i, v in enumerate(values.tolist()):
            k = 0 if not v > 0.0 else 255 if v >= 1.0 else int(v * 255.0 + 0.5)
            if k != shown[i]:
                shown[i] = k
                spots[i].setBrush(lut[k])
        for ghost, i in zip(self._ghosts or (), self._ghost_of):
            ghost.setBrush(lut[shown[i]])

    def set_texts(self, labels) -> None:
        """Write ``labels`` (one per actuator) on the discs, changed ones only."""
        for i, text in enumerate(np.asarray(labels).reshape(-1).tolist()):
            if text != self._text_values[i]:
                self._text_values[i] = text
                self.texts[i].setText(str(text))
                self.texts[i].setColor("k" if self.values[i] > 0.6 else "w")

    def show_texts(self, show: bool) -> None:
        """Show or hide the values on the discs."""
        self._show_texts = bool(show)
        self._text_values = [None] * len(self.texts)
        self.fit_labels()

    def highlight(self, key) -> None:
        """Ring an actuator (None: none)."""
        if key is None:
            self.highlight_item.setVisible(False)
        else:
            self.highlight_item.setPos(*self.layout.positions[key])
            self.highlight_item.setVisible(True)

    def set_frames(self, colors: dict) -> None:
        """Ring actuators ``{index: colour}`` (the activation curves' colours)."""
        for key, item in list(self.frames.items()):
            if key not in colors:
                self.plot.removeItem(item)
                del self.frames[key]
        r = self.size / 2 * 1.12
        for key, color in colors.items():
            item = self.frames.get(key)
            if item is None:
                x, y = self.layout.positions[key]
                item = QtWidgets.QGraphicsEllipseItem(x - r, y - r, 2 * r, 2 * r)
                item.setZValue(9)
                self.plot.addItem(item)
                self.frames[key] = item
            pen = QtGui.QPen(QtGui.QColor(color))
            pen.setWidthF(3)
            pen.setCosmetic(True)
            item.setPen(pen)
            item.setToolTip(self.layout.names[key])

    def fit_labels(self) -> None:
        """Names under the discs, and values on them, only where they fit at this size."""
        px_x, px_y = self.plot.vb.viewPixelSize()
        if not (px_x > 0 and px_y > 0):
            return
        spacing = self.spacing / px_x
        gap = self._label_gap / px_y
        below = self._name_px <= spacing and self._text_px <= gap
        # names too wide for one row of actuators (a belt): every other one above its disc
        stagger = not below and self._name_px <= 2 * spacing and gap == math.inf
        r = self.size / 2
        for i, (item, (x, y)) in enumerate(zip(self.names, self.layout.positions)):
            up = stagger and i % 2 == 1
            item.setAnchor((0.5, 1.0) if up else (0.5, 0.0))
            item.setPos(x, y + NAME_OFFSET * r if up else y - NAME_OFFSET * r)
            item.setVisible(below or stagger)
        for _, label in self.seams:  # beside the seam, over a disc when the strip is small
            label.setVisible(self._seam_px <= 2.5 * spacing)
        texts = self._show_texts and self.size / px_x >= 30
        for item in self.texts:
            item.setVisible(texts)
