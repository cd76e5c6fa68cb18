"""The tuner's window: its title and preset box, its size on a small screen, what it asks before
quitting."""

import pytest

from .tuner_support import settle

pytestmark = pytest.mark.usefixtures("qt_settings")


@pytest.fixture
def window(qtbot):
    from tactile_tuner.window import MainWindow

    win = MainWindow(restore=False, process=False)
    qtbot.addWidget(win)
    win.show()
    qtbot.waitExposed(win)
    yield win
    win.confirm = lambda title, text: True
    win.close()


def test_saving_a_preset_renames_the_scene_in_the_title_and_the_preset_box(window, tmp_path):
    window.state.update(mu=0.5)
    assert "Experiment 1 line *" in window.windowTitle()
    assert window.files.save_preset_file(tmp_path / "my tuning.json")
    assert window.windowTitle().startswith("tactile-tuner - my tuning - AS, mu 0.50")
    assert "*" not in window.windowTitle()  # the scene is the preset saved
    assert window.controls.preset.name_label.text() == "my tuning"
    window.state.update(mu=0.6)
    assert "my tuning *" in window.windowTitle()


def test_no_restore_starts_on_the_built_in_line_with_its_notes(window):
    from tactile_core.files.presets import builtin_presets, load_preset

    line = load_preset(builtin_presets()["exp1-line"])
    assert line.notes.startswith("Paper 3.4.2")
    assert window.controls.preset.name_label.text() == "Experiment 1 line"
    assert window.controls.preset.notes_edit.toPlainText() == line.notes
    assert window.state.scene.replace(epoch=0) == line.scene
    assert "*" not in window.windowTitle()


def _session(qtbot):
    from tactile_tuner.window import MainWindow

    win = MainWindow(restore=True, process=False)
    qtbot.addWidget(win)
    return win


def test_a_session_that_ended_on_a_tact_pattern_comes_back_with_its_tuning(qtbot, tmp_path):
    # The settings held "shape": null, which the next start refused: it came back on the
    # paper's defaults, the tuned mu and gamma lost.
    from . import tact_support as ts

    path = ts.write(tmp_path, ts.dots_only(), "beat.tact")
    first = _session(qtbot)
    first.state.update(method="CT", mu=0.21, gamma=1.9, rate_hz=250.0)
    assert first.files.import_tact_file(path)
    first.close()
    second = _session(qtbot)
    scene = second.state.scene
    assert (scene.method, scene.mu, scene.gamma, scene.rate_hz) == ("CT", 0.21, 1.9, 250.0)
    assert scene.shape is None and second.files.pattern_file(scene.source) == {
        "path": str(path), "position": None}  # every position (none named)  # fmt: skip
    assert "the last session's pattern again" in second.statusBar().currentMessage()
    second.close()
    path.unlink()
    third = _session(qtbot)
    scene = third.state.scene
    assert (scene.method, scene.mu, scene.gamma, scene.rate_hz) == ("CT", 0.21, 1.9, 250.0)
    assert type(scene.shape).__name__ == "Line" and scene.source is None
    said = third.statusBar().currentMessage()
    assert f"the last session's .tact file {path} is gone" in said and "tuning" in said
    third.close()


def choose(win, name: str) -> None:
    combo = win.device_panel.profile_combo
    combo.setCurrentIndex(combo.findData(name))
    combo.activated.emit(combo.currentIndex())


def test_the_next_start_comes_back_on_the_last_sessions_profile(qtbot, tmp_path):
    # The profile was saved with the scene but not used: every start came back on palm-5x6,
    # where a vest .tact file's two positions played as one path over the whole grid.
    from tactile_core.files.pattern import Pattern, example_patterns

    vest_file = tmp_path / "sweep.tact"
    first = _session(qtbot)
    choose(first, "vest-front-back")
    Pattern.load(example_patterns()["vest-sweep"]).save_tact(
        vest_file, first.device.profile.layout, positions={"front": "VestFront", "back": "VestBack"}
    )
    assert first.files.import_tact_file(vest_file)
    first.close()
    second = _session(qtbot)
    assert second.device.profile.name == "vest-front-back"
    source = second.state.scene.source
    assert [(p.position, p.group) for p in source.placement(second.device.profile.layout)] == [
        ("VestFront", "front"), ("VestBack", "back")]  # fmt: skip
    choose(second, "belt-8")
    second.close()
    third = _session(qtbot)
    assert third.device.profile.name == "belt-8"
    third.close()


def test_settings_of_a_pattern_saved_without_its_file_keep_the_tuning(qtbot):
    import json

    from PySide6 import QtCore

    from tactile_core.files.presets import Preset
    from tactile_core.rendering.scene import Scene

    saved = Preset(Scene(None, "IM", mu=0.4, gamma=2.5), "beat").to_dict()
    assert saved["shape"] is None  # what the tuner wrote for a pattern
    QtCore.QSettings().setValue("scene", json.dumps(saved))
    win = _session(qtbot)
    scene = win.state.scene
    assert (scene.method, scene.mu, scene.gamma) == ("IM", 0.4, 2.5)
    assert type(scene.shape).__name__ == "Line"
    assert "pattern was not saved" in win.statusBar().currentMessage()
    win.close()


