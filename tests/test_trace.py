"""The trace clock, frame sampling with temporal filters, the live path and activation curves."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import tactile_core as tc
from tactile_core.rendering.curves import activation_curves
from tactile_core.rendering.trace import LiveFrames, frames_per_cycle

LINE = tc.Line((0.5, 1.84), (4.5, 4.16))
CIRCLE = tc.Circle((2.5, 3.0), 2.0)


def test_trace_maps_seconds_to_t_with_pause_and_repeat():
    trace = tc.Trace(LINE, duration_s=2.0, pause_s=0.5)
    t, on = trace.parameter([0.0, 0.5, 1.0, 1.999, 2.0, 2.4, 2.5, 3.5, 5.0 + 1.0])
    assert on.tolist() == [True, True, True, True, False, False, True, True, True]
    np.testing.assert_allclose(t[on], [0.0, 0.25, 0.5, 0.9995, 0.0, 0.5, 0.5])
    assert trace.period_s == 2.5


def test_trace_reverse_runs_t_from_one_to_zero():
    trace = tc.Trace(CIRCLE, duration_s=2.0, pause_s=0.0, direction="reverse")
    t, on = trace.parameter([0.0, 0.5, 1.5])
    assert on.all()
    np.testing.assert_allclose(t, [1.0, 0.75, 0.25])


def test_trace_without_repeat_stays_off_after_one_trace():
    trace = tc.Trace(LINE, duration_s=1.0, pause_s=0.5, repeat=False)
    _, on = trace.parameter([-0.1, 0.0, 0.99, 1.0, 1.6, 10.0])
    assert on.tolist() == [False, True, True, False, False, False]


@given(st.floats(-100, 1000, allow_nan=False), st.sampled_from(["forward", "reverse"]))
def test_scalar_trace_clock_matches_vectorised(time_s, direction):
    trace = tc.Trace(CIRCLE, duration_s=2.0, pause_s=0.5, direction=direction)
    t, on = trace.parameter(time_s)
    t1 = trace.parameter1(time_s)
    assert (t1 is not None) == bool(on)
    if t1 is not None:
        assert t1 == pytest.approx(float(t), abs=1e-12)


@pytest.mark.parametrize(
    ("kwargs", "word"),
    [
        ({"duration_s": 0.0}, "duration_s"),
        ({"duration_s": float("nan")}, "duration_s"),
        ({"pause_s": -1.0}, "pause_s"),
        ({"direction": "sideways"}, "direction"),
    ],
)
def test_trace_rejects_bad_timing(kwargs, word):
    with pytest.raises(ValueError, match=word):
        tc.Trace(LINE, **kwargs)


@pytest.mark.parametrize(
    ("kwargs", "word"),
    [
        ({"rate_hz": 0.0}, "rate_hz"),
        ({"filter": "gauss"}, "filter"),
        ({"subsamples": 0}, "subsamples"),
    ],
)
def test_sampling_rejects_bad_settings(kwargs, word):
    with pytest.raises(ValueError, match=word):
        tc.Sampling(**kwargs)


def test_sampling_offsets_are_subinterval_centres():
    np.testing.assert_allclose(
        tc.Sampling(100.0, "box", 4).offsets_s(), [1.25e-3, 3.75e-3, 6.25e-3, 8.75e-3]
    )
    np.testing.assert_allclose(tc.Sampling(100.0, "point").offsets_s(), [5e-3])


def test_point_filter_samples_the_middle_of_each_frame():
    trace = tc.Trace(LINE, duration_s=1.0, pause_s=0.0)
    start, frames = tc.render_frames(trace, "AS", sampling=tc.Sampling(10.0, "point"))
    assert len(frames) == 10
    np.testing.assert_allclose(start, np.arange(10) / 10)
    expected = tc.render(LINE, "AS", (np.arange(10) + 0.5) / 10)
    np.testing.assert_allclose(frames, expected)


def test_box_filter_averages_corrected_intensity_over_the_frame():
    trace = tc.Trace(LINE, duration_s=1.0, pause_s=0.0)
    sampling = tc.Sampling(10.0, "box", 4)
    _, frames = tc.render_frames(trace, "IM", sampling=sampling, mu=0.33, gamma=0.7)
    sub_t = (np.arange(40) + 0.5) / 40
    expected = tc.correct(tc.render(LINE, "IM", sub_t), 0.33, 0.7).reshape(10, 4, 6, 5).mean(axis=1)
    np.testing.assert_allclose(frames, expected)


def test_box_filter_preserves_delivered_energy_of_a_brief_activation():
    # CT on the Experiment 1 line at 25 Hz: tactor (0, 2) is on for 0.224 / 4 of a 1 s trace
    # (56 ms, hand-worked in test_methods_handworked). Point sampling sees it 1 or 2 frames
    # (40 or 80 ms); the box filter's energy converges on 56 ms.
    trace = tc.Trace(LINE, duration_s=1.0, pause_s=0.0)
    on_s = (1.0 - (0.5 + 0.16 / 0.58)) / 4
    point = (
        tc.render_frames(trace, "CT", sampling=tc.Sampling(25.0, "point"))[1][:, 2, 0].sum() / 25
    )
    box = (
        tc.render_frames(trace, "CT", sampling=tc.Sampling(25.0, "box", 256))[1][:, 2, 0].sum() / 25
    )
    assert abs(point - on_s) > 0.01
    assert box == pytest.approx(on_s, abs=2e-4)


def test_frames_are_off_during_the_pause():
    trace = tc.Trace(CIRCLE, duration_s=1.0, pause_s=0.5)
    _, frames = tc.render_frames(trace, "MM", sampling=tc.Sampling(100.0, "point"))
    assert len(frames) == 150
    lit = frames.reshape(150, -1).sum(axis=1)
    assert (lit[:100] == 1).all() and (lit[100:] == 0).all()


def test_frames_per_cycle():
    assert frames_per_cycle(2.5, 300.0) == 750
    assert frames_per_cycle(2.5, 25.0) == 125  # two periods
    assert frames_per_cycle(2.0, 300.0) == 600
    assert frames_per_cycle(1.0 / 3.0, 7.0) == 7  # 3 periods of 7/3 frames
    assert frames_per_cycle(math.pi, 300.0) is None


@pytest.mark.parametrize("method", tc.METHOD_NAMES)
@pytest.mark.parametrize(("filt", "s"), [("point", 1), ("box", 4)])
def test_live_frames_match_batch_frames_scalar_and_table(method, filt, s):
    trace = tc.Trace(tc.Square((2.5, 3.5), 4.0), duration_s=2.0, pause_s=0.5)
    sampling = tc.Sampling(100.0, filt, s)
    _, batch = tc.render_frames(trace, method, sampling=sampling, mu=0.33, gamma=0.7, n_frames=500)
    live = LiveFrames(trace, method, sampling, 0.33, 0.7, tc.Grid())
    scalar = np.array([live.frame(k) for k in range(500)])
    live.precompute()
    assert live.precomputed
    table = np.array([live.frame(k) for k in range(500)])  # two cycles: wraps around
    np.testing.assert_allclose(scalar, batch, atol=1e-12)
    np.testing.assert_allclose(table, batch, atol=1e-12)
    # Only the lit tactors are carried: at most 4 per instant, a few more over a box frame.
    assert max(len(live.entries(k)) for k in range(250)) <= 4 * s


def test_live_frames_without_an_exact_cycle_use_the_scalar_path():
    trace = tc.Trace(CIRCLE, duration_s=math.pi, pause_s=0.0)
    live = LiveFrames(trace, "AS", tc.Sampling(300.0, "point"), 0.0, 1.0, tc.Grid())
    live.precompute()
    assert live.cycle is None and not live.precomputed
    assert len(live.entries(10)) > 0


def test_activation_curves_of_the_experiment_1_line():
    curves = activation_curves(LINE, "AS", duration_s=1.0, mu=0.33, gamma=0.7, samples=2001)
    assert curves.raw.shape == curves.corrected.shape == (2001, len(curves.cells))
    np.testing.assert_allclose(curves.corrected, tc.correct(curves.raw, 0.33, 0.7))
    onsets = curves.onsets_s()
    assert (np.diff(onsets) >= 0).all()  # ordered by first activation
    # AS activates every tactor whose cell the unit box around the line touches.
    frames = tc.render(LINE, "AS", np.linspace(0, 1, 2001))
    expected = {(int(c), int(r)) for r, c in zip(*np.nonzero(frames.max(axis=0)))}
    assert set(curves.cells) == expected
    # Raw AS curves sum to 1 at every instant (the line lies inside the tactor hull).
    np.testing.assert_allclose(curves.raw.sum(axis=1), 1.0, atol=1e-12)


def test_activation_curves_reverse_direction_reverses_onsets():
    forward = activation_curves(LINE, "MM", duration_s=1.0, samples=4001)
    backward = activation_curves(LINE, "MM", duration_s=1.0, samples=4001, direction="reverse")
    assert list(backward.cells) == list(reversed(forward.cells))
