"""The tuner's views on layouts that are not grids: the heatmap draws the belt, the sleeve and the
vest as discs where their actuators are, a wrap as one turn with its seam, the curves name the
actuators, and a path drawn across the seam streams on.

Driven through the state object, checked on what the views show and on what the simulated array is
sent."""

import numpy as np
import pyqtgraph as pg
import pytest
from PySide6 import QtWidgets

import tactile_core as tc
from tactile_core.device.profile import find_profile
from tactile_core.rendering.curves import activation_curves
from tactile_core.rendering.placement import default_shape, fits, shape_defaults, unrolled

from .helpers import record_sent

pytestmark = pytest.mark.usefixtures("qt_settings")

LAYOUTS = ("belt-8", "sleeve-2x6", "vest-4x5")
VIRIDIS = pg.colormap.get("viridis").getLookupTable(0.0, 1.0, 256, alpha=False)


def open_window(qtbot, profile):
    from tactile_tuner.window import MainWindow

    win = MainWindow(profile=find_profile(profile), restore=False, process=False)
    qtbot.addWidget(win)
    win.resize(1400, 900)
    win.show()
    qtbot.waitExposed(win)
    qtbot.waitUntil(lambda: win.device.stats.frames > 5, timeout=10000)
    return win


@pytest.fixture
def belt(qtbot):
    win = open_window(qtbot, "belt-8")
    yield win
    win.close()


def disc_colour(heatmap, i):
    return heatmap.cells._spots[i].brush().color().getRgb()[:3]


@pytest.mark.parametrize("name", LAYOUTS)
def test_each_shipped_layout_is_drawn_as_a_disc_per_actuator(qtbot, name):
    win = open_window(qtbot, name)
    layout = find_profile(name).layout
    heatmap = win.tune.heatmap
    assert win.state.layout == layout and heatmap.layout == layout
    assert not heatmap.image.isVisible()  # no grid image: discs
    x, y = heatmap.cells.scatter.getData()
    assert len(x) == layout.size
    np.testing.assert_array_equal(np.column_stack([x, y]), layout.xy)
    names = [item.textItem.toPlainText() for item in heatmap.cells.names]
    assert names == list(layout.names)
    seams = heatmap.cells.seams
    if layout.wrap is None:
        assert seams == [] and heatmap.cells._ghosts is None
    else:  # a dashed line at 0 and at the circumference, each labelled
        c = layout.wrap.circumference
        assert [line.getData()[0][0] for line, _ in seams] == [0.0, c]
        assert [label.textItem.toPlainText().strip() for _, label in seams] == [
            "seam", f"seam ({c:g} = 0)"]  # fmt: skip
        assert seams[0][0].opts["pen"].style() == pg.QtCore.Qt.PenStyle.DashLine
        x0, x1, _, _ = heatmap.cells.range
        assert x0 < 0.0 and x1 > c  # one turn and a little of each neighbour
    groups = [label.textItem.toPlainText() for _, label in heatmap.cells.groups]
    assert groups == [group for group, _ in layout.groups]
    assert win.state.scene.method == "BA" and fits(win.state.scene.shape, layout)
    assert "playing BA instead of AS" in win.statusBar().currentMessage()
    win.close()


def test_the_discs_show_the_levels_sent(belt, qtbot):
    belt.state.set_view_mode("sent")
    belt.state.update(playing=True, hold_s=0.3, dither=False)  # one frame, held
    heatmap = belt.tune.heatmap

    def shown():
        sent = belt.device.sent()
        return sent.any() and np.array_equal(heatmap.values, sent)

    qtbot.waitUntil(shown, timeout=3000)
    sent = belt.device.sent()
    assert sent.shape == (8,) and (sent > 0).sum() >= 2
    for i, v in enumerate(sent):
        assert disc_colour(heatmap, i) == tuple(VIRIDIS[round(v * 255)]), i
    lit = int(np.argmax(sent))
    ghosts = heatmap.cells._ghost_of  # the front actuator, drawn again past the seam
    assert ghosts == [0]
    assert heatmap.cells._ghosts[0].brush().color().getRgb()[:3] == disc_colour(heatmap, 0)
    assert f"actuator {belt.state.layout.names[lit]}" in heatmap.cells.describe(lit)


