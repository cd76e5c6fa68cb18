"""The pattern editor's time line under the mouse (real mouse events, pytest-qt): a block
dragged moves its effect by what the mouse moved, snapped to the 10 ms grid, onto another
track; its right edge resizes one play; the ruler scrubs; each drag is one undoable edit."""

import pytest
from PySide6 import QtCore

import tactile_core as tc
from tactile_core.files.pattern import PatternCue

from .timeline_support import block_point, drag, editor_of
from .tuner_support import WAIT_MS

pytestmark = pytest.mark.usefixtures("qt_settings")


def strokes():
    return tc.Pattern([tc.Effect(tc.Line((0.5, 0.5), (4.5, 5.5)), start_s=0.0, duration_s=0.5),
                       tc.Effect(tc.Line((1, 1), (4, 1)), start_s=1.0, duration_s=0.4,
                                 repeat=2)], name="two strokes")  # fmt: skip


def opened(window, pattern=None):
    editor = editor_of(window)
    editor.open_pattern(pattern or strokes(), None, "Open")
    return editor, editor.panel.view


def snapped(seconds: float) -> float:
    """To the 10 ms grid, as the docs say moves and resizes snap."""
    return round(round(seconds / 0.01) * 0.01, 9)


def test_dragging_a_block_moves_its_start_by_the_mouse_snapped_to_10_ms(window, qtbot):
    editor, view = opened(window)
    start = block_point(view, 0)
    pps = view.pixels_per_s
    dx = round(0.62 * pps) + 1  # about 0.62 s: not a whole number of steps
    drag(qtbot, view.viewport(), start, start + QtCore.QPoint(dx, 0))
    moved = editor.model.pattern.effects[0]
    assert moved.start_s == pytest.approx(snapped(dx / pps), abs=1e-9)
    assert moved.track == 0 and moved.duration_s == 0.5
    assert editor.model.pattern.effects[1] == strokes().effects[1]  # the other left alone
    assert editor.model.selected == 0
    assert editor.undo_stack.undoText() == "Move effect 1"


def test_dragging_a_block_down_puts_it_on_the_next_track(window, qtbot):
    from tactile_tuner.timeline.view import TRACK_PX

    editor, view = opened(window)
    start = block_point(view, 1)
    drag(qtbot, view.viewport(), start, start + QtCore.QPoint(0, TRACK_PX + 3))
    assert editor.model.pattern.effects[1].track == 1
    assert editor.model.pattern.effects[1].start_s == 1.0


def test_dragging_the_right_edge_resizes_one_play(window, qtbot):
    editor, view = opened(window)
    edge = block_point(view, 1, x_fraction=1.0) - QtCore.QPoint(2, 0)
    pps = view.pixels_per_s  # (the view zooms out after, the pattern being longer)
    dx = round(0.3 * pps)
    drag(qtbot, view.viewport(), edge, edge + QtCore.QPoint(dx, 0))
    effect = editor.model.pattern.effects[1]
    # the block spans both plays (2 x 0.4 s): its end moved by dx, each play by half of it
    expected = snapped((0.8 + dx / pps) / 2)
    assert effect.duration_s == pytest.approx(expected, abs=1e-9)
    assert effect.start_s == 1.0 and effect.repeat == 2
    assert editor.undo_stack.undoText() == "Resize effect 2"


def test_a_drag_is_undone_in_one_step(window, qtbot):
    editor, view = opened(window)
    start = block_point(view, 0)
    drag(qtbot, view.viewport(), start, start + QtCore.QPoint(80, 0), steps=10)
    assert editor.model.pattern != strokes()
    editor.undo_stack.undo()
    assert editor.model.pattern == strokes()


def test_a_click_selects_and_a_click_on_nothing_deselects(window, qtbot):
    from tactile_tuner.timeline.view import TRACK_PX

    editor, view = opened(window)
    qtbot.mouseClick(view.viewport(), QtCore.Qt.MouseButton.LeftButton, pos=block_point(view, 1))
    assert editor.model.selected == 1
    assert editor.panel.panel.start_spin.value() == 1.0  # the panel shows it
    below = block_point(view, 1) + QtCore.QPoint(0, 2 * TRACK_PX)
    qtbot.mouseClick(view.viewport(), QtCore.Qt.MouseButton.LeftButton, pos=below)
    assert editor.model.selected is None
    assert editor.model.pattern == strokes()  # clicks edit nothing


def test_the_ruler_scrubs_the_pattern_held_there(window, qtbot):
    editor, view = opened(window)
    x = round(view.mapFromScene(QtCore.QPointF(view.x_of(1.2), 0)).x())
    drag(qtbot, view.viewport(), QtCore.QPoint(x - 40, 8), QtCore.QPoint(x, 8))
    assert editor.model.playhead_s == pytest.approx(view.time_at(x), abs=1e-9)
    source = window.state.scene.source
    assert isinstance(source, PatternCue) and source.hold
    assert source.pattern is editor.model.pattern
    assert source.start_s == pytest.approx(editor.model.playhead_s, abs=1e-9)
    qtbot.waitUntil(lambda: window.device.stats.state == "streaming", timeout=WAIT_MS)
