"""The tune tab's live display repaints only what changed and computes only the lit tactors.

Issue 18 (item 3): the display shares the machine with the stream; a frame that did not change
must not repaint, and a frame must not allocate the whole grid's arrays.
"""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import tactile_core as tc
from tactile_core.rendering.percept import felt_magnitude
from tactile_tuner.tune.live import felt1

pytestmark = pytest.mark.usefixtures("qt_settings")


@given(st.floats(0.0, 1.0), st.floats(0.0, 0.9), st.floats(0.1, 3.0))
def test_the_scalar_felt_magnitude_equals_the_vector_one(drive, threshold, exponent):
    expected = felt_magnitude(np.array([drive]), threshold, exponent)[0]
    assert felt1(drive, threshold, exponent) == pytest.approx(expected, rel=1e-12, abs=1e-300)


def test_the_heatmap_repaints_only_when_its_values_change(qtbot):
    from tactile_tuner.views.heatmap import HeatmapView

    view = HeatmapView(5, 6)
    qtbot.addWidget(view)
    calls = []
    original = view.image.setImage
    view.image.setImage = lambda *a, **k: (calls.append(1), original(*a, **k))
    frame = np.zeros((6, 5))
    frame[2, 1] = 0.5
    view.set_frame(frame)
    view.set_frame(frame.copy())  # the same values: nothing to repaint
    assert len(calls) == 1
    frame[2, 1] = 0.25  # the caller's buffer, changed in place: a new picture
    view.set_frame(frame)
    assert len(calls) == 2 and view.values[2, 1] == 0.25
    view.set_point((1.5, 2.5))
    assert view.point.isVisible() and (view.point.pos().x(), view.point.pos().y()) == (1.5, 2.5)
    view.set_point(None)
    assert not view.point.isVisible() and view.point_xy is None


@pytest.mark.parametrize("mode", ["raw", "corrected", "predicted"])
def test_live_values_equal_the_batch_render_corrected_in_each_view_mode(qtbot, mode):
    from tactile_core.rendering.percept import REFERENCE
    from tactile_tuner.window import MainWindow

    win = MainWindow(restore=False, process=False)
    qtbot.addWidget(win)
    win.state.update(method="IM", mu=0.3, gamma=0.6)
    win.state.set_view_mode(mode)
    scene = win.state.scene
    live = win.tune.live
    for t in (0.0, 0.137, 0.5, 0.8123):
        values, _ = live._values(scene, t)
        expected = tc.render(scene.shape, "IM", np.array([t]))[0]
        if mode != "raw":
            expected = tc.correct(expected, 0.3, 0.6)
        if mode == "predicted":
            expected = felt_magnitude(expected, REFERENCE.threshold, REFERENCE.exponent)
        np.testing.assert_allclose(values, expected, rtol=1e-12, atol=1e-15)
    first = live._values(scene, 0.25)[0]
    assert live._values(scene, 0.75)[0] is first  # one buffer, reused frame after frame
    win.close()
