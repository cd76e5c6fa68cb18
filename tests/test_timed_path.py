"""The time-keyed path: its motion under CONST_SPEED and CONST_TDM, its intensity envelope,
and its forms (dict, spec, preset), with values worked out by hand."""

import numpy as np
import pytest

import tactile_core as tc
from tactile_core.device.profile import find_profile
from tactile_core.files.presets import Preset, load_preset, save_preset
from tactile_core.rendering.scene import Scene
from tactile_core.rendering.shapes import TimedPath, parse_shape, path_from_samples, shape_from_dict

from .helpers import lit

GRID = tc.Grid(5, 6)


def test_two_point_const_speed_path_rendered_by_as_at_its_midpoint_time():
    # (0.5, 1) -> (3.5, 3) from 0.2 s to 1.2 s, intensities 0.4 -> 1.0. At 0.7 s (t = 0.5) the
    # point is at (2, 2), a corner shared by tactors (1, 1), (2, 1), (1, 2), (2, 2): AS gives
    # each a quarter of the unit square, and the envelope is (0.4 + 1) / 2 = 0.7.
    path = TimedPath([(0.5, 1.0), (3.5, 3.0)], [0.2, 1.2], [0.4, 1.0], "CONST_SPEED")
    assert path.duration_s == pytest.approx(1.0)
    frame = tc.render(path, "AS", 0.5, grid=GRID)
    expected = {cell: 0.25 * 0.7 for cell in [(1, 1), (2, 1), (1, 2), (2, 2)]}
    assert lit(frame) == pytest.approx(expected)
    # Traced over its own duration, the frame at 0.5 s into the trace is that frame; the
    # correction then lifts each lit tactor to 0.67 * 0.175 ** 0.7 + 0.33.
    trace = tc.Trace(path, path.duration_s, 0.0, repeat=False)
    _, frames = tc.render_frames(
        trace, "AS", mu=0.33, gamma=0.7, n_frames=1, phase_s=0.495, sampling=tc.Sampling(100.0)
    )
    corrected = 0.67 * 0.175**0.7 + 0.33
    assert lit(frames[0]) == pytest.approx({cell: corrected for cell in expected})


def test_const_tdm_with_uneven_times_reaches_each_point_at_its_time():
    # (0.5, 0.5) -> (4.5, 0.5) in 0.5 s, then -> (4.5, 5.5) in 2 s. At 1.3 s the point is
    # 0.8 s into the second segment: 0.4 of it, (4.5, 2.5), the centre of tactor (4, 2).
    points = [(0.5, 0.5), (4.5, 0.5), (4.5, 5.5)]
    tdm = TimedPath(points, [0.0, 0.5, 2.5])
    assert tdm.knots == pytest.approx((0.0, 0.2, 1.0))
    t = 1.3 / 2.5
    assert tdm.point(t) == pytest.approx((4.5, 2.5))
    assert lit(tc.render(tdm, "CT", t, grid=GRID)) == {(4, 2): 1.0}
    assert lit(tc.render(tdm, "AS", t, grid=GRID)) == pytest.approx({(4, 2): 1.0})
    # The same points at constant speed: 9 pitches in 2.5 s, so at 1.3 s the point has gone
    # 4.68 pitches, 0.68 past the corner: (4.5, 1.18).
    speed = TimedPath(points, [0.0, 0.5, 2.5], pattern="CONST_SPEED")
    assert speed.knots == pytest.approx((0.0, 4 / 9, 1.0))
    assert speed.point(t) == pytest.approx((4.5, 1.18))
    assert lit(tc.render(speed, "CT", t, grid=GRID)) == {(4, 1): 1.0}


