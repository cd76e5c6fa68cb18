"""Keys and the mouse reach what they are meant for (real key and wheel events, pytest-qt):
typing into a field stays in the field, Enter commits it and gives the window's keys back, Esc
closes only the drop-down or dialog it was pressed in, the wheel over the controls scrolls them
rather than turning a spin box, and Help lists the keys."""

import pytest
from PySide6 import QtCore, QtGui, QtWidgets

from .tuner_support import WAIT_MS

Key = QtCore.Qt.Key


def test_digits_typed_into_the_device_box_stay_there(window, qtbot):
    combo = window.device_panel.port_combo
    window.state.update(method="AS")
    combo.setFocus()
    combo.lineEdit().clear()
    qtbot.keyClicks(combo.lineEdit(), "COM2")
    assert combo.currentText() == "COM2"
    assert window.state.scene.method == "AS"  # "2" did not switch to MM
    combo.lineEdit().clear()
    qtbot.keyClicks(combo.lineEdit(), "/dev/pts/1")
    assert combo.currentText() == "/dev/pts/1" and window.state.scene.method == "AS"


def test_enter_commits_a_field_and_gives_the_keys_back(window, qtbot):
    spin = window.controls.correction.mu_spin
    spin.setFocus()
    spin.selectAll()
    qtbot.keyClicks(spin, "0.5")
    qtbot.keyClick(spin, Key.Key_Return)
    assert window.state.scene.mu == pytest.approx(0.5)
    qtbot.waitUntil(lambda: not spin.hasFocus(), timeout=WAIT_MS)
    focus = QtWidgets.QApplication.focusWidget()
    playing = window.state.scene.playing
    qtbot.keyClick(focus or window, Key.Key_Space)  # Space works at once
    assert window.state.scene.playing != playing
    qtbot.keyClick(focus or window, Key.Key_1)
    assert window.state.scene.method == "CT"


def test_esc_in_a_drop_down_closes_only_the_drop_down(window, qtbot):
    window.state.update(playing=True)
    combo = window.controls.shape.shape_combo
    combo.showPopup()
    popup = QtWidgets.QApplication.activePopupWidget()
    assert popup is not None
    qtbot.keyClick(popup, Key.Key_Escape)
    qtbot.waitUntil(lambda: QtWidgets.QApplication.activePopupWidget() is None, timeout=WAIT_MS)
    assert window.state.scene.playing  # the array was not turned off


def test_esc_in_a_dialog_closes_only_the_dialog(window, qtbot):
    window.state.update(playing=True)
    window.show_error("something to read")
    box = QtWidgets.QApplication.activeModalWidget()
    assert isinstance(box, QtWidgets.QMessageBox)
    qtbot.keyClick(box, Key.Key_Escape)
    qtbot.waitUntil(lambda: not box.isVisible(), timeout=WAIT_MS)
    assert window.state.scene.playing
    qtbot.keyClick(window.tune.heatmap, Key.Key_Escape)  # in the window: all off
    assert not window.state.scene.playing


def test_the_mouse_wheel_over_the_controls_scrolls_them(window, qtbot):
    window.resize(1280, 600)
    scroll = window.controls_scroll
    qtbot.waitUntil(lambda: scroll.verticalScrollBar().maximum() > 0, timeout=WAIT_MS)
    spin = window.controls.trace.duration_spin
    before = spin.value()
    pos = QtCore.QPointF(spin.width() / 2, spin.height() / 2)
    event = QtGui.QWheelEvent(pos, spin.mapToGlobal(pos), QtCore.QPoint(0, 0),
                              QtCore.QPoint(0, -120), QtCore.Qt.MouseButton.NoButton,
                              QtCore.Qt.KeyboardModifier.NoModifier,
                              QtCore.Qt.ScrollPhase.NoScrollPhase, False)  # fmt: skip
    QtWidgets.QApplication.sendEvent(spin, event)
    assert spin.value() == before
    assert scroll.verticalScrollBar().value() > 0


def wheel_down(widget) -> None:
    """One notch of the mouse wheel, down, over the middle of ``widget``."""
    pos = QtCore.QPointF(widget.width() / 2, widget.height() / 2)
    event = QtGui.QWheelEvent(pos, widget.mapToGlobal(pos), QtCore.QPoint(0, 0),
                              QtCore.QPoint(0, -120), QtCore.Qt.MouseButton.NoButton,
                              QtCore.Qt.KeyboardModifier.NoModifier,
                              QtCore.Qt.ScrollPhase.NoScrollPhase, False)  # fmt: skip
    QtWidgets.QApplication.sendEvent(widget, event)


def test_the_wheel_over_the_notes_box_scrolls_its_text(window, qtbot):
    # The wheel over the preset's notes opened "internal error: RecursionError": the notes'
    # scroll bar handed the wheel to the scroll area around it, which is the notes box itself.
    notes = window.controls.preset.notes_edit
    notes.setPlainText("\n".join(f"line {i}" for i in range(200)))
    notes.clearFocus()
    bar = notes.verticalScrollBar()
    qtbot.waitUntil(lambda: bar.maximum() > 0, timeout=WAIT_MS)
    wheel_down(notes.viewport())
    assert bar.value() > 0


def test_help_lists_the_keys_and_says_what_the_tuner_is(window, qtbot):
    import tactile_core as tc

    menu = next(a.menu() for a in window.menuBar().actions() if a.text() == "&Help")
    actions = {a.text(): a for a in menu.actions()}
    actions["Keyboard shortcuts"].trigger()
    dialog = window.findChild(QtWidgets.QDialog, "shortcuts")
    text = " ".join(label.text() for label in dialog.findChildren(QtWidgets.QLabel))
    for key in ("Space", "Esc", "1-4", "Shift+click", "Ctrl+Q", "arrow keys"):
        assert key in text
    dialog.close()
    actions["About tactile-tuner"].trigger()
    dialog = window.findChild(QtWidgets.QDialog, "about")
    assert tc.__version__ in dialog.findChild(QtWidgets.QLabel).text()
    dialog.close()
