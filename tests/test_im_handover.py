"""IM across the junctions between strokes: continuous along every shape.

The paper (2.5) gives IM's rule between two column centres of one stroke. Where a shape's trace
passes from one stroke to the next (a circle's octant boundary, a polygon's corner), IM goes
linearly in arc length from the outgoing stroke's last keyframe (a tactor centre passed on its
major axis, or the tactor of a partial column at the junction) to the incoming stroke's first.
The expected values below are worked from that rule and the shapes' formulas.
"""

import itertools
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import tactile_core as tc

from .helpers import lit

EXP3_CIRCLE = tc.Circle((2.5, 3.5), 2.05)


def test_exp3_circle_octant_boundary_is_halfway_between_its_keyframes():
    # Right arc (y-major) passes row 4's centre y = 4.5 at sin(theta) = 1 / 2.05; there
    # x = 2.5 + sqrt(2.05^2 - 1) = 4.29: MM's tactor (4, 4). The top arc (x-major) passes
    # column 3's centre x = 3.5 at cos(theta) = 1 / 2.05; there y = 5.29: MM's tactor (3, 5).
    # Both columns around 45 degrees hold a centre, so no partial keyframe: the 45-degree point
    # is halfway in angle (asin q + acos q = pi / 2).
    got = lit(tc.render(EXP3_CIRCLE, "IM", 0.125))
    assert got == pytest.approx({(4, 4): 0.5, (3, 5): 0.5}, abs=1e-12)


@pytest.mark.parametrize("degrees", [31.0, 40.0, 52.5, 60.0])
def test_exp3_circle_hand_over_is_linear_in_angle(degrees):
    theta_a = math.asin(1 / 2.05)  # (4, 4) alone
    theta_b = math.acos(1 / 2.05)  # (3, 5) alone
    w = (math.radians(degrees) - theta_a) / (theta_b - theta_a)
    got = lit(tc.render(EXP3_CIRCLE, "IM", degrees / 360.0))
    assert got == pytest.approx({(4, 4): 1.0 - w, (3, 5): w}, abs=1e-12)


def test_exp3_circle_outside_hand_overs_follows_the_paper_rule():
    # theta = 75 degrees lies on the top arc between column centres 2.5 and 3.5 (x = 3.03).
    theta = math.radians(75.0)
    x = 2.5 + 2.05 * math.cos(theta)
    share_right = x - 2.5
    row_col2 = math.floor(3.5 + 2.05)  # column 2's centre: y = 5.55 -> row 5
    row_col3 = math.floor(3.5 + math.sqrt(2.05**2 - 1.0))  # 5.29 -> row 5
    got = lit(tc.render(EXP3_CIRCLE, "IM", 75.0 / 360.0))
    expected = {(2, row_col2): 1.0 - share_right, (3, row_col3): share_right}
    assert got == pytest.approx(expected, abs=1e-12)


SQUARE = tc.Square((2.5, 3.5), 3.0)  # corners (1, 2), (4, 2), (4, 5), (1, 5); perimeter 12


def square_t(distance):
    """t of the point ``distance`` along the trace from its start (4, 3.5)."""
    return distance / 12.0


@pytest.mark.parametrize(
    ("distance", "expected"),
    [
        # Right edge x = 4 (column 4 by the up/right tie rule), rows' centres 2.5 .. 4.5.
        (1.0, {(4, 4): 1.0}),  # y = 4.5: row 4's centre
        # Row 5's centre (5.5) lies beyond the edge's end at y = 5: a partial row. Its MM
        # tactor, the cell of the corner (4, 5) by the tie rule, is the keyframe at the corner.
        (1.25, {(4, 4): 0.5, (4, 5): 0.5}),  # y = 4.75: halfway from (4, 4) to the corner
        (1.5, {(4, 5): 1.0}),  # the corner (4, 5), t = 1/8
        # Top edge y = 5 (row 5), running left: column 4's centre 4.5 is beyond its start at
        # x = 4 (partial); column 3's centre 3.5 is its first keyframe, 0.5 past the corner.
        (1.6, {(4, 5): 0.8, (3, 5): 0.2}),  # x = 3.9
        (2.0, {(3, 5): 1.0}),  # x = 3.5
        (2.25, {(3, 5): 0.75, (2, 5): 0.25}),  # x = 3.25: the paper's rule on the edge
    ],
)
def test_off_centre_square_corner(distance, expected):
    got = lit(tc.render(SQUARE, "IM", square_t(distance)))
    assert got == pytest.approx(expected, abs=1e-12)


def test_im_hands_over_without_a_step_on_the_shapes_that_had_one():
    # Measured before the fix: steps of 1.0, 0.50 and 0.086 between samples 1/20000 apart.
    t = np.linspace(0.0, 1.0, 20001)
    for shape in (EXP3_CIRCLE, SQUARE, tc.Circle((2.5, 3.0), 2.0)):
        frames = tc.render(shape, "IM", t)
        arc = shape.length / 20000
        assert np.abs(np.diff(frames, axis=0)).max() <= 4 * arc, shape


# --- properties over random closed shapes inside the hull ------------------------------------


def coord(lo, hi):
    return st.floats(lo, hi, allow_nan=False, allow_infinity=False)


