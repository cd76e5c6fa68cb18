"""Tactile Brush's virtual actuators: the points where a stroke crosses the lines between
actuators, and its two ends (Israr and Poupyrev, CHI 2011, "computing virtual action points").

The paper computes them on a grid: the stroke's intersections with the grid lines through the
tactor centres. A point there lies on the segment between two neighbouring tactors, at relative
position ``beta``, and is rendered by those two (:mod:`.brush`). Here:

- **grid**: the lines ``x = k + 0.5`` and ``y = k + 0.5`` for every whole ``k`` (the grid the
  renderer draws into is not known to a method; cells off it are dropped there, as for every
  method), so on the array these are exactly the paper's grid lines;
- **layout**: the edges of BA's cells (:class:`~._tessellation.Tessellation`: the Delaunay
  triangles' sides, a rectangle's four sides but not its diagonal), which on a grid are the same
  segments between neighbouring tactors; on a layout whose actuators lie on one line (a belt),
  the perpendiculars through the actuators, where the stroke passes one; one actuator: none.

A stroke that runs *along* a line (a row of a grid, a belt) does not cross it: it passes the
actuators on it where it crosses the lines across. The path is the shape's own polyline (lines,
polylines, squares, time-keyed paths: exact) or, for a curve (a circle), a polygon of
:data:`ARC_SEGMENTS` sides through points of the curve (a crossing moves by at most
``r (1 - cos(pi / 1024))``, 5e-6 of the radius; a tangent touch between two of its vertices is
missed). Round a wrap, every segment is taken into the turn of its midpoint (long ones split),
against the tessellation's copies one turn to either side. Consecutive points at one place
(a path through a tactor centre crosses two lines there; a stroke of zero length; a pause) are
one virtual point.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..shapes import Line, Polyline, Square, TimedPath

ARC_SEGMENTS = 1024
"""Sides of the polygon that stands for a curve (a circle) when its crossings are computed."""

MAX_CROSSINGS = 100_000
"""Most crossings of one stroke (a stroke across 100,000 pitches is 1.8 km on the palm array)."""

SAME_PLACE = 1e-9
"""Consecutive points closer than this (layout units, per axis) are one virtual point."""

_PARAM_TOL = 1e-9
"""How far outside a segment (in its own parameter) a crossing is still taken, then clamped."""

_CHUNK = 1_000_000
"""Most segment-edge pairs intersected in one numpy pass."""


class Points(NamedTuple):
    """A stroke's virtual points in trace order.

    Attributes
    ----------
    t : ndarray of float64, shape (n,)
        Trace parameter of each point, ascending, in [0, 1].
    x, y : ndarray of float64, shape (n,)
        Where each point is, in layout units (on a line between actuators, or a stroke's end).
    """

    t: np.ndarray
    x: np.ndarray
    y: np.ndarray


def path(shape) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The vertices ``(t, x, y)`` of a shape's path, each ``(m,)`` with ``m >= 2``: exact for
    the piecewise-straight shapes, :data:`ARC_SEGMENTS` + 1 points along a curve."""
    if isinstance(shape, Square):
        shape = shape.polyline
    if isinstance(shape, Line):
        (x0, y0), (x1, y1) = shape.p0, shape.p1
        return np.array([0.0, 1.0]), np.array([x0, x1]), np.array([y0, y1])
    if isinstance(shape, TimedPath):
        xy = np.array(shape.points, dtype=np.float64)
        return np.array(shape.knots, dtype=np.float64), xy[:, 0], xy[:, 1]
    if isinstance(shape, Polyline):
        pts = list(shape.points) + ([shape.points[0]] if shape.closed else [])
        xy = np.array(pts, dtype=np.float64)
        steps = np.hypot(*np.diff(xy, axis=0).T)
        total = float(steps.sum())
        if total == 0.0:  # every vertex the same: a point
            return np.array([0.0, 1.0]), xy[[0, -1], 0], xy[[0, -1], 1]
        t = np.concatenate([[0.0], np.cumsum(steps) / total])
        t[-1] = 1.0
        return t, xy[:, 0], xy[:, 1]
    t = np.linspace(0.0, 1.0, ARC_SEGMENTS + 1)
    x, y = shape.xy(t)
    return t, np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64)


def _too_many(count: float) -> ValueError:
    return ValueError(
        f"method TB: the stroke crosses {count:,.0f} lines between actuators, more than "
        f"{MAX_CROSSINGS:,}: render a shorter stroke"
    )


