"""The correction curve: adjusted against raw intensity, with the device's level steps."""

from __future__ import annotations

from typing import ClassVar

import numpy as np
import pyqtgraph as pg
from PySide6 import QtCore

from tactile_core.rendering.correction import correct, quantize

from ..theme import plot_colors
from ._common import PaletteMixin, set_title, style_plot


class CorrectionView(PaletteMixin, pg.PlotWidget):
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
        felt_domain = getattr(self, "_felt_domain", False)
        wanted = " (felt)" if felt_domain else ""
        levels = "drive sent" if felt_domain else "device levels"
        parts = [
            f"<span style='color:{c['curve']}'>&#9473; (1-&mu;) I<sup>&gamma;</sup> + &mu;"
            f"{wanted}</span>",
            f"<span style='color:{c['levels']}'>&#9473; {levels}</span>",
        ]
        if self._has_felt:
            parts.append(f"<span style='color:{c['felt']}'>&#9476; motor output</span>")
        set_title(self.plotItem, "&nbsp;&nbsp;".join(parts), size="9pt")

    def apply_palette(self) -> None:
        """Take the background and text colours from the application palette."""
        colors = plot_colors(self.palette())
        self.setBackground(colors["background"])
        style_plot(self.plotItem, colors)
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
        self.setLabel("left", "felt / drive" if felt_domain else "drive")
        if (response is not None) != self._has_felt or felt_domain != self._felt_domain:
            self._has_felt = response is not None
            self._felt_domain = felt_domain
            self._title()
