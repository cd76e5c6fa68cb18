"""Park method (PK): inverse-distance weights over the three nearest tactors.

Park, Kim, Oh and Tan ("Rendering Moving Tactile Stroke on the Palm Using a Sparse 2D Array",
EuroHaptics 2016, LNCS 9774) render a moving stroke on the palm with 3-actuator phantom
sensations: the three actuators nearest to the point, weighted by inverse distance under the
energy model. With ``d_i`` the distance in pitches
from the point to tactor ``i`` of the three, ``I_i = sqrt((1 / d_i) / sum_j (1 / d_j))``, so
``sum I_i^2 = 1``; a point on a tactor's centre lights that tactor alone at 1.

**Which three.** The point lies in a square of four tactor centres; the three nearest tactors of
the whole lattice are always three of those four (a tactor outside the square is never nearer
than its mirror image inside), the one left out being diagonally opposite the nearest. On the
square's centre lines two choices tie; the tie goes to the upper/right tactors, as the paper's
CT breaks ties. The method therefore switches tactors where the point crosses a centre line of
the square: a tactor at ``d = 1.12`` (an edge midpoint) or ``d = 0.71`` (the square's centre)
goes on or off there. Tactors outside the grid are dropped, as for AS, which leaves less than
full energy at the array's edge. Works on any coordinate, with or without a shape.
"""

from __future__ import annotations

import math

import numpy as np

from ..geometry import cell_split, cell_split1

NAME = "PK"
TITLE = "inverse distance, 3 tactors (Park 2016)"
BILEVEL = False
NEEDS_SHAPE = False
MAX_TACTORS = 3


def sample(shape, x, y, t, tol):
    """The three nearest tactors of the points ``(x, y)`` and their inverse-distance weights.

    Parameters
    ----------
    shape, t
        Unused: PK depends on the point only.
    x, y : ndarray of float64, shape (n,)
        Points in grid units.
    tol : float or ndarray
        Snap tolerance of the cell lookup.

    Returns
    -------
    list of (cols, rows, values)
        The four tactors of the square of centres around the point, the farthest at 0.
    """
    c, fx = cell_split(x - 0.5, tol)
    r, fy = cell_split(y - 0.5, tol)
    # The left-out corner: opposite the nearest; on a centre line, the lower/left one.
    drop_x = np.where(fx >= 0.5, 0.0, 1.0)
    drop_y = np.where(fy >= 0.5, 0.0, 1.0)
    on = (fx == 0.0) & (fy == 0.0)
    corners = ((0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0))
    weights = []
    for kx, ky in corners:
        d = np.hypot(fx - kx, fy - ky)
        keep = ~((drop_x == kx) & (drop_y == ky))
        weights.append(np.where(keep & ~on, 1.0 / np.where(d > 0.0, d, 1.0), 0.0))
    total = weights[0] + weights[1] + weights[2] + weights[3]
    total = np.where(on, 1.0, total)
    out = []
    for (kx, ky), w in zip(corners, weights):
        value = np.sqrt(w / total)
        if kx == 0.0 and ky == 0.0:
            value = np.where(on, 1.0, value)
        out.append((c + kx, r + ky, value))
    return out


def sample1(shape, x, y, t, tol):
    """Scalar :func:`sample`: ``(col, row, value)`` of the three lit tactors (one on a centre)."""
    c, fx = cell_split1(x - 0.5, tol)
    r, fy = cell_split1(y - 0.5, tol)
    if fx == 0.0 and fy == 0.0:
        return ((c, r, 1.0),)
    drop = (0 if fx >= 0.5 else 1, 0 if fy >= 0.5 else 1)
    kept = []
    for kx, ky in ((0, 0), (1, 0), (0, 1), (1, 1)):
        if (kx, ky) != drop:
            kept.append((kx, ky, 1.0 / math.hypot(fx - kx, fy - ky)))
    total = kept[0][2] + kept[1][2] + kept[2][2]
    return tuple((c + kx, r + ky, math.sqrt(w / total)) for kx, ky, w in kept)
