"""Strokes: the pieces of a shape along which one axis is the major axis (paper section 2.3).

The midpoint methods (MM, IM) walk a shape stroke by stroke. :class:`Strokes` holds them as one
table for the vectorised path and as tuples for the scalar (live) one; :class:`LineStrokes` are
straight (a line, a polyline's straight runs) and :class:`ArcStrokes` are a circle's four
90-degree arcs. :class:`Run` is one stroke as the trace passes along it.
"""

from __future__ import annotations

import bisect
import math
from dataclasses import dataclass

import numpy as np

from ..geometry import Pieces, cell_floor, clamp

TWO_PI = 2.0 * math.pi


@dataclass(frozen=True)
class Run:
    """One stroke as the trace passes along it, in trace order.

    Attributes
    ----------
    stroke : int
        Row of the strokes' table.
    axis : int
        Major axis: 0 for x, 1 for y.
    t_in, t_out : float
        Trace parameters where the point enters and leaves the stroke, ``t_in < t_out``. For a
        stroke of a closed shape that the trace passes at its start and end (a circle's right
        arc, a square's right edge), ``t_in < 0`` or ``t_out > 1``: the parameter wraps.
    u_in, u_out : float
        Major-axis coordinates where the point enters and leaves the stroke.
    """

    stroke: int
    axis: int
    t_in: float
    t_out: float
    u_in: float
    u_out: float
    arc: tuple | None = None  # (centre u, radius, which arc) for circle arcs

    def t_at(self, u: float) -> float:
        """Trace parameter at which the point is at major coordinate ``u`` on this stroke."""
        if self.arc is None:
            span = self.u_out - self.u_in
            if span == 0.0:
                return self.t_in
            return self.t_in + (u - self.u_in) / span * (self.t_out - self.t_in)
        centre, r, which = self.arc
        q = min(max((u - centre) / r, -1.0), 1.0) if r > 0.0 else 0.0
        if which == 0:  # right arc: y = cy + r sin(2 pi t), t in [-1/8, 1/8]
            return math.asin(q) / TWO_PI
        if which == 1:  # top: x = cx + r cos(2 pi t), t in [1/8, 3/8]
            return math.acos(q) / TWO_PI
        if which == 2:  # left: t in [3/8, 5/8]
            return 0.5 - math.asin(q) / TWO_PI
        return 1.0 - math.acos(q) / TWO_PI  # bottom: t in [5/8, 7/8]


class Strokes:
    """The pieces of a shape along which the midpoint methods work.

    Each stroke is one row of ``table`` (shape ``(m, 9)``), with columns

    ======  ===========  ==========================================================
    column  name         meaning
    ======  ===========  ==========================================================
    0       ``axis``     major axis: 0 for x (one tactor per column), 1 for y
    1, 2    ``lo, hi``   extent along the major axis, ``lo <= hi``
    3, 4    ``first``,   major-axis cells of ``lo`` and ``hi``
            ``last``
    5..8    ``a..d``     coefficients of the minor coordinate (see the subclasses)
    ======  ===========  ==========================================================

    :meth:`gather` returns the rows of the strokes that given points lie on, transposed so
    that ``params[j]`` is column ``j`` for every point (or a plain number for a shape made of a
    single stroke). ``rows1`` holds each row as a tuple of Python numbers for the scalar path.
    ``tol`` is the shape's snap tolerance.
    """

    AXIS, LO, HI, FIRST, LAST, A, B, C, D = range(9)

    def _build(self, axis, lo, hi, a, b, c, d, tol):
        self.tol = tol
        lo = np.asarray(lo, dtype=np.float64)
        hi = np.asarray(hi, dtype=np.float64)
        first = cell_floor(lo, tol)
        last = cell_floor(hi, tol)
        self.table = np.column_stack([axis, lo, hi, first, last, a, b, c, d]).astype(np.float64)
        self.count = len(self.table)
        self._table_t = np.ascontiguousarray(self.table.T)
        self.rows1 = [
            (int(r[0]), r[1], r[2], int(r[3]), int(r[4]), r[5], r[6], r[7], r[8])
            for r in self.table.tolist()
        ]

    def runs(self) -> list[Run]:
        """The strokes as the trace passes them, in trace order (see :class:`Run`)."""
        raise NotImplementedError

    def locate(self, t: np.ndarray) -> np.ndarray | None:
        """Stroke index (int array, shape of ``t``) of the point at each parameter ``t``.

        None when the shape has a single stroke.
        """
        raise NotImplementedError

    def gather(self, ids, count: int = 9):
        """Stroke parameters per point: a ``(count, n)`` array of the first ``count`` (all 9 by
        default), or the row's numbers if ``ids`` is None (a single stroke)."""
        return self.rows1[0] if ids is None else self._table_t[:count].take(ids, axis=1)

    def minor(self, params, u):
        """Minor-axis coordinate at major-axis coordinate ``u`` on the gathered strokes."""
        raise NotImplementedError

    def locate1(self, t: float) -> int:
        """Scalar :meth:`locate` (always an index)."""
        raise NotImplementedError

    def minor1(self, row: tuple, u: float) -> float:
        """Scalar :meth:`minor` for one row of ``rows1``."""
        raise NotImplementedError


