"""The device box says what the current setting costs in felt terms (one row of
``tactile bench --part trade``), follows the setting, and is hidden with the status line when
it would give a stimulus away."""

import pytest

import tactile_core as tc
from tactile_core.bench import felt_readout
from tactile_core.device.profile import find_profile
from tactile_core.rendering.scene import Scene

pytestmark = pytest.mark.usefixtures("qt_settings")
LINE = tc.Line((0.5, 1.84), (4.5, 4.16))


@pytest.fixture
def window(qtbot):
    from tactile_tuner.window import MainWindow

    win = MainWindow(restore=False, process=False)
    qtbot.addWidget(win)
    win.resize(1280, 720)
    win.show()
    qtbot.waitExposed(win)
    yield win
    win.close()


def test_the_read_out_is_the_trade_tables_row_for_the_scene(window, qtbot):
    window.state.update(shape=LINE, method="AS", mu=0.33, gamma=0.7, rate_hz=300.0,
                        filter="point", dither=False, compensate_motors=False)  # fmt: skip
    label = window.device_panel.felt_label
    qtbot.waitUntil(lambda: "at 300 Hz / 23 levels" in label.text(), timeout=10_000)
    expected = felt_readout(window.state.scene, window.device.profile, window.device.lead_ms)
    assert label.text() == expected.text
    assert label.text().startswith("felt ripple 1.1")  # AS on the line: 1.14 (best 1.09)
    assert "30/60 ms" in label.toolTip()  # the motor constants it assumes


def test_the_read_out_follows_the_frame_rate_and_motor_aware_drive(window, qtbot):
    label = window.device_panel.felt_label
    window.state.update(shape=LINE, method="AS", rate_hz=25.0, compensate_motors=False)
    qtbot.waitUntil(lambda: "at 25 Hz / 23 levels" in label.text(), timeout=10_000)
    plain = felt_readout(window.state.scene, window.device.profile, window.device.lead_ms)
    window.state.update(compensate_motors=True)
    aware = felt_readout(window.state.scene, window.device.profile, window.device.lead_ms)
    assert aware.lag_mm < plain.lag_mm - 0.5  # motor-aware drive: the felt point keeps up
    qtbot.waitUntil(lambda: label.text() == aware.text, timeout=10_000)


def test_a_source_scene_is_not_predicted_and_says_why(window, qtbot):
    label = window.device_panel.felt_label
    window.state.update(shape=None)
    qtbot.waitUntil(lambda: label.text().startswith("felt: not predicted"), timeout=10_000)


def test_hidden_with_the_status_line(window, qtbot):
    panel = window.device_panel
    panel.set_status_visible(False)
    assert not panel.felt_label.isVisible() and not panel.status_label.isVisible()
    assert not panel.felt_cost.enabled
    panel.set_status_visible(True)
    assert panel.felt_label.isVisible() and panel.felt_cost.enabled


def test_the_read_out_assumes_the_profiles_motors_and_needs_a_grid():
    scene = Scene(LINE, "AS")
    palm = felt_readout(scene, find_profile("palm-5x6"))
    lra = felt_readout(scene, find_profile("lra-5x6"))  # the same grid, 8/10 ms LRAs
    assert (palm.motor_label, lra.motor_label) == ("30/60 ms", "8/10 ms")
    assert lra.lag_mm < palm.lag_mm - 0.5 and lra.setting.levels == 64
    assert felt_readout(scene, find_profile("belt-8")) is None  # actuators anywhere


def _numbers_shown(qtbot, label):
    qtbot.waitUntil(lambda: label.text().startswith("felt ripple"), timeout=10_000)


def test_draw_mode_is_not_predicted(window, qtbot):
    # Draw mode's free point is a zero-length line: the read-out gave its ripple, lag and onset.
    label = window.device_panel.felt_label
    _numbers_shown(qtbot, label)
    window.tune.gestures.set_draw_mode(True)
    qtbot.waitUntil(lambda: label.text() == "felt: not predicted (draw mode's free point, moved "
                    "by hand: no trace to follow)", timeout=10_000)  # fmt: skip
    window.tune.gestures.set_draw_mode(False)  # the scene from before: its numbers again
    _numbers_shown(qtbot, label)


def test_another_programs_points_are_not_predicted(window, qtbot):
    label = window.device_panel.felt_label
    _numbers_shown(qtbot, label)
    window.serve_panel.port_spin.setValue(0)
    window.serve_panel.toggle.click()
    qtbot.waitUntil(lambda: window.serve.serving == "on", timeout=10_000)
    qtbot.waitUntil(lambda: label.text() == "felt: not predicted (another program drives free "
                    "points)", timeout=10_000)  # fmt: skip
    window.serve_panel.toggle.click()
    _numbers_shown(qtbot, label)


def test_a_pattern_is_not_predicted_and_says_so(window, qtbot):
    from tactile_core.files.pattern import example_patterns

    label = window.device_panel.felt_label
    assert window.files.open_pattern_file(example_patterns()["taps"])
    qtbot.waitUntil(lambda: label.text() == "felt: not predicted (a pattern plays: the model "
                    "follows a point along a shape)", timeout=10_000)  # fmt: skip
