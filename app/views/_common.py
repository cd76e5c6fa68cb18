"""What the plot views share: the tactors' colours and labels, and following the palette."""

from __future__ import annotations

import pyqtgraph as pg
from PySide6 import QtCore

from ..theme import TACTOR_COLORS

pg.setConfigOptions(antialias=True, imageAxisOrder="row-major")

PALETTE = TACTOR_COLORS


def cell_colors(cells) -> dict:
    """``{(col, row): colour}`` for tactors in order of activation (30 distinct colours)."""
    return {cell: PALETTE[i % len(PALETTE)] for i, cell in enumerate(cells)}


def cell_label(cell) -> str:
    """``"(col,row)"``: how a tactor is named on the axes and in tooltips."""
    return f"({cell[0]},{cell[1]})"


def style_plot(plot: pg.PlotItem, colors: dict) -> None:
    """Give a plot's axes and title the palette's foreground colour."""
    fg = colors["foreground"]
    for name in ("left", "bottom", "right", "top"):
        axis = plot.getAxis(name)
        axis.setPen(pg.mkPen(fg))
        axis.setTextPen(pg.mkPen(fg))
    plot.titleLabel.setAttr("color", fg.name())
    plot.titleLabel.setText(plot.titleLabel.text)


class PaletteMixin:
    """Restyle when the application palette changes (light <-> dark)."""

    _ready = False  # set once the view's items exist

    def changeEvent(self, event):  # Qt override
        kinds = (QtCore.QEvent.Type.PaletteChange, QtCore.QEvent.Type.ApplicationPaletteChange)
        if self._ready and event.type() in kinds:
            self.apply_palette()
        super().changeEvent(event)


def set_title(plot: pg.PlotItem, text: str, **args) -> None:
    """Set a plot's title without letting it widen the plot: pyqtgraph gives a title a minimum
    width as wide as its text, which pushed the plot past its view (the felt-amplitude key at
    1280 x 720); here a long title is clipped by the view instead.

    pyqtgraph sets that width again whenever the title is resized or its text set (its
    ``LabelItem.updateMin``): the title's own ``updateMin`` puts it back to 0 each time (a
    Compare column's title had widened its plot past the column once the column was shown)."""
    label = plot.titleLabel
    if not getattr(label, "_kept_narrow", False):
        widen = label.updateMin

        def update_min():
            widen()
            label.setMinimumWidth(0)
            label.setPreferredWidth(0)

        label.updateMin = update_min  # pyqtgraph calls self.updateMin(): this one
        label._kept_narrow = True
        option = label.item.document().defaultTextOption()  # lines centred under one another
        option.setAlignment(QtCore.Qt.AlignmentFlag.AlignHCenter)
        label.item.document().setDefaultTextOption(option)
    label.item.setTextWidth(-1)  # as wide as its widest line...
    plot.setTitle(text, **args)
    if "<br>" in text:  # ...and that width fixed, so that its lines can be centred
        label.item.setTextWidth(label.item.document().idealWidth())
        label.resizeEvent(None)  # (pyqtgraph's: the title centred again)
    label.setMinimumWidth(0)
    label.setPreferredWidth(0)
