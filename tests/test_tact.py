"""Importing bHaptics .tact files: paths and dots on this array, combined, streamed, with values
worked out by hand (the mapping: docs/tact.md)."""

import math

import numpy as np
import pytest

import tactile_core as tc
from tactile_core.device.link import SimulatedArray
from tactile_core.device.profile import find_profile
from tactile_core.files.tact import (
    TactError,
    TactPattern,
    layout_box,
    load_pattern,
    parse_tact,
    read_tact,
    unit_to_layout,
)
from tactile_core.rendering.scene import Scene

from . import tact_support as ts
from .helpers import lit
from .test_streamer import Taps, virtual

PALM = tc.Grid(5, 6)
VEST = find_profile("vest-4x5")


def pattern_of(data, position=None):
    return TactPattern(parse_tact(data), position)


def test_coordinates_map_onto_the_actuator_extent_y_downward():
    assert layout_box(PALM) == (0.5, 4.5, 0.5, 5.5)
    assert unit_to_layout(0.0, 0.0, layout_box(PALM)) == (0.5, 5.5)  # top left
    assert unit_to_layout(1.0, 1.0, layout_box(PALM)) == (4.5, 0.5)  # bottom right
    assert layout_box(VEST.layout) == pytest.approx((0.0, 3.0, 0.0, 4.0))
    belt = find_profile("belt-8").layout
    _, _, y0, y1 = layout_box(belt)
    assert y0 == y1 and unit_to_layout(0.5, 0.3, layout_box(belt))[1] == y0


def test_a_path_on_the_palm_rendered_by_as_at_its_midpoint_time():
    # bHaptics (0, 1) -> (1, 0) is bottom left -> top right: (0.5, 0.5) -> (4.5, 5.5) on the palm
    # array, from 0.5 s to 1.5 s into the file (startTime 500 ms), intensities 0.5 -> 1.0 (as
    # strings, as the Designer writes them). At 1.0 s the point is at (2.5, 3.0), on the edge
    # between tactors (2, 2) and (2, 3): AS gives each half, times the envelope 0.75.
    points = [ts.point("0.000", "1.000", "0.500", 0), ts.point(1, 0, "1.0", 1000)]
    data = ts.document(ts.effect({"VestFront": ts.path_mode(points)}, start_ms=500))
    pattern = pattern_of(data)
    (path,) = pattern.paths(PALM)
    assert path.points == ((0.5, 0.5), (4.5, 5.5)) and path.times_s == (0.5, 1.5)
    assert lit(tc.render(path, "AS", 0.5, grid=PALM)) == pytest.approx(
        {(2, 2): 0.375, (2, 3): 0.375}
    )
    # frames at 2.5 Hz sample the middle of each frame: frame 2 at 1.0 s
    time_s, frames = pattern.frames("AS", PALM, rate_hz=2.5, mu=0.33, gamma=0.7)
    assert time_s == pytest.approx([0.0, 0.4, 0.8, 1.2])  # the file ends at 1.5 s
    corrected = 0.67 * 0.375**0.7 + 0.33
    assert lit(frames[2]) == pytest.approx({(2, 2): corrected, (2, 3): corrected})
    assert not frames[0].any()  # 0.2 s: before the effect


def test_a_const_tdm_path_keeps_its_uneven_times():
    # (0, 0.9) -> (1, 0.9) in 200 ms, then up to (1, 0.1) in 800 ms, on the palm: at 600 ms the
    # point is half way up the right edge, (4.5, 3.0)
    points = [ts.point(0, 0.9, 1, 0), ts.point(1, 0.9, 1, 200), ts.point(1, 0.1, 1, 1000)]
    data = ts.document(ts.effect({"VestFront": ts.path_mode(points, "CONST_TDM")}))
    (path,) = pattern_of(data).paths(PALM)
    assert path.point(0.6) == pytest.approx((4.5, 3.0))
    _, frames = pattern_of(data).frames("CT", PALM, rate_hz=1 / 1.2)  # one frame, at 0.6 s
    assert lit(frames[0]) == {(4, 3): 1.0}  # y = 3.0 is an edge: the tie goes up


