"""Where the pattern editor sits: a dock beside the Device dock, hidden at first, shown by
File > Pattern editor and Ctrl+E; readable at 1280 x 720 (three tracks, the properties whole,
the Tune tab's views above it); put away by Reset layout; disabled by a Blind A/B session."""

import pytest
from PySide6 import QtCore

import tactile_core as tc

from .timeline_support import editor_of
from .tuner_support import settle

pytestmark = pytest.mark.usefixtures("qt_settings")


def menu_action(window, menu: str, text: str):
    bar = next(a.menu() for a in window.menuBar().actions() if a.text() == menu)
    return next(a for a in bar.actions() if a.text() == text)


def test_hidden_at_first_and_shown_by_the_file_menu(window, qtbot):
    editor = window.timeline
    assert not editor.dock.isVisible()
    menu_action(window, "&File", "Pattern editor").trigger()
    settle()
    assert editor.dock.isVisible()
    qtbot.waitUntil(editor.panel.view.hasFocus, timeout=5000)  # the keys are the time line's
    assert window.tabifiedDockWidgets(editor.dock) == [window.device_dock]
    toggle = menu_action(window, "&View", "Pattern editor panel")
    assert toggle.shortcut().toString() == "Ctrl+E"
    menu_action(window, "&View", "Reset layout").trigger()
    settle()
    assert not editor.dock.isVisible()


def front_tab(window) -> str:
    """The text of the tab in front where the pattern editor shares a place with a dock."""
    from PySide6 import QtWidgets

    def has_editor(bar) -> bool:
        return any(bar.tabText(i).startswith("Pattern editor") for i in range(bar.count()))

    bars = [bar for bar in window.findChildren(QtWidgets.QTabBar) if has_editor(bar)]
    assert len(bars) == 1
    return bars[0].tabText(bars[0].currentIndex())


def test_ctrl_e_brings_the_editor_to_the_front(window, qtbot):
    # Ctrl+E added a "Pattern editor" tab but left the Device tab in front: nothing visible
    # changed, while File > Pattern editor brought it up.
    window.activateWindow()
    qtbot.keyClick(window.tabs, QtCore.Qt.Key.Key_E, QtCore.Qt.KeyboardModifier.ControlModifier)
    settle()
    assert window.timeline.dock.isVisible() and front_tab(window).startswith("Pattern editor")
    qtbot.waitUntil(window.timeline.panel.view.hasFocus, timeout=5000)
    window.device_dock.raise_()  # the Device tab clicked
    settle()
    assert front_tab(window) == "Device"


def test_readable_at_1280_by_720(window, qtbot):
    from tactile_tuner.timeline.view import RULER_PX, TRACK_PX

    editor = editor_of(window)
    editor.open_pattern(
        tc.Pattern(
            [tc.Effect(tc.Line((0.5, 1.5), (4.5, 1.5)), duration_s=1.0, track=t) for t in range(3)]
        ),
        None,
        "Open",
    )
    editor.model.select(0)
    settle()
    assert (window.width(), window.height()) == (1280, 720)  # the dock did not grow it
    view = editor.panel.view
    assert view.viewport().height() >= RULER_PX + 3 * TRACK_PX  # three tracks in view
    assert view.horizontalScrollBar().maximum() == 0  # fitted: nothing to scroll to
    side = editor.panel.side
    panel = editor.panel.panel
    assert side.viewport().width() >= panel.minimumSizeHint().width()  # no field cut off
    assert side.horizontalScrollBar().maximum() == 0
    for field in (panel.start_spin, panel.duration_spin, panel.group_combo, panel.envelope_edit):
        corner = field.mapTo(side.viewport(), QtCore.QPoint(field.width(), field.height()))
        assert side.viewport().rect().contains(corner - QtCore.QPoint(1, 1))
    heatmap = window.tune.heatmap
    assert heatmap.isVisible() and heatmap.height() >= 250  # the views above it stay readable


def test_a_blind_session_disables_the_editor(window, qtbot):
    editor = editor_of(window)
    assert editor.panel.isEnabled()
    window.blind.start(seed=3)
    assert not editor.panel.isEnabled()
    window.blind.confirm = lambda title, text: True
    window.blind.cancel()
    assert editor.panel.isEnabled()


def test_picking_tactors_is_dropped_by_a_second_click(window, qtbot):
    editor = editor_of(window)
    editor.set_picking(True)
    window.tune.heatmap.cell_clicked.emit(2, 3, False)  # as a click on tactor (2, 3) does
    window.tune.heatmap.cell_clicked.emit(4, 0, False)
    window.tune.heatmap.cell_clicked.emit(2, 3, False)
    assert editor.picked == [4]
    assert window.statusBar().currentMessage() == "tactors picked: (4,0)"
