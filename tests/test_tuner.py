"""The tuner, driven through its controls (pytest-qt), checked on what the views and the
simulated array show."""

import csv
import json
import math
import subprocess
import sys

import numpy as np
import pytest
from PySide6 import QtCore, QtWidgets

import tactile_core as tc
from tactile_core.files.presets import Preset, builtin_presets
from tactile_core.rendering.scene import Scene

pytestmark = pytest.mark.usefixtures("qt_settings")


@pytest.fixture
def window(qtbot):
    from tactile_tuner.window import MainWindow

    win = MainWindow(restore=False, process=False)  # the stream as a thread: quicker
    qtbot.addWidget(win)
    win.resize(1200, 800)
    win.show()
    qtbot.waitExposed(win)
    qtbot.waitUntil(lambda: win.device.stats.frames > 5, timeout=10000)
    yield win
    win.close()


def lit_levels(win):
    return win.device.sent_levels()


def wait_for_levels(qtbot, win, predicate, timeout=3000):
    qtbot.waitUntil(lambda: predicate(lit_levels(win)), timeout=timeout)


def test_starts_on_the_simulated_array_and_streams(window, qtbot):
    assert window.device.simulated
    assert window.state.scene.method == "AS"
    wait_for_levels(qtbot, window, lambda lv: lv.any())
    assert "streaming" in window.device.stats.state


def test_keys_1_to_4_select_the_method_and_the_array_follows(window, qtbot):
    window.tune.heatmap.setFocus()
    qtbot.keyClick(window.tune.heatmap, QtCore.Qt.Key.Key_1)
    assert window.state.scene.method == "CT"
    assert window.controls.method.method_buttons.checkedButton().objectName() == "method_CT"
    # CT is bi-level: one tactor at full level (22) on the array.
    wait_for_levels(qtbot, window, lambda lv: (lv > 0).sum() == 1 and lv.max() == 22)
    qtbot.keyClick(window.tune.heatmap, QtCore.Qt.Key.Key_4)
    assert window.state.scene.method == "IM"
    qtbot.keyClick(window.tune.heatmap, QtCore.Qt.Key.Key_2)
    assert window.state.scene.method == "MM"


def test_mu_spin_box_reaches_the_wire(window, qtbot):
    window.controls.correction.mu_spin.setValue(1.0)
    assert window.state.scene.mu == 1.0
    assert window.controls.correction.mu_slider.value() == 100
    # mu = 1: every lit tactor at full level, whatever its area.
    wait_for_levels(qtbot, window, lambda lv: lv.any() and set(lv[lv > 0].tolist()) == {22})


def test_gamma_slider_is_logarithmic(window):
    from tactile_tuner.controls import gamma_to_slider, slider_to_gamma

    assert slider_to_gamma(0) == pytest.approx(0.1)
    assert slider_to_gamma(500) == pytest.approx(1.0)
    assert slider_to_gamma(1000) == pytest.approx(10.0)
    assert gamma_to_slider(0.7) == round((math.log10(0.7) + 1) * 500)
    window.controls.correction.gamma_slider.setValue(750)  # 10 ** 0.5
    assert window.state.scene.gamma == pytest.approx(3.162, abs=1e-3)
    assert window.controls.correction.gamma_spin.value() == pytest.approx(3.16, abs=0.01)


def test_nan_from_a_control_is_rejected_and_nothing_changes(window, qtbot):
    before = window.state.scene
    with qtbot.waitSignal(window.state.error_raised):
        assert not window.state.update(mu=float("nan"))
    assert window.state.scene == before
    assert "mu" in window.last_error
    assert window.device.streamer.running


