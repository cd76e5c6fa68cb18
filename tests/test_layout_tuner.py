"""The tuner's controls on layouts that are not grids: the profile chosen by name, the methods that
cannot render there greyed out saying why, a scene that has one playing BA with a status line (never
an exception), presets that say so, and Compare and Blind A/B on the belt with BA, RO and GS."""

import numpy as np
import pytest
from PySide6 import QtCore, QtWidgets

import tactile_core as tc
from tactile_core.files.presets import Preset, builtin_presets, save_preset
from tactile_core.rendering.methods import PAPER_METHODS
from tactile_core.rendering.scene import Scene

from .test_layout_views import belt, open_window  # noqa: F401 - the fixture
from .test_tuner import window  # noqa: F401 - the fixture

pytestmark = pytest.mark.usefixtures("qt_settings")


def choose_profile(win, name):
    combo = win.device_panel.profile_combo
    combo.setCurrentIndex(combo.findData(name))
    combo.activated.emit(combo.currentIndex())


def test_the_profile_box_lists_the_bundled_profiles_and_switches_the_views(window, qtbot):  # noqa: F811
    combo = window.device_panel.profile_combo
    names = [combo.itemData(i) for i in range(combo.count())]
    for name in ("palm-5x6", "grid-3x3", "belt-8", "sleeve-2x6", "vest-4x5"):
        assert name in names
    assert combo.currentData() == "palm-5x6"
    window.state.update(method="IM")
    choose_profile(window, "sleeve-2x6")
    assert window.device.profile.name == "sleeve-2x6" and combo.currentData() == "sleeve-2x6"
    layout = window.state.layout
    assert window.tune.heatmap.layout == layout and layout.wrap.circumference == 6.0
    assert window.state.scene.method == "BA"  # IM cannot render round a sleeve
    message = window.statusBar().currentMessage()
    assert "device profile sleeve-2x6" in message and "playing BA instead of IM" in message
    assert "12 actuators" in window.device_panel.profile_label.text()
    qtbot.waitUntil(lambda: window.device.sent_levels().shape == (12,), timeout=5000)
    qtbot.waitUntil(lambda: window.device.sent_levels().any(), timeout=5000)
    assert window.last_error == ""  # no exception, no error box: a status line
    # and back: the grid's image, the paper's methods on again (BA stays: it is AS there)
    choose_profile(window, "palm-5x6")
    assert window.tune.heatmap.image.isVisible() and window.tune.heatmap.values.shape == (6, 5)
    assert window.controls.method.method_buttons.button(3).isEnabled()


def test_the_array_menu_chooses_a_profile_by_name(window):  # noqa: F811
    menu = window.findChild(QtWidgets.QMenu, "profiles_menu")
    menu.aboutToShow.emit()
    actions = {a.text(): a for a in menu.actions()}
    assert actions["palm-5x6"].isChecked() and "From a file..." in actions
    actions["vest-4x5"].trigger()
    assert window.device.profile.name == "vest-4x5"
    menu.aboutToShow.emit()
    assert {a.text() for a in menu.actions() if a.isChecked()} == {"vest-4x5"}


def test_the_papers_methods_are_greyed_out_on_a_layout_saying_why(belt, qtbot):  # noqa: F811
    method_box = belt.controls.method
    for i, name in enumerate(PAPER_METHODS):
        button = method_box.method_buttons.button(i)
        assert not button.isEnabled()
        assert f"method {name} cannot render on this layout" in button.toolTip()
        assert "grid" in button.toolTip()
    combo = method_box.other_combo
    model = combo.model()
    on = {combo.itemData(i) for i in range(combo.count()) if model.item(i).isEnabled()}
    assert on == {"EN", "PK", "RO", "GS", "VRCH", "BA", "TB"}  # TB follows a shape on any layout
    assert combo.currentData() == "BA" and method_box.other_button.isChecked()
    # keys 1-4 say why and change nothing; so does the state when asked directly
    belt.tune.heatmap.setFocus()
    qtbot.keyClick(belt.tune.heatmap, QtCore.Qt.Key.Key_3)
    assert belt.state.scene.method == "BA" and "method AS cannot render" in belt.last_error
    assert not belt.state.update(method="CT")
    assert belt.state.scene.method == "BA"
    # the predicted view (a grid's percept model) is off, with a note
    predicted = belt.controls.playback.view_buttons.button(4)
    assert not predicted.isEnabled() and "Not available on this layout" in predicted.toolTip()
    belt.state.set_view_mode("predicted")
    assert belt.state.view_mode == "corrected" and "needs a grid" in belt.last_error
    # draw mode keeps a method that needs no shape, as on the grid
    belt.state.update(method="RO")
    belt.controls.playback.draw_check.setChecked(True)
    assert belt.state.scene.method == "RO"


