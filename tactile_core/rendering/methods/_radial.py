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

**The batch path** (:func:`block`, :func:`squared_distances`) takes every candidate column
with every candidate row: consecutive columns (the shared slot on the point's side), so they
make a block of cells the renderer scatters from the block's first cell
(:class:`~._cells.Block`; GS's 3 x 3 block holds the pair of shared slots too, beyond the
radius). It computes squared distances per axis and decides "within the radius" on
``dx^2 + dy^2`` (GS: on the product of per-axis Gaussians), which is faster than ``hypot`` on
every candidate. A candidate whose deciding number lies within :data:`MARGIN` (relative) of its
edge is decided again exactly as ``hypot`` decides (:func:`settle`), so the tactors lit are
those of ``hypot(dx, dy) < radius`` to the last bit; the values differ from ``hypot``'s by
rounding (1e-16). The scalar path (:func:`sample1`) visits only the pairs of
:attr:`Plan.pairs` and uses ``math.hypot``, as it always has.
"""

from __future__ import annotations

import functools
import math
from typing import NamedTuple

import numpy as np

from ..geometry import cell_split, cell_split1
from ._cells import outer

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
        How many pairs, rows outer, in the plan's order (fixed slots, then the shared one) are
        needed: up to the last one in ``pairs`` (the pairs after it, such as the two shared
        slots together, are never in reach).
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
def _block_offsets(radius: float, strict: bool) -> np.ndarray:
    """The block's columns' offsets from ``floor(x - 0.5)``, as a column (``(width, 1)``):
    the plan's, with the shared slot first (its side for ``fx < 0.5``)."""
    p = plan(radius, strict)
    first = p.fixed[0] if p.far is None else -p.far
    width = len(p.fixed) + (p.far is not None)
    column = np.arange(first, first + width, dtype=np.float64)[:, None]
    column.flags.writeable = False
    return column


class Split(NamedTuple):
    """Points placed in their blocks of candidate cells (:func:`block`).

    Attributes
    ----------
    origin : ndarray of float64, shape (2, n)
        The block's first column (``origin[0]``) and row.
    f : ndarray of float64, shape (2, n)
        The point's offset from the block's first cell's tactor, less the plan's first offset:
        the offset from column ``j`` of the block is ``f - column[j]``.
    column : ndarray of float64, shape (width, 1)
        The offsets of the block's columns (rows) that ``f`` is measured against.
    """

    origin: np.ndarray
    f: np.ndarray
    column: np.ndarray

    @property
    def width(self) -> int:
        """Columns (rows) in the block."""
        return len(self.column)

    def offsets(self) -> np.ndarray:
        """``(2, width, n)``: the point's offset from each of the block's columns' (rows')
        tactors, in pitches: ``dx`` and ``dy``, computed as ``fx - k`` for the column
        ``floor(x - 0.5) + k``."""
        return self.f[:, None, :] - self.column

    def squares(self) -> np.ndarray:
        """``(2, width, n)``: the squares of :meth:`offsets` (computed in place)."""
        out = self.offsets()
        return np.square(out, out=out)


def block(xy, tol, radius: float, strict: bool) -> Split:
    """The candidate tactors of points ``xy`` (``(2, n)``) as a block: every column of the
    plan with every row (a superset of :attr:`Plan.pairs`: the others lie beyond the radius),
    the shared slot (``Plan.far``) on the point's side, so the columns are consecutive."""
    p = plan(radius, strict)
    column = _block_offsets(radius, strict)
    base, f = cell_split(xy - 0.5, tol)
    if p.far is None:
        if p.fixed[0] != 0:
            base += p.fixed[0]
        return Split(base, f, column)
    right = f >= 0.5  # the shared slot is the block's last column, not its first
    base += right
    base -= p.far
    f -= right  # exact (f >= 0.5 there); then f - k is computed as the plan's fx - (k + 1)
    return Split(base, f, column)


def squared_distances(squares):
    """``(width * width, n)``: ``dx^2 + dy^2`` of every candidate, rows outer, from
    :meth:`Split.squares`."""
    a, n = squares.shape[1:]
    return outer(np.add, squares[1], squares[0], np.empty((a * a, n)))


def unsettled(key, lo: float, hi: float, below_hi=None, below_lo=None):
    """Flat indices of the candidates whose ``key`` lies in ``[lo, hi)`` (within
    :data:`MARGIN` of a decision's edge), or None when there are none (the common case, found
    by counting). ``below_hi``, ``below_lo``: ``key < hi``, ``key < lo`` if the caller has
    them."""
    if below_hi is None:
        below_hi = key < hi
    if below_lo is None:
        below_lo = key < lo
    if np.count_nonzero(below_lo) == np.count_nonzero(below_hi):
        return None
    return np.flatnonzero(below_hi ^ below_lo)  # (key < lo implies key < hi)


def settle(values, found, split: Split, radius: float, strict: bool, weight, weight1=None):
    """Decide again, in place, the candidates at flat indices ``found`` (within
    :data:`MARGIN` of the edge) as the methods define them: ``weight`` (of an array; ``weight1``
    of a float, the same operations) of ``hypot(dx, dy)`` within the radius, 0 beyond.

    A few candidates (a shape through tactor centres puts neighbours at exactly the radius)
    are decided one by one with ``weight1`` where the method has one: numpy's ``hypot`` of two
    floats is the array's, and ``weight1`` takes the same float operations as ``weight``.
    """
    flat = values.reshape(-1)
    if weight1 is None or len(found) > 16:
        flat[found] = exact(split.offsets(), radius, strict, weight)(found)
        return
    f = split.f
    n = f.shape[1]
    ks = split.column[:, 0].tolist()
    a = len(ks)
    hypot = np.hypot
    for k in found.tolist():
        slot, point = divmod(k, n)
        row, col = divmod(slot, a)
        dx, dy = f.item(0, point) - ks[col], f.item(1, point) - ks[row]  # (Python floats)
        # hypot(x, 0) is |x| exactly (C99 F.10.4.3): the common case, a shape through tactor
        # centres putting a neighbour at exactly the radius
        d = abs(dx) if dy == 0.0 else abs(dy) if dx == 0.0 else float(hypot(dx, dy))
        flat[k] = weight1(d) if (d < radius if strict else d <= radius) else 0.0


def exact(offsets, radius: float, strict: bool, weight):
    """``exact(found)`` for :func:`settle`: the weights of candidates at flat indices ``found``
    of a ``(width * width, n)`` array as the methods define them, ``weight(hypot(dx, dy))``
    within the radius and 0 beyond."""

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
