"""What the tuner's window tells its user: a lost device in a banner, the state in the status
bar and the tuning in the title, a short tooltip with a unit or the paper's section on every
parameter, an All off button legible in both palettes, and Connect only when there is
something to connect."""

from collections import Counter

import pytest
from PySide6 import QtCore, QtGui, QtWidgets

from tactile_core.stream.streamer import StreamStats

from .tuner_support import WAIT_MS

Key = QtCore.Qt.Key


def test_a_lost_device_is_obvious(window, qtbot):
    window.device.url = "/dev/ttyUSB9"  # as if a port were connected
    window.device.status_changed.emit(
        StreamStats(state="disconnected", status="device disconnected: /dev/ttyUSB9")
    )
    assert window.banner.isVisible() and "/dev/ttyUSB9" in window.banner.text()
    assert window.tune.heatmap.banner.isVisible()
    window.device.status_changed.emit(StreamStats(state="streaming", status="reconnected"))
    assert not window.banner.isVisible() and not window.tune.heatmap.banner.isVisible()
    window.device.url = None


def test_status_bar_says_playing_after_all_off(window, qtbot):
    window.all_off()
    assert "all off" in window.statusBar().currentMessage()
    window.toggle_play()
    assert window.statusBar().currentMessage() == "playing"


def test_the_title_follows_the_tuning(window, qtbot, tmp_path):
    from tactile_core.files.presets import builtin_presets

    assert window.files.load_preset_file(builtin_presets()["exp3-circle"])
    title = window.windowTitle()
    assert "Experiment 3 circle" in title and "*" not in title and "mu 0.33" in title
    window.state.update(mu=0.5)
    assert "Experiment 3 circle *" in window.windowTitle() and "mu 0.50" in window.windowTitle()


def test_every_parameter_has_a_short_tooltip_with_unit_or_section(window):
    c = window.controls
    widgets = [c.correction.mu_spin, c.correction.mu_slider, c.correction.gamma_spin,
               c.correction.gamma_slider, c.trace.duration_spin, c.trace.pause_spin,
               c.trace.direction_combo, c.trace.rate_spin, c.trace.filter_combo,
               c.trace.subsamples_spin, c.trace.dither_check, c.trace.emphasis_spin,
               c.trace.gain_spin, c.playback.draw_check,
               *c.method.method_buttons.buttons(), *c.playback.view_buttons.buttons(),
               *[f for fields in c.shape.shape_fields.values() for f in fields]]  # fmt: skip
    for w in widgets:
        text = w.toolTip()
        assert text.startswith("<qt>"), (w, text)  # rich text: wraps, never 1100 px wide
        plain = text[4:-5]
        assert len(plain) < 320, plain
        assert any(k in plain for k in ("paper", " s", "Hz", "grid units", "0-1", "0.1-10",
                                        "1-64", "levels", "no unit")), plain  # fmt: skip


def _contrast(a: QtGui.QColor, b: QtGui.QColor) -> float:
    """WCAG's contrast ratio of two colours."""

    def lum(c):
        ch = [v / 255 for v in (c.red(), c.green(), c.blue())]
        ch = [v / 12.92 if v <= 0.03928 else ((v + 0.055) / 1.055) ** 2.4 for v in ch]
        return 0.2126 * ch[0] + 0.7152 * ch[1] + 0.0722 * ch[2]

    hi, lo = sorted((lum(a), lum(b)), reverse=True)
    return (hi + 0.05) / (lo + 0.05)


@pytest.mark.parametrize("theme", ["light", "dark"])
def test_all_off_reads_in_both_palettes(qtbot, qt_settings, theme):
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


def test_connect_is_disabled_for_the_port_in_use(window, qtbot, emulator_thread):
    _, path = emulator_thread
    panel = window.device_panel
    errors = []
    window.device.error_raised.connect(errors.append)
    panel.port_combo.lineEdit().setText(path)
    qtbot.keyClick(panel.port_combo.lineEdit(), Key.Key_Return)
    qtbot.waitUntil(lambda: window.device.url == path, timeout=WAIT_MS)
    assert not panel.connect_button.isEnabled()
    qtbot.keyClick(panel.port_combo.lineEdit(), Key.Key_Return)  # again: nothing to do
    assert not errors and window.device.url == path
    panel.port_combo.lineEdit().setText("sim")
    assert panel.connect_button.isEnabled()


def test_a_failed_connect_leaves_the_box_on_the_link_in_use(window, qtbot):
    # The box kept "/dev/ttyUSB9" while the simulated array played on.
    panel = window.device_panel
    edit = panel.port_combo.lineEdit()
    edit.selectAll()
    qtbot.keyClicks(edit, "/dev/ttyUSB9")
    assert panel.connect_button.isEnabled()
    qtbot.mouseClick(panel.connect_button, QtCore.Qt.MouseButton.LeftButton)
    assert "/dev/ttyUSB9" in window.last_error  # the message names the link refused
    assert window.device.simulated and panel.port_combo.currentText() == "sim"
    assert panel.link_label.text() == "<b>simulated array</b>"
    assert not panel.connect_button.isEnabled()  # the link in use: nothing to connect
