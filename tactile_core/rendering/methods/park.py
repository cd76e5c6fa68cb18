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

**The jumps, and a continuous variant.** Each switch is a jump in intensity. Crossing a centre
line of the square (a cell boundary) the left-out corner changes: at ``x = 2.0``, ``y = 3.1``
tactor (1,2) goes from 0.54 to 0 and (2,2) from 0 to 0.54 (0.77 after the paper's correction)
within 1e-5 pitches, up to ``sqrt(1/3) = 0.58`` at the square's centre. Crossing a line of
tactor centres the square itself changes, and the third tactor moves from the column (row)
behind to the one ahead: up to 0.43, midway between two tactors. ``PK:blend=w`` crossfades
both over bands ``w`` pitches wide: per axis, the nearest tactor's column and its neighbour on
the point's side are chosen with probabilities that ramp linearly across each band, and the
three-tactor energies of the choices are mixed, ``I_i^2 = sum_k p_k I_i,k^2``, so
``sum I^2 = 1`` still holds and every intensity is continuous (up to six tactors are lit where
bands cross). ``blend = 0`` (the default) is Park's rule with its jumps;
:func:`tactile_core.rendering.jumps.largest_jump` measures both.

PK is driven as computed (``CORRECTION = "none"``): the energy law is its correction.
"""

from __future__ import annotations

import math

import numpy as np

from ..geometry import cell_split, cell_split1
from ._cells import Block, Cells, outer, stack_points

NAME = "PK"
TITLE = "inverse distance, 3 tactors (Park 2016)"
BILEVEL = False
NEEDS_SHAPE = False
PARAMS = {
    "blend": (0.0, 0.0, 0.5, "band in pitches across each centre line over which the left-out "
              "tactor is crossfaded (0: Park's switch, a jump)"),
}  # fmt: skip
CORRECTION = "none"


def MAX_TACTORS(blend=0.0):
    """Most tactors lit at once: 3, or 6 inside crossfade bands (``blend > 0``)."""
    return 3 if blend == 0 else 6


# Per axis, Park's three tactors use the nearest tactor's column ``a`` (offset 0 or 1 from the
# column c = floor(x - 0.5) left of the point) and the column ``b`` next to it on the point's
# side (offset -1..2): the triple is (a_x, a_y), (b_x, a_y), (a_x, b_y). Each (a, b) choice
# below is (a offset, b offset, which ramp it takes).
_AXIS = ((0, 1), (0, -1), (1, 0), (1, 2))


def _axis_shares(f, blend, clip):
    """Probabilities of the four ``(a, b)`` choices of one axis, ``f`` the point's fraction in
    [0, 1) past column c: ``a = c + 1`` ramps in across ``f = 0.5`` (the cell boundary), and
    given ``a``, ``b = a + 1`` ramps in across ``f = a - c`` (the tactor's own centre line)."""
    p_right = clip((f - 0.5) / blend + 0.5, 0.0, 1.0)
    p_left = 1.0 - p_right
    b_up0 = clip(f / blend + 0.5, 0.0, 1.0)
    b_up1 = clip((f - 1.0) / blend + 0.5, 0.0, 1.0)
    return (p_left * b_up0, p_left * (1.0 - b_up0), p_right * (1.0 - b_up1), p_right * b_up1)


def _blended(fx, fy, blend, clip, hypot):
    """``{(dc, dr): energy}`` of the tactors around the point (offsets from ``c``, ``r``),
    the three-tactor energies of every choice mixed by its probability. Works on floats (with
    ``math``'s functions) and on arrays (numpy's) with the same operations in the same order,
    so the live path equals the batch path."""
    sx, sy = _axis_shares(fx, blend, clip), _axis_shares(fy, blend, clip)
    energy = {}
    for (ax, bx), px in zip(_AXIS, sx):
        for (ay, by), py in zip(_AXIS, sy):
            cells = ((ax, ay), (bx, ay), (ax, by))
            inv = [1.0 / hypot(fx - cx, fy - cy) for cx, cy in cells]
            share = px * py / (inv[0] + inv[1] + inv[2])
            for cell, w in zip(cells, inv):
                energy[cell] = energy.get(cell, 0.0) + share * w
    return energy


def _clip1(v, lo, hi):
    return min(max(v, lo), hi)


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
    return sample_cells(shape, stack_points(x, y), t, tol, blend).entries()


def sample_cells(shape, xy, t, tol, blend=0.0):
    """:func:`sample` in the renderer's batch form, for the points ``xy`` (``(2, n)``): per
    axis the nearest corner of the square of centres around each point and the other one, and
    of their pairs the first three, rows outer: (nearest, nearest), (other, nearest) and
    (nearest, other), which leaves out the corner opposite the nearest (a flipped 2 x 2
    :class:`~._cells.Block`; with ``blend``: every tactor a crossfade may light, as
    :class:`~._cells.Cells`). Distances are ``sqrt(dx^2 + dy^2)``."""
    cr, f = cell_split(xy - 0.5, tol)
    if blend > 0.0:
        return _blended_cells(cr[0], cr[1], f[0], f[1], blend)
    n = f.shape[1]
    # Offsets of the nearest corner (1 from the centre line on: a tie goes upper/right) and
    # of the other one.
    near_other = np.empty((2, 2, n))
    near = near_other[:, 0]
    np.multiply(f, 2.0, out=near)
    np.floor(near, out=near)
    np.subtract(1.0, near, out=near_other[:, 1])
    sq = np.subtract(f[:, None, :], near_other)
    np.square(sq, out=sq)
    d = outer(np.add, sq[1], sq[0], np.empty((3, n)))
    np.sqrt(d, out=d)
    on = not d[0].all()  # a point on a tactor's centre (only there is a distance 0)
    if on:
        np.maximum(d[0], 1e-300, out=d[0])
    w = np.divide(1.0, d, out=d)
    total = w[0] + w[1]
    total += w[2]
    w /= total
    values = np.sqrt(w, out=w)
    if on:  # there the centre's tactor is at 1 (1e300 / (1e300 + 2)), the others ~1e-150: off
        # (elsewhere none is below ~1e-7: a point within the snap tolerance of a centre is on it)
        np.putmask(values, values < 1e-100, 0.0)
    cr *= 2.0
    cr += near  # the block's first cell per axis, flagged where it is the upper one
    return Block(cr, values, 2, 2, flip=True)


def _blended_cells(c, r, fx, fy, blend):
    on = (fx == 0.0) & (fy == 0.0)
    gx, gy = np.where(on, 0.5, fx), np.where(on, 0.5, fy)  # (finite, discarded)
    energy = _blended(gx, gy, blend, np.clip, np.hypot)
    keys = list(energy)
    values = np.stack([np.sqrt(np.where(on, float(dc == 0 and dr == 0), energy[dc, dr]))
                       for dc, dr in keys])  # fmt: skip
    col_index = np.array([dc + 1 for dc, _ in keys], dtype=np.intp)
    row_index = np.array([dr + 1 for _, dr in keys], dtype=np.intp)
    offsets = np.array([[-1.0], [0.0], [1.0], [2.0]])
    return Cells(c + offsets, r + offsets, values, (col_index, row_index))


def sample1(shape, x, y, t, tol, blend=0.0):
    """Scalar :func:`sample`: ``(col, row, value)`` of the three lit tactors (one on a centre;
    up to four inside a crossfade band)."""
    c, fx = cell_split1(x - 0.5, tol)
    r, fy = cell_split1(y - 0.5, tol)
    if fx == 0.0 and fy == 0.0:
        return ((c, r, 1.0),)
    if blend > 0.0:
        energy = _blended(fx, fy, blend, _clip1, math.hypot)
        return tuple((c + dc, r + dr, math.sqrt(e)) for (dc, dr), e in energy.items() if e > 0.0)
    drop = (0 if fx >= 0.5 else 1, 0 if fy >= 0.5 else 1)
    kept = []
    for kx, ky in ((0, 0), (1, 0), (0, 1), (1, 1)):
        if (kx, ky) != drop:
            kept.append((kx, ky, 1.0 / math.hypot(fx - kx, fy - ky)))
    total = kept[0][2] + kept[1][2] + kept[2][2]
    return tuple((c + kx, r + ky, math.sqrt(w / total)) for kx, ky, w in kept)