def test_view_modes_show_raw_corrected_sent_and_felt(window, qtbot):
    window.state.update(shape=tc.Line((2.2, 3.5), (2.2, 3.5)), pause_s=0.0)  # a steady point
    window.state.set_view_mode("raw")
    # AS at (2.2, 3.5): 0.3 on (1, 3), 0.7 on (2, 3), nothing else
    qtbot.waitUntil(lambda: abs(window.tune.heatmap.values[3, 1] - 0.3) < 1e-12, timeout=2000)
    raw = window.tune.heatmap.values.copy()
    assert raw[3, 2] == pytest.approx(0.7) and raw.sum() == pytest.approx(1.0)
    window.state.set_view_mode("corrected")
    qtbot.waitUntil(lambda: window.tune.heatmap.values[3, 1] != pytest.approx(0.3), timeout=2000)
    np.testing.assert_allclose(window.tune.heatmap.values, tc.correct(raw, 0.33, 0.7))
    window.state.set_view_mode("sent")
    # whole device levels, once the display's next tick has drawn them
    qtbot.waitUntil(
        lambda: set(np.unique(np.round(window.tune.heatmap.values * 22, 9))) <= set(range(23)),
        timeout=3000,
    )
    sent = window.tune.heatmap.values.copy()
    window.state.set_view_mode("felt")
    qtbot.waitUntil(lambda: not np.array_equal(window.tune.heatmap.values, sent), timeout=3000)
    felt = window.tune.heatmap.values
    assert (felt <= window.device.profile.felt(np.ones(1))[0]).all()
    assert felt[3, 2] > 0


def test_space_pauses_and_resumes(window, qtbot):
    window.tune.heatmap.setFocus()
    qtbot.keyClick(window.tune.heatmap, QtCore.Qt.Key.Key_Space)
    assert not window.state.scene.playing
    wait_for_levels(qtbot, window, lambda lv: not lv.any())
    qtbot.waitUntil(lambda: window.device.stats.state == "paused", timeout=3000)
    qtbot.keyClick(window.tune.heatmap, QtCore.Qt.Key.Key_Space)
    assert window.state.scene.playing
    wait_for_levels(qtbot, window, lambda lv: lv.any())


def test_escape_turns_everything_off_even_from_a_text_field(window, qtbot):
    window.controls.trace.duration_spin.setFocus()
    qtbot.keyClick(window.controls.trace.duration_spin, QtCore.Qt.Key.Key_Escape)
    assert not window.state.scene.playing
    wait_for_levels(qtbot, window, lambda lv: not lv.any())
    qtbot.mouseClick(window.controls.playback.play_button, QtCore.Qt.MouseButton.LeftButton)
    assert window.state.scene.playing
    qtbot.mouseClick(window.controls.playback.off_button, QtCore.Qt.MouseButton.LeftButton)
    assert not window.state.scene.playing


def test_shape_controls_edit_the_shape(window):
    window.controls.shape.shape_combo.setCurrentIndex(1)  # circle
    assert isinstance(window.state.scene.shape, tc.Circle)
    radius = window.controls.shape.shape_fields["circle"][2]
    radius.setValue(1.5)
    assert window.state.scene.shape.radius == 1.5
    window.controls.shape.shape_combo.setCurrentIndex(2)
    assert isinstance(window.state.scene.shape, tc.Square)
    window.controls.trace.duration_spin.setValue(3.0)
    window.controls.trace.filter_combo.setCurrentText("point")
    assert window.state.scene.duration_s == 3.0 and window.state.scene.filter == "point"
    window.controls.trace.emphasis_spin.setValue(0.5)  # corner emphasis, selectable in the tuner
    window.controls.trace.gain_spin.setValue(0.8)
    assert window.state.scene.emphasis == 0.5 and window.state.scene.gain == 0.8


def test_curves_and_heatmap_frames_share_colours(window):
    curves = window.tune.shown_curves
    assert set(window.tune.heatmap._frames) == set(curves.cells)
    solid = window.tune.curves._lines[::2]  # per tactor: corrected (solid), then raw (dashed)
    colours = {frame.pen().color().name() for frame in window.tune.heatmap._frames.values()}
    assert len(colours) == len(curves.cells)  # one colour per tactor
    for i, cell in enumerate(curves.cells):
        frame = window.tune.heatmap._frames[cell]
        assert frame.pen().color().name() == solid[i].opts["pen"].color().name(), cell
        np.testing.assert_array_equal(solid[i].yData, curves.corrected[:, i])


