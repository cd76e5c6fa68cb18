"""The desk: a first start that works, input that behaves, views that explain themselves, and a
layout a researcher feels at home in. Keys are real key events (pytest-qt)."""

import shutil
import subprocess
import sys
from importlib.metadata import entry_points

import numpy as np
import pytest
from PySide6 import QtCore, QtGui, QtWidgets

import tactile_core as tc
from tactile_core.stream.streamer import StreamStats

from .helpers import record_sent

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
    win.close()


# --- first start ------------------------------------------------------------------------------


def test_the_gui_installs_as_tactile_tuner_and_the_core_reaches_its_bench_by_entry_point():
    hooks = {ep.name: ep.value for ep in entry_points(group="tactile.bench")}
    assert hooks.get("gui") == "tactile_tuner.bench:run"
    import tactile_tuner.main

    assert tactile_tuner.main.__file__.endswith("app/main.py")


def test_the_core_imports_nothing_of_the_gui():
    code = (
        "import sys, importlib, pkgutil, tactile_core;"
        "[importlib.import_module(m.name) for m in"
        " pkgutil.walk_packages(tactile_core.__path__, 'tactile_core.')];"
        "bad = [m for m in sys.modules if m.split('.')[0] in ('tactile_tuner', 'app', 'PySide6',"
        " 'pyqtgraph')];"
        "print(bad); sys.exit(1 if bad else 0)"
    )
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd="/")
    assert result.returncode == 0, result.stdout + result.stderr


def test_preflight_reads_what_the_linker_cannot_find():
    from tactile_tuner.preflight import package_of, parse_ldd

    out = (
        "\tlinux-vdso.so.1 (0x00007ffd)\n"
        "\tlibxcb-cursor.so.0 => not found\n"
        "\tlibGL.so.1 => /lib/x86_64-linux-gnu/libGL.so.1 (0x00007f)\n"
        "\tlibxcb-icccm.so.4 => not found\n"
        "\tlibxcb-cursor.so.0 => not found\n"
    )
    assert parse_ldd(out) == ["libxcb-cursor.so.0", "libxcb-icccm.so.4"]
    assert package_of("libxcb-keysyms.so.1") == "libxcb-keysyms1"
    assert package_of("libxkbcommon-x11.so.0") == "libxkbcommon-x11-0"
    assert package_of("libxcb-xinput.so.0") == "libxcb-xinput0"  # by the naming rule


@pytest.mark.skipif(shutil.which("gcc") is None or shutil.which("ldd") is None, reason="gcc")
def test_preflight_names_a_missing_library_and_its_package(tmp_path, monkeypatch):
    from tactile_tuner import preflight

    # A plugin linked against a library that is then removed: ldd reports it not found.
    (tmp_path / "dep.c").write_text("int dep(void) { return 1; }\n")
    (tmp_path / "plugin.c").write_text("int dep(void); int plugin(void) { return dep(); }\n")
    lib = tmp_path / "libxcb-gone.so.0"
    subprocess.run(["gcc", "-shared", "-fPIC", "-o", str(lib), str(tmp_path / "dep.c"),
                    "-Wl,-soname,libxcb-gone.so.0"], check=True)  # fmt: skip
    plugin = tmp_path / "libqxcb.so"
    subprocess.run(["gcc", "-shared", "-fPIC", "-o", str(plugin), str(tmp_path / "plugin.c"),
                    str(lib)], check=True)  # fmt: skip
    lib.unlink()
    assert preflight.missing_libraries(plugin) == ["libxcb-gone.so.0"]
    monkeypatch.setattr(preflight, "xcb_plugin", lambda: plugin)
    line = preflight.check({"DISPLAY": ":0"})
    assert "libxcb-gone.so.0" in line and "apt-get install libxcb-gone0" in line
    assert preflight.check({"QT_QPA_PLATFORM": "offscreen"}) == ""
    assert preflight.check({}).startswith("no display")