class LineStrokes(Strokes):
    """Straight strokes: ``ends[i] = (x0, y0, x1, y1)``; ``breaks`` split ``t`` into pieces.

    ``breaks`` (shape ``(p + 1,)``, from 0 to 1) delimit the parameter range of each piece of
    the trace and ``piece_stroke[j]`` is the stroke that piece ``j`` belongs to. A point exactly
    at a break belongs to the later piece. On a stroke the minor coordinate is the linear
    interpolation ``(1 - s) v0 + s v1`` with ``s = (u - u0) / (u1 - u0)``, exact at both ends;
    coefficients ``a..d`` are ``u0, v0, v1, u1 - u0`` (the divisor is 1 for a zero-length
    stroke, whose ``u`` is always ``u0``).
    """

    def __init__(self, ends, breaks, piece_stroke, tol, closed=False):
        self.closed = closed
        ends = np.asarray(ends, dtype=np.float64).reshape(-1, 4)
        dx = ends[:, 2] - ends[:, 0]
        dy = ends[:, 3] - ends[:, 1]
        # |slope| = 1 is x-major (contract); a zero-length stroke is x-major too.
        axis = np.where(np.abs(dx) >= np.abs(dy), 0, 1)
        xmajor = axis == 0
        u0 = np.where(xmajor, ends[:, 0], ends[:, 1])
        v0 = np.where(xmajor, ends[:, 1], ends[:, 0])
        u1 = np.where(xmajor, ends[:, 2], ends[:, 3])
        v1 = np.where(xmajor, ends[:, 3], ends[:, 2])
        swap = u1 < u0
        self._trace_u = np.column_stack([u0, u1]).tolist()  # entry and exit, in trace order
        u0, v0, u1, v1 = (
            np.where(swap, u1, u0),
            np.where(swap, v1, v0),
            np.where(swap, u0, u1),
            np.where(swap, v0, v1),
        )
        span = u1 - u0
        self._build(axis, u0, u1, u0, v0, v1, np.where(span > 0, span, 1.0), tol)
        self.breaks = np.asarray(breaks, dtype=np.float64)
        self.piece_stroke = np.asarray(piece_stroke, dtype=np.intp)
        self._breaks = self.breaks.tolist()
        self._piece_stroke = self.piece_stroke.tolist()
        self._pieces = Pieces(self.breaks, len(self.piece_stroke) - 1)

    def runs(self):
        breaks, stroke_of = self._breaks, self._piece_stroke
        groups = []  # [stroke, t_in, t_out] of consecutive pieces on one stroke
        for j, s in enumerate(stroke_of):
            if groups and groups[-1][0] == s:
                groups[-1][2] = breaks[j + 1]
            else:
                groups.append([s, breaks[j], breaks[j + 1]])
        if self.closed and len(groups) > 1 and groups[0][0] == groups[-1][0]:
            first = groups.pop(0)  # the trace starts inside this stroke: one run, wrapping
            groups[-1][2] = first[2] + 1.0
        return [
            Run(s, int(self.table[s, 0]), t_in, t_out, *self._trace_u[s])
            for s, t_in, t_out in groups
        ]

    def locate(self, t):
        if self.count == 1:
            return None
        return self.piece_stroke.take(self._pieces.of(t))

    def minor(self, params, u):
        s = (u - params[5]) / params[8]
        return (1.0 - s) * params[6] + s * params[7]

    def locate1(self, t):
        if self.count == 1:
            return 0
        piece = bisect.bisect_right(self._breaks, t) - 1
        return self._piece_stroke[min(max(piece, 0), len(self._piece_stroke) - 1)]

    def minor1(self, row, u):
        s = (u - row[5]) / row[8]
        return (1.0 - s) * row[6] + s * row[7]


