"""A click on the heatmap pulses one tactor on the array (Shift holds it), beside the tuning:
the controls, the window's title and the curves keep showing the user's tuning while a tactor
is pulsed or held, and a change to the tuning meanwhile releases the tactor and is kept."""

import numpy as np
from PySide6 import QtCore

from .helpers import record_sent
from .tuner_support import WAIT_MS

Key = QtCore.Qt.Key
FULL = 22  # full drive on the palm array's 23 levels


def _alone(levels, col, row) -> bool:
    """Whether ``levels`` (rows, cols) light tactor (col, row) alone, at full drive."""
    lit = np.argwhere(levels > 0)
    return levels[row, col] == FULL and len(lit) == 1


def _tune(window, **changes):
    """The user's tuning: ``changes`` on the scene, its plots drawn."""
    assert window.state.update(**changes)
    window.tune.refresh()
    return window.state.scene


def test_clicking_a_cell_pulses_its_tactor_and_shift_holds_it(window, qtbot):
    sent = record_sent(window)  # the pulse lasts 0.3 s: every frame, not the newest one
    window.tune.heatmap.cell_clicked.emit(3, 4, False)
    qtbot.waitUntil(lambda: any(lv[4 * 5 + 3] == FULL for lv in list(sent)), timeout=WAIT_MS)
    pulse = [lv for lv in list(sent) if lv[4 * 5 + 3] == FULL]
    assert all((lv > 0).sum() == 1 for lv in pulse)  # that tactor alone
    qtbot.waitUntil(lambda: not window.tune.gestures.pulsing, timeout=WAIT_MS)  # it ends
    window.tune.heatmap.cell_clicked.emit(1, 1, True)  # Shift: held
    # held: nothing timed ends it, as the pulse's timer ends a pulse
    assert not window.tune.gestures._pulse_timer.isActive()
    qtbot.waitUntil(lambda: _alone(window.device.sent_levels(), 1, 1), timeout=WAIT_MS)
    window.tune.heatmap.cell_clicked.emit(1, 1, False)  # a click releases it
    assert not window.tune.gestures.pulsing
    qtbot.waitUntil(lambda: window.device.streamer.scene.shape == window.state.scene.shape,
                    timeout=WAIT_MS)  # fmt: skip


def test_holding_a_tactor_leaves_the_controls_title_and_curves_on_the_tuning(window, qtbot):
    tuning = _tune(window, method="IM", mu=0.77, gamma=0.142)
    title = window.windowTitle()
    controls = window.controls
    window.tune.heatmap.cell_clicked.emit(2, 2, True)  # Shift+click (2,2): held
    qtbot.waitUntil(lambda: _alone(window.device.sent_levels(), 2, 2), timeout=WAIT_MS)
    assert window.state.scene == tuning  # the pulse plays beside the tuning, not in it
    assert window.windowTitle() == title and "IM, mu 0.77, gamma 0.142" in title
    assert controls.method.method_buttons.checkedButton().text().split()[1] == "IM"
    assert controls.correction.mu_spin.value() == 0.77
    assert controls.correction.gamma_spin.value() == 0.142
    assert controls.shape.isEnabled() and window.state.scene.duration_s == tuning.duration_s
    window.tune.refresh()  # as a redraw would, while held: the tuning's curves, not nothing
    curves = window.tune.curves
    assert curves.curves is not None and len(curves.curves.cells) > 1
    assert curves.plotItem.titleLabel.text.startswith("IM activation")
    # the heatmap shows what the array gets: the held tactor
    qtbot.waitUntil(lambda: window.tune.heatmap.values[2, 2] == 1.0, timeout=WAIT_MS)
    assert np.count_nonzero(window.tune.heatmap.values) == 1


def test_a_change_while_holding_releases_the_tactor_and_is_kept(window, qtbot):
    _tune(window, method="IM", mu=0.77, gamma=0.142)
    window.tune.heatmap.cell_clicked.emit(2, 2, True)
    qtbot.waitUntil(lambda: _alone(window.device.sent_levels(), 2, 2), timeout=WAIT_MS)
    window.tabs.setFocus()
    qtbot.keyClick(window.tabs, Key.Key_3)  # AS, while the tactor is held
    assert not window.tune.gestures.pulsing  # released: the change plays at once
    assert window.device.streamer.scene.method == "AS"
    window.controls.correction.mu_slider.setValue(23)  # mu dragged to 0.23
    assert window.device.streamer.scene.mu == 0.23
    qtbot.keyClick(window.tabs, Key.Key_Escape)  # all off: the changes stay
    scene = window.state.scene
    assert (scene.method, scene.mu, scene.gamma) == ("AS", 0.23, 0.142)
    assert not scene.playing and not window.device.streamer.scene.playing
    assert window.controls.correction.mu_spin.value() == 0.23


def test_space_releases_a_held_tactor_and_the_tuning_plays_from_its_start(window, qtbot):
    tuning = _tune(window, method="AS", mu=0.0, gamma=1.0, playing=True)
    window.tune.heatmap.cell_clicked.emit(4, 0, True)
    qtbot.waitUntil(lambda: _alone(window.device.sent_levels(), 4, 0), timeout=WAIT_MS)
    window.tabs.setFocus()
    qtbot.keyClick(window.tabs, Key.Key_Space)
    assert not window.tune.gestures.pulsing and window.state.scene == tuning  # still playing
    playing = window.device.streamer.scene  # the tuning, from its start (another shape)
    assert (playing.shape, playing.method, playing.playing) == (tuning.shape, "AS", True)


def test_esc_while_a_tactor_is_held_turns_everything_off(window, qtbot):
    window.state.update(playing=True)
    window.tune.heatmap.cell_clicked.emit(0, 5, True)
    qtbot.waitUntil(lambda: _alone(window.device.sent_levels(), 0, 5), timeout=WAIT_MS)
    window.tabs.setFocus()
    qtbot.keyClick(window.tabs, Key.Key_Escape)
    assert not window.tune.gestures.pulsing and not window.state.scene.playing
    qtbot.waitUntil(lambda: not window.device.sent_levels().any(), timeout=WAIT_MS)


def test_the_device_status_says_a_tactor_is_pulsed_then_the_tuning_again(window, qtbot):
    # While (2,3) was held under MM the status read "streaming CT at 300 Hz", the pulse's own
    # method: a user tuning MM could not tell what played.
    _tune(window, method="MM")
    status = window.device_panel.status_label
    window.tune.heatmap.cell_clicked.emit(2, 3, True)  # held: as long as the test needs
    qtbot.waitUntil(lambda: "holding tactor (2,3) (CT) at 300 Hz" in status.text(),
                    timeout=WAIT_MS)  # fmt: skip
    assert "streaming CT" not in status.text()
    window.tune.heatmap.cell_clicked.emit(2, 3, False)  # released: the tuning plays
    qtbot.waitUntil(lambda: "streaming MM at 300 Hz" in status.text(), timeout=WAIT_MS)
    assert "tactor" not in status.text()


def test_a_short_pulse_is_named_in_the_device_status_while_it_plays(window, qtbot):
    status = window.device_panel.status_label
    window.tune.heatmap.cell_clicked.emit(4, 0, False)
    qtbot.waitUntil(lambda: "pulsing tactor (4,0) (CT) at 300 Hz" in status.text(),
                    timeout=WAIT_MS)  # fmt: skip
    qtbot.waitUntil(lambda: "streaming AS at 300 Hz" in status.text(), timeout=WAIT_MS)