TITLE_BAR_PX = 64
"""Room a window manager takes at most on a 1280 x 720 screen, measured: openbox's frame 25 px
(a 20 px title bar, borders 1 and 5), GNOME's title bar 37 px below its 27 px top bar."""


def test_every_tab_fits_a_1280x720_screen_under_a_title_bar(window, qtbot):
    # The Experiments tab's set-up and run column needed 531 px: with the menus, the device
    # dock and the status bar the window's least height was 716 px, and under openbox's title
    # bar 21 px of it (the status bar) fell off a 720 px screen.
    for i in range(window.tabs.count()):
        window.tabs.setCurrentIndex(i)
        settle()  # the tab's layout, with no time waited
        least = window.minimumSizeHint()
        assert least.height() <= 720 - TITLE_BAR_PX, window.tabs.tabText(i)
        assert least.width() <= 1280, window.tabs.tabText(i)
    window.resize(1280, 720 - TITLE_BAR_PX)
    qtbot.waitUntil(lambda: window.height() == 720 - TITLE_BAR_PX)
    bar = window.statusBar()
    assert bar.isVisible() and bar.geometry().bottom() < window.height()


def test_the_gamma_box_and_the_title_show_the_gamma_in_use(window):
    # The log slider sets gamma to 0.001 (10 ** (2 p / 1000 - 1) rounded): at 0.143 the box
    # showed 0.14 and the title 0.14.
    from tactile_tuner.controls.correction import gamma_to_slider

    correction = window.controls.correction
    correction.gamma_slider.setValue(gamma_to_slider(0.143))
    gamma = window.state.scene.gamma
    assert gamma == 0.143  # position 78: 10 ** (2 * 78 / 1000 - 1) = 0.1432, to 0.001
    assert correction.gamma_spin.text() == "0.143"
    assert window.windowTitle().endswith("mu 0.33, gamma 0.143")
    window.state.update(mu=0.333)  # as a preset or a sender may set it
    assert correction.mu_spin.text() == "0.333"


@pytest.mark.parametrize(("mu", "gamma", "shown"), [(0.33, 0.7, ("0.33", "0.70")),
                                                     (0.77, 0.142, ("0.77", "0.142"))])  # fmt: skip
def test_mu_and_gamma_read_the_same_in_the_boxes_and_the_titles(window, mu, gamma, shown):
    # The boxes wrote 0.330 and 0.700 while both titles said 0.33 and 0.70.
    window.state.update(mu=mu, gamma=gamma)
    window.tune.refresh()
    correction = window.controls.correction
    assert (correction.mu_spin.text(), correction.gamma_spin.text()) == shown
    said = f"mu {shown[0]}, gamma {shown[1]}"
    assert window.windowTitle().endswith(f"AS, {said}")
    assert said in window.tune.curves.plotItem.titleLabel.text  # (on one line or two)


def test_the_direction_box_names_a_turn_only_for_circles_and_squares(window):
    import tactile_core as tc

    combo = window.controls.trace.direction_combo
    items = lambda: [combo.itemText(i) for i in range(combo.count())]  # noqa: E731
    assert isinstance(window.state.scene.shape, tc.Line)
    assert items() == ["forward", "reverse"]  # a line has no turn
    for shape in (tc.Circle((2.5, 3.0), 2.0), tc.Square((2.5, 3.0), 3.0)):
        window.state.update(shape=shape)
        assert items() == ["forward (counter-clockwise)", "reverse (clockwise)"]
    window.state.update(shape=tc.Polyline([(0.5, 0.5), (2.5, 4.5), (4.5, 0.5)]))
    assert items() == ["forward", "reverse"]


@pytest.mark.parametrize("width", [1280, 1400, 1600])
def test_the_curves_hint_is_shown_whole(window, qtbot, width):
    # At 1280 and 1400 px it read "drag the cursor to scrub; hove...".
    from PySide6 import QtCore, QtWidgets

    window.resize(width, 720)
    qtbot.waitUntil(lambda: window.width() == width)
    window.tune.fit_heatmap()
    QtWidgets.QApplication.processEvents()
    hint = window.findChild(QtWidgets.QLabel, "curves_hint")
    text = "drag the cursor to scrub; hover for values; dashed: raw"
    assert hint.text() == text
    box = hint.contentsRect()
    flags = int(QtCore.Qt.TextFlag.TextWordWrap)
    needed = hint.fontMetrics().boundingRect(box, flags, text)
    assert needed.width() <= box.width() and needed.height() <= box.height()
    assert hint.mapTo(window, QtCore.QPoint(hint.width(), 0)).x() <= window.width()