def test_preset_round_trip(window, tmp_path):
    window.state.update(
        method="IM", mu=0.2, gamma=1.3, shape=tc.Circle((2.5, 3.5), 1.5), pause_s=0.0
    )
    path = tmp_path / "mine.json"
    assert window.files.save_preset_file(path, name="mine", notes="felt good")
    saved = window.state.scene
    window.state.update(method="CT", mu=0.5)
    assert window.files.load_preset_file(path)
    assert window.state.scene.replace(epoch=0) == saved.replace(epoch=0)
    assert window.files.preset_notes == "felt good"
    data = json.loads(path.read_text())
    assert data["version"] == 1 and data["method"] == "IM"


@pytest.mark.parametrize(
    ("content", "words"),
    [
        ("{ not json", "not valid JSON"),
        (None, "'mu'"),  # filled in below: mu = 1.5
        ('{"format": "tactile-preset", "version": 1}', "'shape' is missing"),
        ('{"format": "tactile-preset", "version": 9, "shape": null}', "newer"),
    ],
)
def test_bad_preset_shows_what_is_wrong_and_changes_nothing(window, tmp_path, content, words):
    path = tmp_path / "bad.json"
    if content is None:
        data = Preset(Scene(tc.Circle((2.5, 3), 2))).to_dict()
        data["mu"] = 1.5
        content = json.dumps(data)
    path.write_text(content)
    before = window.state.scene
    assert not window.files.load_preset_file(path)
    assert window.state.scene == before
    assert words in window.last_error and str(path) in window.last_error


def test_built_in_presets_hold_the_papers_conditions(window):
    presets = builtin_presets()
    expected = {
        "exp1-line": (0.33, 0.7, 0.5),
        "exp1-circle": (0.33, 0.7, 0.5),
        "exp2-L1": (0.33, 0.7, 0.5),
        "exp2-L2": (0.0, 1.4, 0.5),
        "exp2-L3": (0.33, 0.7, 0.5),
        "exp2-L4": (0.0, 1.4, 0.5),
        "exp3-circle": (0.33, 0.7, 0.0),
        "exp3-square": (0.33, 0.7, 0.0),
    }
    assert set(presets) == set(expected)
    for name, (mu, gamma, pause) in expected.items():
        assert window.files.load_preset_file(presets[name]), window.last_error
        s = window.state.scene
        assert (s.mu, s.gamma, s.pause_s, s.duration_s) == (mu, gamma, pause, 2.0), name
    window.files.load_preset_file(presets["exp1-line"])
    line = window.state.scene.shape
    slope = (line.p1[1] - line.p0[1]) / (line.p1[0] - line.p0[0])
    assert slope == pytest.approx(0.58) and line.p0[0] < line.p1[0]  # left to right
    window.files.load_preset_file(presets["exp2-L1"])
    mid = np.mean([window.state.scene.shape.p0, window.state.scene.shape.p1], axis=0)
    assert (mid == np.round(mid)).all()  # a cell corner
    window.files.load_preset_file(presets["exp2-L3"])
    mid = np.mean([window.state.scene.shape.p0, window.state.scene.shape.p1], axis=0)
    assert ((mid - 0.5) == np.round(mid - 0.5)).all()  # a tactor centre
    window.files.load_preset_file(presets["exp3-square"])
    assert window.state.scene.shape == tc.Square((2.5, 3.5), 4.0)


