"""Gaussian method (GS): this project's Gaussian spread, for comparison with the paper's methods.

A point is spread over nearby tactors with Gaussian weights, ``exp(-d^2 / (2 sigma^2))`` for the
distance ``d`` (in pitches) from the point to a tactor, as many hand-rolled array drivers do.
It is not what VRCH-Server computes: there a Gaussian kernel weights a *normalised mean* over the
contacts near each actuator, so one contact lights every actuator within its radius at full
intensity (that rule is :mod:`.vrch`, ``VRCH``). ``sigma = 0.5`` by default; weights below
0.05 are zero, so the support is the disc of radius ``sigma sqrt(2 ln 20)`` (1.22 pitches at
the default: a point on a tactor lights it at 1 and its four neighbours at ``exp(-2) = 0.135``;
a point midway between two tactors lights six). Neither the intensities nor their squares sum
to 1. Works on any coordinate, with or without a shape.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from . import _radial
from ._cells import Block, outer, stack_points

NAME = "GS"
TITLE = "Gaussian spread (this project)"
BILEVEL = False
NEEDS_SHAPE = False
PARAMS = {"sigma": (0.5, 0.1, 5.0, "spread in pitches (weights below 0.05 are off)")}
CUTOFF = 0.05
"""Weights below this are zero."""


def radius(sigma: float) -> float:
    """Distance at which the weight falls to :data:`CUTOFF`: ``sigma sqrt(2 ln(1 / CUTOFF))``."""
    return sigma * math.sqrt(2.0 * math.log(1.0 / CUTOFF))


def MAX_TACTORS(sigma=0.5):
    """Most tactors lit at once for ``sigma`` (6 at ``sigma = 0.5``)."""
    return _radial.max_within(radius(float(sigma)), False)


def sample(shape, x, y, t, tol, sigma=0.5):
    """Tactors within the cut-off radius of the points ``(x, y)`` and their Gaussian weights.

    Parameters
    ----------
    shape, t
        Unused: GS depends on the point only.
    x, y : ndarray of float64, shape (n,)
        Points in grid units.
    tol : float or ndarray
        Snap tolerance of the cell lookup.
    sigma : float
        Standard deviation of the Gaussian, in pitches.

    Returns
    -------
    list of (cols, rows, values)
        One entry per candidate tactor; values ``exp(-d^2 / (2 sigma^2))`` where that is at
        least 0.05, else 0.
    """
    return sample_cells(shape, stack_points(x, y), t, tol, sigma).entries()


def sample_cells(shape, xy, t, tol, sigma=0.5):
    """:func:`sample` in the renderer's batch form (:class:`~._cells.Block`).

    The weight is the product of per-axis Gaussians, ``exp(k dx^2) exp(k dy^2)`` with
    ``k = -1 / (2 sigma^2)``: one exponential per column and row of the block, not per
    tactor. It is cut below :data:`CUTOFF`; a weight within :data:`~._radial.MARGIN` of the
    cut is decided as ``exp(k hypot(dx, dy)^2)`` decides.
    """
    k = -0.5 / (sigma * sigma)
    reach = radius(sigma)
    split = _radial.block(xy, tol, reach, False)
    e = split.squares()
    e *= k
    ex, ey = np.exp(e, out=e)
    a, n = ex.shape
    w = outer(np.multiply, ey, ex, np.empty((a * a, n)))
    lo, hi = CUTOFF * (1.0 - _radial.MARGIN), CUTOFF * (1.0 + _radial.MARGIN)
    below = w < hi
    found = _radial.unsettled(w, lo, hi, below)
    np.putmask(w, below, 0.0)
    if found is not None:
        _radial.settle(w, found, split, reach, False, _exact_weight(k))
    return Block(split.origin, w, a, a)


@functools.lru_cache(maxsize=64)
def _exact_weight(k: float):
    return lambda d: _cut(np.exp(k * d * d))


def _cut(w):
    return np.where(w >= CUTOFF, w, 0.0)


def sample1(shape, x, y, t, tol, sigma=0.5):
    """Scalar :func:`sample`: ``(col, row, value)`` of the lit tactors."""
    return _radial.sample1(x, y, tol, radius(sigma), False, _weight1(sigma))


def sample1_exact(shape, x, y, t, tol, sigma=0.5):
    """:func:`sample1`, or None where a tactor lies within rounding of the cut-off radius
    (where ``math`` and numpy may decide differently: the renderer then takes the array
    path)."""
    return _radial.sample1(x, y, tol, radius(sigma), False, _weight1(sigma), guard=True)


@functools.lru_cache(maxsize=64)
def _weight1(sigma: float):
    k = -0.5 / (sigma * sigma)

    def weight(d):
        w = math.exp(k * d * d)
        return w if w >= CUTOFF else 0.0

    return weight
