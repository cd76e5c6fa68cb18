"""Closest-tactor method (CT), paper section 2.2: a bi-level method.

The tactor of the cell containing the point ``P = f(t)`` is on with intensity 1; all others are
off. The cell is ``(floor(px), floor(py))``. A point equidistant from several tactors (on a cell
edge or corner) lights the upper/right one, which ``floor`` gives directly. Works on any
coordinate, with or without a shape.
"""

from __future__ import annotations

import numpy as np

from ..geometry import cell_split, cell_split1

NAME = "CT"
TITLE = "closest tactor"
BILEVEL = True
NEEDS_SHAPE = False
MAX_TACTORS = 1


def sample(shape, x, y, t):
    """Tactors lit at points ``(x, y)``.

    Parameters
    ----------
    shape : Shape or None
        Unused: CT depends on the point only.
    x, y : ndarray of float64, shape (n,)
        Points in grid units.
    t : ndarray of float64, shape (n,)
        Trace parameters (unused).

    Returns
    -------
    cols, rows, values : ndarray of float64, shape (n, 1)
        Cell indices (possibly outside the grid) and raw intensities.
    """
    col, _ = cell_split(x)
    row, _ = cell_split(y)
    return col[:, None], row[:, None], np.ones((col.shape[0], 1))


def sample1(shape, x, y, t):
    """Scalar :func:`sample`: a tuple of ``(col, row, value)`` with plain Python numbers."""
    return ((cell_split1(x)[0], cell_split1(y)[0], 1.0),)
