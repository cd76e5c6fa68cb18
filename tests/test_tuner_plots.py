"""The tune tab's plots explain themselves: a colour per tactor that no cursor shares, lanes
labelled by tactor, a hovered cell and its curve highlighted together (and no longer once the
mouse leaves), axes in grid units, a key that never covers the curves, the palette followed,
and a paused trace's cursor and point left where they were."""

import pytest
from PySide6 import QtCore, QtGui, QtWidgets

import tactile_core as tc

from .tuner_support import WAIT_MS, frames_shown

Key = QtCore.Qt.Key


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
                    and window.tune.curves.curves.cells[0] == (0, 1), timeout=WAIT_MS)  # fmt: skip
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
    qtbot.waitUntil(lambda: window.tune.curves.curves is not None, timeout=WAIT_MS)
    cell = window.tune.curves.curves.cells[2]
    vb = window.tune.heatmap.plot.vb
    scene_point = vb.mapViewToScene(QtCore.QPointF(cell[0] + 0.5, cell[1] + 0.5))
    qtbot.mouseMove(window.tune.heatmap.viewport(), window.tune.heatmap.mapFromScene(scene_point))
    qtbot.waitUntil(lambda: window.tune.curves._solid[cell].opts["pen"].width() == 5,
                    timeout=WAIT_MS)  # fmt: skip
    assert f"tactor ({cell[0]},{cell[1]})" in window.tune.heatmap.readout.text
    window.tune.curves.curve_hovered.emit((0, 1))
    assert window.tune.heatmap.highlight_item.isVisible()
    assert window.tune.heatmap.highlight_item.rect().topLeft() == QtCore.QPointF(0, 1)


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


def test_heatmap_ticks_are_grid_units(window):
    ticks = window.tune.heatmap.plot.getAxis("bottom")._tickLevels[0]
    assert [v for v, _ in ticks] == [0, 1, 2, 3, 4, 5]


def test_the_correction_key_never_covers_the_curves(window):
    assert window.tune.correction.plotItem.legend is None
    title = window.tune.correction.plotItem.titleLabel.text
    assert "device levels" in title


def test_the_plots_follow_a_dark_palette(window, qtbot):
    from tactile_tuner.theme import apply_theme

    app = QtWidgets.QApplication.instance()
    saved_palette, saved_style = app.palette(), app.style().name()
    curves, heatmap = window.tune.curves, window.tune.heatmap
    try:
        apply_theme(app, "dark")
        qtbot.waitUntil(lambda: curves.backgroundBrush().color().lightness() < 60,
                        timeout=WAIT_MS)  # fmt: skip
        assert heatmap.backgroundBrush().color().lightness() < 60
        apply_theme(app, "light")
        qtbot.waitUntil(lambda: curves.backgroundBrush().color().lightness() > 200,
                        timeout=WAIT_MS)  # fmt: skip
    finally:
        app.setPalette(saved_palette)
        app.setStyle(saved_style)


@pytest.mark.parametrize("how", ["space", "all off"])
def test_pause_and_all_off_leave_the_cursor_and_point_where_they_were(window, qtbot, how):
    curves, heatmap = window.tune.curves, window.tune.heatmap
    qtbot.waitUntil(lambda: curves.cursor.isVisible() and heatmap.point_xy is not None,
                    timeout=WAIT_MS)  # fmt: skip
    if how == "space":
        window.tabs.setFocus()
        qtbot.keyClick(window.tabs, Key.Key_Space)
    else:
        qtbot.mouseClick(window.controls.playback.off_button, QtCore.Qt.MouseButton.LeftButton)
    assert not window.state.scene.playing
    frames_shown(qtbot, window)  # the display has shown the paused trace
    assert curves.cursor.isVisible() and heatmap.point.isVisible() and heatmap.point_xy is not None
    at = curves.cursor.value()
    frames_shown(qtbot, window)
    assert curves.cursor.value() == at  # frozen where it was paused
