"""Tactile Brush (TB) through every path the other methods take: the trace clock binds the
trace's duration (render_frames, LiveFrames, scenes, activation curves, a .tact path's own
times), the command line renders and streams it, and the tuner plays, compares and blinds it.

The expected frames come from the hand-worked timing of tests/test_brush.py: the three columns
``(0.5, 2.5) -> (2.5, 2.5)`` in T = 1 s, points on over [0, 552.07], [223.96, 776.04] and
[447.93, 1000] ms at tactors (0,2), (1,2), (2,2) (flat indices 10, 11, 12).
"""

import subprocess

import numpy as np
import pytest

import tactile_core as tc
from tactile_core.device.profile import find_profile
from tactile_core.files.tact import TactPattern, parse_tact
from tactile_core.rendering.curves import activation_curves
from tactile_core.rendering.scene import Scene
from tactile_core.rendering.trace import LiveFrames, Sampling, Trace, render_frames

from . import tact_support as ts
from .emulator_support import CLI, Emulator

ROW = tc.Line((0.5, 2.5), (2.5, 2.5))
ON_MS = [(0.0, 552.0731707), (223.9634146, 776.0365854), (447.9268293, 1000.0)]
CELLS = [10, 11, 12]  # row 2 x 5 + col


def expected(times_ms, size=30):
    """Frames ``(n, size)`` from the hand-worked intervals: 1 while a point is on."""
    out = np.zeros((len(times_ms), size))
    for k, tau in enumerate(times_ms):
        for cell, (on, off) in zip(CELLS, ON_MS):
            out[k, cell] = 1.0 if on <= tau <= off else 0.0
    return out


def test_the_trace_clock_binds_its_duration_in_render_frames_and_live_frames():
    # 200 frames a second sample the middle of each 5 ms frame: 2.5, 7.5, ... 997.5 ms. None
    # lies within 1e-6 ms of an onset or offset; with TB's default 2 s instead of the trace's
    # 1 s, (1,2) would come on at 209.5 ms of the trace (t = 0.2095), not 223.96.
    trace = Trace(ROW, duration_s=1.0, pause_s=0.0)
    sampling = Sampling(200.0, "point")
    times, frames = render_frames(trace, "TB", sampling=sampling, n_frames=200)
    want = expected(times * 1000.0 + 2.5)
    np.testing.assert_array_equal(frames.reshape(200, -1), want)
    live = LiveFrames(trace, "TB", sampling, 0.0, 1.0, tc.Grid())
    scalar = np.array([live.frame(k).reshape(-1) for k in range(200)])
    np.testing.assert_array_equal(scalar, want)
    live.precompute()
    assert live.precomputed
    np.testing.assert_array_equal([live.frame(k).reshape(-1) for k in range(200)], want)
    scene = Scene(ROW, "TB", mu=0.0, gamma=1.0, duration_s=1.0, pause_s=0.0, rate_hz=200.0)
    assert scene.method == "TB"  # the spec stays the method's: the duration is the trace's
    np.testing.assert_array_equal(scene.live(tc.Grid()).frame(45).reshape(-1), want[45])


def test_traced_in_reverse_the_last_column_starts():
    trace = Trace(ROW, duration_s=1.0, pause_s=0.0, direction="reverse")
    times, frames = render_frames(trace, "TB", sampling=Sampling(200.0, "point"), n_frames=200)
    # at 2.5 ms from the start t = 0.9975: 997.5 ms into the forward schedule: (2,2) alone
    want = expected(1000.0 - (times * 1000.0 + 2.5))
    np.testing.assert_array_equal(frames.reshape(200, -1), want)


def test_activation_curves_follow_the_scene_duration():
    curves = activation_curves(ROW, "TB", duration_s=1.0, samples=2001)  # every 0.5 ms
    assert curves.cells == ((0, 2), (1, 2), (2, 2))
    np.testing.assert_allclose(curves.onsets_s(), [0.0, 0.224, 0.448])  # first sample after
    offsets = curves.time_s[len(curves.time_s) - 1 - np.argmax(curves.raw[::-1] > 0, axis=0)]
    np.testing.assert_allclose(offsets, [0.552, 0.776, 1.0])  # last sample before