def _lattice_hits(t, x, y, tol: float) -> list:
    """Crossings of the path's segments with the lines ``x = k + 0.5``, ``y = k + 0.5``."""
    t0, t1 = t[:-1], t[1:]
    hits = []
    families = ((x[:-1], x[1:], y[:-1], y[1:], 0), (y[:-1], y[1:], x[:-1], x[1:], 1))
    for a, b, c0, c1, axis in families:
        moving = a != b  # a segment along a line of this family crosses none of them
        k_lo = np.ceil(np.minimum(a, b) - 0.5 - tol)
        k_hi = np.floor(np.maximum(a, b) - 0.5 + tol)
        count = np.where(moving, np.maximum(k_hi - k_lo + 1.0, 0.0), 0.0)
        total = float(count.sum())
        if total > MAX_CROSSINGS:
            raise _too_many(total)
        count = count.astype(np.intp)
        seg = np.repeat(np.arange(len(a)), count)
        k = k_lo[seg] + (np.arange(len(seg)) - np.repeat(np.cumsum(count) - count, count))
        u = k + 0.5
        s = np.clip((u - a[seg]) / (b[seg] - a[seg]), 0.0, 1.0)
        other = c0[seg] + s * (c1[seg] - c0[seg])
        when = t0[seg] + s * (t1[seg] - t0[seg])
        hits.append((when, u, other) if axis == 0 else (when, other, u))
    return hits


def layout_edges(tessellation) -> tuple[np.ndarray, bool]:
    """The segments a stroke's virtual points lie on, for a layout's tessellation.

    Returns
    -------
    edges : ndarray of float64, shape (m, 4)
        ``(ax, ay, bx, by)`` per segment, on the tessellation's extended positions (a wrap's
        copies included).
    on_edge : bool
        True when a crossing is taken on the edge itself (the sides of BA's cells); False for
        the perpendiculars of a layout on one line, where it is the stroke's own point.
    """
    tess = tessellation
    if tess.kind == "point":
        return np.zeros((0, 4)), True
    if tess.kind == "line":
        far = 4.0e6  # beyond any coordinate (1e6) and its wrap copies
        nx, ny = -tess.direction[1], tess.direction[0]
        p = tess.line_xy
        return np.column_stack([p[:, 0] - far * nx, p[:, 1] - far * ny,
                                p[:, 0] + far * nx, p[:, 1] + far * ny]), False  # fmt: skip
    simplices, neighbours = tess.tri.simplices, tess.tri.neighbors
    cell_of, xy = tess.cell_of, tess.ext
    seen, out = set(), []
    for s, corners in enumerate(simplices.tolist()):
        if cell_of[s] < 0:
            continue  # a flat sliver: covers nothing
        for j in range(3):  # the side opposite corner j
            p, q = corners[(j + 1) % 3], corners[(j + 2) % 3]
            other = neighbours[s, j]
            if other >= 0 and cell_of[other] == cell_of[s]:
                continue  # the diagonal inside a rectangle: not a side of BA's cell
            key = (min(p, q), max(p, q))
            if key not in seen:
                seen.add(key)
                out.append((*xy[p], *xy[q]))
    return np.array(out, dtype=np.float64).reshape(-1, 4), True


def _into_turns(t, x, y, wrap) -> tuple:
    """Segments ``(t0, t1, x0, y0, x1, y1)``, each taken into the turn of its midpoint along
    the wrap (those longer than a quarter turn split first); unchanged without a wrap."""
    if wrap is None:
        return t[:-1], t[1:], x[:-1], y[:-1], x[1:], y[1:]
    c, k = wrap.circumference, wrap.index
    along = (x, y)[k]
    pieces = np.maximum(np.ceil(np.abs(np.diff(along)) / (c / 4.0)), 1.0)
    if pieces.sum() > MAX_CROSSINGS:
        raise ValueError(
            f"method TB: the stroke goes round the wrap {float(pieces.sum()) / 4.0:,.0f} times, "
            f"more than {MAX_CROSSINGS // 4:,}: render a shorter stroke"
        )
    pieces = pieces.astype(np.intp)
    seg = np.repeat(np.arange(len(pieces)), pieces)
    first = np.repeat(np.cumsum(pieces) - pieces, pieces)
    f0 = (np.arange(len(seg)) - first) / pieces[seg]
    f1 = (np.arange(len(seg)) - first + 1) / pieces[seg]
    ends = []
    for v in (t, x, y):
        a, b = v[:-1][seg], v[1:][seg]
        ends.append((a + f0 * (b - a), a + f1 * (b - a)))
    (t0, t1), (x0, x1), (y0, y1) = ends
    mid = 0.5 * ((x0, y0)[k] + (x1, y1)[k])
    shift = c * np.floor(mid / c)
    if k == 0:
        x0, x1 = x0 - shift, x1 - shift
    else:
        y0, y1 = y0 - shift, y1 - shift
    return t0, t1, x0, y0, x1, y1


