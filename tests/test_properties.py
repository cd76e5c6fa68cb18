"""Properties of the four methods that must hold everywhere (hypothesis)."""

import math

import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st

import tactile_core as tc

from .helpers import lit, on_fraction

GRID = tc.Grid()  # 5 x 6
BIG = tc.Grid(cols=12, rows=12)


def coord(lo, hi):
    return st.floats(lo, hi, allow_nan=False, allow_infinity=False)


def in_hull():
    """Points inside the tactor hull of the 5 x 6 grid: [0.5, 4.5] x [0.5, 5.5]."""
    return st.tuples(coord(0.5, 4.5), coord(0.5, 5.5))


def in_grid():
    """Points inside the grid area, away from its outer edges."""
    return st.tuples(coord(0.01, 4.99), coord(0.01, 5.99))


@st.composite
def circles_in_grid(draw):
    cx, cy = draw(in_grid())
    room = min(cx, 5 - cx, cy, 6 - cy) - 0.01
    assume(room > 0)
    return tc.Circle((cx, cy), draw(coord(0.0, room)))


@st.composite
def squares_in_grid(draw):
    cx, cy = draw(in_grid())
    room = min(cx, 5 - cx, cy, 6 - cy) - 0.01
    assume(room > 0)
    return tc.Square((cx, cy), 2 * draw(coord(0.0, room)))


lines_in_hull = st.builds(tc.Line, in_hull(), in_hull())
lines_in_grid = st.builds(tc.Line, in_grid(), in_grid())
shapes_in_grid = st.one_of(lines_in_grid, circles_in_grid(), squares_in_grid())
params = st.lists(coord(0.0, 1.0), min_size=1, max_size=40)


# --- counts and sums -------------------------------------------------------------------------


@given(in_hull(), in_hull())
def test_as_at_most_four_tactors_summing_to_one_inside_hull(p, q):
    t = np.linspace(0, 1, 33)
    frames = tc.render(tc.Line(p, q), "AS", t)
    counts = (frames > 0).sum(axis=(1, 2))
    assert counts.max() <= 4
    np.testing.assert_allclose(frames.sum(axis=(1, 2)), 1.0, atol=1e-12)


@given(coord(-2, 7), coord(-2, 8))
def test_as_never_more_than_one_in_total_and_loses_area_outside(x, y):
    frame = tc.render_xy("AS", x, y)
    inside_x = min(x + 0.5, 5) - max(x - 0.5, 0)
    inside_y = min(y + 0.5, 6) - max(y - 0.5, 0)
    expected = max(inside_x, 0) * max(inside_y, 0)  # area of the box inside the array
    assert frame.sum() == pytest.approx(expected, abs=1e-12)


@given(shapes_in_grid, params)
def test_im_at_most_two_tactors_summing_to_one(shape, ts):
    frames = tc.render(shape, "IM", np.array(ts))
    assert (frames > 0).sum(axis=(1, 2)).max() <= 2
    np.testing.assert_allclose(frames.sum(axis=(1, 2)), 1.0, atol=1e-12)


@given(shapes_in_grid, params)
def test_mm_and_ct_light_exactly_one_tactor_at_full_intensity(shape, ts):
    for method in ("MM", "CT"):
        frames = tc.render(shape, method, np.array(ts))
        assert ((frames > 0).sum(axis=(1, 2)) == 1).all(), method
        assert set(np.unique(frames)) <= {0.0, 1.0}


@given(shapes_in_grid)
def test_im_tactors_are_mms_tactors(shape):
    t = np.linspace(0, 1, 4001)
    mm = tc.render(shape, "MM", t)
    im = tc.render(shape, "IM", t)
    mm_cells = set(lit(mm.max(axis=0)))
    im_cells = set(lit(im.max(axis=0)))
    assert im_cells <= mm_cells


# --- shape of the curves ---------------------------------------------------------------------