def test_exports(window, tmp_path):
    window.state.update(mu=0.33, gamma=0.7)
    for suffix in (".csv", ".png", ".svg"):
        assert window.files.export_curves(tmp_path / f"curves{suffix}"), window.last_error
        assert (tmp_path / f"curves{suffix}").stat().st_size > 500
    header = next(csv.reader((tmp_path / "curves.csv").read_text().splitlines()))
    assert header[0] == "time" and header[1].endswith(" raw") and header[2].endswith(" corrected")
    assert (tmp_path / "curves.svg").read_text().lstrip().startswith(("<?xml", "<svg"))
    assert window.files.export_lut(tmp_path / "lut.h")
    assert window.files.export_lut(tmp_path / "lut.csv")
    rows = list(csv.DictReader((tmp_path / "lut.csv").read_text().splitlines()))
    assert len(rows) == 256
    levels = [int(r["level"]) for r in rows]
    # Worked by hand: raw 0 -> off; raw 255 -> full (22); raw 64: I = 64/255 = 0.25098,
    # I^0.7 = 0.37977, 0.67 * 0.37977 + 0.33 = 0.58444, floor(0.58444 * 22 + 0.5) = 13.
    assert levels[0] == 0 and levels[255] == 22 and levels[64] == 13
    # raw 1: I = 1/255, I^0.7 = 0.02072, corrected 0.34388 -> floor(8.065) = 8 (the threshold)
    assert levels[1] == 8
    assert levels == sorted(levels)
    text = (tmp_path / "lut.h").read_text()
    assert "static const uint8_t TACTILE_LUT[256]" in text
    values = [int(v) for v in text.split("{", 1)[1].split("}", 1)[0].replace("\n", " ").split(",")]
    assert values == levels
    assert not window.files.export_lut(tmp_path / "lut.txt")
    assert "must end in" in window.last_error


def test_compare_view_renders_all_four_methods_at_the_same_time(window, qtbot):
    window.tabs.setCurrentWidget(window.compare)
    window.state.update(mu=0.0, gamma=1.0)
    qtbot.waitUntil(
        lambda: all(h.values.any() for h in window.compare.heatmaps.values()), timeout=3000
    )
    frames = {name: h.values for name, h in window.compare.heatmaps.items()}
    assert (frames["CT"] > 0).sum() == 1 and (frames["MM"] > 0).sum() == 1
    assert (frames["AS"] > 0).sum() <= 4 and (frames["IM"] > 0).sum() <= 2
    cursors = {c.cursor.value() for c in window.compare.curves.values()}
    assert len(cursors) == 1  # one time axis


def test_draw_mode_moves_a_free_point_with_ct_and_as_only(window, qtbot):
    window.state.update(method="MM")
    window.controls.playback.draw_check.setChecked(True)
    assert window.tune.heatmap.drawing
    assert window.state.scene.method == "AS"  # MM needs a shape
    mm = window.controls.method.method_buttons.button(1)
    assert not mm.isEnabled() and "need a shape" in mm.toolTip()
    window.press_number(2)
    assert window.state.scene.method == "AS" and "draw mode" in window.last_error
    window.tune.heatmap.point_drawn.emit(1.5, 4.5)  # a tactor centre
    assert window.state.scene.shape == tc.Line((1.5, 4.5), (1.5, 4.5))
    assert window.state.scene.playing
    wait_for_levels(qtbot, window, lambda lv: lv[4, 1] == 22 and (lv > 0).sum() == 1)
    window.tune.heatmap.draw_released.emit()
    wait_for_levels(qtbot, window, lambda lv: not lv.any())
    window.controls.playback.draw_check.setChecked(False)
    assert not window.tune.heatmap.drawing and mm.isEnabled()


def test_closing_the_window_turns_the_array_off(qtbot):
    from tactile_tuner.window import MainWindow

    win = MainWindow(restore=False)
    qtbot.addWidget(win)
    win.show()
    win.state.update(mu=1.0, pause_s=0.0)
    qtbot.waitUntil(lambda: win.device.sent_levels().any(), timeout=10000)
    win.close()
    assert not win.device.streamer.running  # the stream process has ended
    assert not win.device.sent_levels().any()  # and the last frame it sent was all off
    stats = win.device.stats
    assert stats.state == "stopped" and stats.status == "stopped: all off"


def test_last_session_is_restored(qtbot):
    from tactile_tuner.window import MainWindow

    first = MainWindow(restore=True)
    qtbot.addWidget(first)
    first.state.update(method="IM", mu=0.44, shape=tc.Circle((2.5, 3.0), 1.25))
    first.state.set_view_mode("sent")
    first.close()
    second = MainWindow(restore=True)
    qtbot.addWidget(second)
    assert second.state.scene.method == "IM" and second.state.scene.mu == 0.44
    assert second.state.scene.shape == tc.Circle((2.5, 3.0), 1.25)
    assert second.state.view_mode == "sent"
    second.close()


