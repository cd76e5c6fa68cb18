"""Shapes traced by the moving point: parametric curves ``f(t)`` for ``t`` in [0, 1].

The contract fixes the parameterisations:

=====================  ===============================================================
``Line(p0, p1)``       ``p0 + (p1 - p0) t``
``Circle(c, r)``       ``(cx + r cos 2 pi t, cy + r sin 2 pi t)``: counter-clockwise from
                       the rightmost point
``Square(c, edge)``    counter-clockwise from the midpoint of its right edge, ``t``
                       proportional to arc length
``Polyline(points)``   through the points in order, ``t`` proportional to arc length;
                       ``closed=True`` returns to the first point
=====================  ===============================================================

Besides ``f(t)``, every shape describes itself as *strokes* for the midpoint methods (MM, IM):
pieces along which one axis is the major axis (paper section 2.3). A line is one stroke; a
polyline is one stroke per maximal straight run (consecutive segments that continue in the same
direction are merged, so the right edge of a square, which the trace enters twice, is one
stroke); a circle is four 90-degree arcs, the top and bottom arcs x-major (``|dy/dx| <= 1``,
including the 45-degree points) and the left and right arcs y-major.
"""

from __future__ import annotations

import bisect
import itertools
import math
import re
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from .._shared import validate as _validate
from .geometry import cell_floor, clamp, snap_tolerance

TWO_PI = 2.0 * math.pi
MAX_POINTS = 10_000
"""Most vertices a polyline may have."""


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

    def gather(self, ids):
        """Stroke parameters per point: a ``(9, n)`` array, or the row's numbers if ``ids``
        is None (a single stroke)."""
        return self.rows1[0] if ids is None else self._table_t.take(ids, axis=1)

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
        piece = np.searchsorted(self.breaks, t, side="right") - 1
        np.clip(piece, 0, len(self.piece_stroke) - 1, out=piece)
        return self.piece_stroke[piece]

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