def _reciprocal(r: float) -> float:
    """``1 / r``, or 0 where it is infinite (r = 0, or a subnormal r such as 5e-324): such a
    circle is its centre to within float resolution."""
    inverse = 1.0 / r if r > 0.0 else 0.0
    return inverse if math.isfinite(inverse) else 0.0


class ArcStrokes(Strokes):
    """The four 90-degree arcs of a circle: right, top, left, bottom (strokes 0..3).

    The top and bottom arcs (``1/8 <= t <= 3/8`` and ``5/8 <= t <= 7/8``, so the 45-degree
    points included) are x-major, the left and right arcs y-major. On a stroke the minor
    coordinate at major coordinate ``u`` is ``c_v +- r sqrt((1 - q)(1 + q))`` with
    ``q = (u - c_u) / r`` clipped to [-1, 1]: that scaled form neither overflows for huge radii
    nor loses the result for tiny ones. Coefficients ``a..d`` are ``c_u, c_v, +-r, 1 / r`` (0
    when ``1 / r`` is infinite, where every point is the centre).
    """

    # Arc of each octant floor(8 t) = 0..8; the boundaries 8t = 3 and 7 are patched in locate.
    _OCTANT_ARC = np.array([0, 1, 1, 2, 2, 3, 3, 0, 0], dtype=np.intp)

    def __init__(self, cx, cy, r, point, tol):
        # Extents from the same point formula as the trace, so they agree to the last bit.
        x45, y45 = point(1 / 8)
        x135, _ = point(3 / 8)
        _, y315 = point(7 / 8)
        xlo, xhi = min(x45, x135), max(x45, x135)
        ylo, yhi = min(y45, y315), max(y45, y315)
        self._runs = [
            Run(0, 1, -0.125, 0.125, ylo, yhi, (cy, r, 0)),
            Run(1, 0, 0.125, 0.375, xhi, xlo, (cx, r, 1)),
            Run(2, 1, 0.375, 0.625, yhi, ylo, (cy, r, 2)),
            Run(3, 0, 0.625, 0.875, xlo, xhi, (cx, r, 3)),
        ]
        self._build(
            axis=[1, 0, 1, 0],
            lo=[ylo, xlo, ylo, xlo],
            hi=[yhi, xhi, yhi, xhi],
            a=[cy, cx, cy, cx],
            b=[cx, cy, cx, cy],
            c=[r, r, -r, -r],
            d=[_reciprocal(r)] * 4,
            tol=tol,
        )

    def runs(self):
        return list(self._runs)

    def locate(self, t):
        q = 8.0 * t
        ids = self._OCTANT_ARC[q.astype(np.intp)]
        ids[q == 3.0] = 1  # 135 degrees: |slope| = 1 is x-major (top)
        ids[q == 7.0] = 3  # 315 degrees (bottom)
        return ids

    def minor(self, params, u):
        q = clamp((u - params[5]) * params[8], -1.0, 1.0)
        return params[6] + params[7] * np.sqrt((1.0 - q) * (1.0 + q))

    def locate1(self, t):
        q = 8.0 * t
        if 1.0 <= q <= 3.0:
            return 1
        if 3.0 < q < 5.0:
            return 2
        if 5.0 <= q <= 7.0:
            return 3
        return 0

    def minor1(self, row, u):
        q = min(max((u - row[5]) * row[8], -1.0), 1.0)
        return row[6] + row[7] * math.sqrt((1.0 - q) * (1.0 + q))
