"""Tactile Brush (TB, Israr and Poupyrev, CHI 2011): values worked out by hand from the paper's
equations, and the properties that hold everywhere.

The equations (docs/methods.md, "Tactile Brush"): ``n`` virtual points along the stroke, each on
for ``d`` ms, onsets ``SOA = 0.32 d + 47.3`` ms apart, ``T = (n - 1) SOA + d``, so
``d = (T - 47.3 (n - 1)) / (1 + 0.32 (n - 1))``; a virtual point at ``beta`` between two
actuators drives them at ``sqrt(1 - beta)`` and ``sqrt(beta)``.
"""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import tactile_core as tc
from tactile_core.device.profile import find_profile
from tactile_core.rendering.layout import Layout
from tactile_core.rendering.methods import brush, get_method
from tactile_core.rendering.methods._brush_points import virtual_points
from tactile_core.rendering.rasterize import render_point

from .helpers import lit

GRID = tc.Grid()  # the palm array, 5 x 6
ROW = tc.Line((0.5, 2.5), (2.5, 2.5))  # across columns 0, 1, 2 on row 2's tactor centres


def tb(seconds):
    """TB timed by a trace of ``seconds`` (as the trace clock binds it)."""
    return get_method("TB").on_clock(seconds)


def frame(shape, t, seconds, grid=GRID):
    return lit(tc.render(shape, tb(seconds), float(t), grid=grid))


# --- the hand-worked example: three columns in one second --------------------------------------

# n = 3 points: the line crosses the column lines x = 0.5, 1.5, 2.5 on tactors (0,2), (1,2),
# (2,2) and runs along the row line y = 2.5 (which it does not cross).
# d   = (1000 - 2 x 47.3) / (1 + 2 x 0.32) = 905.4 / 1.64  = 552.0731707 ms
# SOA = 0.32 x 552.0731707 + 47.3 = 176.6634146 + 47.3    = 223.9634146 ms
# check: 2 x 223.9634146 + 552.0731707 = 1000
# onsets 0, 223.9634146, 447.9268293 ms; offsets 552.0731707, 776.0365854, 1000 ms
D_MS, SOA_MS = 552.0731707, 223.9634146
ONSETS = [0.0, 223.9634146, 447.9268293]
OFFSETS = [552.0731707, 776.0365854, 1000.0]


def test_three_columns_in_one_second_timing():
    assert brush.timing(3, 1000.0) == pytest.approx((3, D_MS, SOA_MS))
    schedule = brush.grid_schedule(ROW, 1.0)
    assert schedule.timing.count == 3
    np.testing.assert_allclose(schedule.onsets_ms, ONSETS, atol=1e-6)
    np.testing.assert_allclose(schedule.offsets_ms, OFFSETS, atol=1e-6)
    assert schedule.x.tolist() == [0.5, 1.5, 2.5] and schedule.y.tolist() == [2.5] * 3


@pytest.mark.parametrize(
    "t, expected",
    [
        (0.0, {(0, 2)}),  # 0 ms: the first onset
        (0.10, {(0, 2)}),  # 100 ms
        (0.22, {(0, 2)}),  # 220 ms: 3.96 ms before (1,2)'s onset at 223.96
        (0.225, {(0, 2), (1, 2)}),  # 225 ms
        (0.45, {(0, 2), (1, 2), (2, 2)}),  # 450 ms: (2,2) on since 447.93
        (0.55, {(0, 2), (1, 2), (2, 2)}),  # 550 ms: (0,2) still on until 552.07
        (0.56, {(1, 2), (2, 2)}),  # 560 ms
        (0.78, {(2, 2)}),  # 780 ms: (1,2) off at 776.04
        (1.0, {(2, 2)}),  # 1000 ms: the last offset
    ],
)
def test_three_columns_in_one_second_lit_tactors(t, expected):
    # Each point lies on a tactor, which gets the whole amplitude: 1.
    assert frame(ROW, t, 1.0) == {cell: 1.0 for cell in expected}


