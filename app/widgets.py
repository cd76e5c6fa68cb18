"""Small widgets the parts share: a spin box that commits on Enter, a label that elides, one
that wraps, a set of methods to compare, and a guard that lets the mouse wheel scroll a panel
instead of turning its values."""

from __future__ import annotations

from PySide6 import QtCore, QtGui, QtWidgets

from tactile_core.rendering.methods import METHODS, get_method, method_names

from .texts import tip


def spin_box(lo, hi, step, decimals, suffix="", kind=QtWidgets.QDoubleSpinBox):
    """A spin box (a ``kind``) over ``lo..hi`` that commits on Enter or focus loss, not on
    every keystroke."""
    box = kind()
    box.setRange(lo, hi)
    box.setSingleStep(step)
    box.setDecimals(decimals)
    box.setKeyboardTracking(False)
    if suffix:
        box.setSuffix(suffix)
    return box


class ElidedLabel(QtWidgets.QLabel):
    """A one-line label that shortens its text with an ellipsis instead of widening its panel.

    The full text stays available as the tooltip.
    """

    def __init__(self, text: str, parent=None):
        super().__init__(text, parent)
        self.setTextFormat(QtCore.Qt.TextFormat.PlainText)  # names from files: never markup
        self.setToolTip(tip(text))
        self.setSizePolicy(
            QtWidgets.QSizePolicy.Policy.Ignored, QtWidgets.QSizePolicy.Policy.Preferred
        )

    def setText(self, text: str) -> None:  # Qt override: the tooltip follows the text
        super().setText(text)
        self.setToolTip(tip(text))

    def minimumSizeHint(self) -> QtCore.QSize:  # Qt override
        return QtCore.QSize(0, super().minimumSizeHint().height())

    def paintEvent(self, event) -> None:  # Qt override
        painter = QtGui.QPainter(self)
        text = self.fontMetrics().elidedText(
            self.text(), QtCore.Qt.TextElideMode.ElideRight, self.contentsRect().width()
        )
        painter.drawText(self.contentsRect(), int(self.alignment()), text)


class WrappedLabel(QtWidgets.QLabel):
    """A label that wraps onto more lines instead of widening its panel or cutting its words
    off: it asks for no width of its own, and as many lines as its width needs."""

    def __init__(self, text: str, parent=None):
        super().__init__(text, parent)
        self.setTextFormat(QtCore.Qt.TextFormat.PlainText)
        self.setWordWrap(True)
        policy = QtWidgets.QSizePolicy(
            QtWidgets.QSizePolicy.Policy.Ignored, QtWidgets.QSizePolicy.Policy.Minimum
        )
        policy.setHeightForWidth(True)
        self.setSizePolicy(policy)

    def minimumSizeHint(self) -> QtCore.QSize:  # Qt override
        return QtCore.QSize(0, self.heightForWidth(max(self.width(), 1)))