class Shape:
    """Base class of the traced shapes: a parametric curve ``f(t)``, ``t`` in [0, 1]."""

    closed: bool = False

    def f(self, t) -> np.ndarray:
        """Points of the trace.

        Parameters
        ----------
        t : float or array_like
            Trace parameter(s), each finite and within [0, 1].

        Returns
        -------
        ndarray of float64, shape ``t.shape + (2,)``
            ``(x, y)`` in grid units (1 unit = one tactor pitch).
        """
        t = _validate.parameter_array(t)
        x, y = self.xy(t)
        return np.stack([x, y], axis=-1)

    def xy(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Vectorised ``f`` on an already checked float64 array: returns ``(x, y)``."""
        raise NotImplementedError

    def point(self, t: float) -> tuple[float, float]:
        """Scalar ``f`` with plain floats, for the live path. ``t`` is not checked."""
        raise NotImplementedError

    @property
    def strokes(self) -> Strokes:
        """The shape's strokes for the midpoint methods."""
        raise NotImplementedError

    @property
    def scale(self) -> float:
        """Largest coordinate magnitude the shape's points are computed from."""
        raise NotImplementedError

    @property
    def corners(self) -> tuple:
        """Trace parameters of the shape's corners, for corner emphasis (none by default)."""
        return ()

    @cached_property
    def snap_tol(self) -> float:
        """Snap tolerance for this shape's points (see ``geometry.SNAP_ULPS``)."""
        return snap_tolerance(self.scale)

    @property
    def spec(self) -> str:
        """The command-line form, e.g. ``"circle:2.5,3,2"``."""
        raise NotImplementedError

    def to_dict(self) -> dict:
        """A JSON-ready description; :func:`shape_from_dict` reverses it."""
        raise NotImplementedError

    def outline(self, n: int = 256) -> np.ndarray:
        """``(n, 2)`` points along the shape for drawing (vertices included for polylines)."""
        return self.f(np.linspace(0.0, 1.0, n))


def _fmt(*values: float) -> str:
    return ",".join(f"{v:.12g}" for v in values)


@dataclass(frozen=True)
class Line(Shape):
    """Line segment from ``p0`` to ``p1``: ``f(t) = p0 + (p1 - p0) t``.

    Parameters
    ----------
    p0, p1 : (float, float)
        Endpoints in grid units. They may coincide (a zero-length line lights the cell of the
        point under every method).

    Notes
    -----
    ``f`` is evaluated as ``(1 - t) p0 + t p1``, which is exact at both ends and makes a
    reversed line at ``1 - t`` produce bit-identical points.

    Examples
    --------
    >>> Line((0.5, 1.0), (4.5, 3.0)).f(0.5)
    array([2.5, 2. ])
    """

    p0: tuple[float, float]
    p1: tuple[float, float]

    def __post_init__(self):
        object.__setattr__(self, "p0", _validate.point("p0", self.p0))
        object.__setattr__(self, "p1", _validate.point("p1", self.p1))

    def xy(self, t):
        (x0, y0), (x1, y1) = self.p0, self.p1
        s = 1.0 - t
        return s * x0 + t * x1, s * y0 + t * y1

    def point(self, t):
        (x0, y0), (x1, y1) = self.p0, self.p1
        s = 1.0 - t
        return (s * x0 + t * x1, s * y0 + t * y1)

    @cached_property
    def strokes(self):
        return LineStrokes([self.p0 + self.p1], [0.0, 1.0], [0], self.snap_tol)

    @property
    def scale(self):
        return max(map(abs, self.p0 + self.p1))

    @property
    def length(self) -> float:
        """Length in grid units."""
        return math.dist(self.p0, self.p1)

    def reversed(self) -> Line:
        """The same segment traced from ``p1`` to ``p0``."""
        return Line(self.p1, self.p0)

    @property
    def spec(self):
        return "line:" + _fmt(*self.p0, *self.p1)

    def to_dict(self):
        return {"type": "line", "p0": list(self.p0), "p1": list(self.p1)}

    def outline(self, n=2):
        return np.array([self.p0, self.p1])


@dataclass(frozen=True)
class Circle(Shape):
    """Circle traced counter-clockwise from its rightmost point.

    ``f(t) = (cx + r cos 2 pi t, cy + r sin 2 pi t)``.

    Parameters
    ----------
    center : (float, float)
        Centre in grid units.
    radius : float
        Radius in grid units, >= 0 (0 is a point).
    """

    center: tuple[float, float]
    radius: float

    closed = True

    def __post_init__(self):
        object.__setattr__(self, "center", _validate.point("center", self.center))
        object.__setattr__(self, "radius", _validate.size("radius", self.radius))

    def xy(self, t):
        cx, cy = self.center
        angle = TWO_PI * t
        return cx + self.radius * np.cos(angle), cy + self.radius * np.sin(angle)

    def point(self, t):
        cx, cy = self.center
        angle = TWO_PI * t
        return (cx + self.radius * math.cos(angle), cy + self.radius * math.sin(angle))

    @cached_property
    def strokes(self):
        cx, cy = self.center
        return ArcStrokes(cx, cy, self.radius, self.point, self.snap_tol)

    @property
    def scale(self):
        return max(map(abs, self.center)) + self.radius

    @property
    def length(self) -> float:
        """Circumference in grid units."""
        return TWO_PI * self.radius

    @property
    def corners(self):
        """A circle has none; the diagonal points (t = 1/8, 3/8, 5/8, 7/8, where a square of
        the same centre has its corners) are used, so that corner emphasis warps circles and
        squares in the same way and only their geometry differs."""
        return (0.125, 0.375, 0.625, 0.875)

    @property
    def spec(self):
        return "circle:" + _fmt(*self.center, self.radius)

    def to_dict(self):
        return {"type": "circle", "center": list(self.center), "radius": self.radius}


@dataclass(frozen=True)
class Polyline(Shape):
    """Path through ``points`` in order, ``t`` proportional to arc length.

    Parameters
    ----------
    points : sequence of (float, float)
        At least two vertices in grid units. Repeated consecutive vertices are allowed and
        skipped; if all coincide the polyline is a point.
    closed : bool
        If True the path returns from the last vertex to the first.
    """

    points: tuple[tuple[float, float], ...]
    closed: bool = False

    def __post_init__(self):
        if isinstance(self.points, (str, bytes, dict)):
            raise ValueError(
                f"points must be a sequence of (x, y), got {_validate.shown(self.points)}"
            )
        try:
            raw = list(self.points)
        except TypeError:
            raise ValueError(
                f"points must be a sequence of (x, y), got {_validate.shown(self.points)}"
            ) from None
        if not 2 <= len(raw) <= MAX_POINTS:
            raise ValueError(f"points must hold 2 to {MAX_POINTS} points, got {len(raw)}")
        pts = tuple(_validate.point(f"points[{i}]", p) for i, p in enumerate(raw))
        object.__setattr__(self, "points", pts)
        object.__setattr__(self, "closed", _validate.boolean("closed", self.closed))

    @cached_property
    def _segments(self):
        """Non-degenerate segments: starts (k, 2), ends (k, 2), breaks (k + 1,) in t."""
        pts = list(self.points)
        if self.closed:
            pts.append(pts[0])
        starts, ends, lengths = [], [], []
        for a, b in itertools.pairwise(pts):
            length = math.dist(a, b)
            if length > 0.0:
                starts.append(a)
                ends.append(b)
                lengths.append(length)
        if not lengths:  # every vertex the same: a point
            p = pts[0]
            return np.array([p]), np.array([p]), np.array([0.0, 1.0])
        cum = np.concatenate([[0.0], np.cumsum(lengths)])
        breaks = cum / cum[-1]
        breaks[-1] = 1.0
        return np.array(starts), np.array(ends), breaks

    @cached_property
    def _segment_table(self):
        """Per segment ``(t0, t1 - t0, ax, ay, bx, by)``: ``(6, k)`` and as tuples.

        The width is a divisor (not a reciprocal factor) so that a segment's end is reached
        exactly; a width that rounds to 0 is stored as 1 (such a segment is never selected).
        """
        starts, ends, breaks = self._segments
        width = np.diff(breaks)
        width[width <= 0] = 1.0
        table = np.vstack([breaks[:-1], width, starts.T, ends.T])
        return table, [tuple(row) for row in table.T.tolist()]

    def xy(self, t):
        breaks = self._segments[2]
        table, _ = self._segment_table
        i = np.searchsorted(breaks, t, side="right") - 1
        np.clip(i, 0, table.shape[1] - 1, out=i)
        t0, width, ax, ay, bx, by = table.take(i, axis=1)
        s = clamp((t - t0) / width, 0.0, 1.0)
        r = 1.0 - s
        return r * ax + s * bx, r * ay + s * by

    def point(self, t):
        breaks = self._scalar_breaks
        rows = self._segment_table[1]
        i = min(max(bisect.bisect_right(breaks, t) - 1, 0), len(rows) - 1)
        t0, width, ax, ay, bx, by = rows[i]
        s = min(max((t - t0) / width, 0.0), 1.0)
        r = 1.0 - s
        return (r * ax + s * bx, r * ay + s * by)

    @cached_property
    def _scalar_breaks(self):
        return self._segments[2].tolist()

    @cached_property
    def strokes(self):
        starts, ends, breaks = self._segments
        k = len(starts)
        # Merge consecutive segments that continue in the same direction into one stroke.
        stroke_of = [0] * k
        runs = [[0, 0]]  # [first segment, last segment] of each stroke
        for j in range(1, k):
            if _continues(starts[j - 1], ends[j - 1], starts[j], ends[j]):
                runs[-1][1] = j
            else:
                runs.append([j, j])
            stroke_of[j] = len(runs) - 1
        if self.closed and len(runs) > 1 and _continues(starts[-1], ends[-1], starts[0], ends[0]):
            # The trace starts in the middle of a straight run (a square's right edge).
            first = runs.pop(0)
            runs[-1][1] = first[1]
            stroke_of = [(s - 1) if s > 0 else len(runs) - 1 for s in stroke_of]
        stroke_ends = [tuple(starts[a]) + tuple(ends[b]) for a, b in runs]
        return LineStrokes(stroke_ends, breaks, stroke_of, self.snap_tol, closed=self.closed)

    @property
    def scale(self):
        return max(abs(c) for p in self.points for c in p)

    @property
    def corners(self):
        """Parameters of the vertices where the path changes direction."""
        strokes = self.strokes
        breaks = self._segments[2]
        out = []
        for j in range(1, len(strokes.piece_stroke)):
            if strokes.piece_stroke[j] != strokes.piece_stroke[j - 1]:
                out.append(float(breaks[j]))
        if (
            self.closed
            and len(strokes.piece_stroke) > 1
            and strokes.piece_stroke[0] != strokes.piece_stroke[-1]
        ):
            out.append(0.0)
        return tuple(sorted(out))

    @property
    def length(self) -> float:
        """Length of the path in grid units (including the closing segment if closed)."""
        starts, ends, _ = self._segments
        return float(np.hypot(*(ends - starts).T).sum())

    @property
    def spec(self):
        kind = "polygon" if self.closed else "polyline"
        return f"{kind}:" + _fmt(*(c for p in self.points for c in p))

    def to_dict(self):
        return {"type": "polyline", "points": [list(p) for p in self.points], "closed": self.closed}

    def outline(self, n=0):
        pts = list(self.points)
        if self.closed:
            pts.append(pts[0])
        return np.array(pts)


def _continues(a0, a1, b0, b1) -> bool:
    """True when segment b continues segment a in the same direction (within rounding)."""
    ax, ay = a1[0] - a0[0], a1[1] - a0[1]
    bx, by = b1[0] - b0[0], b1[1] - b0[1]
    cross = ax * by - ay * bx
    dot = ax * bx + ay * by
    return dot > 0 and abs(cross) <= 1e-12 * math.hypot(ax, ay) * math.hypot(bx, by)


@dataclass(frozen=True)
class Square(Shape):
    """Axis-aligned square traced counter-clockwise from the midpoint of its right edge.

    ``t`` is proportional to arc length, so the corners are reached at ``t`` = 1/8, 3/8, 5/8
    and 7/8.

    Parameters
    ----------
    center : (float, float)
        Centre in grid units.
    edge : float
        Edge length in grid units, >= 0.
    """

    center: tuple[float, float]
    edge: float

    closed = True

    def __post_init__(self):
        object.__setattr__(self, "center", _validate.point("center", self.center))
        object.__setattr__(self, "edge", _validate.size("edge", self.edge))

    @cached_property
    def polyline(self) -> Polyline:
        """The square as a closed :class:`Polyline` starting at its right edge's midpoint."""
        cx, cy = self.center
        h = self.edge / 2.0
        right, left, top, bottom = cx + h, cx - h, cy + h, cy - h
        return Polyline(
            ((right, cy), (right, top), (left, top), (left, bottom), (right, bottom)), closed=True
        )

    def xy(self, t):
        return self.polyline.xy(t)

    def point(self, t):
        return self.polyline.point(t)

    @property
    def strokes(self):
        return self.polyline.strokes

    @property
    def scale(self):
        return max(map(abs, self.center)) + self.edge / 2.0

    @property
    def corners(self):
        return self.polyline.corners

    @property
    def snap_tol(self):
        return self.polyline.snap_tol

    @property
    def length(self) -> float:
        """Perimeter in grid units."""
        return 4.0 * self.edge

    @property
    def spec(self):
        return "square:" + _fmt(*self.center, self.edge)

    def to_dict(self):
        return {"type": "square", "center": list(self.center), "edge": self.edge}

    def outline(self, n=0):
        return self.polyline.outline()


SHAPE_KINDS = ("line", "circle", "square", "polyline", "polygon")
_NUMBER = re.compile(r"[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?")
"""A decimal number as a user types it (no nan, inf, hex or underscores)."""


def parse_shape(text: str) -> Shape:
    """Parse the command-line form of a shape.

    Parameters
    ----------
    text : str
        ``line:X0,Y0,X1,Y1``, ``circle:CX,CY,R``, ``square:CX,CY,EDGE``, or (beyond the
        contract) ``polyline:X0,Y0,X1,Y1,...`` and ``polygon:...`` (closed).

    Returns
    -------
    Shape

    Raises
    ------
    ValueError
        Naming ``shape`` and what is wrong with the text.

    Examples
    --------
    >>> parse_shape("circle:2.5,3,2")
    Circle(center=(2.5, 3.0), radius=2.0)
    """
    if not isinstance(text, str) or ":" not in text:
        raise ValueError(
            f"shape must look like 'circle:2.5,3,2' ({', '.join(SHAPE_KINDS)}), "
            f"got {_validate.shown(text)}"
        )
    kind, _, args = text.partition(":")
    kind = kind.strip().lower()
    if kind not in SHAPE_KINDS:
        raise ValueError(
            f"shape kind must be one of {', '.join(SHAPE_KINDS)}, got {_validate.shown(kind)}"
        )
    parts = [a.strip() for a in args.split(",")] if args.strip() else []
    if len(parts) > 2 * MAX_POINTS:
        raise ValueError(f"shape {kind}: at most {2 * MAX_POINTS} numbers, got {len(parts)}")
    bad = next((a for a in parts if not _NUMBER.fullmatch(a)), None)
    if bad is not None:
        raise ValueError(
            f"shape {kind}: coordinates must be decimal numbers separated by commas, "
            f"got {_validate.shown(bad)}"
        )
    values = [float(a) for a in parts]
    need = {"line": 4, "circle": 3, "square": 3}
    if kind in need and len(values) != need[kind]:
        raise ValueError(f"shape {kind}: needs {need[kind]} numbers, got {len(values)}")
    if kind not in need and (len(values) < 4 or len(values) % 2):
        raise ValueError(f"shape {kind}: needs an even number (>= 4) of coordinates")
    try:
        if kind == "line":
            return Line(values[0:2], values[2:4])
        if kind == "circle":
            return Circle(values[0:2], values[2])
        if kind == "square":
            return Square(values[0:2], values[2])
        return Polyline(list(zip(values[0::2], values[1::2])), closed=kind == "polygon")
    except ValueError as exc:
        raise ValueError(f"shape {kind}: {exc}") from None


def shape_from_dict(data) -> Shape:
    """Build a shape from :meth:`Shape.to_dict` output; ``ValueError`` names a bad field."""
    if not isinstance(data, dict):
        raise ValueError(f"shape must be an object with a 'type', got {_validate.shown(data)}")
    kind = data.get("type")
    fields = {
        "line": ("p0", "p1"),
        "circle": ("center", "radius"),
        "square": ("center", "edge"),
        "polyline": ("points",),
    }
    if not isinstance(kind, str) or kind not in fields:
        raise ValueError(
            f"shape.type must be one of {', '.join(fields)}, got {_validate.shown(kind)}"
        )
    for name in fields[kind]:
        if name not in data:
            raise ValueError(f"shape.{name} is missing for a {kind}")
    try:
        if kind == "line":
            return Line(data["p0"], data["p1"])
        if kind == "circle":
            return Circle(data["center"], data["radius"])
        if kind == "square":
            return Square(data["center"], data["edge"])
        return Polyline(data["points"], closed=data.get("closed", False))
    except ValueError as exc:
        raise ValueError(f"shape.{exc}") from None
