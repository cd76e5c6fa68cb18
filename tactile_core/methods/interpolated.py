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

import numpy as np

from ..geometry import cell_split, cell_split1
from .midpoint import _major_minor, tactor_of_cell

NAME = "IM"
TITLE = "interpolated midpoint"
BILEVEL = False
NEEDS_SHAPE = True
MAX_TACTORS = 2


def sample(shape, x, y, t):
    """Tactors lit at the points ``(x, y) = shape.f(t)``.

    Parameters
    ----------
    shape : Shape
        The traced shape; its strokes select the tactors.
    x, y : ndarray of float64, shape (n,)
        Points of the trace in grid units.
    t : ndarray of float64, shape (n,)
        Their trace parameters.

    Returns
    -------
    cols, rows, values : ndarray of float64, shape (n, 2)
        MM's tactors of major cells ``k`` and ``k + 1`` and their intensities.
    """
    strokes = shape.strokes
    ids = strokes.locate(t)
    xmajor, u, lo, hi = _major_minor(strokes, ids, x, y)
    k, w = cell_split(u - 0.5)  # w: share of cell k + 1
    w = np.where(k < strokes.first[ids], 1.0, w)  # before the first centre
    w = np.where(k + 1.0 > strokes.last[ids], 0.0, w)  # after the last centre
    k1 = k + 1.0
    na = tactor_of_cell(strokes, ids, k, lo, hi)
    nb = tactor_of_cell(strokes, ids, k1, lo, hi)
    cols = np.stack([np.where(xmajor, k, na), np.where(xmajor, k1, nb)], axis=-1)
    rows = np.stack([np.where(xmajor, na, k), np.where(xmajor, nb, k1)], axis=-1)
    values = np.stack([1.0 - w, w], axis=-1)
    return cols, rows, values


def sample1(shape, x, y, t):
    """Scalar :func:`sample`: ``(col, row, value)`` tuples with nonzero intensity."""
    strokes = shape.strokes
    i = strokes.locate1(t)
    axis, lo, hi, first, last = strokes.extent1[i]
    u = x if axis == 0 else y
    u = min(max(u, lo), hi)
    k, w = cell_split1(u - 0.5)
    if k < first:
        w = 1.0
    if k + 1 > last:
        w = 0.0
    out = []
    for m, value in ((k, 1.0 - w), (k + 1, w)):
        if value > 0.0:
            n, _ = cell_split1(strokes.minor1(i, min(max(m + 0.5, lo), hi)))
            out.append((m, n, value) if axis == 0 else (n, m, value))
    return tuple(out)