def test_a_virtual_actuator_at_a_quarter_splits_the_energy():
    # The row y = 2.75 crosses each column line a quarter of the way from tactor (c, 2) (y 2.5)
    # to (c, 3) (y 3.5): beta = 0.25, A1 = sqrt(0.75) = 0.8660254, A2 = sqrt(0.25) = 0.5, and
    # A1^2 + A2^2 = 0.75 + 0.25 = 1. Timing as above (n = 3, T = 1 s).
    line = tc.Line((0.5, 2.75), (2.5, 2.75))
    a1, a2 = math.sqrt(0.75), 0.5
    assert frame(line, 0.1, 1.0) == pytest.approx({(0, 2): a1, (0, 3): a2})  # 100 ms
    assert frame(line, 0.3, 1.0) == pytest.approx(  # 300 ms: points 0 and 1
        {(0, 2): a1, (0, 3): a2, (1, 2): a1, (1, 3): a2}
    )
    assert frame(line, 0.9, 1.0) == pytest.approx({(2, 2): a1, (2, 3): a2})  # 900 ms


def test_two_virtual_points_on_at_once_add_their_energies_at_a_shared_tactor():
    # Line (1.5, 2.2) -> (1.8, 2.5): it starts on the column line x = 1.5, 0.7 of the way from
    # (1,1) to (1,2) (beta 0.7: sqrt(0.3) = 0.5477 and sqrt(0.7) = 0.8367), and ends on the row
    # line y = 2.5, 0.3 of the way from (1,2) to (2,2) (sqrt(0.7), sqrt(0.3)); it crosses no
    # other line: n = 2.
    # d = (1000 - 47.3) / 1.32 = 721.7424242 ms, SOA = 0.32 d + 47.3 = 278.2575758 ms
    # (278.2575758 + 721.7424242 = 1000). Between 278.26 and 721.74 ms both are on: (1,2) gets
    # sqrt(0.7 + 0.7) = 1.18, capped at full drive, 1.
    line = tc.Line((1.5, 2.2), (1.8, 2.5))
    assert brush.timing(2, 1000.0) == pytest.approx((2, 721.7424242, 278.2575758))
    lo, hi = math.sqrt(0.3), math.sqrt(0.7)
    assert frame(line, 0.1, 1.0) == pytest.approx({(1, 1): lo, (1, 2): hi})
    assert frame(line, 0.5, 1.0) == pytest.approx({(1, 1): lo, (1, 2): 1.0, (2, 2): lo})
    assert frame(line, 0.9, 1.0) == pytest.approx({(1, 2): hi, (2, 2): lo})


def test_a_stroke_too_short_for_its_points_keeps_the_ends():
    # The three columns in T = 200 ms: three points would need
    # d = (200 - 2 x 47.3) / 1.64 = 64.27 ms < SOA = 0.32 x 64.27 + 47.3 = 67.87 ms, separate taps
    # with gaps; vibrations overlap only while d >= SOA, d >= 47.3 / 0.68 = 69.56 ms, which holds
    # for n <= T / 69.56 = 2.88: the two ends play.
    # d = (200 - 47.3) / 1.32 = 115.6818182 ms, SOA = 0.32 x 115.6818182 + 47.3 = 84.3181818 ms
    # (84.3181818 + 115.6818182 = 200): (0,2) over [0, 115.68] ms, (2,2) over [84.32, 200] ms,
    # (1,2) never.
    assert brush.timing(3, 200.0) == pytest.approx((2, 115.6818182, 84.3181818))
    assert frame(ROW, 0.3, 0.2) == {(0, 2): 1.0}  # 60 ms
    assert frame(ROW, 0.5, 0.2) == {(0, 2): 1.0, (2, 2): 1.0}  # 100 ms: both on
    assert frame(ROW, 0.8, 0.2) == {(2, 2): 1.0}  # 160 ms
    # Two points need T >= 2 x 69.56 = 139.12 ms: in 139.2 ms d = (139.2 - 47.3) / 1.32 =
    # 69.6212121 ms >= SOA = 0.32 x 69.6212121 + 47.3 = 69.5787879 ms; in 139.1 ms and in
    # 90 ms (where d = (90 - 47.3) / 1.32 = 32.3 ms < SOA = 57.7 ms) the start alone, for T.
    assert brush.timing(3, 139.2) == pytest.approx((2, 69.6212121, 69.5787879))
    assert brush.timing(3, 139.1) == pytest.approx((1, 139.1, 0.32 * 139.1 + 47.3))
    assert brush.timing(3, 90.0) == pytest.approx((1, 90.0, 76.1))
    assert frame(ROW, 0.99, 0.09) == {(0, 2): 1.0}


