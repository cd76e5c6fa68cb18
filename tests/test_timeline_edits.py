"""The pattern editor's edits in the window: the property panel's fields change the selected
effect (a refused value is explained under them and nothing changes), effects are added from
the scene, a drawing, tactors clicked on the heatmap and as a Tactile Brush stroke, and every
edit undoes and redoes to exactly the pattern there was."""

import pytest
from PySide6 import QtCore

import tactile_core as tc

from .timeline_support import click_tactor, editor_of

pytestmark = pytest.mark.usefixtures("qt_settings")

LINE = tc.Line((0.5, 1.5), (4.5, 1.5))


def opened(window, pattern):
    editor = editor_of(window)
    editor.open_pattern(pattern, None, "Open")
    return editor, editor.panel.panel


def test_the_panel_edits_the_selected_effect(window, qtbot):
    editor, panel = opened(window, tc.Pattern([tc.Effect(LINE, duration_s=0.5)]))
    editor.model.select(0)
    assert panel.kind_label.text() == "line"
    panel.repeat_spin.setValue(3)
    panel.start_spin.setValue(0.25)
    panel.duration_spin.setValue(0.4)
    panel.track_spin.setValue(2)
    panel.intensity_spin.setValue(0.5)
    panel.name_edit.setText("bar")
    panel.name_edit.editingFinished.emit()
    effect = editor.model.pattern.effects[0]
    assert (effect.repeat, effect.start_s, effect.duration_s, effect.track, effect.name) == (
        3, 0.25, 0.4, 1, "bar")  # fmt: skip
    assert effect.envelope == ((0.0, 0.5),)  # intensity 0.5: the gain throughout
    panel.envelope_edit.setText("0:0.2, 0.2:1")
    panel.envelope_edit.editingFinished.emit()
    assert editor.model.pattern.effects[0].envelope == ((0.0, 0.2), (0.2, 1.0))
    assert panel.intensity_spin.value() == 1.0  # the envelope's peak
    assert editor.undo_stack.count() == 1 + 7  # the open, then one command per field


def test_method_and_group_come_from_the_scene_and_the_layout(window, qtbot):
    window.files.use_profile("vest-front-back")
    qtbot.waitUntil(lambda: window.device.profile.name == "vest-front-back", timeout=10_000)
    editor, panel = opened(window, tc.Pattern([tc.Effect(tc.Line((0, 2), (3, 2)),
                                                         duration_s=0.8)]))  # fmt: skip
    editor.model.select(0)
    groups = [panel.group_combo.itemText(i) for i in range(panel.group_combo.count())]
    assert groups == ["every actuator", "front", "back"]
    methods = [panel.method_combo.itemText(i) for i in range(panel.method_combo.count())]
    assert methods[0] == "the scene's" and "TB" in methods and "AS" not in methods  # a layout
    panel.group_combo.setCurrentIndex(1)
    panel.group_combo.activated.emit(1)
    panel.method_combo.setCurrentText("TB")
    panel.method_combo.activated.emit(panel.method_combo.currentIndex())
    effect = editor.model.pattern.effects[0]
    assert (effect.group, effect.method) == ("front", "TB")
    panel.method_combo.setCurrentIndex(0)
    panel.method_combo.activated.emit(0)
    assert editor.model.pattern.effects[0].method is None


def test_a_refused_value_is_explained_and_changes_nothing(window, qtbot):
    editor, panel = opened(window, tc.Pattern([tc.Effect(LINE, duration_s=0.5)]))
    editor.model.select(0)
    before = editor.model.pattern
    panel.envelope_edit.setText("0:0.5, 0.3:0.2, 0.1:1")
    panel.envelope_edit.editingFinished.emit()
    assert "envelope[2].time_s must be later than envelope[1].time_s" in panel.message.text()
    assert panel.envelope_edit.text() == ""  # the value in force again
    panel.envelope_edit.setText("0:2")
    panel.envelope_edit.editingFinished.emit()
    assert "envelope[0].gain must be within [0, 1], got 2" in panel.message.text()
    panel.method_combo.setCurrentText("XX:r=1")
    panel.method_combo.lineEdit().editingFinished.emit()
    assert "XX" in panel.message.text()
    panel.start_spin.setValue(3599.9)  # 3599.9 + 0.5 s ends after the hour a pattern may last
    assert "after the 3600 s a pattern may last" in panel.message.text()
    assert panel.start_spin.value() == 0.0
    assert editor.model.pattern is before and editor.undo_stack.count() == 1
    assert window.isVisible()  # nothing raised out of a slot


def test_an_edit_that_would_no_longer_play_here_is_refused(window, qtbot):
    window.files.use_profile("vest-front-back")
    qtbot.waitUntil(lambda: window.device.profile.name == "vest-front-back", timeout=10_000)
    back_dot = tc.Dots([tc.Dot(32, 1.0, 0.0, 0.1)])  # actuator 32: on the back panel (20-39)
    editor, panel = opened(window, tc.Pattern([tc.Effect(back_dot, group="back")]))
    editor.model.select(0)
    panel.group_combo.setCurrentIndex(1)  # front
    panel.group_combo.activated.emit(1)
    assert "which is not in the effect's group 'front'" in panel.message.text()
    assert editor.model.pattern.effects[0].group == "back"


