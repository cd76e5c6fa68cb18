"""Motor-aware drive in the tuner: the setting under Correction streams overdrive while a motor
spins up, and Compare shows the drive sent beside the plain drive."""

import numpy as np
import pytest

import tactile_core as tc
from tactile_core.device.profile import default_profile
from tactile_core.rendering.curves import activation_curves
from tactile_core.rendering.motor_drive import motor_drive

from .helpers import record_sent

pytestmark = pytest.mark.usefixtures("qt_settings")
LINE = tc.Line((0.5, 1.84), (4.5, 4.16))


@pytest.fixture
def window(qtbot):
    from tactile_tuner.window import MainWindow

    win = MainWindow(restore=False, process=False)  # the stream as a thread: its taps here
    qtbot.addWidget(win)
    win.resize(1200, 800)
    win.show()
    qtbot.waitExposed(win)
    qtbot.waitUntil(lambda: win.device.stats.frames > 5, timeout=10000)
    yield win
    win.close()


def test_the_setting_streams_spin_up_overdrive_then_the_drive_asked_for(window, qtbot):
    check = window.controls.correction.motor_drive_check
    assert check.isEnabled() and not check.isChecked()  # the palm array has motor constants
    check.click()
    assert window.state.scene.compensate_motors
    sent = record_sent(window)
    # One tactor, (1, 4), asked for half drive: level 11; from rest its motor needs full drive
    # (level 22) for several frames first (tests/test_motor_drive.py works them by hand).
    point = tc.Line((1.5, 4.5), (1.5, 4.5))
    window.state.update(shape=point, method="AS", mu=0.0, gamma=1.0, gain=0.5, dither=False)
    channel = 4 * 5 + 1

    def overdrive_then_held():
        levels = [int(f[channel]) for f in list(sent)]
        return 22 in levels and 11 in levels[levels.index(22) :]

    qtbot.waitUntil(overdrive_then_held, timeout=10000)
    check.click()
    assert not window.state.scene.compensate_motors


def test_compare_shows_the_motor_aware_drive_beside_the_plain_one(window, qtbot):
    window.tabs.setCurrentWidget(window.compare)
    window.state.update(shape=LINE, mu=0.33, gamma=0.7, compensate_motors=True)
    view = window.compare.curves["AS"]
    qtbot.waitUntil(lambda: view.curves is not None and view._raw, timeout=5000)
    plain = activation_curves(LINE, "AS", mu=0.33, gamma=0.7, samples=600)
    rate = 599 / 2.0  # the curves' samples, each held until the next
    expected, _ = motor_drive(plain.corrected, default_profile().motor, rate)
    np.testing.assert_allclose(view.curves.raw, plain.corrected)  # dashed: plain drive
    np.testing.assert_allclose(view.curves.corrected, expected)  # solid: what is sent
    assert view.curves.corrected.max() == 1.0 > plain.corrected.max()
    window.state.update(compensate_motors=False)
    qtbot.waitUntil(lambda: not view._raw, timeout=5000)
    np.testing.assert_allclose(view.curves.corrected, plain.corrected)
