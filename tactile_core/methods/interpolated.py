"""Interpolated-midpoint method (IM), paper section 2.5: MM's tactors, interpolated.

On a stroke with major axis x, the point's x lies between the column centres
``x_k = floor(x - 0.5) + 0.5`` and ``x_k + 1``. MM's tactor of column ``k`` gets intensity
``x_k+1 - x`` and MM's tactor of column ``k + 1`` gets the rest, so intensities move linearly
along the major axis and always sum to 1.

Ends of strokes: while the point lies between a stroke's end and the centre of the end cell
(``x`` before the first column's centre, or after the last column's centre), the end tactor keeps
the full intensity 1 instead of sharing it with a column the stroke never reaches. Intensities
therefore sum to 1 everywhere along lines, squares and circles (the paper states the
interpolation only between two columns of the stroke). Where consecutive strokes meet at a
polyline vertex or a circle's octant boundary, the tactors switch to the next stroke's; when
the end cell's centre lies beyond the stroke's end, the last tactor carries ``1 - d`` at the
junction (``d`` = distance to that centre), so the hand-over has a step of at most ``d < 0.5``.
"""

from __future__ import annotations

import math

import numpy as np

from ..geometry import cell_split, cell_split1
from .midpoint import on_stroke, tactor_of_cell, to_cells

NAME = "IM"
TITLE = "interpolated midpoint"
BILEVEL = False
NEEDS_SHAPE = True
MAX_TACTORS = 2


def sample(shape, x, y, t, tol):
    """Tactors lit at the points ``(x, y) = shape.f(t)``.

    Parameters
    ----------
    shape : Shape
        The traced shape; its strokes select the tactors.
    x, y : ndarray of float64, shape (n,)
        Points of the trace in grid units.
    t : ndarray of float64, shape (n,)
        Their trace parameters.
    tol : float
        The shape's snap tolerance.

    Returns
    -------
    list of (cols, rows, values)
        MM's tactors of major cells ``k`` and ``k + 1`` and their intensities.
    """
    strokes = shape.strokes
    params, xmajor, u = on_stroke(strokes, x, y, t)
    k, w = cell_split(u - 0.5, tol)  # w: share of cell k + 1
    pair = np.stack([k, k + 1.0])  # major cells k and k + 1, shape (2, n)
    # Between a stroke's end and its end cell's centre, the end tactor keeps everything:
    # w = 1 before the first centre (k < first), w = 0 after the last (k + 1 > last).
    w = np.where(k < params[3], 1.0, w)
    w = np.where(pair[1] > params[4], 0.0, w)
    cols, rows = to_cells(xmajor, pair, tactor_of_cell(strokes, params, pair))
    return [(cols[0], rows[0], 1.0 - w), (cols[1], rows[1], w)]


def sample1(shape, x, y, t, tol):
    """Scalar :func:`sample`: ``(col, row, value)`` tuples with nonzero intensity."""
    strokes = shape.strokes
    row = strokes.rows1[strokes.locate1(t)]
    axis, lo, hi, first, last = row[:5]
    u = min(max(x if axis == 0 else y, lo), hi)
    k, w = cell_split1(u - 0.5, tol)
    if k < first:
        w = 1.0
    if k + 1 > last:
        w = 0.0
    out = []
    for m, value in ((k, 1.0 - w), (k + 1, w)):
        if value > 0.0:
            n = math.floor(strokes.minor1(row, min(max(m + 0.5, lo), hi)) + tol)
            out.append((m, n, value) if axis == 0 else (n, m, value))
    return tuple(out)