def test_timing_refuses_no_points_and_no_time():
    for n, duration_ms in [(0, 1000.0), (3, 0.0), (3, -5.0)]:
        with pytest.raises(ValueError, match="timing needs"):
            brush.timing(n, duration_ms)


def test_the_experiment_1_line_has_seven_virtual_points():
    # (0.5, 1.84) -> (4.5, 4.16), slope 2.32 / 4 = 0.58: the column lines x = 0.5 ... 4.5 at
    # y = 1.84, 2.42, 3.0, 3.58, 4.16 and the row lines y = 2.5, 3.5 at x = 0.5 + 0.66 / 0.58
    # = 1.6379 and 0.5 + 1.66 / 0.58 = 3.3621: n = 7. In 2 s:
    # d = (2000 - 6 x 47.3) / (1 + 6 x 0.32) = 1716.2 / 2.92 = 587.7397260 ms,
    # SOA = 0.32 x 587.7397260 + 47.3 = 235.3767123 ms.
    schedule = brush.grid_schedule(tc.Line((0.5, 1.84), (4.5, 4.16)), 2.0)
    assert schedule.timing == pytest.approx((7, 587.7397260, 235.3767123))
    np.testing.assert_allclose(schedule.x, [0.5, 1.5, 0.5 + 0.66 / 0.58, 2.5,
                                            0.5 + 1.66 / 0.58, 3.5, 4.5])  # fmt: skip
    np.testing.assert_allclose(schedule.y, [1.84, 2.42, 2.5, 3.0, 3.5, 3.58, 4.16])
    # the middle point (2.5, 3.0) lies halfway between (2,2) and (2,3): sqrt(0.5) each
    assert dict(schedule.shares[3]) == pytest.approx({(2, 2): 0.5**0.5, (2, 3): 0.5**0.5})


# --- on layouts --------------------------------------------------------------------------------


def test_on_the_vest_the_points_lie_on_the_sides_of_bas_squares():
    # The vest panel's actuators at (col, row), index 4 row + col. The line (0, 0) -> (3, 4)
    # (slope 4/3) crosses the squares' sides at x = 0.75 (y 1), 1 (y 4/3), 1.5 (y 2),
    # 2 (y 8/3), 2.25 (y 3): with its ends, n = 7, timed as the Experiment 1 line in 2 s.
    # (0.75, 1) is 0.75 of the way from actuator 4 (0, 1) to 5 (1, 1): sqrt(0.25), sqrt(0.75).
    vest = find_profile("vest-4x5").layout
    line = tc.Line((0.0, 0.0), (3.0, 4.0))
    t = 100.0 / 2000.0  # 100 ms: the start alone, actuator 0
    assert render_point(line, "TB", t, grid=vest) == ((0, 1.0),)
    # 240 ms: the start (0-587.74) and (0.75, 1) (235.38-823.12) are on
    assert dict(render_point(line, "TB", 0.12, grid=vest)) == pytest.approx(
        {0: 1.0, 4: 0.5, 5: math.sqrt(0.75)}
    )


def test_round_the_belt_every_actuator_in_turn_and_the_first_again():
    # Once round the 8-actuator belt (circumference 8) along its line: the stroke passes the 8
    # actuators and the first again at x = 8: n = 9.
    # d = (2000 - 8 x 47.3) / (1 + 8 x 0.32) = 1621.6 / 3.56 = 455.5056180 ms,
    # SOA = 0.32 x 455.5056180 + 47.3 = 193.0617978 ms; actuator 0 again from 8 SOA = 1544.49 ms.
    belt = find_profile("belt-8").layout
    line = tc.Line((0.0, 0.0), (8.0, 0.0))
    ms = np.array([50.0, 300.0, 1000.0, 1990.0])
    frames = tc.render(line, "TB", ms / 2000.0, grid=belt)
    on = [set(np.flatnonzero(f).tolist()) for f in frames]
    # point i on over [193.06 i, 193.06 i + 455.51] ms: at 50 ms point 0; at 300 ms points 0 and
    # 1 (from 193.06); at 1000 ms points 3 (579.19-1034.69), 4 (772.25-1227.76) and 5
    # (965.31-1420.82), point 2 off at 841.63; at 1990 ms point 8 (1544.49-2000), on actuator
    # 0, point 7 off at 1806.94
    assert on == [{0}, {0, 1}, {3, 4, 5}, {0}]


