"""VRCH method (VRCH): VRCH-Server's rule for one contact, for comparison with the paper's methods.

VRCH-Server (VRC-Haptics, the VRChat haptics bridge) gives each actuator the *normalised
weighted mean* of the contacts ("input nodes") within their radius ``r`` of it,
``v = sum_j w_j v_j / sum_j w_j``, with a Gaussian weight ``w_j`` of the distance
(``InterpState::single_node`` in ``src-core/src/mapping/interp.rs``; the kernel falls to 0.05 at
the radius), then plays ``offset + (intensity - offset) v`` for ``v > 0``. With a single contact
of value 1 the weight cancels: every actuator within ``r`` of the point gets 1 and every other
gets 0, whatever the distance. That is this method: bi-level, ``1`` for ``d_i < r`` (``d_i`` in
pitches), ``r = 1`` by default (a point at a cell corner lights the four tactors around it at
full drive, a point on a tactor lights it alone). The server's offset is a threshold with
gamma 1 (``CORRECTION = "threshold"``). Works on any coordinate, with or without a shape.
"""

from __future__ import annotations

import numpy as np

from . import _radial
from ._cells import Block, stack_points

NAME = "VRCH"
TITLE = "every tactor within r (VRCH-Server, one contact)"
BILEVEL = True
NEEDS_SHAPE = False
PARAMS = {"r": (1.0, 0.1, 10.0, "contact radius in pitches: tactors within it are on")}
CORRECTION = "threshold"


def MAX_TACTORS(r=1.0):
    """Most tactors lit at once for radius ``r`` (4 at ``r = 1``)."""
    return _radial.max_within(float(r), True)


def sample(shape, x, y, t, tol, r=1.0):
    """Tactors within ``r`` of the points ``(x, y)``, each at 1.

    Parameters
    ----------
    shape, t
        Unused: VRCH depends on the point only.
    x, y : ndarray of float64, shape (n,)
        Points in grid units.
    tol : float or ndarray
        Snap tolerance of the cell lookup.
    r : float
        Contact radius in pitches.

    Returns
    -------
    list of (cols, rows, values)
        One entry per candidate tactor, values 1 at ``d < r`` and 0 beyond.
    """
    return sample_cells(shape, stack_points(x, y), t, tol, r).entries()


def sample_cells(shape, xy, t, tol, r=1.0):
    """:func:`sample` in the renderer's batch form (:class:`~._cells.Block`): within ``r`` by
    ``dx^2 + dy^2 < r^2``, and as ``hypot(dx, dy) < r`` decides within
    :data:`~._radial.MARGIN` of the edge."""
    split = _radial.block(xy, tol, r, True)
    d2 = _radial.squared_distances(split.squares())
    lo, hi = r * r * (1.0 - _radial.MARGIN), r * r * (1.0 + _radial.MARGIN)
    inside = d2 < lo
    found = _radial.unsettled(d2, lo, hi, below_lo=inside)
    values = inside.astype(np.float64)
    if found is not None:
        _radial.settle(values, found, split, r, True, np.ones_like, _one)
    return Block(split.origin, values, split.width, split.width)


def sample1(shape, x, y, t, tol, r=1.0):
    """Scalar :func:`sample`: ``(col, row, 1.0)`` of the lit tactors."""
    return _radial.sample1(x, y, tol, r, True, _one)


def sample1_exact(shape, x, y, t, tol, r=1.0):
    """:func:`sample1`, or None where a tactor lies within rounding of ``r`` (the renderer then
    takes the array path)."""
    return _radial.sample1(x, y, tol, r, True, _one, guard=True)


def _one(d):
    return 1.0