def _breaks(p0, p1, offset):
    """Parameters where x - offset or y - offset crosses an integer on the line p0 -> p1."""
    out = [0.0, 1.0]
    for a, b in zip(p0, p1):
        if a == b:
            continue
        lo, hi = sorted((a - offset, b - offset))
        for k in range(math.ceil(lo), math.floor(hi) + 1):
            out.append((k + offset - a) / (b - a))
    return np.unique(np.clip(out, 0, 1))


def _piece_residual(p0, p1, method, offset, degree):
    """Largest residual of a degree-`degree` fit to each tactor's curve on each piece."""
    line = tc.Line(p0, p1)
    worst = 0.0
    bends = 0.0
    for a, b in zip(*(lambda br: (br[:-1], br[1:]))(_breaks(p0, p1, offset))):
        if b - a < 1e-6:
            continue
        t = np.linspace(a + (b - a) * 1e-3, b - (b - a) * 1e-3, 9)
        curves = tc.render(line, method, t).reshape(len(t), -1)
        s = (t - a) / (b - a)
        for k in np.flatnonzero(curves.any(axis=0)):
            coeffs = np.polyfit(s, curves[:, k], degree)
            fit = np.polyval(coeffs, s)
            worst = max(worst, np.abs(fit - curves[:, k]).max())
            bends = max(bends, abs(coeffs[0]) if degree == 2 else 0.0)
    return worst, bends


@given(in_hull(), in_hull())
def test_as_curves_are_quadratic_pieces(p0, p1):
    residual, _ = _piece_residual(p0, p1, "AS", 0.5, 2)
    assert residual < 1e-9


def test_as_curves_bend_on_a_diagonal():
    # Products of two linear factors: genuinely quadratic, not linear.
    _, bend = _piece_residual((0.7, 0.9), (4.2, 4.6), "AS", 0.5, 2)
    assert bend > 0.01


@given(in_hull(), in_hull())
def test_im_curves_are_linear_pieces(p0, p1):
    residual, _ = _piece_residual(p0, p1, "IM", 0.5, 1)
    assert residual < 1e-9


# --- durations -------------------------------------------------------------------------------


@given(in_grid(), in_grid())
def test_mm_durations_equal_for_full_cells_and_proportional_at_the_ends(p0, p1):
    dx, dy = p1[0] - p0[0], p1[1] - p0[1]
    major = 0 if abs(dx) >= abs(dy) else 1
    a, b = sorted((p0[major], p1[major]))
    assume(b - a > 0.05)
    n = 20001
    frames = tc.render(tc.Line(p0, p1), "MM", np.linspace(0, 1, n))
    by_cell = {}
    for (c, r), share in on_fraction(frames).items():
        by_cell[(c, r)[major]] = by_cell.get((c, r)[major], 0) + share
    for cell in range(math.floor(a), math.floor(b) + 1):
        span = min(cell + 1, b) - max(cell, a)  # the stroke's extent in this cell
        assert by_cell.get(cell, 0.0) == pytest.approx(span / (b - a), abs=3 / n)


# --- symmetry --------------------------------------------------------------------------------


@given(in_grid(), in_grid(), st.sampled_from(tc.METHOD_NAMES))
def test_reversing_a_line_reverses_the_frames(p0, p1, method):
    t = np.arange(1025) / 1024  # dyadic: 1 - t is exact
    forward = tc.render(tc.Line(p0, p1), method, t)
    backward = tc.render(tc.Line(p0, p1).reversed(), method, 1.0 - t)
    np.testing.assert_array_equal(forward, backward)


def bresenham(c0, r0, c1, r1):
    """Integer incremental Bresenham; a tie (error exactly half a cell) goes up/right."""
    dx, dy = c1 - c0, r1 - r0
    if abs(dx) >= abs(dy):  # x-major, |slope| = 1 included
        du, dv, su, sv, u, v, swap = (
            abs(dx),
            abs(dy),
            1 if dx >= 0 else -1,
            1 if dy >= 0 else -1,
            c0,
            r0,
            False,
        )
    else:
        du, dv, su, sv, u, v, swap = (
            abs(dy),
            abs(dx),
            1 if dy >= 0 else -1,
            1 if dx >= 0 else -1,
            r0,
            c0,
            True,
        )
    cells, err = [], 0  # err = 2 du (exact minor - v) sv
    for _ in range(du + 1):
        cells.append((v, u) if swap else (u, v))
        err += 2 * dv
        if err > du or (err == du and sv > 0):
            v += sv
            err -= 2 * du
        u += su
    return cells