def test_free_points_are_refused_on_grids_and_layouts():
    for grid in (GRID, find_profile("belt-8").layout):
        with pytest.raises(ValueError, match="method TB needs a shape"):
            tc.render_xy("TB", 1.0, 1.0, grid=grid)


def test_a_stroke_across_too_many_lines_is_refused_naming_the_method():
    # x from -60000 to 60000 crosses x = k + 0.5 for k = -60000 ... 59999: 120,000 lines
    with pytest.raises(ValueError, match="method TB: the stroke crosses 120,000 lines"):
        tc.render(tc.Line((-6e4, 0.2), (6e4, 0.2)), "TB", 0.5)
    # round the belt (8 pitches a turn) 125,000 times
    with pytest.raises(ValueError, match="method TB: the stroke goes round the wrap 125,000"):
        tc.render(tc.Line((0.0, 0.0), (1e6, 0.0)), "TB", 0.5, grid=find_profile("belt-8").layout)


def test_the_spec_carries_no_duration_and_the_clock_is_bound_not_parsed():
    method = get_method("TB")
    assert method.spec == "TB" and method.duration_s == 2.0 and method.correction == "none"
    timed = method.on_clock(1.0)
    assert timed.spec == "TB" and timed.duration_s == 1.0 and timed != method
    assert get_method("AS").on_clock(1.0) is get_method("AS")  # no clock: itself
    with pytest.raises(ValueError, match="method TB has no parameter 'duration_s'"):
        get_method("TB:duration_s=1")
    with pytest.raises(ValueError, match="duration_s"):
        method.on_clock(0.0)


# --- properties --------------------------------------------------------------------------------


def coord(lo, hi):
    return st.floats(lo, hi, allow_nan=False, allow_infinity=False)


def lines_in_hull():
    point = st.tuples(coord(0.5, 4.5), coord(0.5, 5.5))
    return st.builds(tc.Line, point, point)


shapes = st.one_of(
    st.builds(
        tc.Line, st.tuples(coord(-1, 6), coord(-1, 7)), st.tuples(coord(-1, 6), coord(-1, 7))
    ),
    st.builds(tc.Circle, st.tuples(coord(1, 4), coord(1, 5)), coord(0, 2.5)),
    st.builds(tc.Square, st.tuples(coord(1, 4), coord(1, 5)), coord(0, 4)),
)
seconds = coord(0.01, 10.0)


@given(lines_in_hull(), seconds)
def test_every_virtual_point_inside_the_hull_keeps_the_energy(line, duration_s):
    # A^2 = sum A_i^2 = 1 per point; a crossing is shared by at most two tactors.
    schedule = brush.grid_schedule(line, duration_s)
    for k, shares in enumerate(schedule.shares):
        assert math.fsum(v * v for _, v in shares) == pytest.approx(1.0, abs=1e-12)
        if 0 < k < len(schedule.shares) - 1:
            assert len(shares) <= 2


@given(shapes, seconds, st.lists(coord(0, 1), min_size=1, max_size=40))
def test_values_within_0_1_and_at_most_max_tactors(shape, duration_s, ts):
    frames = tc.render(shape, tb(duration_s), np.array(ts))
    assert np.isfinite(frames).all() and frames.min() >= 0.0 and frames.max() <= 1.0
    assert (frames > 0).sum(axis=(1, 2)).max() <= brush.MAX_TACTORS