def test_envelope_multiplies_raw_intensity_and_zero_stays_zero():
    path = TimedPath([(0.5, 0.5), (4.5, 0.5)], [0.0, 1.0], [0.0, 0.0])
    t = np.linspace(0.0, 1.0, 41)
    for method in ("CT", "MM", "AS", "IM", "EN", "PK", "RO", "GS"):
        raw = tc.render(path, method, t, grid=GRID)
        assert not raw.any(), method
        assert not tc.correct(raw, mu=0.33, gamma=0.7).any()  # off, not at mu
        assert tc.render_point(path, method, 0.5, grid=GRID) == ()
    ramp = TimedPath([(2.5, 2.5), (2.5, 2.5)], [0.0, 1.0], [0.2, 1.0], fade="FADE_OUT")
    # a point resting on tactor (2, 2): CT lights it at the envelope (0.2 + 0.8 t)(1 - t)
    values = tc.render(ramp, "CT", t, grid=GRID)[:, 2, 2]
    assert values == pytest.approx((0.2 + 0.8 * t) * (1.0 - t))


@pytest.mark.parametrize("method", ["CT", "MM", "AS", "IM", "EN", "PK", "RO", "GS", "VRCH"])
def test_live_path_equals_batch_on_a_grid_and_a_layout(method):
    # (the pause is off any distance that is a whole number of pitches from an actuator, where
    # d < r decides within rounding)
    path = TimedPath(
        [(0.4, 0.7), (3.55, 1.2), (3.55, 1.2), (1.0, 4.3)],
        [0.0, 0.4, 0.7, 1.5],
        [0.3, 1.0, 0.8, 0.5],
        fade="FADE_IN_OUT",
    )
    targets = [GRID]
    if method not in tc.METHOD_NAMES:
        targets.append(find_profile("vest-4x5").layout)
    for target in targets:
        trace = tc.Trace(path, path.duration_s, 0.25)
        sampling = tc.Sampling(200.0, "box", 3)
        live = tc.LiveFrames(trace, method, sampling, 0.2, 0.8, target)
        _, batch = tc.render_frames(
            trace, method, sampling=sampling, mu=0.2, gamma=0.8, grid=target
        )
        scalar = np.array([live.frame(k) for k in range(len(batch))])
        assert scalar == pytest.approx(batch, abs=1e-12)
        assert batch.any()


def test_im_stays_continuous_through_a_pause_and_sums_to_the_envelope():
    # Under CONST_TDM a repeated vertex is a pause: IM holds the vertex's tactor meanwhile.
    path = TimedPath([(0.7, 0.5), (2.3, 0.5), (2.3, 0.5), (2.3, 4.1)], [0.0, 1.0, 2.0, 3.0])
    t = np.linspace(0.0, 1.0, 3001)
    frames = tc.render(path, "IM", t, grid=GRID)
    assert frames.sum(axis=(1, 2)) == pytest.approx(np.ones_like(t))
    assert np.abs(np.diff(frames, axis=0)).max() < 0.02  # no jumps at 3,000 samples
    pause = frames[(t > 1 / 3 + 1e-3) & (t < 2 / 3 - 1e-3)]
    assert (pause == pause[0]).all() and lit(pause[0]) == pytest.approx({(2, 0): 1.0})


def test_strokes_merge_only_segments_at_one_speed():
    # three collinear segments: the first two at 1 pitch/s, the third faster
    path = TimedPath([(0.5, 2.5), (1.5, 2.5), (2.5, 2.5), (4.5, 2.5)], [0.0, 1.0, 2.0, 2.5])
    runs = path.strokes.runs()
    assert [r.t_in for r in runs] == pytest.approx([0.0, 0.8])
    assert [r.t_out for r in runs] == pytest.approx([0.8, 1.0])
    assert path.corners == pytest.approx((0.8,))
    same = TimedPath(path.points, [0.0, 1.0, 2.0, 4.0], pattern="CONST_SPEED")
    assert len(same.strokes.runs()) == 1  # constant speed: one straight stroke, as a polyline
    polyline = tc.Polyline(path.points)
    t = np.linspace(0.0, 1.0, 101)
    for method in ("MM", "IM", "AS"):
        assert tc.render(same, method, t, grid=GRID) == pytest.approx(
            tc.render(polyline, method, t, grid=GRID), abs=1e-12
        )