def test_the_readme_names_the_window_libraries_in_one_line():
    from pathlib import Path

    from tactile_tuner.preflight import APT_LINE

    readme = (Path(__file__).resolve().parent.parent / "README.md").read_text()
    assert APT_LINE in readme
    for package in ("python3-venv", "libxcb-cursor0", "libxcb-icccm4", "libxcb-keysyms1"):
        assert package in APT_LINE


# --- input ------------------------------------------------------------------------------------


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
    qtbot.waitUntil(lambda: not spin.hasFocus(), timeout=5000)
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
    qtbot.waitUntil(lambda: QtWidgets.QApplication.activePopupWidget() is None, timeout=5000)
    assert window.state.scene.playing  # the array was not turned off


def test_esc_in_a_dialog_closes_only_the_dialog(window, qtbot):
    window.state.update(playing=True)
    window.show_error("something to read")
    box = QtWidgets.QApplication.activeModalWidget()
    assert isinstance(box, QtWidgets.QMessageBox)
    qtbot.keyClick(box, Key.Key_Escape)
    qtbot.waitUntil(lambda: not box.isVisible(), timeout=5000)
    assert window.state.scene.playing
    qtbot.keyClick(window.tune.heatmap, Key.Key_Escape)  # in the window: all off
    assert not window.state.scene.playing


# --- views ------------------------------------------------------------------------------------


def test_thirty_tactors_get_thirty_colours_none_the_cursors():
    from tactile_tuner.theme import TACTOR_COLORS
    from tactile_tuner.views import cell_colors

    cells = [(c, r) for r in range(6) for c in range(5)]
    colors = cell_colors(cells)
    assert len(set(colors.values())) == 30
    assert len(set(TACTOR_COLORS)) == 30
    for color in TACTOR_COLORS:  # no greys, nothing near black or white
        q = QtGui.QColor(color)
        assert q.hslSaturation() > 60 and 50 < q.lightness() < 215, color


def test_lanes_show_one_row_per_tactor_labelled(window, qtbot):
    window.state.update(shape=tc.Line((0.5, 1.84), (4.5, 4.16)), method="MM")
    qtbot.waitUntil(lambda: window.tune.curves.curves is not None
                    and window.tune.curves.curves.cells[0] == (0, 1), timeout=2000)  # fmt: skip
    window.tune.lanes_check.setChecked(True)
    cells = window.tune.curves.curves.cells
    ticks = window.tune.curves.getAxis("left")._tickLevels[0]
    assert [label for _, label in ticks] == [f"({c},{r})" for c, r in cells]
    y0 = window.tune.curves._solid[cells[0]].yData.max()
    y1 = window.tune.curves._solid[cells[1]].yData.max()
    assert y0 > y1 + 0.5  # separate lanes, not all at 1.0
    cursor = window.tune.curves.cursor.pen.color().name()
    assert cursor not in {c.lower() for c in window.tune.curves.colors.values()}


def test_hovering_a_cell_highlights_its_curve_and_back(window, qtbot):
    window.state.update(shape=tc.Line((0.5, 1.84), (4.5, 4.16)), method="AS")
    qtbot.waitUntil(lambda: window.tune.curves.curves is not None, timeout=2000)
    cell = window.tune.curves.curves.cells[2]
    vb = window.tune.heatmap.plot.vb
    scene_point = vb.mapViewToScene(QtCore.QPointF(cell[0] + 0.5, cell[1] + 0.5))
    qtbot.mouseMove(window.tune.heatmap.viewport(), window.tune.heatmap.mapFromScene(scene_point))
    qtbot.waitUntil(lambda: window.tune.curves._solid[cell].opts["pen"].width() == 5, timeout=2000)
    assert f"tactor ({cell[0]},{cell[1]})" in window.tune.heatmap.readout.text
    window.tune.curves.curve_hovered.emit((0, 1))
    assert window.tune.heatmap.highlight_item.isVisible()
    assert window.tune.heatmap.highlight_item.rect().topLeft() == QtCore.QPointF(0, 1)


