"""Energy method (EN): Tactile Brush's energy model on the cells of area sampling.

Tactile Brush (Israr and Poupyrev, "Tactile Brush: Drawing on Skin with a Tactile Grid
Display", CHI 2011) creates a phantom sensation between actuators with the energy model: the
intensities ``A_i`` of the actuators sharing a virtual point satisfy ``sum A_i^2 = A_v^2``, so
felt energy stays constant as the point moves. Here the point is shared among AS's cells (the
unit box around it, paper section 2.4) in proportion to the area weights ``a_i``:
``I_i = sqrt(a_i)``, hence ``sum I_i^2 = sum a_i = 1`` inside the tactor hull. At the array's
edge the area outside is lost, as for AS. Works on any coordinate, with or without a shape.

EN is driven as computed (``CORRECTION = "none"``): the energy law is its correction, and the
paper's threshold/gamma on top would compress it a second time (its 1.27 ripple in the
predicted percept under mu 0.33, gamma 0.7).
"""

from __future__ import annotations

import math

import numpy as np

from . import area
from ._cells import stack_points

NAME = "EN"
TITLE = "energy model (Tactile Brush)"
BILEVEL = False
NEEDS_SHAPE = False
MAX_TACTORS = 4
CORRECTION = "none"


def sample(shape, x, y, t, tol):
    """AS's cells with the square roots of their areas.

    Parameters
    ----------
    shape, t
        Unused: EN depends on the point only.
    x, y : ndarray of float64, shape (n,)
        Points in grid units.
    tol : float or ndarray
        Snap tolerance of the cell lookup.

    Returns
    -------
    list of (cols, rows, values)
        The four cells of :func:`tactile_core.rendering.methods.area.sample`, values ``sqrt(a_i)``.
    """
    return sample_cells(shape, stack_points(x, y), t, tol).entries()


def sample_cells(shape, xy, t, tol):
    """:func:`sample` in the renderer's batch form (:class:`~._cells.Cells`): AS's cells, the
    square roots of their areas."""
    cells = area.sample_cells(shape, xy, t, tol)
    return cells._replace(values=np.sqrt(cells.values, out=cells.values))


def sample1(shape, x, y, t, tol):
    """Scalar :func:`sample`: ``(col, row, value)`` of the lit tactors."""
    return tuple((c, r, math.sqrt(v)) for c, r, v in area.sample1(shape, x, y, t, tol))
