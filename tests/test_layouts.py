"""Actuators anywhere: hand-worked values of the layout methods on a triangle, a belt and a vest
panel; BA against AS on grids; the peers on a grid's layout against their grid form."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import tactile_core as tc
from tactile_core.device.profile import load_profile
from tactile_core.rendering.layout import Layout, Wrap

TRIANGLE = Layout([(0.0, 0.0), (2.0, 0.0), (1.0, 1.5)])
BELT = Layout([(float(k), 0.0) for k in range(8)], wrap=Wrap("x", 8.0))
VEST01 = Layout([(c / 3, r / 4) for r in range(5) for c in range(4)])  # 0..1 coordinates


def xy(layout, method, x, y):
    """One point's frame on a layout, through the batch path."""
    return tc.render_xy(method, x, y, grid=layout)


def smoothstep(u):
    return u * u * (3 - 2 * u)


# -- the triangle -------------------------------------------------------------------------------


def test_triangle_ba_at_the_centroid_is_a_third_each():
    # (1, 0.5) = A + u (B - A) + v (C - A) with u = v = 1/3: the centroid
    np.testing.assert_allclose(xy(TRIANGLE, "BA", 1.0, 0.5), [1 / 3, 1 / 3, 1 / 3], atol=1e-15)


def test_triangle_ba_on_an_edge_and_a_corner():
    np.testing.assert_allclose(xy(TRIANGLE, "BA", 1.0, 0.0), [0.5, 0.5, 0.0], atol=1e-15)
    np.testing.assert_allclose(xy(TRIANGLE, "BA", 1.5, 0.75), [0.0, 0.5, 0.5], atol=1e-15)
    np.testing.assert_array_equal(xy(TRIANGLE, "BA", 2.0, 0.0), [0.0, 1.0, 0.0])
    # u = 0.25, v = 0.5 -> (0.25, 0.25, 0.5)
    np.testing.assert_allclose(xy(TRIANGLE, "BA", 1.0, 0.75), [0.25, 0.25, 0.5], atol=1e-15)


def test_triangle_ba_fades_out_beyond_the_hull():
    # below the edge AB: nearest boundary point (1, 0), 0.25 away in y: fade 0.75
    np.testing.assert_allclose(xy(TRIANGLE, "BA", 1.0, -0.25), [0.375, 0.375, 0.0], atol=1e-15)
    # beyond the corner B by (0.5, -0.25): fade 0.5 * 0.75
    np.testing.assert_allclose(xy(TRIANGLE, "BA", 2.5, -0.25), [0.0, 0.375, 0.0], atol=1e-15)
    np.testing.assert_array_equal(xy(TRIANGLE, "BA", 1.0, -1.0), [0.0, 0.0, 0.0])


def test_triangle_peers_at_the_centroid():
    dA = math.hypot(1.0, 0.5)  # to A and to B; to C: 1.0
    d = np.array([dA, dA, 1.0])
    np.testing.assert_array_equal(xy(TRIANGLE, "RO", 1.0, 0.5), [0, 0, 0])  # all at d >= 1
    np.testing.assert_allclose(
        xy(TRIANGLE, "RO:r=1.5", 1.0, 0.5), smoothstep(1 - d / 1.5), atol=1e-15
    )
    np.testing.assert_allclose(
        xy(TRIANGLE, "RO:r=1.5,curve=linear", 1.0, 0.5), 1 - d / 1.5, atol=1e-15
    )
    g = np.exp(-(d**2) / (2 * 0.5**2))  # 0.082, 0.082, 0.135: all above the 0.05 cut
    np.testing.assert_allclose(xy(TRIANGLE, "GS", 1.0, 0.5), g, atol=1e-15)
    np.testing.assert_array_equal(xy(TRIANGLE, "VRCH:r=1.1", 1.0, 0.5), [0, 0, 1])
    inv = 1 / d
    np.testing.assert_allclose(xy(TRIANGLE, "PK", 1.0, 0.5), np.sqrt(inv / inv.sum()), atol=1e-15)
    np.testing.assert_allclose(xy(TRIANGLE, "EN", 1.0, 0.5), np.sqrt([1 / 3] * 3), atol=1e-15)


def test_pk_on_an_actuator_lights_it_alone():
    np.testing.assert_array_equal(xy(TRIANGLE, "PK", 1.0, 1.5), [0, 0, 1])