class MethodSetWidget(QtWidgets.QWidget):
    """A set of methods to compare, typed as specs (``AS EN RO:r=1.5``) or picked from a menu
    of every registered method; a set outside ``low..high`` methods, with an unknown name or
    with a method that :attr:`check` refuses (one that cannot render on the device's layout) is
    refused with the reason shown, and the last good set stays.

    The reason stays under the field until another set is applied: the field gives up the focus
    after Enter (the window takes the keys back) and says its editing finished once more, with
    the set in use back in it; that is no new set, and changes nothing (nor does Enter on it)."""

    methods_changed = QtCore.Signal(list)

    def __init__(self, methods, low: int, high: int, parent=None, label: str | None = "methods"):
        super().__init__(parent)
        self.low, self.high = low, high
        self.methods = list(methods)
        self.check = lambda spec: ""
        """Why a method may not be in the set ("" when it may): the owner sets it."""
        column = QtWidgets.QVBoxLayout(self)
        column.setContentsMargins(0, 0, 0, 0)
        column.setSpacing(2)
        row = QtWidgets.QHBoxLayout()
        row.setContentsMargins(0, 0, 0, 0)
        column.addLayout(row)
        if label:
            row.addWidget(QtWidgets.QLabel(label))
        self.edit = QtWidgets.QLineEdit(" ".join(self.methods))
        self.edit.setObjectName("method_set")
        self.edit.setToolTip(
            f"{low} to {high} methods, separated by spaces; parameters as RO:r=1.5 or "
            "GS:sigma=0.7. Enter applies."
        )
        self.edit.editingFinished.connect(self._on_edited)
        row.addWidget(self.edit, 1)
        # A push button sizes itself for its text and its menu's arrow (a tool button with an
        # instant popup drew the arrow over "pick").
        self.pick = QtWidgets.QPushButton("pick")
        self.pick.setObjectName("method_set_pick")
        self.pick.setToolTip("Tick the methods to use from the list of every method")
        self.menu = QtWidgets.QMenu(self.pick)
        self.menu.setToolTipsVisible(True)
        self.menu.aboutToShow.connect(self._fill_menu)
        self.pick.setMenu(self.menu)
        row.addWidget(self.pick)
        # Under the field, across the whole width, wrapped: never beside it, where a long
        # refusal was pushed past the window's edge.
        self.problem = QtWidgets.QLabel("")
        self.problem.setObjectName("method_set_problem")
        self.problem.setWordWrap(True)
        self.problem.setVisible(False)
        column.addWidget(self.problem)

    def _fill_menu(self) -> None:
        self.menu.clear()
        chosen = {get_method(m).name for m in self.methods}
        for name in method_names():
            action = self.menu.addAction(f"{name}  {METHODS[name].title}")
            action.setCheckable(True)
            action.setChecked(name in chosen)
            why = self.check(name)
            action.setEnabled(not why)
            action.setToolTip(why)
            action.toggled.connect(lambda on, n=name: self._toggle(n, on))

    def _toggle(self, name: str, on: bool) -> None:
        kept = [m for m in self.methods if get_method(m).name != name]
        self.apply([*kept, name] if on else kept)

    def _on_edited(self) -> None:
        if self.edit.text().split() == self.methods:
            return  # the set in use: nothing new (the field was left after a refusal put it back)
        self.apply(self.edit.text().split())

    def refuse(self, message: str, keep=None, *, warn: bool = True) -> None:
        """Show why a set was refused and show the set in use again (``keep``, by default
        the last good one); ``warn=False``: a note in the text colour (the set was changed for
        the layout) rather than a refusal in red."""
        if keep is not None:
            self.methods = list(keep)
        # A red that reads on the palette's window colour, light or dark.
        dark = self.palette().color(QtGui.QPalette.ColorRole.Window).lightness() < 128
        self.problem.setStyleSheet(f"color: {'#ff8a80' if dark else '#c62828'}" if warn else "")
        self.problem.setText(message)
        self.problem.setVisible(bool(message))
        self.show_methods()

    def show_methods(self) -> None:
        """The set in use in the field (the owner changed it, or a set was refused)."""
        self.edit.setText(" ".join(self.methods))

    def apply(self, specs) -> bool:
        """Use ``specs`` if they are a valid set; otherwise show why and keep the last one."""
        try:
            methods = [get_method(s).spec for s in specs]
            if not self.low <= len(methods) <= self.high:
                raise ValueError(f"choose {self.low} to {self.high} methods, got {len(methods)}")
            if len(set(methods)) != len(methods):
                raise ValueError("each method once")
            why = next((w for w in map(self.check, methods) if w), "")
            if why:
                raise ValueError(why)
        except ValueError as exc:
            self.refuse(str(exc))
            return False
        self.problem.setText("")
        self.problem.setVisible(False)
        self.edit.setText(" ".join(methods))
        if methods != self.methods:
            self.methods = methods
            self.methods_changed.emit(methods)
        return True


class _WheelGuard(QtCore.QObject):
    """Hands a wheel event over an unfocused value widget to the scroll area around it."""

    def eventFilter(self, obj, event):  # Qt override
        if event.type() != QtCore.QEvent.Type.Wheel or obj.hasFocus():
            return False
        area = obj.parent()
        while area is not None and not isinstance(area, QtWidgets.QAbstractScrollArea):
            area = area.parent()
        if area is not None:  # its scroll bar takes the wheel as the panel would
            bar = area.verticalScrollBar()
            if event.angleDelta().x() and not event.angleDelta().y():
                bar = area.horizontalScrollBar()
            QtWidgets.QApplication.sendEvent(bar, event)
        return True


def guard_wheel(root: QtWidgets.QWidget) -> None:
    """Spin boxes, drop-downs and sliders under ``root`` take the mouse wheel only once clicked
    (focused): over a scrolling panel the wheel scrolls the panel, never a value by accident."""
    guard = _WheelGuard(root)
    kinds = (QtWidgets.QAbstractSpinBox, QtWidgets.QComboBox, QtWidgets.QAbstractSlider)
    for widget in root.findChildren(QtWidgets.QWidget):
        # a scroll bar is how a text box scrolls (handing its wheel on to it looped for ever)
        if isinstance(widget, kinds) and not isinstance(widget, QtWidgets.QScrollBar):
            widget.setFocusPolicy(QtCore.Qt.FocusPolicy.StrongFocus)
            widget.installEventFilter(guard)