def test_heatmap_ticks_are_grid_units(window):
    ticks = window.tune.heatmap.plot.getAxis("bottom")._tickLevels[0]
    assert [v for v, _ in ticks] == [0, 1, 2, 3, 4, 5]


def test_dragging_the_cursor_holds_and_shows_that_moment(window, qtbot):
    scene = window.state.scene.replace(shape=tc.Line((0.5, 1.84), (4.5, 4.16)), method="AS",
                                       mu=0.0, gamma=1.0, playing=True)  # fmt: skip
    window.state.set_scene(scene)
    window.tune.curves.scrubbed.emit(0.5)  # a quarter into the 2 s trace: x = 1.5
    assert window.state.scene.hold_s == 0.5  # the array holds that instant (issue 19)
    window.state.set_view_mode("corrected")
    expected = tc.render(scene.shape, "AS", 0.25)
    qtbot.waitUntil(
        lambda: np.allclose(window.tune.heatmap.values, expected, atol=1e-12), timeout=2000
    )
    assert window.tune.curves.cursor.value() == pytest.approx(0.5)


def test_clicking_a_cell_pulses_its_tactor_and_shift_holds_it(window, qtbot):
    before = window.state.scene
    sent = record_sent(window)  # the pulse lasts 0.3 s: every frame, not the newest one
    window.tune.heatmap.cell_clicked.emit(3, 4, False)
    scene = window.state.scene
    assert scene.shape == tc.Line((3.5, 4.5), (3.5, 4.5)) and scene.method == "CT"
    qtbot.waitUntil(lambda: any(lv[4 * 5 + 3] == 22 for lv in list(sent)), timeout=3000)
    qtbot.waitUntil(lambda: window.state.scene.shape == before.shape, timeout=3000)  # back
    window.tune.heatmap.cell_clicked.emit(1, 1, True)  # Shift: held
    qtbot.wait(600)  # longer than a pulse
    assert window.state.scene.shape == tc.Line((1.5, 1.5), (1.5, 1.5))
    qtbot.waitUntil(lambda: window.device.sent_levels()[1, 1] == 22, timeout=3000)
    window.tune.heatmap.cell_clicked.emit(1, 1, False)  # a click releases it
    assert window.state.scene.shape == before.shape


def test_the_correction_key_never_covers_the_curves(window):
    assert window.tune.correction.plotItem.legend is None
    title = window.tune.correction.plotItem.titleLabel.text
    assert "device levels" in title


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


# --- the desk ---------------------------------------------------------------------------------


def test_the_view_menu_brings_a_closed_dock_back(window, qtbot):
    actions = {a.text(): a for a in window.view_menu.actions()}
    window.controls_dock.close()
    assert not actions["Controls panel"].isChecked()
    actions["Controls panel"].trigger()
    assert window.controls_dock.isVisible()
    window.device_dock.setFloating(True)
    window.reset_layout()
    assert not window.device_dock.isFloating() and window.device_dock.isVisible()


def test_a_saved_size_larger_than_the_screen_is_fitted(qtbot):
    from tactile_tuner.window import MainWindow

    win = MainWindow(restore=False)
    qtbot.addWidget(win)
    win.resize(5000, 4000)
    win.fit_to_screen()
    area = win.screen().availableGeometry()
    assert win.frameGeometry().width() <= area.width()
    assert win.frameGeometry().height() <= area.height()
    win.close()


def test_at_1280x720_the_controls_never_scroll_sideways(window, qtbot):
    window.resize(1280, 720)
    qtbot.wait(50)
    scroll = window.controls_scroll
    assert scroll.horizontalScrollBarPolicy() == QtCore.Qt.ScrollBarPolicy.ScrollBarAlwaysOff
    assert scroll.viewport().width() >= window.controls.minimumSizeHint().width()