@given(lines_in_hull(), seconds)
def test_no_tactor_is_lit_before_its_onset_nor_after_its_offset(line, duration_s):
    # Brute force from the schedule's onsets: a tactor is lit at time tau only while a point
    # that names it is on, and every tactor an active point names is lit.
    schedule = brush.grid_schedule(line, duration_s)
    # the onsets from the paper's equations, computed here: of the stroke's n points, the most
    # whose vibrations overlap, m = min(n, floor(T / 69.56)) (d >= SOA <=> m <= T / (47.3 / 0.68)),
    # at least 1; d = (T - 47.3 (m - 1)) / (1 + 0.32 (m - 1)); onsets i SOA
    total_ms, m = 1000.0 * duration_s, len(schedule.shares)
    n = len(virtual_points(line).t)
    assert m == min(n, max(1, math.floor(total_ms / (47.3 / 0.68) + 1e-9)))
    d = (total_ms - 47.3 * (m - 1)) / (1.0 + 0.32 * (m - 1))
    assert m == 1 or d >= 0.32 * d + 47.3 - 1e-9
    np.testing.assert_allclose(schedule.onsets_ms, np.arange(m) * (0.32 * d + 47.3), atol=1e-9)
    np.testing.assert_allclose(schedule.offsets_ms[-1], total_ms, rtol=1e-12)
    t = np.linspace(0.0, 1.0, 397)
    frames = tc.render(line, tb(duration_s), t)
    for tau, f in zip(t * 1000.0 * duration_s, frames):
        on = [i for i in range(len(schedule.shares))
              if schedule.onsets_ms[i] - 1e-6 <= tau <= schedule.offsets_ms[i] + 1e-6]  # fmt: skip
        named = {cell for i in on for cell, _ in schedule.shares[i]}
        inside = {(c, r) for c, r in named if 0 <= c < GRID.cols and 0 <= r < GRID.rows}
        assert set(lit(f)) == inside


@given(shapes, seconds, st.lists(coord(0, 1), min_size=1, max_size=12))
def test_live_path_equals_batch(shape, duration_s, ts):
    method = tb(duration_s)
    batch = tc.render(shape, method, np.array(ts)).reshape(len(ts), -1)
    for t, row in zip(ts, batch):
        sparse = np.zeros(GRID.size)
        for i, v in render_point(shape, method, t):
            sparse[i] = v
        np.testing.assert_array_equal(sparse, row)


@given(st.tuples(coord(0.5, 4.5), coord(0.5, 5.5)), st.tuples(coord(0.5, 4.5), coord(0.5, 5.5)),
       st.lists(coord(0, 1), min_size=1, max_size=20))  # fmt: skip
def test_traced_backwards_it_is_the_brush_of_the_reversed_stroke(p0, p1, ts):
    # In 2 s every point of a stroke inside the palm array is played (at most 5 column lines, 6
    # row lines and 2 ends: 13 x 69.56 ms < 2000 ms), and with one d and one SOA for all, the
    # schedule played backwards is the reversed stroke's: point i's [i SOA, i SOA + d] seen
    # from the end, T - (i SOA + d) = (n - 1 - i) SOA, is point n - 1 - i's.
    t = np.array(ts)
    backwards = tc.render(tc.Line(p0, p1), "TB", 1.0 - t)
    np.testing.assert_allclose(backwards, tc.render(tc.Line(p1, p0), "TB", t), atol=1e-9)


PALM_AS_LAYOUT = Layout([(c + 0.5, r + 0.5) for r in range(6) for c in range(5)])
assert not PALM_AS_LAYOUT.is_grid  # rendered by the layout path


@given(lines_in_hull(), st.lists(coord(0, 1), min_size=1, max_size=20))
def test_on_a_grid_shaped_layout_it_equals_the_grid(line, ts):
    # BA's cells of the tactor centres are the grid's squares: the same virtual points, the
    # same energy split (BA is AS on a grid).
    t = np.array(ts)
    on_layout = tc.render(line, "TB", t, grid=PALM_AS_LAYOUT)
    np.testing.assert_allclose(on_layout, tc.render(line, "TB", t).reshape(len(t), -1), atol=1e-9)


@pytest.mark.parametrize("profile", ["belt-8", "sleeve-2x6", "vest-4x5"])
def test_on_layouts_live_equals_batch_and_values_stay_in_range(profile):
    from tactile_core.rendering import placement

    layout = find_profile(profile).layout
    t = np.linspace(0.0, 1.0, 301)
    for shape in placement.shape_defaults(layout).values():
        frames = tc.render(shape, "TB", t, grid=layout)
        assert frames.min() >= 0.0 and frames.max() <= 1.0 and frames.max() > 0.0
        for k in range(0, len(t), 7):
            live = np.zeros(layout.size)
            for i, v in render_point(shape, "TB", float(t[k]), grid=layout):
                live[i] = v
            np.testing.assert_array_equal(live, frames[k])
