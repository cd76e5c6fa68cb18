"""The tuner's "Measure the motors..." dialog: tactile measure on the tuner's device, the
profile it writes put to use, and the views then saying "measured" instead of "estimate"."""

import pytest
from PySide6 import QtGui

pytestmark = pytest.mark.usefixtures("qt_settings")


@pytest.fixture
def window(qtbot):
    from tactile_tuner.window import MainWindow

    win = MainWindow(restore=False, process=False)
    qtbot.addWidget(win)
    win.show()
    qtbot.waitExposed(win)
    qtbot.waitUntil(lambda: win.device.stats.frames > 5, timeout=10000)
    yield win
    win.close()


def menu_action(win, text):
    found = [a for a in win.findChildren(QtGui.QAction) if a.text() == text]
    assert found, f"no action {text!r}"
    return found[0]


def test_measure_dialog_measures_the_simulated_array_and_uses_the_profile(window, qtbot,
                                                                          tmp_path):  # fmt: skip
    assert "(estimate)" in window.controls.correction.motor_drive_check.toolTip()
    menu_action(window, "Measure the motors...").trigger()
    dialog = window.measure_dialog
    assert dialog.input_edit.text() == "sim"  # the simulated array: the simulated sensor
    dialog.tactors_edit.setText("r0c0")
    dialog.quick_check.setChecked(True)
    out = tmp_path / "palm-measured.json"
    dialog.out_edit.setText(str(out))
    assert dialog.arguments()[:4] == ["measure", "--input", "sim", "--device"]
    dialog.measure_button.click()
    qtbot.waitUntil(lambda: dialog.measure_button.isEnabled(), timeout=90_000)
    log = dialog.log_view.toPlainText()
    assert "r0c0: spin-up" in log and "median over 1 tactors" in log, log
    assert dialog.result["tau_up_ms"] == pytest.approx(30.0, rel=0.1)
    assert dialog.use_button.isEnabled() and out.is_file()
    dialog.use_button.click()
    assert window.device.profile.motor.measured
    tip = window.controls.correction.motor_drive_check.toolTip()
    assert "measured" in tip and "(estimate)" not in tip