# -- the belt -----------------------------------------------------------------------------------


def test_belt_ba_across_the_seam():
    # actuators at x = 0..7 round a circumference of 8: x = 7.25 is between 7 and 8 = 0
    f = xy(BELT, "BA", 7.25, 0.0)
    expected = np.zeros(8)
    expected[7], expected[0] = 0.75, 0.25
    np.testing.assert_allclose(f, expected, atol=1e-15)
    np.testing.assert_allclose(xy(BELT, "BA", -0.75, 0.0), expected, atol=1e-15)  # a turn back
    np.testing.assert_allclose(xy(BELT, "BA", 15.25, 0.0), expected, atol=1e-15)  # a turn on


def test_belt_ro_measures_distance_the_short_way_round():
    f = xy(BELT, "RO:curve=linear", 7.6, 0.0)
    expected = np.zeros(8)
    expected[7], expected[0] = 1 - 0.6, 1 - 0.4  # 0.4 across the seam, not 7.6
    np.testing.assert_allclose(f, expected, atol=1e-12)


def test_belt_point_crossing_the_seam_is_continuous():
    line = tc.Line((5.5, 0.0), (10.5, 0.0))
    t = np.linspace(0, 1, 5001)
    for method in ("BA", "EN", "RO", "RO:r=1.5"):  # (GS jumps at its 0.05 cut, by definition)
        frames = tc.render(line, method, t, grid=BELT)
        if method == "EN":
            frames = frames**2  # its energies are BA's weights (sqrt is steep at 0)
        step = np.abs(np.diff(frames, axis=0)).max()
        assert step < 0.01, (method, step)  # 1/1000 of a pitch per sample
        if method == "BA":
            np.testing.assert_allclose(frames.sum(axis=1), 1.0, atol=1e-12)


@pytest.mark.parametrize("method", ["BA", "EN", "PK", "RO", "GS", "VRCH", "GS:sigma=3"])
def test_belt_frames_repeat_every_turn(method):
    x = np.linspace(-3, 11, 141)
    np.testing.assert_allclose(
        tc.render_xy(method, x, 0.1, grid=BELT),
        tc.render_xy(method, x + 8, 0.1, grid=BELT),
        atol=1e-12,
    )


def test_belt_ba_off_the_belt_line_fades():
    f = xy(BELT, "BA", 2.5, 0.25)
    expected = np.zeros(8)
    expected[2] = expected[3] = 0.5 * 0.75
    np.testing.assert_allclose(f, expected, atol=1e-15)


# -- the vest panel -----------------------------------------------------------------------------


def test_vest_ba_between_columns_and_rows():
    # in 0..1 coordinates, x = 0.5 is midway between columns 1 and 2, y = 0.5 is row 2
    f = xy(VEST01, "BA", 0.5, 0.5)
    expected = np.zeros(20)
    expected[2 * 4 + 1] = expected[2 * 4 + 2] = 0.5
    np.testing.assert_allclose(f, expected, atol=1e-15)
    # (1/6, 1/8): the centre of the cell of r0c0, r0c1, r1c0, r1c1
    f = xy(VEST01, "BA", 1 / 6, 1 / 8)
    expected = np.zeros(20)
    expected[[0, 1, 4, 5]] = 0.25
    np.testing.assert_allclose(f, expected, atol=1e-15)


def test_vest_ba_is_bilinear_in_each_cell():
    # x = 0.1 is 0.3 of the way from column 0 to 1; y = 0.3 is 0.2 from row 1 to 2
    f = xy(VEST01, "BA", 0.1, 0.3)
    expected = np.zeros(20)
    expected[4], expected[5] = 0.7 * 0.8, 0.3 * 0.8
    expected[8], expected[9] = 0.7 * 0.2, 0.3 * 0.2
    np.testing.assert_allclose(f, expected, atol=1e-15)


def test_vest_profile_units_are_pitches():
    profile = load_profile("vest-4x5")  # 0..1 across 300 x 400 mm, pitch 100 mm
    np.testing.assert_allclose(profile.layout.xy[[0, 3, 16, 19]], [[0, 0], [3, 0], [0, 4], [3, 4]])
    f = tc.render_xy("BA", 1.5, 2.0, grid=profile.layout)
    np.testing.assert_allclose(f, xy(VEST01, "BA", 0.5, 0.5), atol=1e-15)


