"""Shared machinery of the distance-weighted methods (RO, GS, VRCH): every tactor within a radius
of the point gets a weight that depends only on its distance ``d`` (in pitches) from the point.

Only the tactors that can lie within the radius are visited: the point sits in the square of
tactor centres ``[c + 0.5, c + 1.5) x [r + 0.5, r + 1.5)`` (``c = floor(x - 0.5)``), so a tactor
``k`` columns away is at least ``max(0, -k, k - 1)`` pitches away along x; columns (rows) whose
bound reaches the radius are skipped, and so are pairs of a column and a row whose bounds
together do (``bx^2 + by^2 > radius^2``). When the outermost columns on the two sides, ``-j``
and ``j + 1``, can never both be in reach (``radius - j < 0.5``), they share one slot: ``-j``
when the point is in the left half of its square (``fx < 0.5``), ``j + 1`` otherwise. With the
default radii that leaves a 2 x 2 block (RO, VRCH) or 8 candidates (GS), at most 4 (RO) or 6
(GS) of them nonzero.

**The batch path** (:func:`candidates`, :func:`squared_distances`) takes every candidate
column with every candidate row, computes squared distances per axis and decides "within the
radius" on ``dx^2 + dy^2`` (GS: on the product of per-axis Gaussians), which is faster than
``hypot`` on every candidate. A candidate whose deciding number lies within :data:`MARGIN`
(relative) of its edge is decided again exactly as ``hypot`` decides (:func:`settle`), so the
tactors lit are those of ``hypot(dx, dy) < radius`` to the last bit; the values differ from
``hypot``'s by rounding (1e-16). The scalar path (:func:`sample1`) visits only the pairs of
:attr:`Plan.pairs` and uses ``math.hypot``, as it always has.
"""

from __future__ import annotations

import functools
import math
from typing import NamedTuple

import numpy as np

from ..geometry import cell_split, cell_split1

MARGIN = 1e-9
"""Relative distance from a decision's edge within which the batch and exact scalar paths
decide as ``hypot`` does (rounding moves the fast numbers by ~1e-15)."""


def offsets(radius: float, strict: bool) -> tuple[int, ...]:
    """Column (row) offsets from ``floor(x - 0.5)`` that may hold a tactor within ``radius``."""
    reach = math.ceil(radius) + 1
    out = []
    for k in range(-reach, reach + 2):
        nearest = max(0, -k, k - 1)
        if nearest < radius or (not strict and nearest == radius):
            out.append(k)
    return tuple(out)


class Plan(NamedTuple):
    """The candidate tactors of one radius (see the module's docstring).

    Attributes
    ----------
    fixed : tuple of int
        Offsets every point has as candidates, per axis.
    far : int or None
        ``j`` when the offsets ``-j`` and ``j + 1`` share the last slot, else None.
    pairs : frozenset of (int, int)
        ``(column slot, row slot)`` pairs whose nearest possible distance is within the radius
        (slots: ``fixed`` in order, then the shared one); the scalar path visits only these.
    leading : int
        How many pairs, rows outer, the batch path computes: up to the last one in ``pairs``
        (the pairs after it, such as the two shared slots together, are never in reach).
    """

    fixed: tuple
    far: int | None
    pairs: frozenset
    leading: int


@functools.lru_cache(maxsize=64)
def plan(radius: float, strict: bool) -> Plan:
    """The candidates of ``radius`` (``strict``: within means ``d < radius``)."""
    ks = offsets(radius, strict)
    far = None
    if len(ks) >= 4 and ks[0] == -(ks[-1] - 1) and radius - (ks[-1] - 1) < 0.5:
        far, ks = ks[-1] - 1, ks[1:-1]
    nearest = [max(0, -k, k - 1) for k in ks] + ([far] if far is not None else [])
    pairs = frozenset((i, j) for j, ny in enumerate(nearest) for i, nx in enumerate(nearest)
                      if nx * nx + ny * ny <= radius * radius)  # fmt: skip
    leading = 1 + max(j * len(nearest) + i for i, j in pairs)
    return Plan(ks, far, pairs, leading)


@functools.lru_cache(maxsize=64)
def _fixed_column(fixed: tuple) -> np.ndarray:
    column = np.array(fixed, dtype=np.float64)[:, None]
    column.flags.writeable = False
    return column


