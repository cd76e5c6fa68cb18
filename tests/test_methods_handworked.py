"""Frames worked out by hand from the paper's definitions (sections 2.2-2.5).

The Experiment 1 line: from (0.5, 1.84) to (4.5, 4.16), slope 0.58, tactor centre to tactor
centre. Its height is y(x) = 1.84 + 0.58 (x - 0.5): 1.84, 2.42, 3.00, 3.58, 4.16 at the column
centres, and it crosses y = 2 at x = 0.5 + 0.16/0.58, y = 3 at x = 2.5 and y = 4 at
x = 0.5 + 2.16/0.58. Since x = 0.5 + 4 t, a trace of one second spends (span in x) / 4 seconds
in each stretch.

The Experiment 1 circle: centre (2.5, 3), radius 2 (the centre of the 5 x 6 array).
"""

import math

import numpy as np
import pytest

import tactile_core as tc
from tactile_core.rendering.curves import activation_curves

from .helpers import lit, on_fraction, sequence

LINE = tc.Line((0.5, 1.84), (4.5, 4.16))
CIRCLE = tc.Circle((2.5, 3.0), 2.0)
DENSE = np.linspace(0.0, 1.0, 40001)


def y_line(x):
    return 1.84 + 0.58 * (x - 0.5)


def test_line_ct_sequence_and_durations():
    x2 = 0.5 + 0.16 / 0.58  # crosses y = 2
    x4 = 0.5 + 2.16 / 0.58  # crosses y = 4
    expected = {  # (col, row): span in x while in that cell
        (0, 1): x2 - 0.5,
        (0, 2): 1.0 - x2,
        (1, 2): 1.0,
        (2, 2): 0.5,  # x in [2, 2.5): y < 3
        (2, 3): 0.5,  # x in [2.5, 3): y >= 3 (y = 3.0 at x = 2.5 is a tie: upper)
        (3, 3): 1.0,
        (4, 3): x4 - 4.0,
        (4, 4): 4.5 - x4,
    }
    frames = tc.render(LINE, "CT", DENSE)
    assert sequence(frames) == list(expected)
    durations = on_fraction(frames)
    for cell, span in expected.items():
        assert durations[cell] == pytest.approx(span / 4.0, abs=1e-4), cell
    # Non-uniform: the paper's concern about CT (2.2).
    assert max(expected.values()) / min(expected.values()) > 3.0


def test_line_mm_one_tactor_per_column_with_uniform_durations():
    rows = [math.floor(y_line(c + 0.5) + 1e-12) for c in range(5)]  # 3.00 at column 2: upper
    assert rows == [1, 2, 3, 3, 4]
    frames = tc.render(LINE, "MM", DENSE)
    assert sequence(frames) == [(c, r) for c, r in zip(range(5), rows)]
    durations = on_fraction(frames)
    spans = [0.5, 1.0, 1.0, 1.0, 0.5]  # endpoints at column centres
    for c, r in enumerate(rows):
        assert durations[(c, r)] == pytest.approx(spans[c] / 4.0, abs=1e-4)


@pytest.mark.parametrize(
    ("t", "expected"),
    [
        # P = (0.5, 1.84): box [0, 1] x [1.34, 2.34]
        (0.0, {(0, 1): 0.66, (0, 2): 0.34}),
        # P = (1.5, 2.42): box [1, 2] x [1.92, 2.92]
        (0.25, {(1, 1): 0.08, (1, 2): 0.92}),
        # P = (2.0, 2.71): box [1.5, 2.5] x [2.21, 3.21]
        (0.375, {(1, 2): 0.5 * 0.79, (2, 2): 0.5 * 0.79, (1, 3): 0.5 * 0.21, (2, 3): 0.5 * 0.21}),
        # P = (2.5, 3.0): box [2, 3] x [2.5, 3.5]
        (0.5, {(2, 2): 0.5, (2, 3): 0.5}),
        # P = (4.5, 4.16): box [4, 5] x [3.66, 4.66]
        (1.0, {(4, 3): 0.34, (4, 4): 0.66}),
    ],
)
def test_line_as_frames(t, expected):
    got = lit(tc.render(LINE, "AS", t))
    assert got.keys() == expected.keys()
    for cell, value in expected.items():
        assert got[cell] == pytest.approx(value, abs=1e-12)


@pytest.mark.parametrize(
    ("t", "expected"),
    [
        (0.0, {(0, 1): 1.0}),  # at the first tactor centre
        (0.0625, {(0, 1): 0.75, (1, 2): 0.25}),  # x = 0.75
        (0.25, {(1, 2): 1.0}),  # x = 1.5, a column centre
        (0.375, {(1, 2): 0.5, (2, 3): 0.5}),  # x = 2.0, halfway
        (0.6, {(2, 3): 0.6, (3, 3): 0.4}),  # x = 2.9
        (1.0, {(4, 4): 1.0}),
    ],
)
def test_line_im_frames(t, expected):
    got = lit(tc.render(LINE, "IM", t))
    assert got.keys() == expected.keys()
    for cell, value in expected.items():
        assert got[cell] == pytest.approx(value, abs=1e-12)


