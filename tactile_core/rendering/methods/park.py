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

**The jump, and a continuous variant.** The switch is a jump in intensity: crossing ``x = 2.0``
at ``y = 3.1`` tactor (1,2) goes from 0 to 0.54 (0.77 after the paper's correction) within
1e-5 pitches; the largest jump, at the square's centre, is ``sqrt(1/3) = 0.58``. ``PK:blend=w``
crossfades the left-out tactor over a band ``w`` pitches wide across each centre line: the
four choices of three tactors are mixed in energy, ``I_i^2 = sum_k p_k I_i,k^2`` with weights
``p_k`` that ramp linearly across the band, so ``sum I^2 = 1`` still holds and the intensities
are continuous (four tactors are lit inside the band). ``blend = 0`` (the default) is Park's
rule with its jump. :func:`tactile_core.rendering.percept.largest_jump` measures both.

PK is driven as computed (``CORRECTION = "none"``): the energy law is its correction.
"""

from __future__ import annotations

import math

import numpy as np

from ..geometry import cell_split, cell_split1

NAME = "PK"
TITLE = "inverse distance, 3 tactors (Park 2016)"
BILEVEL = False
NEEDS_SHAPE = False
PARAMS = {
    "blend": (0.0, 0.0, 0.5, "band in pitches across each centre line over which the left-out "
              "tactor is crossfaded (0: Park's switch, a jump)"),
}  # fmt: skip
CORRECTION = "none"
_CORNERS = ((0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0))


def MAX_TACTORS(blend=0.0):
    """Most tactors lit at once: 3, or 4 with a crossfade band (``blend > 0``)."""
    return 3 if blend == 0 else 4


def _ramp(f, blend):
    """Share of the choices that leave out the lower/left corner: 0 below the centre line,
    1 above it, linear across a band ``blend`` wide (a step at ``blend = 0``)."""
    return np.clip((f - 0.5) / blend + 0.5, 0.0, 1.0)


def _ramp1(f, blend):
    return min(max((f - 0.5) / blend + 0.5, 0.0), 1.0)


def _blended(inv, px, py):
    """Energy shares of the four corners, mixing the four choices of three.

    ``inv``: the corners' inverse distances (in :data:`_CORNERS` order); ``px``/``py``: the
    probability that the left-out corner is the one at x = 0 / y = 0. Works on floats and on
    arrays alike (the same operations in the same order, so live and batch agree)."""
    qx, qy = 1.0 - px, 1.0 - py
    total = inv[0] + inv[1] + inv[2] + inv[3]
    # Choice k leaves out corner k: its weight, and the sum over the other three.
    share = (px * py / (total - inv[0]), qx * py / (total - inv[1]),
             px * qy / (total - inv[2]), qx * qy / (total - inv[3]))  # fmt: skip
    everything = share[0] + share[1] + share[2] + share[3]
    return [inv[k] * (everything - share[k]) for k in range(4)]


def sample(shape, x, y, t, tol, blend=0.0):
    """The three nearest tactors of the points ``(x, y)`` and their inverse-distance weights.

    Parameters
    ----------
    shape, t
        Unused: PK depends on the point only.
    x, y : ndarray of float64, shape (n,)
        Points in grid units.
    tol : float or ndarray
        Snap tolerance of the cell lookup.

    blend : float
        Width of the crossfade band in pitches (0: Park's switch).

    Returns
    -------
    list of (cols, rows, values)
        The four tactors of the square of centres around the point, the farthest at 0 (outside
        a crossfade band).
    """
    c, fx = cell_split(x - 0.5, tol)
    r, fy = cell_split(y - 0.5, tol)
    if blend > 0.0:
        on = (fx == 0.0) & (fy == 0.0)
        inv = [1.0 / np.where(on, 1.0, np.hypot(fx - kx, fy - ky)) for kx, ky in _CORNERS]
        energy = _blended(inv, _ramp(fx, blend), _ramp(fy, blend))
        out = []
        for k, (kx, ky) in enumerate(_CORNERS):
            value = np.sqrt(np.where(on, 1.0 if k == 0 else 0.0, energy[k]))
            out.append((c + kx, r + ky, value))
        return out
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


def sample1(shape, x, y, t, tol, blend=0.0):
    """Scalar :func:`sample`: ``(col, row, value)`` of the three lit tactors (one on a centre;
    up to four inside a crossfade band)."""
    c, fx = cell_split1(x - 0.5, tol)
    r, fy = cell_split1(y - 0.5, tol)
    if fx == 0.0 and fy == 0.0:
        return ((c, r, 1.0),)
    if blend > 0.0:
        inv = [1.0 / math.hypot(fx - kx, fy - ky) for kx, ky in _CORNERS]
        energy = _blended(inv, _ramp1(fx, blend), _ramp1(fy, blend))
        return tuple((c + int(kx), r + int(ky), math.sqrt(e))
                     for (kx, ky), e in zip(_CORNERS, energy) if e > 0.0)  # fmt: skip
    drop = (0 if fx >= 0.5 else 1, 0 if fy >= 0.5 else 1)
    kept = []
    for kx, ky in ((0, 0), (1, 0), (0, 1), (1, 1)):
        if (kx, ky) != drop:
            kept.append((kx, ky, 1.0 / math.hypot(fx - kx, fy - ky)))
    total = kept[0][2] + kept[1][2] + kept[2][2]
    return tuple((c + kx, r + ky, math.sqrt(w / total)) for kx, ky, w in kept)