def test_the_quit_question_keeps_the_autosave_path_on_one_line(window, tmp_path):
    # The message box wrapped the path where Qt may break a line: after "/home/" and "blind-".
    from pathlib import Path

    from PySide6 import QtGui

    from tactile_tuner.dialogs import message_html

    path = Path("/home/researcher/.local/share/tactile-tuner/tactile-tuner/blind-ab/"
                "blind-ab-2025-11-28T14-20-33-seed1234567.csv")  # fmt: skip
    window.blind.session.unsaved, window.blind.session.autosave_path = True, path
    asked = []
    window.confirm = lambda title, text: asked.append(text) or False
    window.close()
    assert window.isVisible() and str(path) in asked[0]
    window.blind.session.unsaved = False
    metrics = QtGui.QFontMetrics(QtGui.QFont())
    for width_px, shortened in ((2000, False), (300, True)):
        rich, elided = message_html(asked[0], metrics, width_px)
        assert elided == shortened
        document = QtGui.QTextDocument()
        document.setHtml(rich)
        document.setTextWidth(320)  # narrower than the path: the words wrap, the path does not
        document.documentLayout().documentSize()
        lines = {}
        block = document.begin()
        while block.isValid():
            lines[block.text()] = block.layout().lineCount()
            block = block.next()
        (shown,) = [text for text in lines if text.startswith("/home/")]
        assert lines[shown] == 1
        assert shown == str(path) if not shortened else ("…" in shown and shown.endswith(".csv"))
        words = next(iter(lines))  # the sentence before it wraps as words do
        assert words.startswith("The Blind A/B ratings are not saved") and lines[words] >= 2


def test_the_osc_host_is_shown_whole_beside_a_long_profile_line(qtbot):
    # With the belt's profile line ("8 actuators, wrapping in x (circumference 8), ...") the
    # OSC host box was squeezed to ".0.1" at 1280 x 720.
    from tactile_core.device.profile import find_profile
    from tactile_tuner.window import MainWindow

    win = MainWindow(profile=find_profile("belt-8"), restore=False, process=False)
    qtbot.addWidget(win)
    win.resize(1280, 720)
    win.show()
    qtbot.waitExposed(win)
    try:
        host = win.serve_panel.host_edit
        assert host.text() == "127.0.0.1"
        qtbot.waitUntil(lambda: host.fontMetrics().horizontalAdvance(host.text()) + 8
                        <= host.width())  # fmt: skip
        assert "circumference 8" in win.device_panel.profile_label.toolTip()
    finally:
        win.close()


def test_a_start_on_a_belt_is_not_marked_modified(qtbot):
    # The start preset plays BA on its own shape on a belt: that is the preset on this layout,
    # not a change of the user's.
    from tactile_core.device.profile import find_profile
    from tactile_tuner.window import MainWindow

    win = MainWindow(profile=find_profile("belt-8"), restore=False, process=False)
    qtbot.addWidget(win)
    try:
        assert win.state.scene.method == "BA"
        assert win.windowTitle().startswith("tactile-tuner - Experiment 1 line - BA")
        win.state.update(mu=0.5)
        assert "Experiment 1 line *" in win.windowTitle()
    finally:
        win.close()


@pytest.mark.parametrize("size", [(1280, 720), (1600, 1000)])
def test_the_predicted_views_title_fits_its_plot(window, qtbot, size):
    # On one line it was wider than the curves' plot, cut off at both ends at 1600 x 1000.
    window.resize(*size)
    qtbot.waitUntil(lambda: window.size().toTuple() == size)
    window.state.set_view_mode("predicted")
    window.tune.refresh()
    window.tune.fit_heatmap()
    label = window.tune.curves.plotItem.titleLabel
    assert "over 25 participants" in label.text
    qtbot.waitUntil(lambda: 0 < label.item.boundingRect().width() <= window.tune.curves.width())


def test_tactile_tuner_without_profile_leaves_the_profile_to_the_last_session(qtbot, monkeypatch):
    # main() turned a missing --profile into the palm array, which the window then took as
    # asked for: the last session's profile never came back.
    import tactile_tuner.window
    from tactile_tuner.main import main

    asked = {}

    class Stop(Exception):
        pass

    def window(**kwargs):
        asked.update(kwargs)
        raise Stop

    monkeypatch.setattr(tactile_tuner.window, "MainWindow", window)
    with pytest.raises(Stop):
        main(["--no-realtime"])
    assert asked["profile"] is None and asked["restore"]
    with pytest.raises(Stop):
        main(["--profile", "belt-8"])
    assert asked["profile"].name == "belt-8"  # asked for: it wins over the last session's


def test_a_changed_scene_keeps_its_star_at_the_next_start(qtbot, tmp_path):
    # "Experiment 1 line *" came back as "Experiment 1 line": the title read as the preset
    # unchanged, though mu was not the preset's.
    def named(win) -> str:
        return win.windowTitle().split(" - ")[1]

    first = _session(qtbot)
    assert named(first) == "Experiment 1 line"
    first.state.update(mu=0.41)
    assert named(first) == "Experiment 1 line *"
    first.close()
    second = _session(qtbot)
    assert second.state.scene.mu == 0.41 and named(second) == "Experiment 1 line *"
    assert second.files.save_preset_file(tmp_path / "mine.json")  # saved: no star
    assert named(second) == "mine"
    second.close()
    third = _session(qtbot)
    assert named(third) == "mine"  # unchanged since its save: none at the next start either
    third.close()