def test_the_experiments_say_they_need_a_grid(belt):  # noqa: F811
    start = belt.experiments.setup.start_button
    assert not start.isEnabled() and "need a grid profile" in start.toolTip()
    assert "need a grid profile" in belt.experiments.run_label.text()


def test_a_preset_whose_method_cannot_render_on_its_layout_says_so(window, tmp_path):  # noqa: F811
    path = tmp_path / "belt-as.json"
    scene = Scene(tc.Line((1.0, 0.0), (5.0, 0.0)), "AS", mu=0.2, gamma=0.9)
    save_preset(Preset(scene, name="belt-as", device_profile="belt-8"), path)
    assert window.files.load_preset_file(path)
    assert window.device.profile.name == "belt-8"
    assert window.state.scene.method == "BA" and window.state.scene.mu == 0.2
    message = window.statusBar().currentMessage()
    assert "loaded preset belt-as on its device profile belt-8" in message
    assert "playing BA instead of AS" in message
    # a built-in preset (the palm array's) brings its profile back, and AS with it
    assert window.files.load_preset_file(builtin_presets()["exp1-line"])
    assert window.device.profile.name == "palm-5x6" and window.state.scene.method == "AS"


def test_compare_and_blind_ab_run_ba_ro_gs_on_the_belt(belt, qtbot):  # noqa: F811
    compare, blind = belt.compare, belt.blind
    assert compare.methods == ["BA", "RO", "GS", "EN"]  # the paper's four cannot render here
    assert "CT MM AS IM cannot render on this layout" in compare.chooser.problem.text()
    assert not compare.chooser.apply(["AS", "BA"])
    assert "method AS cannot render" in compare.chooser.problem.text()
    compare.set_methods(["BA", "RO", "GS"])
    belt.tabs.setCurrentWidget(compare)
    belt.state.update(mu=0.0, gamma=1.0)
    heat = compare.heatmaps
    assert all(h.layout == belt.state.layout and not h.image.isVisible() for h in heat.values())
    qtbot.waitUntil(lambda: all(h.values.any() for h in heat.values()), timeout=3000)
    scene = belt.state.scene
    points = {h.point_xy for h in heat.values()}  # the same instant in every column
    assert len(points) == 1 and None not in points
    assert compare.curves["RO"].names()[0] == "front"
    for name, h in heat.items():
        values = h.values.copy()
        assert values.shape == (8,) and (values > 0).sum() <= 4, name
    ba = tc.render(scene.shape, "BA", np.linspace(0, 1, 9), grid=belt.state.layout)
    assert np.allclose(ba.sum(axis=1), 1.0)  # BA's weights sum to 1 round the belt
    # Blind A/B: the same three, shuffled onto keys, each playing on the belt
    belt.tabs.setCurrentWidget(blind)
    assert blind.session.methods == ("BA", "RO", "GS", "EN")
    blind.set_methods(["BA", "RO", "GS"])
    assert blind.start(seed=5)
    assert sorted(blind.session.mapping) == ["BA", "GS", "RO"]
    for key in (1, 2, 3):
        belt.press_number(key)
        assert belt.state.scene.method == blind.session.mapping[key - 1]
        qtbot.waitUntil(lambda: belt.device.sent_levels().any(), timeout=3000)
    assert belt.files.use_profile("palm-5x6") is False  # not during a blind session
    assert "Blind A/B" in belt.last_error and belt.device.profile.name == "belt-8"
    assert blind.cancel()


def test_the_grid_sets_come_back_on_a_grid(belt):  # noqa: F811
    assert belt.compare.chosen_methods == list(PAPER_METHODS)  # remembered for the next start
    assert belt.files.use_profile("palm-5x6")
    assert belt.compare.methods == list(PAPER_METHODS) == list(belt.blind.session.methods)
    assert belt.compare.chooser.problem.text() == ""


def test_a_scene_made_for_the_belt_starts_on_the_palm_array_with_a_shape_that_fits(qtbot):
    from tactile_tuner.window import MainWindow

    belt_scene = Scene(tc.Line((0.0, 0.0), (8.0, 0.0)), "RO", mu=0.1, gamma=1.2)
    preset = Preset(belt_scene, name="round the waist", device_profile="belt-8")
    win = MainWindow(preset=preset, restore=False, process=False)  # the palm array
    qtbot.addWidget(win)
    scene = win.state.scene
    assert scene.shape == tc.Line((0.5, 1.84), (4.5, 4.16))  # the palm's own line
    assert (scene.method, scene.mu, scene.gamma) == ("RO", 0.1, 1.2)  # the rest is kept
    assert "the shape lies off this layout (5 x 6 grid)" in win.statusBar().currentMessage()
    win.close()