@settings(max_examples=200, deadline=None, derandomize=True, database=None)
@given(st.floats(0, 1), st.floats(0, 1))
def test_vest_ba_weights_sum_to_one_inside_the_hull(x, y):
    assert math.isclose(xy(VEST01, "BA", x, y).sum(), 1.0, abs_tol=1e-12)


@settings(max_examples=200, deadline=None, derandomize=True, database=None)
@given(st.floats(0, 1), st.floats(0, 1))
def test_triangle_ba_weights_sum_to_one_inside(u, v):
    if u + v > 1:
        u, v = 1 - u, 1 - v
    p = np.array([0.0, 0.0]) + u * np.array([2.0, 0.0]) + v * np.array([1.0, 1.5])
    f = xy(TRIANGLE, "BA", p[0], p[1])
    assert math.isclose(f.sum(), 1.0, abs_tol=1e-12)
    np.testing.assert_allclose(f, [1 - u - v, u, v], atol=1e-12)


# -- on a grid ----------------------------------------------------------------------------------


def grid_points_layout(grid):
    """The grid's tactor centres as a layout that is not flagged a grid (so the layout path
    computes everything from the tessellation)."""
    return Layout(grid.positions)


@settings(max_examples=60, deadline=None, derandomize=True, database=None)
@given(
    st.integers(1, 7),
    st.integers(1, 7),
    st.lists(st.tuples(st.floats(-2, 9), st.floats(-2, 9)), min_size=1, max_size=40),
)
def test_ba_equals_as_on_any_grid(cols, rows, points):
    grid = tc.Grid(cols, rows)
    x, y = np.array(points).T
    expected = tc.render_xy("AS", x, y, grid=grid).reshape(len(x), -1)
    got = tc.render_xy("BA", x, y, grid=grid_points_layout(grid))
    np.testing.assert_allclose(got, expected, atol=1e-12)


@pytest.mark.parametrize("method", ["RO", "GS", "VRCH", "EN", "RO:r=1.7", "GS:sigma=0.9"])
@pytest.mark.parametrize(
    "shape", [tc.Line((0.5, 1.84), (4.5, 4.16)), tc.Circle((2.5, 3), 2), tc.Square((2.5, 3), 3)]
)
def test_peers_on_a_grids_layout_equal_their_grid_form(method, shape):
    t = np.linspace(0, 1, 2001)
    grid = tc.Grid()
    expected = tc.render(shape, method, t, grid=grid).reshape(len(t), -1)
    got = tc.render(shape, method, t, grid=grid_points_layout(grid))
    np.testing.assert_allclose(got, expected, atol=1e-12)


def test_pk_on_a_layout_takes_the_three_nearest_that_exist():
    # at the grid's left edge the grid form drops a lattice tactor outside; the layout form
    # gives the energy to three real actuators, so sum I^2 = 1 there
    layout = grid_points_layout(tc.Grid())
    f = tc.render_xy("PK", 0.5, 3.2, grid=layout)
    assert math.isclose((f**2).sum(), 1.0, rel_tol=1e-12)
    assert np.count_nonzero(f) == 3


def test_a_grid_is_a_layout_of_its_cell_centres():
    grid = tc.Grid(4, 3)
    assert isinstance(grid, Layout) and grid.is_grid
    centres = [(c + 0.5, r + 0.5) for r in range(3) for c in range(4)]  # row-major, by hand
    assert grid.positions == tuple(centres) and grid.size == 12
    assert grid.names[:5] == ("r0c0", "r0c1", "r0c2", "r0c3", "r1c0")
    assert grid.frame_shape == (3, 4) and grid.wire_shape == (4, 3)
    np.testing.assert_array_equal(grid.xy, np.array(centres))
    assert grid.distances(0.5, 0.5)[5] == pytest.approx(np.hypot(1.0, 1.0))  # to (1.5, 1.5)


def test_a_layout_at_a_grids_centres_is_not_a_grid():
    grid = tc.Grid(4, 3)
    same = Layout(grid.positions)
    assert not same.is_grid and same != grid and same.frame_shape == (12,)
    line = tc.Line((0.2, 0.4), (3.7, 2.6))
    with pytest.raises(ValueError, match="IM"):
        tc.render(line, "IM", [0.5], grid=same)
    # a method that renders anywhere gives the same values (to float rounding), flat
    t = np.linspace(0, 1, 11)
    np.testing.assert_allclose(
        tc.render(line, "GS", t, grid=same),
        tc.render(line, "GS", t, grid=grid).reshape(11, 12),
        rtol=0,
        atol=1e-15,
    )


