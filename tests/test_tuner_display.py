"""The tune tab's live display shows what the stream renders, repaints only what changed and
computes only the lit tactors.

The *raw*, *corrected* and *predicted* heatmaps and the Compare columns are the frame the stream
sent last, computed by the stream's own function (``Scene.live``): the expected frames here come
from the stream's plan and, independently, from the batch renderer ``render_frames``.
"""

from types import SimpleNamespace

import numpy as np
import pytest

import tactile_core as tc
from tactile_core.device.profile import load_profile
from tactile_core.rendering.correction import quantize
from tactile_core.rendering.methods import get_method
from tactile_core.rendering.percept import felt_magnitude
from tactile_core.rendering.shapes import parse_shape
from tactile_core.rendering.trace import Sampling, render_frames
from tactile_core.stream import StreamStats
from tactile_core.stream._plan import _Plan

pytestmark = pytest.mark.usefixtures("qt_settings")
LINE = tc.Line((0.5, 1.84), (4.5, 4.16))


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


def _window(qtbot, profile):
    from tactile_tuner.window import MainWindow

    win = MainWindow(restore=False, process=False, profile=load_profile(profile))
    qtbot.addWidget(win)
    return win


def _stream_reports(win, scene, start_s, stats=None):
    """The display reads this stream: its last frame starts ``start_s`` into ``scene``."""
    win.tune.display.device = SimpleNamespace(
        streamer=SimpleNamespace(last_frame=(scene, start_s)), divert=None,
        stats=stats or StreamStats(state="streaming"),
    )  # fmt: skip


def _batch(scene, target, k, rate_hz, corrected=True):
    """Frame ``k`` by the vectorised batch renderer (independent of the live path)."""
    sampling = Sampling(rate_hz, scene.filter, scene.subsamples)
    _, frames = render_frames(scene.trace(), scene.method, sampling=sampling, mu=scene.mu,
                              gamma=scene.gamma, grid=target, n_frames=1, first_frame=k,
                              corrected=corrected, gain=scene.gain)  # fmt: skip
    return frames[0]


CASES = {
    "IM on the palm": ("palm-5x6", dict(shape=LINE, method="IM"), 123),
    "AS, box filter": ("palm-5x6", dict(shape=LINE, method="AS", filter="box", subsamples=4), 200),
    # a path that fades in: the display once left the envelope out on a layout (0.17 too high)
    "BA on the belt, fading in": (
        "belt-8",
        dict(shape=parse_shape("timed:0.5,0.5,0,0.2,7.5,0.5,2,1"), method="BA"),
        150,
    ),
}


@pytest.mark.parametrize(
    ("case", "mode"),
    [(case, mode) for case in CASES for mode in ("raw", "corrected", "predicted")
     if mode != "predicted" or CASES[case][0] == "palm-5x6"],  # predicted: grids only
)  # fmt: skip
def test_the_views_show_the_frame_the_stream_renders_for_the_same_scene_and_time(qtbot, case, mode):
    profile_name, changes, k = CASES[case]
    win = _window(qtbot, profile_name)
    profile = win.device.profile
    win.state.set_scene(win.state.scene.replace(mu=0.3, gamma=0.6, gain=0.9, **changes))
    win.state.set_view_mode(mode)
    scene = win.state.scene
    plan = _Plan(scene, profile, 10.0)  # what the stream's output thread works from
    _stream_reports(win, scene, k / plan.rate)
    win.tune.display._on_timer_timeout()
    shown = win.tune.heatmap.values
    batch = _batch(scene, profile.layout, k, plan.rate, corrected=mode != "raw")
    # predicted: for the reference participant, TH 0.2 and K 1 (docs/tuner.md)
    expected = {"raw": batch, "corrected": batch, "predicted": felt_magnitude(batch, 0.2, 1.0)}
    assert expected[mode].any()
    np.testing.assert_allclose(shown, expected[mode].reshape(shown.shape), rtol=1e-9,
                               atol=1e-12)  # fmt: skip
    if mode != "raw":  # and exactly what the stream's plan computes for that frame
        stream = plan.live.frame(k)
        stream = stream if mode == "corrected" else felt_magnitude(stream, 0.2, 1.0)
        np.testing.assert_array_equal(shown, stream.reshape(shown.shape))
    win.close()


def test_the_views_follow_the_rate_the_stream_capped(qtbot):
    win = _window(qtbot, "palm-5x6")
    profile = win.device.profile
    win.state.set_view_mode("corrected")
    win.state.update(method="AS", rate_hz=300.0)
    scene = win.state.scene
    plan = _Plan(scene, profile, 10.0, 250.0)  # a link that carries 250 frames a second
    stats = StreamStats(state="streaming", requested_rate_hz=300.0, rate_hz=250.0, capped=True)
    _stream_reports(win, scene, 77 / 250.0, stats)
    win.tune.display._on_timer_timeout()
    np.testing.assert_allclose(win.tune.heatmap.values, plan.live.frame(77), rtol=1e-12)
    win.close()


def test_compare_shows_each_method_as_the_stream_would_render_it(qtbot):
    win = _window(qtbot, "palm-5x6")
    profile = win.device.profile
    win.state.update(method="IM", mu=0.3, gamma=0.6)
    win.state.set_view_mode("corrected")
    win.compare.set_methods(["IM", "AS", "EN", "RO:r=1.5"])
    scene = win.state.scene
    k = 321
    win.compare.tick(scene, k / 300.0, 300.0, None)
    for name in win.compare.methods:
        mu, gamma = get_method(name).own_correction(scene.mu, scene.gamma)
        own = scene.replace(method=name, mu=mu, gamma=gamma)
        expected = _Plan(own, profile, 10.0).live.frame(k)
        assert expected.any(), name
        np.testing.assert_allclose(win.compare.heatmaps[name].values, expected, rtol=1e-12)
    _stream_reports(win, scene, k / 300.0)
    win.tune.display._on_timer_timeout()  # the method the array plays: the same in both tabs
    np.testing.assert_array_equal(win.tune.heatmap.values, win.compare.heatmaps["IM"].values)
    win.close()


def test_the_corrected_view_of_a_held_instant_is_what_the_array_is_sent(qtbot):
    win = _window(qtbot, "palm-5x6")
    win.state.set_view_mode("corrected")
    win.state.update(method="IM", mu=0.3, gamma=0.6, playing=True, hold_s=0.731)
    device = win.device
    qtbot.waitUntil(lambda: getattr(device.streamer.last_frame[0], "hold_s", None) == 0.731,
                    timeout=10_000)  # fmt: skip
    qtbot.waitUntil(lambda: device.sent_levels().any(), timeout=10_000)
    win.tune.display._on_timer_timeout()
    shown = win.tune.heatmap.values
    assert shown.any()
    np.testing.assert_array_equal(quantize(shown, device.profile.levels), device.sent_levels())
    win.close()


def test_the_live_display_reuses_one_buffer(qtbot):
    win = _window(qtbot, "palm-5x6")
    win.state.set_view_mode("corrected")
    live = win.tune.display
    scene = win.state.scene
    first = live._values(scene, 0.25, 300.0)[0]
    assert live._values(scene, 0.75, 300.0)[0] is first  # one buffer, reused frame after frame
    win.close()
