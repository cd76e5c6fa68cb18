"""What the control boxes share: a spin box for one scene field, and the write-back guard."""

from __future__ import annotations

import math
import re

from PySide6 import QtCore, QtGui, QtWidgets

from ..texts import value3
from ..widgets import spin_box  # noqa: F401 (the boxes' spin box, shared with the editor)


class CorrectionSpinBox(QtWidgets.QDoubleSpinBox):
    """A spin box for mu or gamma that holds the value in use exactly and writes it as the
    titles and the status line do (:func:`~app.texts.value3`: ``0.70``, ``0.142``, ``50.00``,
    ``1e-05``).

    Its range is every value the core accepts (``lo`` to ``hi``; gamma: any finite value above
    0), so a preset's or another program's gamma of 50 or 0.05 shows as itself, never as the
    end of a narrower range (the box read 10.00 while gamma 50 played). Nothing is rounded to
    the box's decimals: a value set from outside stays as it is when the box is left or Enter
    pressed without typing (the text shown reads back as the value it shows); a typed number
    is taken as typed.

    Parameters
    ----------
    lo, hi : float
        The values accepted, inclusive.
    relative : bool
        Step (the arrows, the wheel once clicked) by one in the value's second significant digit
        (0.70 -> 0.71, 1.0 -> 1.1, 50 -> 51, 0.05 -> 0.051), which never reaches 0 (gamma);
        else by 0.01 (mu).
    """

    def __init__(self, lo: float, hi: float, relative: bool = False, parent=None):
        super().__init__(parent)
        self._lo, self._hi = lo, hi  # (Qt rounds the range: gamma's 5e-324 becomes 0)
        self.setDecimals(_EXACT_DECIMALS)
        self.setRange(lo, hi)
        self.setSingleStep(0.01)
        if relative:
            self.setStepType(QtWidgets.QAbstractSpinBox.StepType.AdaptiveDecimalStepType)
        self.setKeyboardTracking(False)

    refused = QtCore.Signal(str)
    """Text typed and given up (Enter, or the box left) that is no value of the box: the box
    shows the value in use again."""

    def fixup(self, text: str) -> str:  # Qt override: called for such text
        if text.strip():
            self.refused.emit(text.strip())
        return super().fixup(text)

    def textFromValue(self, value: float) -> str:  # Qt override
        return value3(value)

    def valueFromText(self, text: str) -> float:  # Qt override
        if text.strip() == value3(self.value()):
            return self.value()  # what it shows of the value in use: that value, not rounded
        return float(text)

    def validate(self, text: str, pos: int):  # Qt override
        state = QtGui.QValidator.State
        body = text.strip()
        try:
            value = float(body)
        except ValueError:
            return state.Intermediate if _PARTIAL_NUMBER.fullmatch(body) else state.Invalid
        if math.isfinite(value) and self._lo <= value <= self._hi:
            return state.Acceptable
        return state.Intermediate

    def sizeHint(self) -> QtCore.QSize:  # Qt override: as wide as a usual value, not 1e+308
        return self._sized(super().sizeHint())

    def minimumSizeHint(self) -> QtCore.QSize:  # Qt override
        return self._sized(super().minimumSizeHint())

    def _sized(self, hint: QtCore.QSize) -> QtCore.QSize:
        widest = max(value3(self.minimum()), value3(self.maximum()), key=len)
        extra = self.fontMetrics().horizontalAdvance(widest)
        hint.setWidth(hint.width() - extra + self.fontMetrics().horizontalAdvance("10.000"))
        return hint


_EXACT_DECIMALS = 323
"""QDoubleSpinBox's most decimals (``DBL_MAX_10_EXP + DBL_DIG``): it rounds what it holds to its
decimals, and at this many a double keeps its own value."""
_PARTIAL_NUMBER = re.compile(r"[+-]?\d*\.?\d*(?:[eE][+-]?\d*)?")
"""What may become a number as one types it (``1e-``, ``.``)."""


class SceneGroupWidget(QtWidgets.QGroupBox):
    """A group of controls that writes scene fields to the state and shows the state's values.

    While :meth:`refresh` shows the state's values, the widgets' change signals are not written
    back (``_updating``).
    """

    def __init__(self, title: str, state, parent=None):
        super().__init__(title, parent)
        self.state = state
        self._updating = False

    def _set(self, **changes) -> None:
        if not self._updating and not self.state.update(**changes):
            self.refresh()  # refused (said in the status line): the values in use again

    def refresh(self, *_) -> None:
        """Show the state's values (without writing them back)."""
        self._updating = True
        try:
            self._show(self.state.scene)
        finally:
            self._updating = False

    def _show(self, scene) -> None:  # each box shows its own fields
        raise NotImplementedError