def test_a_frame_changes_only_the_discs_whose_colour_changed(qtbot):
    from tactile_tuner.views.heatmap import HeatmapView

    view = HeatmapView(layout=find_profile("vest-4x5").layout)
    qtbot.addWidget(view)
    calls = []
    for i, spot in enumerate(view.cells._spots):
        spot.setBrush = lambda brush, i=i, f=spot.setBrush: (calls.append(i), f(brush))
    frame = np.zeros(20)
    frame[[5, 6]] = 0.5
    view.set_frame(frame)
    assert sorted(calls) == [5, 6]
    calls.clear()
    view.set_frame(frame.copy())  # the same values: nothing to repaint
    frame[6] = 0.25  # the caller's buffer, changed in place
    view.set_frame(frame)
    assert calls == [6] and view.values[6] == 0.25
    view.set_point((1.0, 2.0))
    assert view.point.isVisible() and view.point_xy == (1.0, 2.0)


def test_the_moving_point_and_the_outline_go_round_the_belt(belt):
    heatmap = belt.tune.heatmap
    heatmap.set_point((9.25, 0.0))  # past the seam: drawn a quarter pitch after it
    assert heatmap.point_xy == (1.25, 0.0)
    belt.state.update(shape=tc.Line((6.0, 0.0), (10.0, 0.0)))
    belt.tune.refresh()
    x, _ = heatmap.outline.getData()
    assert list(x[:2]) == [6.0, 8.0] and list(x[-2:]) == [0.0, 2.0]  # cut at the seam
    assert np.isnan(x).sum() == 1


def test_the_curves_panel_lists_the_actuators_by_name(belt):
    belt.tune.refresh()
    curves = belt.tune.curves
    scene = belt.state.scene
    expected = activation_curves(scene.shape, "BA", duration_s=scene.duration_s,
                                 grid=belt.state.layout, samples=400)  # fmt: skip
    assert curves.names() == list(expected.names)
    assert curves.names()[:3] == ["front", "front-left", "left"]  # round the waist
    assert curves._solid[2].toolTip() == "left"
    assert set(belt.tune.heatmap._frames) == set(expected.cells)  # rings in the curves' colours
    belt.tune.lanes_check.setChecked(True)
    ticks = [label for _, label in curves.getAxis("left")._tickLevels[0]]
    assert sorted(ticks) == sorted(expected.names)
    assert curves.getAxis("left").labelText == "actuator"


def test_a_path_drawn_across_the_seam_streams_on(belt, qtbot):
    belt.controls.playback.draw_check.setChecked(True)
    heatmap = belt.tune.heatmap
    assert heatmap.drawing and belt.state.scene.method == "BA"
    levels = belt.device.sent_levels
    heatmap.point_drawn.emit(7.2, 0.0)  # by front-right (7), towards the seam at 8
    assert belt.state.scene.shape == tc.Line((7.2, 0.0), (7.2, 0.0))
    qtbot.waitUntil(lambda: levels()[7] > levels()[0] > 0, timeout=3000)  # front (0) too
    heatmap.point_drawn.emit(8.3, 0.1)  # dragged past the seam: front, a little way round
    shape = belt.state.scene.shape
    assert shape.p0 == pytest.approx((0.3, 0.1))
    qtbot.waitUntil(lambda: levels()[0] > levels()[1] > 0 and levels()[7] == 0, timeout=3000)
    heatmap.point_drawn.emit(-0.7, 0.0)  # and back across it, the other way
    assert belt.state.scene.shape.p0 == pytest.approx((7.3, 0.0))
    qtbot.waitUntil(lambda: levels()[7] > levels()[0] > 0 and levels()[1] == 0, timeout=3000)
    assert heatmap.point_xy is None or 0.0 <= heatmap.point_xy[0] <= 8.0
    heatmap.draw_released.emit()
    qtbot.waitUntil(lambda: not levels().any(), timeout=3000)


