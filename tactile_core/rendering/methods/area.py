"""Area sampling method (AS), paper section 2.4: an anti-aliased method.

A unit square centred on the point ``P = f(t)`` overlaps one, two or four cells; each overlapped
cell's tactor gets the area of the overlap. With ``a = px - 0.5`` and ``c = floor(a)``, the box
covers ``1 - (a - c)`` of column ``c`` and ``a - c`` of column ``c + 1`` (likewise in y), so the
four intensities are products of those widths and sum to 1. Along a line each is a product of
two functions linear in ``t``: the activation curves are quadratic pieces.

At the array's edge the part of the box outside the array is lost, as the paper defines the
method: the intensities then sum to less than 1 (0.5 with the point on the boundary edge
midway between tactors, 0.25 in a corner). Inside the tactor hull (``0.5 <= px <= cols - 0.5``,
likewise in y) they sum to 1. Works on any coordinate, with or without a shape.
"""

from __future__ import annotations

import numpy as np

from ..geometry import cell_split, cell_split1
from ._cells import Block, stack_points

NAME = "AS"
TITLE = "area sampling"
BILEVEL = False
NEEDS_SHAPE = False
MAX_TACTORS = 4


def sample(shape, x, y, t, tol):
    """Tactors lit at points ``(x, y)``: see :func:`tactile_core.rendering.methods.closest.sample`.

    Returns
    -------
    list of (cols, rows, values)
        The lower-left, lower-right, upper-left and upper-right overlapped cells and their
        areas (zero where the box does not reach a cell).
    """
    return sample_cells(shape, stack_points(x, y), t, tol).entries()


def sample_cells(shape, xy, t, tol):
    """:func:`sample` in the renderer's batch form (:class:`~._cells.Block`), for the points
    ``xy`` (``(2, n)``: x, then y).

    The 2 x 2 block of columns ``c, c + 1`` and rows ``r, r + 1`` from the box's lower-left
    cell; the areas are the products of the widths ``(1 - fx, fx)`` and ``(1 - fy, fy)``, rows
    outer.
    """
    cr, f = cell_split(xy - 0.5, tol)
    n = f.shape[1]
    widths = np.empty((2, 2, n))  # [axis, (1 - f, f), point]
    np.subtract(1.0, f, out=widths[:, 0])
    widths[:, 1] = f
    values = np.multiply(widths[1][:, None, :], widths[0][None, :, :], out=np.empty((2, 2, n)))
    return Block(cr, values.reshape(4, n), 2, 2)


def sample1(shape, x, y, t, tol):
    """Scalar :func:`sample`: ``(col, row, value)`` tuples, only those with nonzero area."""
    c, fx = cell_split1(x - 0.5, tol)
    r, fy = cell_split1(y - 0.5, tol)
    if fx == 0.0:
        if fy == 0.0:
            return ((c, r, 1.0),)
        return ((c, r, 1.0 - fy), (c, r + 1, fy))
    gx = 1.0 - fx
    if fy == 0.0:
        return ((c, r, gx), (c + 1, r, fx))
    gy = 1.0 - fy
    return ((c, r, gx * gy), (c + 1, r, fx * gy), (c, r + 1, gx * fy), (c + 1, r + 1, fx * fy))
