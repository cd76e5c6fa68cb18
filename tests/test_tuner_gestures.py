"""What the hands do on the tune tab's plots, and what the array gets: dragging the cursor holds
the trace at that instant on the array as on the views, and draw mode keeps the method picked in
it and puts back the scene it changed. (A click that pulses a tactor: test_tuner_pulses.py.)"""

import numpy as np
import pytest
from PySide6 import QtCore

import tactile_core as tc

from .helpers import record_sent
from .tuner_support import WAIT_MS, frames_sent, frames_shown

Key = QtCore.Qt.Key


def test_dragging_the_cursor_holds_and_shows_that_moment(window, qtbot):
    scene = window.state.scene.replace(shape=tc.Line((0.5, 1.84), (4.5, 4.16)), method="AS",
                                       mu=0.0, gamma=1.0, playing=True)  # fmt: skip
    window.state.set_scene(scene)
    window.tune.curves.scrubbed.emit(0.5)  # a quarter into the 2 s trace: x = 1.5
    assert window.state.scene.hold_s == 0.5  # the array holds that instant, as the views show it
    window.state.set_view_mode("corrected")
    expected = tc.render(scene.shape, "AS", 0.25)
    qtbot.waitUntil(
        lambda: np.allclose(window.tune.heatmap.values, expected, atol=1e-12), timeout=WAIT_MS
    )
    assert window.tune.curves.cursor.value() == pytest.approx(0.5)


def test_scrubbing_plays_that_instant_on_the_array(window, qtbot):
    window.state.update(mu=0.0, gamma=1.0)
    sent = record_sent(window)
    window.tune.curves.scrubbed.emit(0.9)  # the cursor dragged to 0.9 s of the 2 s trace
    scene = window.state.scene
    t = scene.trace().parameter1(0.9)
    expected = tc.quantize(tc.render(scene.shape, scene.method, np.array([t]))[0], 23)
    expected = expected.reshape(-1)[window.device.profile.array.channel_index]
    qtbot.waitUntil(lambda: any(np.array_equal(f, expected) for f in list(sent)),
                    timeout=WAIT_MS)  # fmt: skip
    first = next(i for i, f in enumerate(list(sent)) if np.array_equal(f, expected))
    frames_sent(qtbot, sent, 30)  # 0.1 s of frames at 300 Hz
    assert all(np.array_equal(f, expected) for f in sent[first:])  # held, not moving on
    assert "paused" not in window.device.stats.status
    window.tabs.setFocus()
    qtbot.keyClick(window.tabs, Key.Key_Space)  # Space plays the trace again
    assert window.state.scene.playing and window.state.scene.hold_s is None


def test_a_held_instant_offers_play_and_the_button_plays_on(window, qtbot):
    # The controls' button said "Pause (Space)" while the cursor held an instant (the pattern
    # editor's said "Play"), and a click paused instead of playing on.
    button = window.controls.playback.play_button
    assert button.text() == "Pause (Space)"
    window.tune.curves.scrubbed.emit(0.9)
    assert window.state.held and button.text() == "Play (Space)"
    qtbot.mouseClick(button, QtCore.Qt.MouseButton.LeftButton)
    assert window.state.scene.playing and not window.state.held
    assert button.text() == "Pause (Space)"


def test_draw_mode_clears_its_curves_and_restores_the_scene(window, qtbot):
    before = window.state.scene.replace(method="IM", pause_s=0.7)
    window.state.set_scene(before)
    qtbot.waitUntil(lambda: window.tune.curves.curves is not None, timeout=WAIT_MS)
    window.controls.playback.draw_check.setChecked(True)
    qtbot.waitUntil(lambda: window.tune.curves.curves is None, timeout=WAIT_MS)
    assert window.state.scene.method == "AS" and window.state.scene.pause_s == 0.0
    window.controls.playback.draw_check.setChecked(False)
    scene = window.state.scene
    assert (scene.method, scene.pause_s, scene.shape) == ("IM", 0.7, before.shape)
    qtbot.waitUntil(lambda: window.tune.curves.curves is not None, timeout=WAIT_MS)


def test_a_method_picked_in_draw_mode_stays_and_titles_the_curves(window, qtbot):
    window.state.update(method="MM")
    window.controls.playback.draw_check.setChecked(True)
    assert window.state.scene.method == "AS"
    window.tabs.setFocus()
    qtbot.keyClick(window.tabs, Key.Key_1)  # CT
    title = window.tune.curves.plotItem.titleLabel
    qtbot.waitUntil(lambda: title.text.startswith("CT"), timeout=WAIT_MS)
    window.state.update(playing=True)  # the point held down: no trace, no cursor
    frames_shown(qtbot, window)
    assert not window.tune.curves.cursor.isVisible()
    window.controls.playback.draw_check.setChecked(False)
    assert window.state.scene.method == "CT" and window.state.scene.shape.length > 1
    qtbot.waitUntil(lambda: title.text.startswith("CT activ"), timeout=WAIT_MS)