def test_grids_are_equal_by_size_immutable_and_survive_pickling():
    import pickle

    grid = tc.Grid(4, 3)
    assert grid == tc.Grid(cols=4, rows=3) and hash(grid) == hash(tc.Grid(4, 3))
    assert grid != tc.Grid(3, 4) and repr(grid) == "Grid(cols=4, rows=3)"
    assert pickle.loads(pickle.dumps(grid)) == grid
    with pytest.raises(AttributeError, match="immutable"):
        grid.cols = 5


# -- refusals -----------------------------------------------------------------------------------


@pytest.mark.parametrize("method", ["CT", "MM", "AS", "IM"])
def test_paper_methods_are_refused_on_layouts_saying_why(method):
    with pytest.raises(ValueError, match=rf"method {method} cannot render on this layout") as e:
        tc.render(tc.Line((0, 0), (3, 0)), method, [0.0, 0.5], grid=BELT)
    assert "grid" in str(e.value) and "BA" in str(e.value) and "EN, PK, RO, GS" in str(e.value)


def test_pk_blend_is_refused_on_layouts():
    with pytest.raises(ValueError, match=r"PK:blend=0\.2 needs a grid"):
        tc.render_xy("PK:blend=0.2", 1.0, 0.0, grid=BELT)


@pytest.mark.parametrize(
    "positions, kwargs, words",
    [
        ([], {}, "1 to 1024 actuators"),
        ([(0, 0), (0, 0)], {}, "duplicate positions"),
        (
            [(0.0, 0.0), (1.0, 0.0), (3.0, 0.0)],
            {"wrap": Wrap("x", 3.0)},
            "outside the circumference",
        ),
        ([(0.0, 0.0), (2.9999999999, 0.0)], {"wrap": Wrap("x", 3.0)}, "round the wrap"),
        ([(float("nan"), 0.0)], {}, "positions\\[0\\] must be finite"),
        ([(0, 0), (1, 0)], {"names": ("a", "a")}, "names must differ"),
        ([(0, 0), (1, 0)], {"groups": {"g": [0, 2]}}, "layout group g"),
        ("not a list", {}, "pairs of numbers"),
    ],
)
def test_bad_layouts_are_refused_naming_the_field(positions, kwargs, words):
    with pytest.raises(ValueError, match=words):
        Layout(positions, **kwargs)


def test_free_points_beyond_the_coordinate_bound_are_refused():
    # 1e300 reached a float -> int cast (a RuntimeWarning, an error under -W error)
    for grid in (tc.Grid(), BELT):
        with pytest.raises(ValueError, match="x and y must be coordinates within 1e\\+06"):
            tc.render_xy("RO", 1e300, 0.0, grid=grid)
    assert tc.render_xy("AS", [1e6, -1e6], 0.5).sum() == 0.0  # at the bound: off the array


def test_ba_beyond_a_45_degree_edge_fades_by_the_product_not_the_distance():
    # The fade is max(0, 1 - |dx|) * max(0, 1 - |dy|) of the offset from the nearest boundary
    # point: one pitch straight out from the hypotenuse x + y = 2, dx = dy = 1/sqrt(2), leaves
    # (1 - 1/sqrt(2))^2 = 0.0858 of that point's weights (the midpoint's: 0.5 and 0.5); a point
    # sqrt(2) pitches out (dx = dy = 1) is off.
    triangle = Layout([(0.0, 0.0), (2.0, 0.0), (0.0, 2.0)])
    out = 1.0 + 1.0 / np.sqrt(2.0)
    fade = (1.0 - 1.0 / np.sqrt(2.0)) ** 2
    np.testing.assert_allclose(tc.render_xy("BA", out, out, grid=triangle),
                               [0.0, 0.5 * fade, 0.5 * fade], atol=1e-12)  # fmt: skip
    assert tc.render_xy("BA", 2.0, 2.0, grid=triangle).sum() == 0.0
    # along an axis-aligned edge one pitch is enough: below the edge y = 0
    assert tc.render_xy("BA", 1.0, -1.0, grid=triangle).sum() == 0.0
