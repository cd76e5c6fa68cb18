"""Shapes made of straight segments, ``t`` proportional to arc length: Polyline and Square."""

from __future__ import annotations

import bisect
import itertools
import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ..._shared import validate as _validate
from ..geometry import Pieces, clamp
from ._shape import Shape, _fmt
from ._strokes import LineStrokes

MAX_POINTS = 10_000
"""Most vertices a polyline may have."""


def checked_points(points) -> tuple:
    """``points`` as a tuple of 2 to :data:`MAX_POINTS` finite ``(x, y)`` floats, or
    ``ValueError`` naming ``points`` (or ``points[i]``)."""
    if isinstance(points, (str, bytes, dict)):
        raise ValueError(f"points must be a sequence of (x, y), got {_validate.shown(points)}")
    try:
        raw = list(points)
    except TypeError:
        raise ValueError(
            f"points must be a sequence of (x, y), got {_validate.shown(points)}"
        ) from None
    if not 2 <= len(raw) <= MAX_POINTS:
        raise ValueError(f"points must hold 2 to {MAX_POINTS} points, got {len(raw)}")
    return tuple(_validate.point(f"points[{i}]", p) for i, p in enumerate(raw))


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
        object.__setattr__(self, "points", checked_points(self.points))
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

    @cached_property
    def _pieces(self) -> Pieces:
        return Pieces(self._segments[2], self._segment_table[0].shape[1] - 1)

    def xy(self, t):
        table, _ = self._segment_table
        if type(t) is np.ndarray and t.ndim == 1:
            x, y = self.xy_rows(t)
            return x, y
        breaks = self._segments[2]
        # Not clipped in place: for a scalar t, searchsorted returns a scalar (f(0.25) works).
        i = np.clip(np.searchsorted(breaks, t, side="right") - 1, 0, table.shape[1] - 1)
        t0, width, ax, ay, bx, by = table.take(i, axis=1)
        s = clamp((t - t0) / width, 0.0, 1.0)
        r = 1.0 - s
        return r * ax + s * bx, r * ay + s * by

    def xy_rows(self, t):
        rows = self._segment_table[0].take(self._pieces.of(t), axis=1)
        s = rows[0]
        np.subtract(t, s, out=s)
        s /= rows[1]
        np.maximum(s, 0.0, out=s)
        np.minimum(s, 1.0, out=s)
        out = rows[2:4]
        out *= 1.0 - s
        b = rows[4:6]
        b *= s
        out += b
        return out

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
        cx, cy = self.center
        h = self.edge / 2.0
        _validate.extent("edge", "square", self.edge, (cx - h, cx + h, cy - h, cy + h))

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

    def xy_rows(self, t):
        return self.polyline.xy_rows(t)

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