def test_forms_round_trip_dict_spec_and_preset(tmp_path):
    path = TimedPath(
        [(0.5, 1.0), (2.25, 3.5), (4.5, 1.0)],
        [0.1, 0.9, 2.1],
        [1.0, 0.25, 0.6],
        "CONST_SPEED",
        "FADE_OUT",
    )
    assert shape_from_dict(path.to_dict()) == path
    assert path.spec == "timed:0.5,1,0.1,1,2.25,3.5,0.9,0.25,4.5,1,2.1,0.6;speed;fade-out"
    assert parse_shape(path.spec) == path
    scene = Scene(path, "IM", duration_s=path.duration_s, pause_s=0.0)
    save_preset(Preset(scene, name="drawn"), tmp_path / "drawn.json")
    loaded = load_preset(tmp_path / "drawn.json")
    assert loaded.scene.shape == path and loaded.scene.duration_s == pytest.approx(2.0)
    assert parse_shape("timed:0,0,0,1,1,1,2,1").pattern == "CONST_TDM"


def test_a_preset_holds_a_path_of_the_most_points(tmp_path):
    n = 10_000
    rng = np.random.default_rng(1)
    path = TimedPath(rng.uniform(0, 5, (n, 2)).tolist(), (np.arange(n) * 1.234567e-3).tolist(),
                     rng.uniform(0, 1, n).tolist())  # fmt: skip
    save_preset(Preset(Scene(path, duration_s=path.duration_s)), tmp_path / "long.json")
    assert (tmp_path / "long.json").stat().st_size > 1 << 20  # past the other files' bound
    assert load_preset(tmp_path / "long.json").scene.shape == path


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"times_s": [0.0, 1.0, 1.0]}, "times_s[2] must be later than times_s[1]"),
        ({"times_s": [0.0, 2.0, 1.0]}, "times_s[2] must be later than times_s[1]"),
        ({"times_s": [0.0, 1.0]}, "times_s must hold 3 numbers"),
        ({"times_s": [-1.0, 1.0, 2.0]}, "times_s[0] must be within [0, 3600]"),
        ({"intensities": [0.5, 1.5, 1.0]}, "intensities[1] must be within [0, 1]"),
        ({"intensities": [0.5, float("nan"), 1.0]}, "intensities[1] must be a finite number"),
        ({"pattern": "CONST_FAST"}, "pattern must be one of"),
        ({"fade": "FADE"}, "fade must be one of"),
        ({"points": [(0, 0)]}, "points must hold 2 to 10000 points, got 1"),
    ],
)
def test_bad_paths_are_refused_naming_the_field(kwargs, message):
    args = {"points": [(0, 0), (1, 1), (2, 0)], "times_s": [0.0, 1.0, 2.0]} | kwargs
    with pytest.raises(ValueError, match=message.replace("[", r"\[").replace("]", r"\]")):
        TimedPath(**args)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("timed:0,0,0,1,1,1", "a multiple of 4 numbers, >= 8"),
        ("timed:0,0,0,1,1,1,1,1;slow", "options are speed"),
        ("timed:0,0,1,1,1,1,0.5,1", "times_s\\[1\\] must be later"),
        ("timed:0,0,0,1,1,1,x,1", "decimal numbers"),
    ],
)
def test_bad_timed_specs_are_refused(text, message):
    with pytest.raises(ValueError, match=message):
        parse_shape(text)


def test_path_from_samples_drops_repeated_times_and_thins_long_recordings():
    path = path_from_samples([10.0, 10.0, 10.02, 10.05], [(1, 1), (1, 1), (2, 1), (3, 2)])
    assert path.times_s == pytest.approx((0.0, 0.02, 0.05))
    assert path.points == ((1.0, 1.0), (2.0, 1.0), (3.0, 2.0))
    n = 25_000
    long = path_from_samples(np.arange(n) / 100.0, [(k % 5, 1.0) for k in range(n)])
    assert len(long.points) == 10_000
    assert long.times_s[-1] == pytest.approx((n - 1) / 100.0)
    with pytest.raises(ValueError, match="at least 2 samples"):
        path_from_samples([1.0, 1.0], [(0, 0), (1, 1)])