def test_a_dot_on_the_vest_lights_the_nearest_actuator_over_its_span():
    # Motor 6 of bHaptics' vest is at (0.667, 0.25): (2.001, 3.0) on the vest profile (x right,
    # y up over 0..3 x 0..4), nearest to actuator r3c2, index 14. The dot is on from 100 to
    # 300 ms of an effect starting at 200 ms: 0.3 to 0.5 s of the file.
    data = ts.document(
        ts.effect({"VestFront": ts.dot_mode([(6, 0.8)], 100, 300)}, start_ms=200, length_ms=400)
    )
    pattern = pattern_of(data)
    assert pattern.dots(VEST.layout) == ((0.3, 0.5, 14, 0.8, "NONE"),)
    time_s, frames = pattern.frames("EN", VEST.layout, rate_hz=100.0)
    on = np.flatnonzero(frames.any(axis=1))
    assert on.tolist() == list(range(30, 50))  # frame k's middle (k + 0.5) / 100 s in [0.3, 0.5)
    assert (frames[30:50, 14] == 0.8).all() and frames[30:50].sum() == pytest.approx(20 * 0.8)
    assert len(time_s) == 60  # the file ends with the effect, at 0.6 s
    # the palm array: (0.5 + 0.667 * 4, 5.5 - 0.25 * 5) = (3.168, 4.25), nearest tactor (3, 4)
    assert pattern.dots(PALM)[0][2] == 4 * 5 + 3


def test_a_patterns_activation_curves_are_its_frames_per_actuator():
    # Path 1 runs (0.5, 0.5) -> (4.5, 5.5) and path 2 (0.5, 5.5) -> (4.5, 0.5), each over 1 s.
    # AS lights tactor (3, 4) (centre (3.5, 4.5)) only while a point is within one pitch of it
    # on both axes: path 1 for t in (0.6, 1), path 2 never (x > 2.5 needs t > 0.5, y > 3.5
    # needs t < 0.4). So from 0.3 to 0.5 s only the dot lights it, at 0.8.
    pattern = pattern_of(ts.crossing_paths_and_a_dot())
    assert pattern.effects == 3
    curves = pattern.curves("AS", PALM, mu=0.25, gamma=0.5, samples=400)
    # 400 samples over 1 s, each in the middle of its frame, as the stream samples
    assert curves.time_s == pytest.approx((np.arange(400) + 0.5) / 400)
    k = curves.cells.index((3, 4))
    t = curves.time_s
    dot = (t > 0.301) & (t < 0.499)
    assert curves.raw[dot, k] == pytest.approx(np.full(dot.sum(), 0.8))
    assert not curves.raw[(t < 0.299) | ((t > 0.501) & (t < 0.599)), k].any()
    assert curves.corrected[dot, k] == pytest.approx(0.75 * np.sqrt(0.8) + 0.25)  # (1-mu)I^g+mu
    # the first sample, 1.25 ms in: path 1 at (0.505, 0.50625), its intensity 0.5 -> 1 at
    # 0.500625; path 2 at (0.505, 5.49375) at 1. AS: the unit box's overlap with each cell.
    first = {cell: curves.raw[0, i] for i, cell in enumerate(curves.cells)}
    assert first[(0, 0)] == pytest.approx(0.995 * 0.99375 * 0.500625)
    assert first[(0, 5)] == pytest.approx(0.995 * 0.99375)
    assert first[(1, 5)] == pytest.approx(0.005 * 0.99375)


def test_paths_and_dots_combine_by_the_maximum_per_actuator():
    # a point resting on the vest's actuator 5 (bHaptics (0.333, 0.75)) at 0.5, and a dot on
    # the same motor (index 13) at 0.3, then 0.9
    rest = [ts.point(0.333, 0.75, 0.5, 0), ts.point(0.333, 0.75, 0.5, 1000)]
    for level, expected in ((0.3, 0.5), (0.9, 0.9)):
        data = ts.document(
            ts.effect({"VestFront": ts.path_mode(rest)}),
            ts.effect({"VestFront": ts.dot_mode([(13, level)], 0, 1000)}),
        )
        _, frames = pattern_of(data).frames("VRCH:r=0.5", VEST.layout, rate_hz=10.0)
        assert frames[:, 5] == pytest.approx(np.full(10, expected))
        assert np.count_nonzero(frames) == 10