@given(
    st.integers(0, 11),
    st.integers(0, 11),
    st.integers(0, 11),
    st.integers(0, 11),
)
def test_mm_matches_bresenham_between_tactor_centres(c0, r0, c1, r1):
    line = tc.Line((c0 + 0.5, r0 + 0.5), (c1 + 0.5, r1 + 0.5))
    frames = tc.render(
        line, "MM", np.linspace(0, 1, 400 * (abs(c1 - c0) + abs(r1 - r0)) + 2), grid=BIG
    )
    seen = []
    for f in frames:
        (cell,) = lit(f)
        if cell not in seen:
            seen.append(cell)
    assert seen == bresenham(c0, r0, c1, r1)


def test_bresenham_reference_ties_go_up_and_right():
    # The reference itself, on lines whose midpoints fall exactly between two cells.
    assert bresenham(0, 0, 2, 1) == [(0, 0), (1, 1), (2, 1)]
    assert bresenham(2, 1, 0, 0) == [(2, 1), (1, 1), (0, 0)]
    assert bresenham(0, 0, 1, 2) == [(0, 0), (1, 1), (1, 2)]
    assert bresenham(0, 2, 2, 1) == [(0, 2), (1, 2), (2, 1)]


# --- the live path agrees with the batch path ------------------------------------------------


@given(
    st.one_of(shapes_in_grid, st.builds(tc.Line, in_grid(), in_grid())),
    params,
    st.sampled_from(tc.METHOD_NAMES),
)
def test_scalar_live_path_matches_batch(shape, ts, method):
    batch = tc.render(shape, method, np.array(ts)).reshape(len(ts), -1)
    for t, row in zip(ts, batch):
        sparse = np.zeros(GRID.size)
        for i, v in tc.render_point(shape, method, t):
            sparse[i] = v
        np.testing.assert_allclose(sparse, row, atol=1e-15, rtol=0)


anywhere = st.tuples(coord(-2, 7), coord(-2, 8))


@given(st.one_of(shapes_in_grid, st.builds(tc.Line, anywhere, anywhere)))
def test_as_matches_the_textbook_overlap_with_every_cell(shape):
    # Independent computation: overlap of the point-centred unit box with each cell.
    from tactile_core.bench import dense_area_sampling

    t = np.linspace(0, 1, 257)
    np.testing.assert_allclose(
        tc.render(shape, "AS", t), dense_area_sampling(shape, t, GRID), atol=1e-12
    )


@pytest.mark.parametrize(
    "spec", ["CT", "MM", "AS", "IM", "EN", "PK", "PK:blend=0.2", "RO", "RO:r=1.5", "GS",
             "GS:sigma=0.3", "VRCH"],
)  # fmt: skip
def test_sample_protocol_form_equals_the_batch_render(spec):
    # ``sample`` (the protocol's entries, as plug-ins return them) and ``render`` (the built-in
    # methods' batch form: blocks, flipped blocks, table entries) give the same frames,
    # through points on tactor centres, cell edges and corners, and anywhere.
    from tactile_core.rendering.methods import get_method
    from tactile_core.rendering.rasterize import scatter

    method = get_method(spec)
    rng = np.random.default_rng(7)
    t = np.concatenate([np.linspace(0.0, 1.0, 257), rng.random(300)])
    for shape in (
        tc.Circle((2.5, 3.0), 2.0),
        tc.Square((2.5, 3.5), 4.0),
        tc.Line((-1.0, 0.5), (6.0, 5.5)),
        tc.Polyline(((0.5, 0.5), (2.5, 4.5), (4.5, 0.5)), closed=True),
    ):
        x, y = shape.xy(t)
        frames = scatter(method.sample(shape, x, y, t, shape.snap_tol), len(t), tc.Grid())
        np.testing.assert_array_equal(frames, tc.render(shape, spec, t))