def _edge_hits(segments, edges: np.ndarray, on_edge: bool) -> list:
    """Crossings of the segments with the edges (every pair, in chunks)."""
    t0, t1, px, py, qx, qy = segments
    ax, ay, bx, by = edges.T
    dx, dy, ex, ey = qx - px, qy - py, bx - ax, by - ay
    d_len, e_len = np.hypot(dx, dy), np.hypot(ex, ey)
    hits, found = [], 0
    step = max(1, _CHUNK // max(len(ax), 1))
    for lo in range(0, len(px), step):
        sl = slice(lo, lo + step)
        denom = dx[sl, None] * ey[None] - dy[sl, None] * ex[None]
        wx, wy = ax[None] - px[sl, None], ay[None] - py[sl, None]
        with np.errstate(divide="ignore", invalid="ignore"):
            s = (wx * ey[None] - wy * ex[None]) / denom
            u = (wx * dy[sl, None] - wy * dx[sl, None]) / denom
        ok = np.abs(denom) > 1e-12 * d_len[sl, None] * e_len[None]  # parallel: no crossing
        lo_ok, hi_ok = -_PARAM_TOL, 1.0 + _PARAM_TOL
        ok &= (s >= lo_ok) & (s <= hi_ok) & (u >= lo_ok) & (u <= hi_ok)
        i, j = np.nonzero(ok)
        found += len(i)
        if found > MAX_CROSSINGS:
            raise _too_many(found)
        s = np.clip(s[i, j], 0.0, 1.0)
        u = np.clip(u[i, j], 0.0, 1.0)
        i += lo
        when = t0[i] + s * (t1[i] - t0[i])
        if on_edge:  # on the side itself: exactly between its two actuators
            hits.append((when, ax[j] + u * ex[j], ay[j] + u * ey[j]))
        else:
            hits.append((when, px[i] + s * dx[i], py[i] + s * dy[i]))
    return hits


def virtual_points(shape, edges=None, wrap=None) -> Points:
    """A stroke's virtual points: its ends and its crossings, in trace order, one per place.

    Parameters
    ----------
    shape : Shape
    edges : (ndarray, bool), optional
        :func:`layout_edges` of a layout; None: the grid's lines ``x, y = k + 0.5``.
    wrap : Wrap, optional
        The layout's wrap, if any.

    Returns
    -------
    Points

    Raises
    ------
    ValueError
        When the stroke crosses more than :data:`MAX_CROSSINGS` lines.
    """
    t, x, y = path(shape)
    x0, y0 = shape.point(0.0)
    x1, y1 = shape.point(1.0)
    hits = [(np.array([0.0]), np.array([x0]), np.array([y0]))]
    if edges is None:
        hits += _lattice_hits(t, x, y, shape.snap_tol)
    elif len(edges[0]):
        hits += _edge_hits(_into_turns(t, x, y, wrap), *edges)
    hits.append((np.array([1.0]), np.array([x1]), np.array([y1])))
    when = np.concatenate([h[0] for h in hits])
    px = np.concatenate([h[1] for h in hits])
    py = np.concatenate([h[2] for h in hits])
    order = np.argsort(when, kind="stable")
    when, px, py = when[order], px[order], py[order]
    dx, dy = np.diff(px), np.diff(py)
    if wrap is not None:  # the same place one turn on
        c = wrap.circumference
        if wrap.index == 0:
            dx = dx - c * np.round(dx / c)
        else:
            dy = dy - c * np.round(dy / c)
    moved = (np.abs(dx) > SAME_PLACE) | (np.abs(dy) > SAME_PLACE)
    keep = np.concatenate([[True], moved])
    return Points(when[keep], px[keep], py[keep])


def kept(n: int, count: int) -> list[int]:
    """Indices of ``count`` of ``n`` points spread evenly by index, both ends kept (the first
    alone for ``count == 1``): ``floor(k (n - 1) / (count - 1) + 0.5)``."""
    if count <= 1:
        return [0]
    return [math.floor(k * (n - 1) / (count - 1) + 0.5) for k in range(count)]