def test_fades_ramp_dots_and_paths_linearly_over_their_span():
    data = ts.document(ts.effect({"VestFront": ts.dot_mode([(0, 1.0)], 0, 1000, "FADE_IN")}))
    _, frames = pattern_of(data).frames("EN", VEST.layout, rate_hz=10.0)
    assert frames[:, 16] == pytest.approx(np.arange(10) / 10 + 0.05)  # motor 0: top left
    rest = [ts.point(0, 0, 1.0, 0), ts.point(0, 0, 1.0, 1000)]
    data = ts.document(ts.effect({"VestFront": ts.path_mode(rest, fade="FADE_OUT")}))
    _, frames = pattern_of(data).frames("EN", VEST.layout, rate_hz=10.0)
    assert frames[:, 16] == pytest.approx(1.0 - (np.arange(10) / 10 + 0.05))


def test_a_single_point_is_held_to_the_end_of_its_effect():
    data = ts.document(
        ts.effect({"VestFront": ts.path_mode([ts.point(1, 1, 0.7, 250)])}, length_ms=500)
    )
    _, frames = pattern_of(data).frames("EN", VEST.layout, rate_hz=20.0)
    on = np.flatnonzero(frames[:, 3])  # bHaptics (1, 1): bottom right, actuator r0c3
    assert on.tolist() == [5, 6, 7, 8, 9] and frames[5, 3] == pytest.approx(0.7)


def test_positions_disabled_tracks_and_the_end():
    data = ts.simple()
    data["project"]["tracks"].append(
        {
            "enable": False,
            "effects": [ts.effect({"VestBack": ts.dot_mode([(0, 1.0)], 0, 5000)}, length_ms=5000)],
        }
    )
    pattern = pattern_of(data)
    assert pattern.position == "VestFront" and pattern.skipped == ()
    assert pattern.duration_s == pytest.approx(1.0)  # a disabled track is not played
    data["project"]["tracks"][1]["enable"] = True
    assert pattern_of(data).skipped == ("VestBack",)
    data["project"]["tracks"].reverse()  # positions in the order the file plays them
    assert pattern_of(data).position == "VestBack"
    data["project"]["tracks"].reverse()
    assert pattern_of(data, "VestBack").dots(VEST.layout)[0][2] == 16
    with pytest.raises(TactError, match="position 'Head' holds no paths or dots"):
        pattern_of(data, "Head")
    live = pattern_of(data).live("EN", VEST.layout, tc.Sampling(100.0), 0.0, 1.0)
    assert live.n_frames == 100 and live.entries(100) == () and live.entries(-1) == ()  # 1 s


def test_a_position_whose_paths_follow_another_positions_dots_is_found():
    # The reader used to take the positions from the slice of (paths, dots) after the items
    # it had, so a path added after a dot was never looked at: a file with a dot on the back
    # and then a path on the front could not play its front ("holds no paths or dots").
    data = ts.document(
        ts.effect({"VestBack": ts.dot_mode([(1, 0.5)], 0, 100)}),
        ts.effect({"VestFront": ts.path_mode([ts.point(0, 0, 1.0, 0), ts.point(1, 1, 1.0, 500)])}),
        ts.effect({"VestBack": ts.dot_mode([(2, 0.5)], 0, 100)}),
    )
    assert parse_tact(data).positions == ("VestBack", "VestFront")
    front = pattern_of(data, "VestFront")
    assert len(front.paths(VEST.layout)) == 1 and front.skipped == ("VestBack",)


def test_layout_only_methods_are_refused_on_a_layout():
    with pytest.raises(ValueError, match="AS"):
        pattern_of(ts.simple()).live("AS", VEST.layout, tc.Sampling(100.0), 0.0, 1.0)