def test_clicking_a_disc_pulses_that_actuator_alone(belt, qtbot):
    before = belt.state.scene
    sent = record_sent(belt)  # the pulse lasts 0.3 s: every frame, not the newest one
    belt.tune.heatmap.actuator_clicked.emit(3, False)
    assert belt.device.streamer.scene.method == "PK"  # on the array, beside the tuning
    assert belt.state.scene == before
    qtbot.waitUntil(lambda: any(lv[3] == 22 for lv in list(sent)), timeout=3000)
    pulse = [lv for lv in list(sent) if lv[3] == 22]
    assert all((lv > 0).sum() == 1 for lv in pulse)  # that actuator alone
    qtbot.waitUntil(lambda: belt.device.streamer.scene.shape == before.shape,
                    timeout=3000)  # fmt: skip


def test_a_grid_profile_keeps_the_grid_image(qtbot):
    win = open_window(qtbot, "grid-3x3")
    heatmap = win.tune.heatmap
    assert heatmap.image.isVisible() and heatmap.values.shape == (3, 3)
    assert heatmap.cells.range == (0.0, 3.0, 0.0, 3.0)
    assert win.state.scene.method == "AS"  # the paper's methods render on any grid
    assert fits(win.state.scene.shape, win.state.layout)  # the palm's line did not fit
    win.close()


def test_shapes_for_a_layout_fit_it_and_paths_unroll_at_the_seam():
    belt, sleeve, vest = (find_profile(n).layout for n in LAYOUTS)
    assert default_shape(belt) == tc.Line((0.0, 0.0), (8.0, 0.0))  # once round the waist
    assert default_shape(sleeve) == tc.Line((0.0, 0.0), (6.0, 1.5))  # a helix, wrist to elbow
    assert isinstance(default_shape(vest), tc.Circle)
    for layout in (belt, sleeve, vest):
        assert all(fits(shape, layout) for shape in shape_defaults(layout).values())
    assert not fits(tc.Circle((2.5, 3.0), 2.0), belt)  # the palm's circle is off the belt
    assert fits(tc.Line((-3.0, 0.0), (20.0, 0.0)), belt)  # any way round
    x, y = unrolled([(6.0, 0.0), (10.0, 1.0)], belt)
    np.testing.assert_allclose(x, [6.0, 8.0, np.nan, 0.0, 2.0])
    np.testing.assert_allclose(y, [0.0, 0.5, np.nan, 0.5, 1.0])
    x, _ = unrolled([(1.0, 0.0), (-17.0, 0.0)], belt)  # twice round the other way
    np.testing.assert_allclose(x, [1, 0, np.nan, 8, 0, np.nan, 8, 0, np.nan, 8, 7])
    # a drawn path with a point exactly on the seam, and paths that stop on it
    x, _ = unrolled([(7.5, 0.0), (8.0, 0.0), (8.5, 0.0)], belt)
    np.testing.assert_allclose(x, [7.5, 8, np.nan, 0, 0, 0.5])
    np.testing.assert_allclose(unrolled([(0.0, 0.0), (8.0, 0.0)], belt)[0], [0, 8])
    np.testing.assert_allclose(unrolled([(0.0, 0.0), (-8.0, 0.0)], belt)[0], [8, 0])
    x, _ = unrolled([(0.5, 0.5), (2.5, 1.5)], vest)
    np.testing.assert_allclose(x, [0.5, 2.5])


def _tick_labels(axis) -> list[str]:
    from PySide6 import QtGui

    image = QtGui.QImage(10, 10, QtGui.QImage.Format.Format_ARGB32)
    painter = QtGui.QPainter(image)
    try:
        _, _, texts = axis.generateDrawSpecs(painter)
    finally:
        painter.end()
    return [text for _, _, text in texts]


