"""Midpoint method (MM), paper section 2.3: a bi-level method with one tactor per major cell.

For a stroke whose major axis is x (a line with ``|slope| <= 1``, or the top or bottom arc of a
circle), the trace lights one tactor per column: while the point is in column ``c``, the tactor
at row ``floor(v(c + 0.5))``, where ``v(u)`` is the stroke's y at x = ``u`` (the closest tactor
to the stroke in that column, or tied with the one below: ties go up). y-major strokes are the
same with the axes swapped.

Where a column's centre lies beyond the stroke's end (a segment ending inside a column, a small
circle whose column centre falls outside it, the column at an octant boundary of a circle), the
centre is clamped to the stroke's extent: the row is that of the stroke's own point closest to
the column centre, so MM never lights a row the stroke does not visit in that column. For
segments between tactor centres this never happens, and MM selects the cells of Bresenham's
line algorithm. A zero-length stroke lights the cell of its point.
"""

from __future__ import annotations

import numpy as np

from ..geometry import cell_split, cell_split1

NAME = "MM"
TITLE = "midpoint"
BILEVEL = True
NEEDS_SHAPE = True
MAX_TACTORS = 1


def _major_minor(strokes, ids, x, y):
    xmajor = strokes.axis[ids] == 0
    lo = strokes.lo[ids]
    hi = strokes.hi[ids]
    # The point lies on its stroke; the clip only absorbs rounding at the stroke's ends.
    u = np.clip(np.where(xmajor, x, y), lo, hi)
    return xmajor, u, lo, hi


def tactor_of_cell(strokes, ids, m, lo, hi):
    """Minor-axis cell of the MM tactor for major cell ``m`` of strokes ``ids`` (float array)."""
    v = strokes.minor(ids, np.clip(m + 0.5, lo, hi))
    n, _ = cell_split(v)
    return n


def sample(shape, x, y, t):
    """Tactors lit at the points ``(x, y) = shape.f(t)``.

    Parameters
    ----------
    shape : Shape
        The traced shape; its strokes select the tactors.
    x, y : ndarray of float64, shape (n,)
        Points of the trace in grid units.
    t : ndarray of float64, shape (n,)
        Their trace parameters (which stroke each point is on).

    Returns
    -------
    cols, rows, values : ndarray of float64, shape (n, 1)
    """
    strokes = shape.strokes
    ids = strokes.locate(t)
    xmajor, u, lo, hi = _major_minor(strokes, ids, x, y)
    m, _ = cell_split(u)
    n = tactor_of_cell(strokes, ids, m, lo, hi)
    cols = np.where(xmajor, m, n)
    rows = np.where(xmajor, n, m)
    return cols[:, None], rows[:, None], np.ones((cols.shape[0], 1))


def sample1(shape, x, y, t):
    """Scalar :func:`sample`: a tuple with one ``(col, row, 1.0)``."""
    strokes = shape.strokes
    i = strokes.locate1(t)
    axis, lo, hi, _, _ = strokes.extent1[i]
    u = x if axis == 0 else y
    u = min(max(u, lo), hi)
    m, _ = cell_split1(u)
    n, _ = cell_split1(strokes.minor1(i, min(max(m + 0.5, lo), hi)))
    return ((m, n, 1.0),) if axis == 0 else ((n, m, 1.0),)