@pytest.mark.parametrize(
    ("method", "target"), [("IM", PALM), ("AS", PALM), ("GS", VEST.layout), ("BA", VEST.layout)]
)
def test_table_and_scalar_frames_agree(method, target):
    pattern = pattern_of(ts.simple())
    live = pattern.live(method, target, tc.Sampling(300.0, "box", 3), 0.3, 0.6, 0.9)
    scalar = np.array([live.frame(k) for k in range(live.n_frames)])
    live.precompute()
    assert live.precomputed
    table = np.array([live.frame(k) for k in range(live.n_frames)])
    assert scalar == pytest.approx(table, abs=1e-12) and table.any()


def test_the_designer_sample_imports():
    data = read_tact("tests/data/testfeedback.tact")
    assert data.positions == ("VestFront",) and data.duration_s == 1.0
    (path,) = data.paths
    assert len(path.points) == 20 and path.pattern == "CONST_SPEED"
    assert path.points[3] == (1.0, 0.0) and path.times_s[3] == 0.17
    pattern = load_pattern("tests/data/testfeedback.tact")
    _, frames = pattern.frames("BA", VEST.layout, rate_hz=100.0)
    assert frames.shape == (100, 20) and (frames.sum(axis=1) > 0).all()


def test_a_pattern_streamed_into_the_simulated_array_matches_the_batch_frames():
    pattern = pattern_of(ts.simple())
    scene = Scene(None, "EN", mu=0.2, gamma=0.8, rate_hz=100.0, source=pattern)
    n = 100  # the file ends at 1.0 s
    _, frames = pattern.frames("EN", VEST.layout, sampling=scene.sampling(), mu=0.2, gamma=0.8)
    expected = tc.quantize(frames, VEST.levels)[:, VEST.array.channel_index]
    taps = Taps()
    sim = SimulatedArray(VEST)
    with virtual(sim, VEST, scene=scene, taps=[taps]):
        taps.wait_for(n + 20)
        last = sim.levels()
    # on a virtual clock no deadline is missed: frame k of the stream is frame k of the file
    sent = np.array([f[2] for f in taps.frames])
    assert np.array_equal(sent[:n], expected) and expected.any()
    assert not sent[n:].any() and not last.any()  # then off, until stopped


def test_timed_path_is_at_the_top_level_as_line_is():
    from tactile_core.rendering.shapes import TimedPath

    assert tc.TimedPath is TimedPath and "TimedPath" in tc.__all__
    path = tc.TimedPath([(0.5, 0.5), (2.5, 0.5), (2.5, 0.5)], [0.0, 1.0, 2.0])
    assert path.duration_s == 2.0 and path.point(0.5) == pytest.approx((2.5, 0.5))
    frames = tc.render(path, "AS", np.array([0.0, 0.25]))
    assert frames[0, 0, 0] == 1.0 and frames[1, 0, 1] == 1.0  # (1.5, 0.5) at t = 0.25


def test_many_overlapping_dots_match_a_dot_by_dot_computation():
    # The frames' dots are found by searching sorted starts (a file may hold 200,000 dots:
    # looking at every dot made a frame cost 4.4 ms and the table 107 s). Here 400 dots of
    # every fade overlap on a few motors; the expected frames come from a plain loop over
    # every dot, with the fades and bHaptics' sum written out as docs/tact.md states them:
    # each dot cut to whole hundredths, the dots on an actuator added, capped at 1.
    rng = np.random.default_rng(7)
    fades = ("NONE", "FADE_IN", "FADE_OUT", "FADE_IN_OUT")
    effects, dots = [], []
    for j in range(100):
        start_ms, length_ms = int(rng.integers(0, 900)), int(rng.integers(20, 400))
        fade = fades[j % 4]
        items = [(int(rng.integers(0, 20)), round(float(rng.uniform(0.05, 1.0)), 3))
                 for _ in range(4)]  # fmt: skip
        effects.append(ts.effect({"VestFront": ts.dot_mode(items, 0, length_ms, fade)},
                                 start_ms=start_ms, length_ms=length_ms))  # fmt: skip
        dots += [(start_ms / 1e3, (start_ms + length_ms) / 1e3, motor, level, fade)
                 for motor, level in items]  # fmt: skip
    pattern = pattern_of(ts.document(*effects))
    # (each motor's nearest actuator: tested above; the dots come in the file's order)
    actuators = [d[2] for d in pattern.dots(VEST.layout)]
    time_s, frames = pattern.frames("EN", VEST.layout, rate_hz=200.0, corrected=False)
    expected = np.zeros_like(frames)
    ramp = {"NONE": lambda u: 1.0, "FADE_IN": lambda u: u, "FADE_OUT": lambda u: 1.0 - u,
            "FADE_IN_OUT": lambda u: 1.0 - abs(2.0 * u - 1.0)}  # fmt: skip
    for k, t in enumerate(time_s + 0.5 / 200.0):  # each frame's point sample, its middle
        for (s, e, _, level, fade), i in zip(dots, actuators):
            if s <= t <= e:
                expected[k, i] += math.floor(100 * level * ramp[fade]((t - s) / (e - s)) + 1e-9)
    expected = np.minimum(expected / 100.0, 1.0)
    assert frames == pytest.approx(expected, abs=1e-12) and (expected == 1.0).any()
    live = pattern.live("EN", VEST.layout, tc.Sampling(200.0, "point"), 0.0, 1.0)
    scalar = np.array([live.frame(k) for k in range(live.n_frames)])
    assert scalar == pytest.approx(expected, abs=1e-12)