def test_line_frames_of_figures_3_and_4_tactor_sets():
    # The bi-level and anti-aliased methods on the Figure 2 line activate these tactors.
    expected = {
        "CT": [(0, 1), (0, 2), (1, 2), (2, 2), (2, 3), (3, 3), (4, 3), (4, 4)],
        "MM": [(0, 1), (1, 2), (2, 3), (3, 3), (4, 4)],
        "IM": [(0, 1), (1, 2), (2, 3), (3, 3), (4, 4)],
    }
    for method, cells in expected.items():
        curves = activation_curves(LINE, method, duration_s=1.0, samples=4001)
        assert list(curves.cells) == cells, method


def test_circle_mm_ring():
    # Worked per arc. Top arc (x-major, x in [2.5 - sqrt2, 2.5 + sqrt2]): column 1 at x = 1.5
    # has y = 3 + sqrt(3) = 4.73 -> row 4; column 2: y = 5.0, a tie -> row 5; column 3 -> row 4.
    # Right arc (y-major): row 3 at y = 3.5 has x = 2.5 + sqrt(3.75) = 4.44 -> column 4; row 4's
    # centre 4.5 lies beyond the arc's end at y = 3 + sqrt2, clamped there: x = 3.91 -> column 3.
    # Bottom arc: column 2: y = 1.0 -> row 1. Left arc: rows 2, 3 -> column 0.
    ring = [(4, 3), (3, 4), (2, 5), (1, 4), (0, 3), (0, 2), (1, 1), (2, 1), (3, 1), (4, 2), (4, 3)]
    assert sequence(tc.render(CIRCLE, "MM", DENSE)) == ring


def test_circle_as_and_im_at_quarter_points():
    # t = 0.25: P = (2.5, 5.0), a tactor column centre on the edge between rows 4 and 5.
    assert lit(tc.render(CIRCLE, "AS", 0.25)) == pytest.approx({(2, 4): 0.5, (2, 5): 0.5})
    assert lit(tc.render(CIRCLE, "IM", 0.25)) == {(2, 5): 1.0}
    # t = 0: P = (4.5, 3.0), a row edge at the column centre 4.5.
    assert lit(tc.render(CIRCLE, "AS", 0.0)) == pytest.approx({(4, 2): 0.5, (4, 3): 0.5})


def test_circle_im_between_columns():
    t = 0.3  # on the top arc
    x = 2.5 + 2.0 * math.cos(2 * math.pi * t)  # 1.882
    share_right = x - 1.5  # distance past column 1's centre
    got = lit(tc.render(CIRCLE, "IM", t))
    assert got == pytest.approx({(1, 4): 1.0 - share_right, (2, 5): share_right})


def test_square_of_experiment_3_mm_and_im():
    # Edge 4 centred on the centre column and fourth row: corners at tactor centres
    # (0.5, 1.5), (4.5, 1.5), (4.5, 5.5), (0.5, 5.5). The trace starts at (4.5, 3.5).
    square = tc.Square((2.5, 3.5), 4.0)
    ring = (
        [(4, r) for r in (3, 4, 5)]
        + [(c, 5) for c in (3, 2, 1, 0)]
        + [(0, r) for r in (4, 3, 2, 1)]
        + [(c, 1) for c in (1, 2, 3, 4)]
        + [(4, r) for r in (2, 3)]
    )
    assert sequence(tc.render(square, "MM", DENSE)) == ring
    # A quarter of the way along the top edge: t = 3/16 -> (3.5, 5.5), a tactor centre.
    assert lit(tc.render(square, "IM", 3 / 16)) == {(3, 5): 1.0}
    # t = 0.5 -> (0.5, 3.5) on the left edge; t = 0.5 + 1/32 -> y = 3.0: halfway down.
    assert lit(tc.render(square, "IM", 0.5 + 1 / 32)) == pytest.approx({(0, 3): 0.5, (0, 2): 0.5})


def test_free_points_ct_and_as_at_a_cell_corner():
    frame = tc.render_xy("AS", 2.0, 3.0)  # a cell corner: four tactors at 0.25
    assert lit(frame) == pytest.approx({(1, 2): 0.25, (2, 2): 0.25, (1, 3): 0.25, (2, 3): 0.25})
    assert lit(tc.render_xy("CT", 2.0, 3.0)) == {(2, 3): 1.0}  # tie: upper/right
    with pytest.raises(ValueError, match="MM needs a shape"):
        tc.render_xy("MM", 2.0, 3.0)
