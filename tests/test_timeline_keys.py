"""The pattern editor without a mouse (real key events, pytest-qt): Tab goes through the
effects in time and then on to the properties, the arrows move the selected effect by 10 ms
(Shift: 100 ms) or a track, Alt+arrows resize it, Delete and Ctrl+D, Space plays the pattern
(the window's Space is the time line's there), and Help and docs/tuner.md list the keys."""

from pathlib import Path

import pytest
from PySide6 import QtCore, QtWidgets

import tactile_core as tc
from tactile_core.files.pattern import PatternCue

from .timeline_support import editor_of
from .tuner_support import WAIT_MS

pytestmark = pytest.mark.usefixtures("qt_settings")
Key = QtCore.Qt.Key
Mod = QtCore.Qt.KeyboardModifier
LINE = tc.Line((0.5, 1.5), (4.5, 1.5))


def focused(window, qtbot):
    editor = editor_of(window)
    pattern = tc.Pattern([tc.Effect(LINE, start_s=1.0, duration_s=0.5),
                          tc.Effect(LINE, start_s=0.0, duration_s=0.5, track=1),
                          tc.Effect(LINE, start_s=0.5, duration_s=0.5)])  # fmt: skip
    editor.open_pattern(pattern, None, "Open")
    view = editor.panel.view
    view.setFocus()
    qtbot.waitUntil(view.hasFocus, timeout=WAIT_MS)
    return editor, view


def test_tab_selects_the_effects_in_time_then_goes_on(window, qtbot):
    editor, view = focused(window, qtbot)
    order = []
    for _ in range(3):
        qtbot.keyClick(view, Key.Key_Tab)
        order.append(editor.model.selected)
    assert order == [1, 2, 0]  # by start: 0.0 s, 0.5 s, 1.0 s
    assert view.hasFocus()
    qtbot.keyClick(view, Key.Key_Backtab)
    assert editor.model.selected == 2
    qtbot.keyClick(view, Key.Key_Right, Mod.ControlModifier)
    assert editor.model.selected == 0
    qtbot.keyClick(view, Key.Key_Tab)  # past the last effect: on to the next field
    assert not view.hasFocus()


def test_the_arrows_move_the_selected_effect(window, qtbot):
    editor, view = focused(window, qtbot)
    editor.model.select(2)
    qtbot.keyClick(view, Key.Key_Right)
    qtbot.keyClick(view, Key.Key_Right)
    assert editor.model.pattern.effects[2].start_s == 0.52
    qtbot.keyClick(view, Key.Key_Left, Mod.ShiftModifier)
    assert editor.model.pattern.effects[2].start_s == 0.42
    qtbot.keyClick(view, Key.Key_Down)
    assert editor.model.pattern.effects[2].track == 1
    qtbot.keyClick(view, Key.Key_Up)
    qtbot.keyClick(view, Key.Key_Up)  # no track above 0
    assert editor.model.pattern.effects[2].track == 0
    qtbot.keyClick(view, Key.Key_Right, Mod.AltModifier)
    qtbot.keyClick(view, Key.Key_Right, Mod.AltModifier | Mod.ShiftModifier)
    assert editor.model.pattern.effects[2].duration_s == 0.61
    # a key pressed again and again (held down) is one step of the undo stack, each other
    # key one more
    steps = []
    while editor.undo_stack.index() > 1:  # (the first command opened the pattern)
        editor.undo_stack.undo()
        effect = editor.model.pattern.effects[2]
        steps.append((effect.start_s, effect.track, effect.duration_s))
    assert steps == [(0.42, 0, 0.51), (0.42, 0, 0.5), (0.42, 1, 0.5), (0.42, 0, 0.5),
                     (0.52, 0, 0.5), (0.5, 0, 0.5)]  # fmt: skip


def test_delete_and_ctrl_d(window, qtbot):
    editor, view = focused(window, qtbot)
    editor.model.select(1)
    qtbot.keyClick(view, Key.Key_D, Mod.ControlModifier)
    assert len(editor.model.pattern.effects) == 4
    assert editor.model.pattern.effects[3].start_s == 0.5 and editor.model.selected == 3
    qtbot.keyClick(view, Key.Key_Delete)
    qtbot.keyClick(view, Key.Key_Delete)
    assert [e.start_s for e in editor.model.pattern.effects] == [1.0, 0.0]


def test_space_in_the_time_line_plays_the_pattern_from_the_playhead(window, qtbot):
    editor, view = focused(window, qtbot)
    window.state.update(playing=True)  # the Experiment 1 line plays
    editor.model.set_playhead(0.5)
    qtbot.keyClick(view, Key.Key_Space)
    scene = window.state.scene
    assert scene.playing and scene.shape is None
    assert scene.source == PatternCue(editor.model.pattern, 0.5)
    qtbot.keyClick(view, Key.Key_Space)  # pause
    assert not window.state.scene.playing
    qtbot.keyClick(view, Key.Key_Space)  # and on from where it paused
    assert window.state.scene.playing and window.state.scene.source == scene.source


def test_home_and_end_scrub(window, qtbot):
    editor, view = focused(window, qtbot)
    qtbot.keyClick(view, Key.Key_End)
    assert editor.model.playhead_s == 1.5
    assert window.state.scene.source == PatternCue(editor.model.pattern, 1.5, hold=True)
    qtbot.keyClick(view, Key.Key_Home)
    assert editor.model.playhead_s == 0.0


def test_the_brackets_resize_where_alt_shift_arrows_belong_to_the_window_manager(window, qtbot):
    # openbox takes Alt+Shift+Right ("send to the next desktop"): the window went to desktop 2.
    editor, view = focused(window, qtbot)
    editor.model.select(2)  # 0.5 s long
    qtbot.keyClick(view, Key.Key_BracketRight)  # ]: 10 ms longer
    assert editor.model.pattern.effects[2].duration_s == 0.51
    qtbot.keyClick(view, Key.Key_BraceRight, Mod.ShiftModifier)  # } (Shift+]): 100 ms longer
    assert editor.model.pattern.effects[2].duration_s == 0.61
    qtbot.keyClick(view, Key.Key_BracketLeft)  # [: 10 ms shorter
    assert editor.model.pattern.effects[2].duration_s == 0.6


def test_help_and_the_docs_list_the_editors_keys(window, qtbot):
    menu = next(a.menu() for a in window.menuBar().actions() if a.text() == "&Help")
    next(a for a in menu.actions() if a.text() == "Keyboard shortcuts").trigger()
    dialog = window.findChild(QtWidgets.QDialog, "shortcuts")
    text = " ".join(label.text() for label in dialog.findChildren(QtWidgets.QLabel))
    docs = (Path(__file__).resolve().parents[1] / "docs" / "tuner.md").read_text()
    for key in ("Tab / Shift+Tab", "Alt+Right / Alt+Left", "] / [", "Delete / Ctrl+D",
                "Ctrl+Z / Ctrl+Shift+Z", "Home / End", "Pattern editor"):  # fmt: skip
        assert key in text and key in docs
    dialog.close()