def test_the_heatmaps_x_axis_labels_the_grids_edges(qtbot):
    # 1 to 4 were labelled, 0 and 5 (the palm array's edges, on the axis's ends) were not.
    from tactile_tuner.views import HeatmapView

    view = HeatmapView(5, 6)
    qtbot.addWidget(view)
    view.resize(500, 600)
    view.show()
    qtbot.waitExposed(view)
    assert _tick_labels(view.plot.getAxis("bottom")) == ["0", "1", "2", "3", "4", "5"]
    assert _tick_labels(view.plot.getAxis("left")) == ["0", "1", "2", "3", "4", "5", "6"]


@pytest.mark.parametrize("size", [(1280, 720), (1400, 900)])
def test_the_vests_names_are_written_over_the_outline_clear_of_the_discs(qtbot, size):
    # The dashed outline of the shape ran through the names (r3c0, r2c0, r4c1 on the vest's
    # circle), a lit actuator's ring touched the name under it, and at 1280 x 720 a name's
    # box covered the top of the disc below it.
    from PySide6 import QtCore

    win = open_window(qtbot, "vest-4x5")
    try:
        win.resize(*size)
        qtbot.waitUntil(lambda: win.size().toTuple() == size)
        heatmap = win.tune.heatmap
        win.tune.fit_heatmap()
        win.tune.refresh()
        QtWidgets.QApplication.processEvents()
        heatmap.cells.fit_labels()
        cells, outline = heatmap.cells, heatmap.outline
        x, y = outline.getData()
        r = cells.size / 2
        xy = win.state.layout.xy
        crossed = 0
        for item, (px, py) in zip(cells.names, win.state.layout.positions):
            if not item.isVisible():
                continue
            box = item.mapRectToView(item.boundingRect())
            top, bottom = max(box.top(), box.bottom()), min(box.top(), box.bottom())
            assert top <= py - 1.12 * r  # under the ring, wholly
            below = [v for u, v in xy if abs(u - px) < 2 * r and v < py]
            assert bottom >= max(below, default=-np.inf) + r  # above the disc below
            if any(box.contains(QtCore.QPointF(u, v)) for u, v in zip(x, y)):
                crossed += 1
                assert item.zValue() > outline.zValue()
                fill = item.fill.color()
                assert fill.alpha() >= 128
                assert fill.rgb() == heatmap.backgroundBrush().color().rgb()
        if size == (1400, 900):
            assert all(item.isVisible() for item in cells.names)
            assert crossed >= 2  # the default circle crosses names
    finally:
        win.close()


@pytest.mark.parametrize(("size", "px_per_pitch"), [((1280, 720), 40), ((1600, 1000), 70)])
def test_the_belt_spans_the_tab_above_the_plots(qtbot, size, px_per_pitch):
    # Beside the plots the belt's strip and its caption took the top of a tall, narrow panel
    # and left the rest of it empty: 50 % of it at 1280 x 720 (36 px a pitch), 63 % at
    # 1600 x 1000 (55 px a pitch).
    win = open_window(qtbot, "belt-8")
    try:
        win.resize(*size)
        tune = win.tune
        qtbot.waitUntil(lambda: win.size().toTuple() == size)
        tune.fit_heatmap()
        qtbot.waitUntil(lambda: tune.stacked)
        heatmap = tune.heatmap
        assert heatmap.width() >= 0.95 * tune.width()  # across the tab
        assert tune.plots.orientation() == pg.QtCore.Qt.Orientation.Horizontal  # side by side

        def empty_below() -> float:  # the part of the panel under the caption
            bottom = heatmap.caption.mapRectToScene(heatmap.caption.boundingRect()).bottom()
            return (heatmap.height() - bottom) / heatmap.height()

        qtbot.waitUntil(lambda: empty_below() <= 0.15)
        assert 1 / heatmap.plot.vb.viewPixelSize()[0] >= px_per_pitch
        win.device.set_profile(find_profile("palm-5x6"))  # a grid stands beside them
        tune.fit_heatmap()
        assert not tune.stacked
    finally:
        win.close()