def test_a_pattern_is_tabulated_before_it_plays_and_the_stream_plays_that_table():
    # Computed as it plays, 400 paths at once cost 1.4 ms a frame, and the table built beside
    # the output thread took its turns: 197 of 285 frames late. open_array().play and
    # tactile stream now tabulate first; live() gives the stream that very table.
    pattern = pattern_of(ts.crossing_paths_and_a_dot())
    args = ("AS", PALM, tc.Sampling(300.0), 0.33, 0.7, 1.0)
    live = pattern.live(*args)
    assert pattern.live(*args) is live and not live.precomputed
    assert live.busiest_frame() == int(0.3 * 300)  # two paths and the dot from 0.3 s
    with tc.open_array("sim", rate_hz=300.0) as array:
        array.play(pattern, "AS", mu=0.33, gamma=0.7, duration_s=0.05, wait=False)
        assert live.precomputed  # tabulated before play returned
        array.all_off()


def center_x():
    """Shaped as bHaptics' CenterX.tact (bhaptics/tact-python): the front's paths in an effect
    of 0-800 ms, the back's paths in one of 1007-1807 ms and its dots in two of 200 ms, the
    last ending at 2417 ms."""
    front = [ts.point(0.5, 0.5, 0.2, 0), ts.point(0, 0, 0.2, 800)]
    back = [ts.point(1, 1, 0.2, 0), ts.point(0.5, 0.5, 0.2, 800)]
    return ts.document(
        ts.effect({"VestFront": ts.path_mode(front, "CONST_TDM")}, 0, 800),
        ts.effect({"VestBack": ts.path_mode(back, fade="FADE_OUT")}, 1007, 800),
        ts.effect({"VestBack": ts.dot_mode([(1, 0.4), (2, 0.4)], 0, 200)}, 2217, 200),
        ts.effect({"VestBack": ts.dot_mode([(1, 0.4), (2, 0.4)], 0, 200)}, 1950, 200),
    )


def test_a_position_played_alone_lasts_as_long_as_its_own_effects(tmp_path, capsys):
    """Before: every position lasted the whole file (2.417 s), so the front's 0.8 s played
    with 1.6 s of silence after it."""
    from tactile_core.cli import main

    assert parse_tact(center_x()).duration_s == pytest.approx(2.417)
    assert pattern_of(center_x(), "VestFront").duration_s == pytest.approx(0.8)
    assert pattern_of(center_x(), "VestBack").duration_s == pytest.approx(2.417)
    time_s, _ = pattern_of(center_x(), "VestFront").frames("BA", VEST.layout, rate_hz=100.0)
    assert len(time_s) == 80
    path = ts.write(tmp_path, center_x())
    args = ["render", "--shape", f"tact:{path}", "--method", "BA", "--profile", "vest-4x5",
            "--out", str(tmp_path / "f.csv")]  # fmt: skip
    assert main(args) == 0
    assert "wrote 80 frames of VestFront" in capsys.readouterr().out
