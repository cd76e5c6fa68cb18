"""Every string a window shows: titles, labels, buttons, tooltips, the status bar, menus, drop-down
items, plot titles, axis labels and texts, read by walking the widgets (and the plots' items)."""

import pyqtgraph as pg
from PySide6 import QtWidgets


def _menu_strings(menu, where, add):
    for action in menu.actions():
        add(f"{where} > action", action.text())
        add(f"{where} > action tooltip", action.toolTip() if action.toolTip() != action.text()
            .replace("&", "") else "")  # fmt: skip
        add(f"{where} > action status tip", action.statusTip())
        if action.menu() is not None:
            _menu_strings(action.menu(), f"{where} > {action.text()}", add)


def _plot_strings(view, where, add):
    for item in view.scene().items():
        if not item.isVisible():
            continue
        add(f"{where} item tooltip", item.toolTip())
        if isinstance(item, pg.LabelItem):
            add(f"{where} label", item.text)
        elif isinstance(item, pg.TextItem):
            add(f"{where} text", item.textItem.toPlainText())
        elif isinstance(item, QtWidgets.QGraphicsTextItem):
            add(f"{where} text", item.toPlainText())
        elif isinstance(item, pg.AxisItem):
            add(f"{where} axis label", item.labelText)


def visible_strings(windows) -> list[tuple[str, str]]:
    """``(where, text)`` for every non-empty string the visible ``windows`` show."""
    out: list[tuple[str, str]] = []

    def add(where, text):
        if text:
            out.append((where, str(text)))

    for top in windows:
        if not top.isVisible():
            continue
        add("window title", top.windowTitle())
        for w in (top, *top.findChildren(QtWidgets.QWidget)):
            if not w.isVisible():
                continue
            where = f"{type(w).__name__} {w.objectName()}".strip()
            for name in ("toolTip", "statusTip", "whatsThis", "accessibleName",
                         "accessibleDescription"):  # fmt: skip
                add(f"{where} {name}", getattr(w, name)())
            if isinstance(w, (QtWidgets.QLabel, QtWidgets.QAbstractButton)):
                add(where, w.text())
            if isinstance(w, QtWidgets.QLineEdit):
                add(where, w.text())
                add(f"{where} placeholder", w.placeholderText())
            if isinstance(w, QtWidgets.QAbstractSpinBox):
                add(where, w.text())
            if isinstance(w, QtWidgets.QComboBox):
                add(where, w.currentText())
                for i in range(w.count()):
                    add(f"{where} item", w.itemText(i))
                    add(f"{where} item tooltip", w.itemData(i, 3))  # Qt.ToolTipRole
            if isinstance(w, QtWidgets.QGroupBox):
                add(where, w.title())
            if isinstance(w, QtWidgets.QTabWidget):
                for i in range(w.count()):
                    add(f"{where} tab", w.tabText(i))
                    add(f"{where} tab tooltip", w.tabToolTip(i))
            if isinstance(w, QtWidgets.QDockWidget):
                add(where, w.windowTitle())
            if isinstance(w, (QtWidgets.QPlainTextEdit, QtWidgets.QTextEdit)):
                add(where, w.toPlainText())
            if isinstance(w, QtWidgets.QProgressBar) and w.isTextVisible():
                add(where, w.text())
            if isinstance(w, QtWidgets.QStatusBar):
                add(where, w.currentMessage())
            if isinstance(w, QtWidgets.QMenuBar):
                for action in w.actions():
                    add("menu", action.text())
                    if action.menu() is not None:
                        _menu_strings(action.menu(), action.text(), add)
            if isinstance(w, pg.GraphicsView):
                _plot_strings(w, where, add)
    return out
