"""Properties of the layout methods that must hold for every layout: values in [0, 1], BA's
weights summing to 1 inside the hull, the live path equal to the batch path, wraps periodic."""

import numpy as np
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from scipy.spatial import Delaunay

import tactile_core as tc
from tactile_core.rendering.layout import Layout, Wrap
from tactile_core.rendering.methods import LAYOUT_METHODS, get_method, layout_sampler

SETTINGS = settings(max_examples=40, deadline=None, derandomize=True, database=None)


@st.composite
def layouts(draw, wrap=None):
    n = draw(st.integers(1, 12))
    pts = draw(
        st.lists(
            st.tuples(st.floats(0, 5.875, width=32), st.floats(0, 4, width=32)),
            min_size=n,
            max_size=n,
            unique_by=lambda p: (round(p[0], 3), round(p[1], 3)),
        )
    )
    use_wrap = draw(st.booleans()) if wrap is None else wrap
    return Layout(pts, wrap=Wrap("x", 6.0) if use_wrap else None)


def points(n=30, seed=0):
    rng = np.random.default_rng(seed)
    return rng.uniform(-2, 8, n), rng.uniform(-2, 6, n)


@SETTINGS
@given(layouts(), st.sampled_from([*LAYOUT_METHODS, "RO:r=2.5", "GS:sigma=1.5"]))
def test_values_within_0_1_and_live_equals_batch(layout, method):
    x, y = points()
    sampler = layout_sampler(get_method(method), layout)
    frames = sampler.frames(x, y, 1e-14)
    assert frames.shape == (len(x), layout.size)
    assert np.isfinite(frames).all() and frames.min() >= 0 and frames.max() <= 1 + 1e-12
    for k in range(len(x)):
        live = np.zeros(layout.size)
        for i, v in sampler.entries1(float(x[k]), float(y[k]), 1e-14):
            live[i] += v
        np.testing.assert_allclose(live, frames[k], atol=1e-12)


@SETTINGS
@given(layouts(wrap=False))
def test_ba_sums_to_one_inside_the_hull(layout):
    xy = layout.xy
    assume(len(xy) >= 3 and np.linalg.matrix_rank(xy - xy.mean(0), tol=1e-6) == 2)
    hull = Delaunay(xy)
    x, y = points(200, seed=1)
    inside = hull.find_simplex(np.column_stack([x, y]), tol=-1e-9) >= 0
    frames = tc.render_xy("BA", x, y, grid=layout)
    np.testing.assert_allclose(frames[inside].sum(axis=1), 1.0, atol=1e-9)
    assert (frames.sum(axis=1) <= 1 + 1e-9).all()


@SETTINGS
@given(layouts(wrap=True), st.sampled_from(LAYOUT_METHODS))
def test_wrapped_layouts_repeat_every_turn(layout, method):
    x, y = points(40, seed=2)
    a = tc.render_xy(method, x, y, grid=layout)
    b = tc.render_xy(method, x + 6.0, y, grid=layout)
    np.testing.assert_allclose(a, b, atol=1e-9)


def has_sliver(layout, ratio=1e-3) -> bool:
    """Whether a Delaunay cell of ``layout`` is a sliver: its least height under ``ratio`` of
    its longest side. Across a sliver BA's weights change by up to 1 over its width (1e-5 of a
    pitch for three actuators 1e-5 off a line): continuous, but steeper than 1,001 samples of
    the line's steepest interval resolve, so the zoom test above would call it a jump."""
    xy = layout.xy
    if len(xy) < 3 or np.linalg.matrix_rank(xy - xy.mean(0), tol=1e-9) < 2:
        return False
    for tri in Delaunay(xy).simplices:
        a, b, c = xy[tri]
        area2 = abs((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
        longest = max(np.hypot(*(b - a)), np.hypot(*(c - b)), np.hypot(*(a - c)))
        if area2 / longest < ratio * longest:  # least height = 2 * area / longest side
            return True
    return False


@SETTINGS
@given(layouts(wrap=False))
def test_ba_is_continuous_along_a_line(layout):
    # no jump: the interval holding the largest step between 2,001 samples, sampled 1,001 times
    # more finely, has no step of even half that size (a jump would stay whole)
    assume(not has_sliver(layout))
    line = tc.Line((-1.5, 0.3), (7.5, 3.7))
    t = np.linspace(0, 1, 2001)
    steps = np.abs(np.diff(tc.render(line, "BA", t, grid=layout), axis=0)).max(axis=1)
    k = int(np.argmax(steps))
    zoom = np.linspace(t[k], t[k + 1], 1001)
    fine = np.abs(np.diff(tc.render(line, "BA", zoom, grid=layout), axis=0)).max()
    assert fine <= 0.5 * steps[k] + 1e-12