@st.composite
def circles_in_hull(draw):
    r = draw(coord(0.05, 2.0))
    cx = draw(coord(0.5 + r, 4.5 - r)) if r < 2.0 else 2.5
    cy = draw(coord(0.5 + r, 5.5 - r))
    return tc.Circle((cx, cy), r)


@st.composite
def squares_in_hull(draw):
    e = draw(coord(0.05, 4.0))
    cx = draw(coord(0.5 + e / 2, 4.5 - e / 2)) if e < 4.0 else 2.5
    cy = draw(coord(0.5 + e / 2, 5.5 - e / 2))
    return tc.Square((cx, cy), e)


polygons_in_hull = st.builds(
    lambda pts: tc.Polyline(pts, closed=True),
    st.lists(st.tuples(coord(0.5, 4.5), coord(0.5, 5.5)), min_size=3, max_size=7),
).filter(lambda shape: shape.length > 0.2)
closed_shapes = st.one_of(circles_in_hull(), squares_in_hull(), polygons_in_hull)


def events(shape):
    """Trace parameters where IM may have a keyframe, found without the code under test: the
    trace crossing a line x = k + 0.5 or y = k + 0.5 (a tactor centre on either axis), and
    the shape's corners (a circle's 45-degree points)."""
    if isinstance(shape, tc.Circle):
        (cx, cy), r = shape.center, shape.radius
        angles = [math.pi / 4 * k for k in (1, 3, 5, 7)]
        for k in range(-1, 8):
            for c0, trig in ((cx, math.acos), (cy, math.asin)):
                q = (k + 0.5 - c0) / r
                if -1 <= q <= 1:  # x = cx + r cos(a) or y = cy + r sin(a): both solutions
                    a = trig(q)
                    angles += [a, -a] if trig is math.acos else [a, math.pi - a]
        return sorted((a / (2 * math.pi)) % 1.0 for a in angles)
    poly = shape.polyline if isinstance(shape, tc.Square) else shape
    pts = [*poly.points, poly.points[0]]
    lengths = [math.dist(a, b) for a, b in itertools.pairwise(pts)]
    total = sum(lengths)
    out, s = [], 0.0
    for (a, b), length in zip(itertools.pairwise(pts), lengths):
        out.append(s / total)
        for axis in (0, 1):
            lo, hi = sorted((a[axis], b[axis]))
            for k in range(math.ceil(lo - 0.5), math.floor(hi - 0.5) + 1):
                if b[axis] != a[axis]:
                    f = (k + 0.5 - a[axis]) / (b[axis] - a[axis])
                    out.append((s + f * length) / total)
        s += length
    return sorted(out)


@settings(max_examples=150, deadline=None)
@given(closed_shapes)
def test_im_is_continuous_along_closed_shapes(shape):
    ev = np.array(events(shape))
    gaps = np.diff(np.concatenate([ev, [ev[0] + 1.0]])) * shape.length
    gaps = gaps[gaps > 1e-9]  # coinciding events are one keyframe
    g = gaps.min()
    n = 20001
    t = np.linspace(0.0, 1.0, n)
    frames = tc.render(shape, "IM", t).reshape(n, -1)
    step = np.abs(np.diff(frames, axis=0)).max(axis=1)
    arc = np.diff(t) * shape.length  # t is proportional to arc length on these shapes
    # Linear pieces between keyframes span at least one gap g; within a stroke, intensity moves
    # one unit per unit of the major coordinate, never faster than per unit of arc.
    allowed = arc * max(1.0, 1.0 / g) * (1 + 1e-6) + 1e-12
    worst = int(np.argmax(step - allowed))
    assert step[worst] <= allowed[worst], (shape, t[worst], step[worst], allowed[worst])


@settings(max_examples=150, deadline=None)
@given(closed_shapes)
def test_im_sums_to_one_and_lights_only_mm_tactors(shape):
    t = np.linspace(0.0, 1.0, 4001)
    im = tc.render(shape, "IM", t)
    np.testing.assert_allclose(im.sum(axis=(1, 2)), 1.0, atol=1e-12)
    assert ((im > 0).sum(axis=(1, 2))).max() <= 2
    # MM sampled densely and at every event (a partial column's tactor may be MM's only at the
    # junction itself when the corner lies on a cell edge).
    mm_t = np.concatenate([np.linspace(0.0, 1.0, 40001), events(shape)])
    mm_cells = (tc.render(shape, "MM", mm_t) > 0).any(axis=0)
    im_cells = (im > 0).any(axis=0)
    assert not (im_cells & ~mm_cells).any()


@settings(max_examples=60, deadline=None)
@given(closed_shapes, st.lists(coord(0.0, 1.0), min_size=1, max_size=20))
def test_im_live_path_equals_batch_on_closed_shapes(shape, ts):
    for t in ts:
        dense = tc.render(shape, "IM", t).reshape(-1)
        live = dict(tc.render_point(shape, "IM", t))
        expected = {i: v for i, v in enumerate(dense) if v > 0}
        assert live.keys() == expected.keys()
        for i, v in expected.items():
            assert live[i] == pytest.approx(v, abs=1e-12)
