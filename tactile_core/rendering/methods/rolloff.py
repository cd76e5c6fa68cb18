"""Roll-off method (RO): Syntacts' spatializer, for comparison with the paper's methods.

Syntacts (Pezent et al., "Syntacts: Open-Source Software and Hardware for Audio-Controlled
Haptics", IEEE Transactions on Haptics 14(1), 2021) spatialises a virtual source over an array by
giving each channel a gain that rolls off with its distance ``d`` from the source, zero beyond a
radius ``r``. This module uses the contract's smoothstep roll-off, ``s(1 - d / r)`` for
``d < r`` with ``s(x) = x^2 (3 - 2x)``: 1 on the tactor, falling smoothly to 0 with zero slope
at both ends. Distances are in pitches; ``r = 1`` by default, so a point on a tactor lights it
alone and a point at a cell corner lights the four around it at ``s(1 - 0.707) = 0.21`` each.
Intensities do not sum to 1 (nor their squares): Syntacts leaves the balance to the user.
Works on any coordinate, with or without a shape.
"""

from __future__ import annotations

import numpy as np

from . import _radial

NAME = "RO"
TITLE = "roll-off (Syntacts)"
BILEVEL = False
NEEDS_SHAPE = False
PARAMS = {"r": (1.0, 0.1, 10.0, "roll-off radius in pitches: tactors farther away are off")}


def MAX_TACTORS(r=1.0):
    """Most tactors lit at once for radius ``r`` (4 at ``r = 1``)."""
    return _radial.max_within(float(r), True)


def smoothstep(x):
    """``x^2 (3 - 2x)`` on [0, 1]: 0 and 1 at the ends, zero slope at both."""
    return x * x * (3.0 - 2.0 * x)


def sample(shape, x, y, t, tol, r=1.0):
    """Tactors within ``r`` of the points ``(x, y)`` and their roll-off gains.

    Parameters
    ----------
    shape, t
        Unused: RO depends on the point only.
    x, y : ndarray of float64, shape (n,)
        Points in grid units.
    tol : float or ndarray
        Snap tolerance of the cell lookup.
    r : float
        Roll-off radius in pitches.

    Returns
    -------
    list of (cols, rows, values)
        One entry per candidate tactor (see :mod:`tactile_core.rendering.methods._radial`), values
        ``s(1 - d / r)`` in [0, 1], 0 at ``d >= r``.
    """
    inv = 1.0 / r
    return _radial.sample(x, y, tol, r, True, lambda d: smoothstep(np.clip(1.0 - d * inv, 0, 1)))


def sample1(shape, x, y, t, tol, r=1.0):
    """Scalar :func:`sample`: ``(col, row, value)`` of the lit tactors."""
    inv = 1.0 / r
    return _radial.sample1(x, y, tol, r, True, lambda d: smoothstep(1.0 - d * inv))
