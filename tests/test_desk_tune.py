"""The desk, second pass (issue 19): the Tune, Compare and Blind tabs, the docks, the menus and
the files, looked at as a new user would, with real key and mouse events where there are some."""

import csv
import subprocess
import sys
from collections import Counter

import numpy as np
import pytest
from PySide6 import QtCore, QtGui, QtWidgets

pytestmark = pytest.mark.usefixtures("qt_settings")
Key = QtCore.Qt.Key


@pytest.fixture
def window(qtbot):
    from tactile_tuner.window import MainWindow

    win = MainWindow(restore=False, process=False)  # the stream as a thread: quicker
    qtbot.addWidget(win)
    win.resize(1280, 720)
    win.show()
    qtbot.waitExposed(win)
    qtbot.waitUntil(lambda: win.device.stats.frames > 5, timeout=10000)
    yield win
    win.confirm = lambda title, text: True
    win.close()


def _right_edge(widget, window):
    return widget.mapTo(window, QtCore.QPoint(widget.width(), 0)).x()


@pytest.mark.parametrize("width", [1280, 1400, 1600])
def test_a_refused_method_set_is_shown_inside_the_window(window, qtbot, width):
    window.resize(width, 720)
    for tab, chooser in ((window.compare, window.compare.chooser),
                         (window.blind, window.blind.chooser)):  # fmt: skip
        window.tabs.setCurrentWidget(tab)
        chooser.edit.setText("CT XX")
        qtbot.keyClick(chooser.edit, Key.Key_Return)
        problem = chooser.problem
        qtbot.waitUntil(problem.isVisible)
        assert "XX" in problem.text()
        assert _right_edge(problem, window) <= window.width()
        lines = max(1, problem.height() // problem.fontMetrics().lineSpacing())
        assert problem.fontMetrics().horizontalAdvance(problem.text()) <= problem.width() * lines
        assert chooser.pick.width() >= chooser.pick.sizeHint().width()  # "pick" not clipped


def test_connect_is_disabled_for_the_port_in_use(window, qtbot, emulator_thread):
    _, path = emulator_thread
    panel = window.device_panel
    errors = []
    window.device.error_raised.connect(errors.append)
    panel.port_combo.lineEdit().setText(path)
    qtbot.keyClick(panel.port_combo.lineEdit(), Key.Key_Return)
    qtbot.waitUntil(lambda: window.device.url == path, timeout=5000)
    assert not panel.connect_button.isEnabled()
    qtbot.keyClick(panel.port_combo.lineEdit(), Key.Key_Return)  # again: nothing to do
    assert not errors and window.device.url == path
    panel.port_combo.lineEdit().setText("sim")
    assert panel.connect_button.isEnabled()


def test_felt_amplitude_keeps_the_plots_inside_a_1280_window(window, qtbot):
    check = window.controls.correction.felt_domain_check
    assert check.isEnabled()
    for on in (True, False, True):
        check.setChecked(on)
        qtbot.waitUntil(lambda on=on: window.tune.correction._felt_domain == on)
        QtWidgets.QApplication.processEvents()
        window.tune.fit_heatmap()
        for view in (window.tune.correction, window.tune.curves):
            assert _right_edge(view, window) <= window.width(), on
            # the plot inside its view: never pushed past it by a title wider than the view
            assert view.plotItem.geometry().right() <= view.viewport().width() + 1, on
            assert view.width() >= 250


def test_the_mouse_wheel_over_the_controls_scrolls_them(window, qtbot):
    window.resize(1280, 600)
    scroll = window.controls_scroll
    qtbot.waitUntil(lambda: scroll.verticalScrollBar().maximum() > 0)
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


@pytest.mark.parametrize("how", ["space", "all off"])
def test_pause_and_all_off_leave_the_cursor_and_point_where_they_were(window, qtbot, how):
    curves, heatmap = window.tune.curves, window.tune.heatmap
    qtbot.waitUntil(lambda: curves.cursor.isVisible() and heatmap.point_xy is not None)
    if how == "space":
        window.tabs.setFocus()
        qtbot.keyClick(window.tabs, Key.Key_Space)
    else:
        qtbot.mouseClick(window.controls.playback.off_button, QtCore.Qt.MouseButton.LeftButton)
    assert not window.state.scene.playing
    qtbot.wait(100)
    assert curves.cursor.isVisible() and heatmap.point.isVisible() and heatmap.point_xy is not None
    at = curves.cursor.value()
    qtbot.wait(100)
    assert curves.cursor.value() == at  # frozen where it was paused


def test_scrubbing_plays_that_instant_on_the_array(window, qtbot):
    import tactile_core as tc

    window.state.update(mu=0.0, gamma=1.0)
    window.tune.curves.scrubbed.emit(0.9)  # the cursor dragged to 0.9 s of the 2 s trace
    scene = window.state.scene
    t = scene.trace().parameter1(0.9)
    expected = tc.quantize(tc.render(scene.shape, scene.method, np.array([t]))[0], 23)
    qtbot.waitUntil(lambda: np.array_equal(window.device.sent_levels(), expected), timeout=3000)
    qtbot.wait(150)
    assert np.array_equal(window.device.sent_levels(), expected)  # held, not moving on
    assert "paused" not in window.device.stats.status
    window.tabs.setFocus()
    qtbot.keyClick(window.tabs, Key.Key_Space)  # Space plays the trace again
    assert window.state.scene.playing and window.state.scene.hold_s is None


def test_a_method_picked_in_draw_mode_stays_and_titles_the_curves(window, qtbot):
    window.state.update(method="MM")
    window.controls.playback.draw_check.setChecked(True)
    assert window.state.scene.method == "AS"
    window.tabs.setFocus()
    qtbot.keyClick(window.tabs, Key.Key_1)  # CT
    qtbot.waitUntil(lambda: window.tune.curves.plotItem.titleLabel.text.startswith("CT"))
    window.state.update(playing=True)  # the point held down: no trace, no cursor
    qtbot.wait(100)
    assert not window.tune.curves.cursor.isVisible()
    window.controls.playback.draw_check.setChecked(False)
    assert window.state.scene.method == "CT" and window.state.scene.shape.length > 1
    qtbot.waitUntil(lambda: window.tune.curves.plotItem.titleLabel.text.startswith("CT activ"))


def test_a_typed_extension_of_any_filter_is_kept():
    from tactile_tuner.dialogs import with_filter_extension

    filters = ["CSV (*.csv)", "PNG (*.png)", "SVG (*.svg)"]
    assert with_filter_extension("/a/curves.png", "CSV (*.csv)", filters).name == "curves.png"
    assert with_filter_extension("/a/curves", "CSV (*.csv)", filters).name == "curves.csv"
    assert with_filter_extension("/a/v1.2", "PNG (*.png)", filters).name == "v1.2.png"


def test_exported_curves_name_tactors_as_the_gui_does(window, tmp_path):
    assert window.files.export_curves(tmp_path / "c.csv")
    with open(tmp_path / "c.csv", newline="") as f:
        header = next(csv.reader(f))
    cells = window.tune.shown_curves.cells
    assert header[1:3] == [f"({cells[0][0]},{cells[0][1]}) raw",
                           f"({cells[0][0]},{cells[0][1]}) corrected"]  # fmt: skip
    assert f"({cells[0][0]},{cells[0][1]})" == window.tune.curves._solid[cells[0]].toolTip()


def _contrast(a: QtGui.QColor, b: QtGui.QColor) -> float:
    def lum(c):
        ch = [v / 255 for v in (c.red(), c.green(), c.blue())]
        ch = [v / 12.92 if v <= 0.03928 else ((v + 0.055) / 1.055) ** 2.4 for v in ch]
        return 0.2126 * ch[0] + 0.7152 * ch[1] + 0.0722 * ch[2]

    hi, lo = sorted((lum(a), lum(b)), reverse=True)
    return (hi + 0.05) / (lo + 0.05)


@pytest.mark.parametrize("theme", ["light", "dark"])
def test_all_off_reads_in_both_palettes(qtbot, theme):
    from tactile_tuner.theme import apply_theme
    from tactile_tuner.window import MainWindow

    app = QtWidgets.QApplication.instance()
    style, palette = app.style().name(), app.palette()
    try:
        apply_theme(app, theme)  # as --theme does, before the window is built
        win = MainWindow(restore=False)
        qtbot.addWidget(win)
        win.show()
        qtbot.waitExposed(win)
        button = win.controls.playback.off_button
        image = button.grab().toImage()
        text = button.palette().color(QtGui.QPalette.ColorRole.ButtonText)
        inner = Counter(image.pixelColor(x, y).name() for x in range(4, image.width() - 4)
                        for y in range(4, image.height() - 4))  # fmt: skip
        background = QtGui.QColor(next(c for c, _ in inner.most_common() if c != text.name()))
        assert _contrast(text, background) >= 4.5, (text.name(), background.name())
        win.close()
    finally:
        app.setStyle(style)
        app.setPalette(palette)


def test_screenshot_size_is_the_size_asked(tmp_path):
    out = tmp_path / "shot.png"
    env = {"QT_QPA_PLATFORM": "offscreen", "HOME": str(tmp_path), "PATH": "/usr/bin:/bin"}
    proc = subprocess.run(
        [sys.executable, "-m", "tactile_tuner.main", "--screenshot", str(out), "--size",
         "1280x720"], capture_output=True, text=True, timeout=120, env=env,
    )  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    image = QtGui.QImage(str(out))
    assert (image.width(), image.height()) == (1280, 720)


def test_compare_methods_and_results_folder_come_back(qtbot, tmp_path):
    from tactile_tuner.window import MainWindow

    first = MainWindow(restore=True)
    qtbot.addWidget(first)
    first.compare.chooser.apply(["AS", "IM", "EN"])
    first.experiments.setup.folder_edit.setText(str(tmp_path / "study"))
    first.close()
    second = MainWindow(restore=True)
    qtbot.addWidget(second)
    assert second.compare.methods == ["AS", "IM", "EN"]
    assert second.experiments.setup.folder_edit.text() == str(tmp_path / "study")
    second.close()


def test_hover_highlights_go_when_the_mouse_leaves(window, qtbot):
    heatmap, curves = window.tune.heatmap, window.tune.curves
    cell = window.tune.shown_curves.cells[0]
    heatmap._hover(cell)
    assert heatmap.highlight_item.isVisible()
    QtWidgets.QApplication.sendEvent(heatmap, QtCore.QEvent(QtCore.QEvent.Type.Leave))
    assert not heatmap.highlight_item.isVisible()
    assert all(line.opts["pen"].width() == 2 for line in curves._solid.values())
    curves._hover(cell)
    assert curves._solid[cell].opts["pen"].width() == 5
    QtWidgets.QApplication.sendEvent(curves, QtCore.QEvent(QtCore.QEvent.Type.Leave))
    assert curves._solid[cell].opts["pen"].width() == 2 and not heatmap.highlight_item.isVisible()


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


def test_preset_notes_are_shown_and_editable(window, qtbot, tmp_path):
    from tactile_core.files.presets import builtin_presets, load_preset

    path = builtin_presets()["exp2-L1"]
    assert window.files.load_preset_file(path)
    notes = window.controls.preset.notes_edit
    assert notes.toPlainText() == load_preset(path).notes and notes.isVisible()
    notes.setPlainText("lines 1 mm lower on this array")
    assert window.files.save_preset_file(tmp_path / "mine.json")
    assert load_preset(tmp_path / "mine.json").notes == "lines 1 mm lower on this array"