def test_a_tact_path_is_brushed_over_its_own_duration():
    # bHaptics (0, 0.6) -> (0.5, 0.6) over 1000 ms maps onto the palm as (0.5, 2.5) -> (2.5, 2.5)
    # (x 0.5 + 4 u, y 5.5 - 5 v): the three columns in 1 s, whatever TB's default clock.
    points = [ts.point(0, 0.6, 1, 0), ts.point(0.5, 0.6, 1, 1000)]
    pattern = TactPattern(parse_tact(ts.document(ts.effect({"VestFront": ts.path_mode(points)}))))
    (path,) = pattern.paths(tc.Grid())
    np.testing.assert_allclose(path.points, [(0.5, 2.5), (2.5, 2.5)])
    assert path.duration_s == 1.0
    time_s, frames = pattern.frames("TB", tc.Grid(), rate_hz=200.0)
    want = expected(time_s * 1000.0 + 2.5)
    np.testing.assert_array_equal(frames.reshape(len(time_s), -1), want)
    live = pattern.live("TB", tc.Grid(), Sampling(200.0, "point"), 0.0, 1.0)
    for k in (10, 45, 100, 150):  # the scalar path: 52.5, 227.5, 502.5, 752.5 ms
        np.testing.assert_array_equal(live.frame(k).reshape(-1), want[k])


def test_the_command_line_renders_and_streams_tb(tmp_path):
    out = tmp_path / "tb.npz"
    proc = subprocess.run(
        [*CLI, "render", "--shape", "line:0.5,2.5,2.5,2.5", "--method", "TB", "--duration", "1",
         "--rate", "200", "--out", str(out)],
        capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    with np.load(out) as data:
        time_s, frames = data["time"], data["frames"]
    # samples at 0, 5, ... 1000 ms (k / rate, the trace only): none within 1 ms of an onset
    np.testing.assert_array_equal(frames.reshape(len(time_s), -1), expected(time_s * 1e3))
    emu = Emulator(tmp_path)
    try:
        proc = subprocess.run(
            [*CLI, "stream", "--device", emu.path, "--shape", "line:0.5,2.5,2.5,2.5", "--method",
             "TB", "--mu", "0", "--gamma", "1", "--duration", "1", "--pause", "0.5", "--rate",
             "100", "--seconds", "1.2", "--no-dither"],
            capture_output=True, text=True, timeout=120,
        )  # fmt: skip
        assert proc.returncode == 0, proc.stderr
        _, log = emu.finish()
    finally:
        emu.kill()
    levels = log[:, 2:]
    others = [i for i in range(30) if i not in CELLS]
    assert set(np.unique(levels)) == {0.0, 22.0} and not levels[:, others].any()
    # the columns come on one after the other (the mean frame each is lit in: about 276, 500
    # and 724 ms into the trace; robust to frames a loaded machine skips) and overlap
    when = [float(np.flatnonzero(levels[:, c] > 0).mean()) for c in CELLS]
    assert when[0] < when[1] < when[2], when
    assert (levels[:, CELLS] > 0).all(axis=1).any()  # all three at once (448-552 ms)
    assert not levels[-1].any()  # all off at the end


def test_on_a_layout_the_scene_streams_from_the_trace_clock():
    vest = find_profile("vest-4x5").layout
    line = tc.Line((0.0, 0.0), (3.0, 4.0))
    trace = Trace(line, duration_s=1.0, pause_s=0.0)
    live = LiveFrames(trace, "TB", Sampling(100.0, "point"), 0.0, 1.0, vest)
    _, frames = render_frames(trace, "TB", sampling=Sampling(100.0, "point"), grid=vest)
    np.testing.assert_array_equal([live.frame(k) for k in range(len(frames))], frames)
    # n = 7 in 1 s: d = (1000 - 283.8) / 2.92 = 245.27 ms, SOA = 125.79 ms: at 5 ms the start
    # alone (actuator 0), at 995 ms the end alone (actuator 19, the corner (3, 4))
    assert set(np.flatnonzero(frames[0])) == {0} and set(np.flatnonzero(frames[-1])) == {19}


@pytest.mark.usefixtures("qt_settings")
def test_the_tuner_plays_compares_and_blinds_tb(qtbot):
    from tactile_tuner.window import MainWindow

    win = MainWindow(restore=False, process=False)
    qtbot.addWidget(win)
    win.show()
    win.confirm = lambda title, text: True
    combo = win.controls.method.other_combo
    assert combo.findData("TB") >= 0
    assert win.state.update(shape=ROW, method="TB", duration_s=1.0, pause_s=0.0, mu=0.0,
                            gamma=1.0, dither=False)  # fmt: skip
    assert win.controls.method.other_button.isChecked() and combo.currentData() == "TB"
    seen = set()

    def all_three_at_once():
        levels = win.device.sent_levels().reshape(-1)
        seen.add(tuple(np.flatnonzero(levels)))
        return (10, 11, 12) in seen

    qtbot.waitUntil(all_three_at_once, timeout=10000)
    win.compare.set_methods(["AS", "TB"])
    win.compare._refresh()
    assert win.compare.curves["TB"].listDataItems()
    win.blind.set_methods(["AS", "TB"])
    win.blind.start(seed=1)
    assert sorted(win.blind.session.mapping) == ["AS", "TB"]
    win.close()
