"""Closest-tactor method (CT), paper section 2.2: a bi-level method.

The tactor of the cell containing the point ``P = f(t)`` is on with intensity 1; all others are
off. The cell is ``(floor(px), floor(py))``. A point equidistant from several tactors (on a cell
edge or corner) lights the upper/right one, which ``floor`` gives directly. Works on any
coordinate, with or without a shape.
"""

from __future__ import annotations

import math

from ..geometry import cell_floor
from ._cells import ZIP, Cells

NAME = "CT"
TITLE = "closest tactor"
BILEVEL = True
NEEDS_SHAPE = False
MAX_TACTORS = 1


def sample(shape, x, y, t, tol):
    """Tactors lit at points ``(x, y)``.

    Parameters
    ----------
    shape : Shape or None
        Unused: CT depends on the point only.
    x, y : ndarray of float64, shape (n,)
        Points in grid units.
    t : ndarray of float64, shape (n,)
        Trace parameters (unused).
    tol : float or ndarray
        Snap tolerance for cell lookup.

    Returns
    -------
    list of (cols, rows, values)
        One entry per lit tactor: cell indices as float arrays of shape (n,) (possibly
        outside the grid) and intensities (an array or a scalar broadcast over all samples).
    """
    return [(cell_floor(x, tol), cell_floor(y, tol), 1.0)]


def sample_cells(shape, xy, t, tol):
    """:func:`sample` in the renderer's batch form (:class:`~._cells.Cells`), for the points
    ``xy`` (``(2, n)``)."""
    cells = cell_floor(xy, tol)
    return Cells(cells[:1], cells[1:], 1.0, ZIP)


def sample1(shape, x, y, t, tol):
    """Scalar :func:`sample`: a tuple of ``(col, row, value)`` with plain Python numbers."""
    return ((math.floor(x + tol), math.floor(y + tol), 1.0),)