def test_damaged_settings_fall_back_to_the_default(qtbot):
    from tactile_tuner.window import MainWindow

    QtCore.QSettings().setValue("scene", "{broken")
    win = MainWindow(restore=True)
    qtbot.addWidget(win)
    assert win.state.scene.method == "AS"
    win.close()


def test_a_missing_port_is_reported_and_the_simulated_array_keeps_running(window, qtbot):
    window.device_panel.port_combo.setCurrentText("/dev/ttyNOPE7")
    qtbot.mouseClick(window.device_panel.connect_button, QtCore.Qt.MouseButton.LeftButton)
    assert "no such port: /dev/ttyNOPE7" in window.last_error
    assert window.device.simulated and window.device.streamer.running
    n = window.device.stats.frames
    qtbot.waitUntil(lambda: window.device.stats.frames > n + 5, timeout=3000)


def test_connect_to_an_emulated_device_and_disconnect(window, qtbot, emulator_thread):
    emulator, path = emulator_thread
    window.state.update(mu=1.0, pause_s=0.0)
    window.device_panel.port_combo.setCurrentText(path)
    qtbot.mouseClick(window.device_panel.connect_button, QtCore.Qt.MouseButton.LeftButton)
    assert not window.device.simulated, window.last_error
    qtbot.waitUntil(lambda: len(emulator.log) > 30 and any(emulator.log.last()), timeout=5000)
    qtbot.waitUntil(lambda: "achieved" in window.device_panel.status_label.text(), timeout=3000)
    qtbot.mouseClick(window.device_panel.disconnect_button, QtCore.Qt.MouseButton.LeftButton)
    assert window.device.simulated
    # all off before letting go of the device (nothing else writes to it afterwards)
    qtbot.waitUntil(lambda: not any(emulator.log.last()), timeout=3000)


def test_screenshot_command(tmp_path):
    out = tmp_path / "shot.png"
    env = {"QT_QPA_PLATFORM": "offscreen", "HOME": str(tmp_path), "PATH": "/usr/bin:/bin"}
    proc = subprocess.run(
        [sys.executable, "-m", "tactile_tuner.main", "--screenshot", str(out)],
        capture_output=True, text=True, timeout=120, env=env,
    )  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    from PySide6 import QtGui

    image = QtGui.QImage(str(out))
    assert image.width() >= 800 and image.height() >= 600


def test_bad_command_line_files_exit_2(tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text("{")
    for args in (["--preset", str(bad)], ["--profile", str(bad)]):
        proc = subprocess.run(
            [sys.executable, "-m", "tactile_tuner.main", *args, "--screenshot",
             str(tmp_path / "x.png")],
            capture_output=True, text=True, timeout=60,
            env={"QT_QPA_PLATFORM": "offscreen", "PATH": "/usr/bin:/bin"},
        )  # fmt: skip
        assert proc.returncode == 2 and "not valid JSON" in proc.stderr


def test_app_has_no_stray_top_level_message_boxes_after_errors(window):
    window.show_error("test message")
    boxes = [
        w for w in QtWidgets.QApplication.topLevelWidgets() if isinstance(w, QtWidgets.QMessageBox)
    ]
    assert boxes and boxes[-1].text() == "test message"
    for box in boxes:
        box.close()


def test_felt_view_needs_a_response_curve(qtbot, tmp_path):
    from tactile_core.device.profile import default_profile, profile_from_dict
    from tactile_tuner.window import MainWindow

    data = default_profile().to_dict()
    data.pop("response")
    win = MainWindow(profile=profile_from_dict(data), restore=False)
    qtbot.addWidget(win)
    felt = win.controls.playback.view_buttons.button(3)
    assert not felt.isEnabled() and "response" in felt.toolTip()
    win.state.set_view_mode("felt")
    win.controls.set_felt_available(False)
    assert win.state.view_mode == "sent"
    win.close()
