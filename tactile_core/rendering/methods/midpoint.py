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

import math
from typing import NamedTuple

import numpy as np

from ..geometry import cell_floor, clamp
from ..shapes import Strokes
from ._cells import ZIP, Cells, stack_points

NAME = "MM"
TITLE = "midpoint"
BILEVEL = True
NEEDS_SHAPE = True
MAX_TACTORS = 1


def on_stroke(strokes, x, y, t, count: int = 9):
    """Locate points on their strokes.

    ``count``: how many of the strokes' parameters to gather (the first three are all this
    function needs; :func:`tactor_of_cell` needs all nine).

    Returns
    -------
    params : ndarray, shape (count, n), or tuple
        The strokes' parameters per point (:meth:`~tactile_core.rendering.shapes.Strokes.gather`).
    xmajor : ndarray of bool or bool
        Whether each point's stroke is x-major.
    u : ndarray of float64, shape (n,)
        Major-axis coordinate of each point, clipped to its stroke's extent (the point lies on
        the stroke; the clip only absorbs rounding at the ends).
    ids : ndarray of intp or None
        Each point's stroke (None for a shape of one stroke).
    """
    ids = strokes.locate(t)
    params = strokes.gather(ids, count)
    if ids is None:
        xmajor = params[0] == 0
        u = x if xmajor else y
    else:
        xmajor = params[0] == 0.0
        u = np.where(xmajor, x, y)
    return params, xmajor, clamp(u, params[1], params[2]), ids


MAX_LOOKUP = 4096
"""Most major cells (over all strokes) whose MM tactors :func:`lookup` tabulates."""


class Lookup(NamedTuple):
    """MM's tactor of every major cell a shape's strokes reach, tabulated once per shape.

    Stroke ``s``'s major cell ``m`` is entry ``m + offset[s]`` of ``cols`` and ``rows``; each
    stroke's table runs from two cells before its first to two after its last (IM asks for the
    cell beyond the point's, MM for the point's own).
    """

    offset: np.ndarray
    cols: np.ndarray
    rows: np.ndarray

    def cells(self, major, ids):
        """``(cols, rows)`` of MM's tactors of major cells ``major`` (whole floats, any shape
        ending in ``n``) on strokes ``ids`` (None: the shape's one stroke)."""
        index = major + (self.offset[0] if ids is None else self.offset.take(ids))
        index = index.astype(np.intp)
        return self.cols.take(index), self.rows.take(index)


def lookup(strokes) -> Lookup | None:
    """The strokes' :class:`Lookup` (built on first use and kept with them), or None when they
    span more than :data:`MAX_LOOKUP` cells (MM's tactors are then computed point by point).

    The table holds exactly what :func:`tactor_of_cell` and :func:`to_cells` give for each cell,
    computed the same way, so looking up and computing agree to the last bit.
    """
    try:
        return strokes.mm_lookup
    except AttributeError:
        pass
    first = strokes.table[:, Strokes.FIRST] - 2.0
    span = strokes.table[:, Strokes.LAST] + 3.0 - first
    table = None
    if np.isfinite(span).all() and span.sum() <= MAX_LOOKUP:
        counts = span.astype(np.intp)
        ids = np.repeat(np.arange(strokes.count), counts)
        start = np.cumsum(counts) - counts
        major = first.take(ids) + (np.arange(counts.sum()) - start.take(ids))
        params = strokes.gather(ids)
        cols, rows = to_cells(params[0] == 0.0, major, tactor_of_cell(strokes, params, major))
        table = Lookup(start - first, cols, rows)
    strokes.mm_lookup = table
    return table


def tactor_of_cell(strokes, params, m):
    """Minor-axis cell of the MM tactor of major cell(s) ``m`` of the gathered strokes."""
    centre = clamp(m + 0.5, params[1], params[2])
    return cell_floor(strokes.minor(params, centre), strokes.tol)


def to_cells(xmajor, major, minor):
    """``(cols, rows)`` from major- and minor-axis cells."""
    if np.ndim(xmajor) == 0:
        return (major, minor) if xmajor else (minor, major)
    return np.where(xmajor, major, minor), np.where(xmajor, minor, major)


def sample(shape, x, y, t, tol):
    """Tactors lit at the points ``(x, y) = shape.f(t)``.

    Parameters
    ----------
    shape : Shape
        The traced shape; its strokes select the tactors.
    x, y : ndarray of float64, shape (n,)
        Points of the trace in grid units.
    t : ndarray of float64, shape (n,)
        Their trace parameters (which stroke each point is on).
    tol : float
        The shape's snap tolerance.

    Returns
    -------
    list of (cols, rows, values)
        One entry: the lit tactor at intensity 1.
    """
    return sample_cells(shape, stack_points(x, y), t, tol).entries()


def sample_cells(shape, xy, t, tol):
    """:func:`sample` in the renderer's batch form (:class:`~._cells.Cells`), for the points
    ``xy`` (``(2, n)``): one candidate."""
    strokes = shape.strokes
    table = lookup(strokes)
    params, xmajor, u, ids = on_stroke(strokes, xy[0], xy[1], t, 9 if table is None else 3)
    m = cell_floor(u, tol)
    if table is not None:
        cols, rows = table.cells(m, ids)
    else:
        cols, rows = to_cells(xmajor, m, tactor_of_cell(strokes, params, m))
    return Cells(cols[None], rows[None], 1.0, ZIP)


def sample1(shape, x, y, t, tol):
    """Scalar :func:`sample`: a tuple with one ``(col, row, 1.0)``."""
    strokes = shape.strokes
    row = strokes.rows1[strokes.locate1(t)]
    axis, lo, hi = row[0], row[1], row[2]
    u = min(max(x if axis == 0 else y, lo), hi)
    m = math.floor(u + tol)
    n = math.floor(strokes.minor1(row, min(max(m + 0.5, lo), hi)) + tol)
    return ((m, n, 1.0),) if axis == 0 else ((n, m, 1.0),)