def candidates(xy, tol, radius: float, strict: bool):
    """The candidate tactors of points ``xy`` (``(2, n)``): every pair of a candidate column
    and row (a superset of :attr:`Plan.pairs`: the others lie beyond the radius).

    Returns
    -------
    cells : ndarray of float64, shape (2, a, n)
        Candidate columns (``cells[0]``) and rows (``cells[1]``).
    offsets : ndarray of float64, shape (2, a, n)
        The point's offset from each candidate column's (row's) tactor, in pitches: ``dx``
        and ``dy``.
    """
    p = plan(radius, strict)
    base, f = cell_split(xy - 0.5, tol)
    fixed = _fixed_column(p.fixed)
    if p.far is None:
        off = fixed
    else:
        off = np.empty((2, len(p.fixed) + 1, f.shape[1]))
        off[:, :-1] = fixed
        off[:, -1] = p.far + 1.0
        np.copyto(off[:, -1], -float(p.far), where=f < 0.5)
    return base[:, None, :] + off, f[:, None, :] - off


def squared_distances(offsets):
    """``(a, a, n)``: ``dx^2 + dy^2`` of every candidate, rows outer."""
    sq = np.square(offsets)
    return sq[1][:, None, :] + sq[0][None, :, :]


def unsettled(key, lo: float, hi: float, below_hi=None):
    """Flat indices of the candidates whose ``key`` lies in ``[lo, hi)`` (within
    :data:`MARGIN` of a decision's edge), or None when there are none (the common case, found
    by counting). ``below_hi``: ``key < hi`` if the caller has it."""
    if below_hi is None:
        below_hi = key < hi
    below_lo = key < lo
    if np.count_nonzero(below_lo) == np.count_nonzero(below_hi):
        return None
    return np.flatnonzero(below_hi ^ below_lo)  # (key < lo implies key < hi)


def settle(values, key, lo: float, hi: float, exact) -> None:
    """Decide again, in place, the candidates whose ``key`` lies in ``[lo, hi)``: their values
    become ``exact(flat indices)``."""
    found = unsettled(key, lo, hi)
    if found is not None:
        values.reshape(-1)[found] = exact(found)


def exact(offsets, radius: float, strict: bool, weight):
    """``exact(found)`` for :func:`settle`: the weights of candidates at flat indices ``found``
    of an ``(a, a, n)`` array as the methods define them, ``weight(hypot(dx, dy))`` within the
    radius and 0 beyond."""

    dx, dy = offsets

    def values(found):
        row, col, point = np.unravel_index(found, (len(dy), *dx.shape))
        d = np.hypot(dx[col, point], dy[row, point])
        inside = d < radius if strict else d <= radius
        return np.where(inside, weight(np.where(inside, d, 0.0)), 0.0)

    return values


@functools.lru_cache(maxsize=256)
def _pairs1(radius: float, strict: bool, left: bool, low: bool) -> tuple:
    """The scalar path's candidates: ``(column offset, row offset)`` of the pairs of
    :attr:`Plan.pairs`, in ascending column, then row, the shared slots on the point's side
    (``left``: ``fx < 0.5``; ``low``: ``fy < 0.5``)."""
    p = plan(radius, strict)

    def axis(first: bool) -> list:
        slots = list(enumerate(p.fixed))
        if p.far is not None:
            slots.append((len(p.fixed), -p.far if first else p.far + 1))
        return sorted(slots, key=lambda slot: slot[1])

    return tuple((dc, dr) for i, dc in axis(left) for j, dr in axis(low) if (i, j) in p.pairs)


def sample1(x, y, tol, radius: float, strict: bool, weight1, guard: bool = False):
    """Scalar sampler: ``(col, row, value)`` of the tactors with a nonzero weight, in
    ascending column, then row.

    With ``guard``, None when a candidate's distance lies within :data:`MARGIN` of the radius
    (where ``math.hypot`` and numpy's ``hypot`` may decide differently).
    """
    c, fx = cell_split1(x - 0.5, tol)
    r, fy = cell_split1(y - 0.5, tol)
    edge = MARGIN * radius
    hypot = math.hypot
    out = []
    for dc, dr in _pairs1(radius, strict, fx < 0.5, fy < 0.5):
        d = hypot(fx - dc, fy - dr)
        if guard and abs(d - radius) <= edge:
            return None
        if d < radius or (not strict and d == radius):
            value = weight1(d)
            if value > 0.0:
                out.append((c + dc, r + dr, value))
    return tuple(out)


@functools.lru_cache(maxsize=64)
def max_within(radius: float, strict: bool) -> int:
    """Most lattice points within ``radius`` of any point (the most tactors one frame lights).

    Searched over the points of a 64 x 64 grid of one cell of tactor centres, its edges and
    corners included (the counts change only on circles through lattice points, and the
    maxima sit at the grid's symmetric points: the centre, edge midpoints and corners).
    """
    ks = offsets(radius, strict)
    best = 0
    for i in range(65):
        fx = i / 64
        for j in range(65):
            fy = j / 64
            n = 0
            for dc in ks:
                for dr in ks:
                    d = math.hypot(fx - dc, fy - dr)
                    n += d < radius or (not strict and d == radius)
            best = max(best, n)
    return best