def test_at_1280x720_the_window_fits_on_every_tab(window, qtbot):
    # The window cannot be narrower than its widest tab: one wide tab widened it to 1472 px.
    for i in range(window.tabs.count()):
        window.tabs.setCurrentIndex(i)
        window.resize(1280, 720)
        qtbot.wait(20)
        assert window.minimumSizeHint().width() <= 1280, window.tabs.tabText(i)
        assert window.width() <= 1280, window.tabs.tabText(i)
    window.tabs.setCurrentIndex(0)


@pytest.mark.parametrize("size", [(1280, 720), (1600, 1000)])
def test_the_curve_title_and_hint_fit_their_panel(window, qtbot, size):
    # A title wider than its plot is cut off at the right (it was, at 1600 x 1000).
    window.resize(*size)
    qtbot.wait(50)
    window.tune.fit_heatmap()
    qtbot.wait(20)
    title = window.tune.curves.plotItem.titleLabel.item.boundingRect().width()
    assert 0 < title <= window.tune.curves.width()
    hint = window.findChild(QtWidgets.QLabel, "curves_hint")
    assert hint.minimumSizeHint().width() == 0  # elides; never sets the panel's width
    assert "drag the dashed cursor" in hint.toolTip()


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


def test_the_plots_follow_a_dark_palette(window, qtbot):
    from tactile_tuner.theme import apply_theme

    app = QtWidgets.QApplication.instance()
    saved_palette, saved_style = app.palette(), app.style().name()
    try:
        apply_theme(app, "dark")
        qtbot.wait(50)
        background = window.tune.curves.backgroundBrush().color()
        assert background.lightness() < 60
        assert window.tune.heatmap.backgroundBrush().color().lightness() < 60
        apply_theme(app, "light")
        qtbot.wait(50)
        assert window.tune.curves.backgroundBrush().color().lightness() > 200
    finally:
        app.setPalette(saved_palette)
        app.setStyle(saved_style)


def test_the_title_follows_the_tuning(window, qtbot, tmp_path):
    from tactile_core.files.presets import builtin_presets

    assert window.files.load_preset_file(builtin_presets()["exp3-circle"])
    title = window.windowTitle()
    assert "Experiment 3 circle" in title and "*" not in title and "mu 0.33" in title
    window.state.update(mu=0.5)
    assert "Experiment 3 circle *" in window.windowTitle() and "mu 0.50" in window.windowTitle()


def test_dialog_names_and_extensions():
    from tactile_core.rendering.scene import Scene
    from tactile_tuner import dialogs

    assert dialogs.with_filter_extension("/tmp/curves", "PNG (*.png)").name == "curves.png"
    assert dialogs.with_filter_extension("/tmp/a.csv", "CSV (*.csv)").name == "a.csv"
    assert dialogs.tuning_tag(Scene(tc.Circle((2, 3), 1), "IM", 0.33, 0.7)) == (
        "IM-mu0.33-gamma0.70"
    )
    assert dialogs.safe_name("P 01/x") == "P-01-x"


def test_dialogs_remember_their_folder_per_kind(tmp_path):
    from tactile_tuner import dialogs

    (tmp_path / "exports").mkdir()
    dialogs._remember("exports", tmp_path / "exports" / "x.csv")
    assert dialogs._folder("exports") == str(tmp_path / "exports")
    assert dialogs._folder("presets") != str(tmp_path / "exports")


def test_draw_mode_clears_its_curves_and_restores_the_scene(window, qtbot):
    before = window.state.scene.replace(method="IM", pause_s=0.7)
    window.state.set_scene(before)
    qtbot.waitUntil(lambda: window.tune.curves.curves is not None, timeout=2000)
    window.controls.playback.draw_check.setChecked(True)
    qtbot.waitUntil(lambda: window.tune.curves.curves is None, timeout=2000)
    assert window.state.scene.method == "AS" and window.state.scene.pause_s == 0.0
    window.controls.playback.draw_check.setChecked(False)
    scene = window.state.scene
    assert (scene.method, scene.pause_s, scene.shape) == ("IM", 0.7, before.shape)
    qtbot.waitUntil(lambda: window.tune.curves.curves is not None, timeout=2000)