def test_undo_and_redo_restore_exactly_every_pattern_there_was(window, qtbot):
    editor, _ = opened(window, tc.Pattern([tc.Effect(LINE, duration_s=0.5)]))
    model = editor.model
    seen = [model.pattern]
    edits = [lambda: model.move(0, 0.33, 1), lambda: model.resize(0, 0.77),
             lambda: model.change(0, repeat=2, envelope=((0.0, 0.3), (0.5, 1.0))),
             lambda: model.add(tc.Effect(tc.Circle((2.5, 3), 1.5), duration_s=1.0)),
             lambda: model.duplicate(1), lambda: model.delete(0),
             lambda: model.change_pattern(name="renamed", combine="sum")]  # fmt: skip
    for edit in edits:
        assert editor.push(edit)
        seen.append(model.pattern)
    for k in range(len(edits), 0, -1):
        editor.undo_stack.undo()
        assert model.pattern == seen[k - 1]
    assert model.pattern is seen[0]  # the very object
    for k in range(1, len(edits) + 1):
        editor.undo_stack.redo()
        assert model.pattern == seen[k]


def test_ctrl_z_and_ctrl_shift_z_undo_and_redo(window, qtbot):
    editor, _ = opened(window, tc.Pattern([tc.Effect(LINE, duration_s=0.5)]))
    editor.model.select(0)
    view = editor.panel.view
    view.setFocus()
    qtbot.keyClick(view, QtCore.Qt.Key.Key_Right)
    assert editor.model.pattern.effects[0].start_s == 0.01
    qtbot.keyClick(view, QtCore.Qt.Key.Key_Z, QtCore.Qt.KeyboardModifier.ControlModifier)
    assert editor.model.pattern.effects[0].start_s == 0.0
    qtbot.keyClick(view, QtCore.Qt.Key.Key_Z, QtCore.Qt.KeyboardModifier.ControlModifier
                   | QtCore.Qt.KeyboardModifier.ShiftModifier)  # fmt: skip
    assert editor.model.pattern.effects[0].start_s == 0.01


def test_add_the_scenes_shape_at_the_playhead(window, qtbot):
    editor, _ = opened(window, tc.Pattern([tc.Effect(LINE, duration_s=1.0)]))
    window.state.update(shape=tc.Circle((2.5, 3.0), 1.5), method="IM", duration_s=1.5)
    editor.model.set_playhead(0.504)
    assert editor.add_from_scene()
    added = editor.model.pattern.effects[-1]
    assert added.content == tc.Circle((2.5, 3.0), 1.5)
    assert (added.method, added.duration_s, added.start_s) == ("IM", 1.5, 0.5)
    assert added.track == 1  # track 0 is busy then
    assert editor.model.selected == 1


def test_add_the_drawing_at_the_pace_it_was_drawn(window, qtbot):
    editor, _ = opened(window, tc.Pattern())
    ticks = iter([10.0, 10.25, 10.75])
    editor.clock = lambda: next(ticks)
    window.tune.gestures.set_draw_mode(True)
    heatmap = window.tune.heatmap
    for x, y in ((0.5, 0.5), (2.5, 3.0), (4.5, 5.5)):
        heatmap.point_drawn.emit(x, y)  # as a drag on the heatmap does
    heatmap.draw_released.emit()
    window.tune.gestures.set_draw_mode(False)  # the drawing stays the editor's
    assert editor.add_from_drawing()
    (effect,) = editor.model.pattern.effects
    assert effect.content.points == ((0.5, 0.5), (2.5, 3.0), (4.5, 5.5))
    assert effect.content.times_s == (0.0, 0.25, 0.75)
    assert effect.duration_s == 0.75 and effect.method is None


def test_add_dots_clicked_on_the_heatmap(window, qtbot):
    editor, _ = opened(window, tc.Pattern())
    add_menu = editor.panel.add_button.menu()
    pick = next(a for a in add_menu.actions() if a.text().startswith("Pick tactors"))
    pick.trigger()
    assert editor.picking
    heatmap = window.tune.heatmap
    for col, row in ((2, 3), (4, 0), (0, 5)):
        click_tactor(qtbot, heatmap, col + 0.5, row + 0.5)
    qtbot.waitUntil(lambda: len(editor.picked) == 3, timeout=5000)
    assert not window.tune.gestures.pulsing  # picking, not pulsing
    next(a for a in add_menu.actions() if a.text().startswith("Dots")).trigger()
    (effect,) = editor.model.pattern.effects
    assert [d.at for d in effect.content.dots] == [3 * 5 + 2, 4, 5 * 5]  # row * 5 + col
    assert not editor.picking


def test_add_a_tactile_brush_stroke_and_delete_and_duplicate(window, qtbot):
    editor, _ = opened(window, tc.Pattern())
    window.state.update(shape=LINE, duration_s=0.8)
    assert editor.add_brush()
    (stroke,) = editor.model.pattern.effects
    assert (stroke.content, stroke.method, stroke.duration_s) == (LINE, "TB", 0.8)
    assert editor.duplicate_selected()
    assert editor.model.pattern.effects[1] == stroke.replace(start_s=0.8)
    assert editor.delete_selected()
    assert editor.model.pattern.effects == (stroke,)
