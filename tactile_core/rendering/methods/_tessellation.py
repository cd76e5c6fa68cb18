"""BA's cells: the layout's Delaunay triangulation, rectangles kept whole.

Barycentric weights over a Delaunay triangulation make every layout smooth: inside the
actuators' convex hull the point lies in one triangle, and its three corners get the point's
barycentric coordinates (they sum to 1 and vary linearly). Where four actuators lie on one
circle the triangulation is not unique (a grid's squares: either diagonal will do, and the
weights would depend on which Qhull picked); where those four form a rectangle the two
triangles are merged and the rectangle is interpolated bilinearly, which on a grid is exactly
AS's area weights. Collinear layouts (a belt, one row) interpolate linearly between
neighbours; a single actuator is a point.

Outside the hull the point takes the weights of the nearest point ``q`` of the hull's boundary
(linear along that edge), faded by ``max(0, 1 - |dx|) max(0, 1 - |dy|)`` with ``(dx, dy) =
p - q`` in layout units: AS's own falloff beyond a grid's edge (the unit box's overlap with the
cells that exist), so BA equals AS on every grid, and a point one pitch beyond the hull is off.

A wrapped layout is tessellated with its copies one circumference to either side, so cells
span the seam; points are taken into ``[0, circumference)`` first.
"""

from __future__ import annotations

import bisect
import math

import numpy as np

from ..layout import Layout

_FLAT = 1e-9
"""A layout whose points spread less than this (relative) across their main direction is a line."""
_RECT = 1e-9
"""Relative tolerance of 'these four points form a rectangle'."""


class Tessellation:
    """The cells of one layout, in two forms: arrays for batches, tuples for one point.

    Parameters
    ----------
    layout : Layout

    Attributes
    ----------
    kind : {"point", "line", "plane"}
    origin : ndarray, (cells, 2)
        A corner of each cell (``v0``).
    inverse : ndarray, (cells, 2, 2)
        Maps ``p - origin`` to the cell's ``(u, v)``.
    verts : ndarray of intp, (cells, 4)
        Actuator indices of ``v0, v1, v2`` and (rectangles) ``v3 = v1 + v2 - v0``; -1 for a
        triangle's fourth and a segment's third and fourth.
    rect : ndarray of bool, (cells,)
    """

    def __init__(self, layout: Layout):
        self.layout = layout
        self.wrap = layout.wrap
        xy = layout.xy
        index = np.arange(layout.size)
        if layout.wrap is not None:
            shift = np.zeros(2)
            shift[layout.wrap.index] = layout.wrap.circumference
            xy = np.concatenate([xy - shift, xy, xy + shift])
            index = np.tile(index, 3)
        self.ext, self.ext_index = xy, index
        centred = xy - xy.mean(axis=0)
        if len(xy) == 1:
            self.kind = "point"
            self._segments(xy, index, np.zeros(2))
        else:
            _, s, vt = np.linalg.svd(centred, full_matrices=False)
            if len(s) < 2 or s[1] <= _FLAT * max(s[0], 1.0):
                self.kind = "line"
                self._segments(xy, index, vt[0])
            else:
                self.kind = "plane"
                self._triangulate(xy, index)
        self._build_scalar()

    # -- building ---------------------------------------------------------------------------

    def _segments(self, xy, index, direction) -> None:
        """A line: segments between neighbours along ``direction`` (a point: none)."""
        self.direction = direction
        along = xy @ direction
        order = np.argsort(along, kind="stable")
        self.line_xy, self.line_index, self.line_s = xy[order], index[order], along[order]

    def _triangulate(self, xy, index) -> None:
        from scipy.spatial import Delaunay

        tri = Delaunay(xy)
        self.tri = tri
        simplices = tri.simplices
        cell_of = np.full(len(simplices), -1, dtype=np.intp)
        origin, inverse, verts, rect = [], [], [], []
        for t, (a, b, c) in enumerate(simplices):
            if cell_of[t] >= 0:
                continue
            merged = self._rectangle(tri, t, xy)
            if merged is not None:
                other, corner, v1, v2, v3 = merged
                e1, e2 = xy[v1] - xy[corner], xy[v2] - xy[corner]
                cell_of[t] = cell_of[other] = len(origin)
                origin.append(xy[corner])
                inverse.append(np.linalg.inv(np.column_stack([e1, e2])))
                verts.append(index[[corner, v1, v2, v3]])
                rect.append(True)
                continue
            e1, e2 = xy[b] - xy[a], xy[c] - xy[a]
            if abs(e1[0] * e2[1] - e1[1] * e2[0]) <= 1e-12 * max(1.0, np.abs(xy).max()) ** 2:
                continue  # a flat sliver of cocircular points: covers no area
            cell_of[t] = len(origin)
            origin.append(xy[a])
            inverse.append(np.linalg.inv(np.column_stack([e1, e2])))
            verts.append(np.array([index[a], index[b], index[c], -1]))
            rect.append(False)
        self.cell_of = cell_of
        self.origin = np.array(origin)
        self.inverse = np.array(inverse)
        self.verts = np.array(verts, dtype=np.intp)
        self.rect = np.array(rect, dtype=bool)
        hull = _boundary(simplices, cell_of)  # (edges, 2) point indices
        self.hull_a, self.hull_b = xy[hull[:, 0]], xy[hull[:, 1]]
        self.hull_index = index[hull]

    @staticmethod
    def _rectangle(tri, t, xy):
        """The neighbour of triangle ``t`` with which it forms a rectangle, across ``t``'s
        longest edge: ``(neighbour, corner, v1, v2, v3)`` or None."""
        a, b, c = tri.simplices[t]
        pts = xy[[a, b, c]]
        lengths = [np.sum((pts[(j + 1) % 3] - pts[(j + 2) % 3]) ** 2) for j in range(3)]
        j = int(np.argmax(lengths))  # the edge opposite vertex j
        other = tri.neighbors[t, j]
        if other < 0:
            return None
        right = tri.simplices[t][j]
        p, q = tri.simplices[t][(j + 1) % 3], tri.simplices[t][(j + 2) % 3]
        opposite = [v for v in tri.simplices[other] if v not in (p, q)]
        if len(opposite) != 1:
            return None
        far = opposite[0]
        scale = max(1.0, float(np.abs(xy[[right, p, q, far]]).max()))
        # A rectangle: the diagonals (right-far, p-q) share their midpoint and their length.
        if np.abs(xy[right] + xy[far] - xy[p] - xy[q]).max() > _RECT * scale:
            return None
        d1, d2 = np.sum((xy[right] - xy[far]) ** 2), np.sum((xy[p] - xy[q]) ** 2)
        if abs(d1 - d2) > _RECT * scale * scale:
            return None
        return other, right, p, q, far

    def _build_scalar(self) -> None:
        """Tuples and buckets for :meth:`weights1`."""
        self.repeats = False
        if self.kind != "plane":
            self._line = (self.line_s.tolist(), self.line_xy.tolist(), self.line_index.tolist())
            return
        for v in self.verts.tolist():
            used = [i for i in v if i >= 0]
            self.repeats |= len(set(used)) < len(used)
        self.repeats |= bool((self.hull_index[:, 0] == self.hull_index[:, 1]).any())
        cells = []
        for o, m, v, r in zip(self.origin, self.inverse, self.verts, self.rect):
            cells.append(
                (o[0], o[1], m[0, 0], m[0, 1], m[1, 0], m[1, 1], tuple(v.tolist()), bool(r))
            )
        self._cells = cells
        self._edges = [
            (a[0], a[1], b[0], b[1], int(i), int(j))
            for a, b, (i, j) in zip(self.hull_a, self.hull_b, self.hull_index)
        ]
        lo = self.ext.min(axis=0) - 1.0
        span = self.ext.max(axis=0) + 1.0 - lo
        n_cells = max(len(cells), 1)
        self._h = max(float(np.sqrt(span[0] * span[1] / n_cells)) / 2.0, 1e-6)
        self._lo = (float(lo[0]), float(lo[1]))
        buckets: dict = {}
        edges: dict = {}
        for k in range(len(cells)):
            corners = self._corners(k)
            self._file(buckets, k, corners.min(axis=0), corners.max(axis=0))
        for k, (ax, ay, bx, by, _, _) in enumerate(self._edges):
            self._file(edges, k, np.minimum((ax, ay), (bx, by)) - 1.0,
                       np.maximum((ax, ay), (bx, by)) + 1.0)  # fmt: skip
        self._buckets = {key: tuple(v) for key, v in buckets.items()}
        self._edge_buckets = {key: tuple(v) for key, v in edges.items()}

    def _corners(self, k: int) -> np.ndarray:
        m = np.linalg.inv(self.inverse[k])
        e1, e2 = m[:, 0], m[:, 1]
        o = self.origin[k]
        if self.rect[k]:
            return np.array([o, o + e1, o + e2, o + e1 + e2])
        return np.array([o, o + e1, o + e2])

    def _file(self, table: dict, k: int, lo, hi) -> None:
        h, (x0, y0) = self._h, self._lo
        i0, i1 = math.floor((lo[0] - x0) / h), math.floor((hi[0] - x0) / h)
        j0, j1 = math.floor((lo[1] - y0) / h), math.floor((hi[1] - y0) / h)
        for i in range(i0, i1 + 1):
            for j in range(j0, j1 + 1):
                table.setdefault((i, j), []).append(k)

    # -- batch ------------------------------------------------------------------------------

    def weights(self, x: np.ndarray, y: np.ndarray, tol) -> tuple[np.ndarray, np.ndarray]:
        """Actuators and weights of points ``(x, y)`` (arrays ``(n,)``).

        Returns
        -------
        index : ndarray of intp, (n, 4)
            Actuator indices, -1 where a slot is unused.
        weight : ndarray of float64, (n, 4)
            BA's weights (0 in unused slots); they sum to 1 inside the hull.
        """
        x, y = self.layout.canonical(x, y)
        p = np.stack([x, y], axis=1)
        n = len(p)
        tol = np.broadcast_to(np.asarray(tol, dtype=np.float64), (n,))
        index = np.full((n, 4), -1, dtype=np.intp)
        weight = np.zeros((n, 4))
        if self.kind != "plane":
            q, idx, w = self._on_line(p, tol)
        else:
            simplex = self.tri.find_simplex(p)
            cell = np.where(simplex >= 0, self.cell_of[np.maximum(simplex, 0)], -1)
            inside = cell >= 0
            q = p.copy()
            idx = np.full((n, 4), -1, dtype=np.intp)
            w = np.zeros((n, 4))
            if inside.any():
                idx[inside], w[inside] = self._in_cells(p[inside], cell[inside], tol[inside])
            out = ~inside
            if out.any():
                q[out], idx[out], w[out] = self._on_hull(p[out])
        d = np.abs(p - q)
        fade = np.maximum(1.0 - d[:, 0], 0.0) * np.maximum(1.0 - d[:, 1], 0.0)
        w = w * fade[:, None]
        index[:], weight[:] = idx, np.where(idx >= 0, w, 0.0)
        return index, weight

    def _in_cells(self, p, cell, tol):
        rel = p - self.origin[cell]
        m = self.inverse[cell]
        u = m[:, 0, 0] * rel[:, 0] + m[:, 0, 1] * rel[:, 1]
        v = m[:, 1, 0] * rel[:, 0] + m[:, 1, 1] * rel[:, 1]
        rect = self.rect[cell]
        u, v = _snap(u, tol), _snap(v, tol)
        w = np.empty((len(p), 4))
        w[:, 0] = np.where(rect, (1 - u) * (1 - v), 1 - u - v)
        w[:, 1] = np.where(rect, u * (1 - v), u)
        w[:, 2] = np.where(rect, (1 - u) * v, v)
        w[:, 3] = np.where(rect, u * v, 0.0)
        w[w < tol[:, None]] = 0.0
        w /= w.sum(axis=1, keepdims=True)
        return self.verts[cell], w

    def _on_hull(self, p):
        """Nearest boundary point of each (outside) point, and the weights there."""
        a, b = self.hull_a, self.hull_b
        ab = b - a
        length2 = np.sum(ab * ab, axis=1)
        s = ((p[:, None, :] - a) * ab).sum(axis=2) / length2
        np.clip(s, 0.0, 1.0, out=s)
        q = a + s[..., None] * ab
        d2 = np.sum((p[:, None, :] - q) ** 2, axis=2)
        e = np.argmin(d2, axis=1)
        rows = np.arange(len(p))
        s = _snap(s[rows, e], 1e-12)
        idx = np.full((len(p), 4), -1, dtype=np.intp)
        idx[:, :2] = self.hull_index[e]
        w = np.zeros((len(p), 4))
        w[:, 0], w[:, 1] = 1.0 - s, s
        return q[rows, e], idx, w

    def _on_line(self, p, tol):
        n = len(p)
        idx = np.full((n, 4), -1, dtype=np.intp)
        w = np.zeros((n, 4))
        if self.kind == "point":
            idx[:, 0] = self.line_index[0]
            w[:, 0] = 1.0
            return np.broadcast_to(self.line_xy[0], p.shape), idx, w
        s = p @ self.direction
        ls = self.line_s
        k = np.clip(np.searchsorted(ls, s, side="right") - 1, 0, len(ls) - 2)
        f = _snap(np.clip((s - ls[k]) / (ls[k + 1] - ls[k]), 0.0, 1.0), tol)
        q = self.line_xy[k] + f[:, None] * (self.line_xy[k + 1] - self.line_xy[k])
        idx[:, 0], idx[:, 1] = self.line_index[k], self.line_index[k + 1]
        w[:, 0], w[:, 1] = 1.0 - f, f
        same = idx[:, 0] == idx[:, 1]  # one actuator round a wrap: its two copies
        w[same, 0], w[same, 1], idx[same, 1] = 1.0, 0.0, -1
        return q, idx, w

    # -- one point --------------------------------------------------------------------------

    def weights1(self, x: float, y: float, tol: float) -> tuple:
        """:meth:`weights` for one point with plain floats: ``((index, weight), ...)`` of the
        actuators with a weight above 0."""
        wrap = self.wrap
        if wrap is not None:
            c = wrap.circumference
            if wrap.axis == "x":
                x = x % c
            else:
                y = y % c
        if self.kind != "plane":
            return self._line1(x, y, tol)
        h, (x0, y0) = self._h, self._lo
        key = (math.floor((x - x0) / h), math.floor((y - y0) / h))
        cells = self._cells
        for k in self._buckets.get(key, ()):
            ox, oy, m00, m01, m10, m11, verts, rect = cells[k]
            rx, ry = x - ox, y - oy
            u = m00 * rx + m01 * ry
            v = m10 * rx + m11 * ry
            e = 1e-12
            if rect:
                if -e <= u <= 1 + e and -e <= v <= 1 + e:
                    u, v = _snap1(u, tol), _snap1(v, tol)
                    ws = ((1 - u) * (1 - v), u * (1 - v), (1 - u) * v, u * v)
                    return _entries(verts, ws, tol, 1.0)
            elif u >= -e and v >= -e and u + v <= 1 + e:
                u, v = _snap1(u, tol), _snap1(v, tol)
                return _entries(verts, (1 - u - v, u, v, 0.0), tol, 1.0)
        best = None
        for k in self._edge_buckets.get(key, ()):
            ax, ay, bx, by, i, j = self._edges[k]
            ex, ey = bx - ax, by - ay
            s = ((x - ax) * ex + (y - ay) * ey) / (ex * ex + ey * ey)
            s = _snap1(0.0 if s < 0.0 else (1.0 if s > 1.0 else s), 1e-12)
            qx, qy = ax + s * ex, ay + s * ey
            d2 = (x - qx) ** 2 + (y - qy) ** 2
            if best is None or d2 < best[0]:
                best = (d2, qx, qy, i, j, s)
        if best is None:
            return ()
        _, qx, qy, i, j, s = best
        fade = max(1.0 - abs(x - qx), 0.0) * max(1.0 - abs(y - qy), 0.0)
        if fade <= 0.0:
            return ()
        return _entries((i, j, -1, -1), (1.0 - s, s, 0.0, 0.0), tol, fade)

    def _line1(self, x: float, y: float, tol: float) -> tuple:
        ls, lxy, lidx = self._line
        if self.kind == "point":
            qx, qy = lxy[0]
            fade = max(1.0 - abs(x - qx), 0.0) * max(1.0 - abs(y - qy), 0.0)
            return ((lidx[0], fade),) if fade > 0.0 else ()
        dx, dy = self.direction
        s = x * dx + y * dy

        k = min(max(bisect.bisect_right(ls, s) - 1, 0), len(ls) - 2)
        f = (s - ls[k]) / (ls[k + 1] - ls[k])
        f = _snap1(0.0 if f < 0.0 else (1.0 if f > 1.0 else f), tol)
        (ax, ay), (bx, by) = lxy[k], lxy[k + 1]
        qx, qy = ax + f * (bx - ax), ay + f * (by - ay)
        fade = max(1.0 - abs(x - qx), 0.0) * max(1.0 - abs(y - qy), 0.0)
        if fade <= 0.0:
            return ()
        i, j = lidx[k], lidx[k + 1]
        if i == j:
            return ((i, fade),)
        return tuple((a, w * fade) for a, w in ((i, 1.0 - f), (j, f)) if w > 0.0)


def _boundary(simplices: np.ndarray, cell_of: np.ndarray) -> np.ndarray:
    """The edges of the kept triangles that only one of them has: ``(edges, 2)`` point indices.

    Where no triangle is skipped these are Qhull's convex hull. A flat sliver left out (an
    actuator a rounding error inside the hull's edge makes one) leaves its own sides as the
    boundary instead of Qhull's edge across it, so a point just outside projects onto the
    sides the cells inside it use, and the weights go on without a step across the boundary.
    """
    count: dict = {}
    for t, tri in enumerate(simplices.tolist()):
        if cell_of[t] < 0:
            continue
        for u, v in ((tri[0], tri[1]), (tri[1], tri[2]), (tri[2], tri[0])):
            key = (u, v) if u < v else (v, u)
            count[key] = count.get(key, 0) + 1
    edges = sorted(key for key, n in count.items() if n == 1)
    return np.array(edges, dtype=np.intp).reshape(-1, 2)


def _snap(u, tol):
    """``u`` with values within ``tol`` of 0 or 1 set to 0 or 1 (float noise on an edge)."""
    u = np.where(np.abs(u) < tol, 0.0, u)
    return np.where(np.abs(1.0 - u) < tol, 1.0, u)


def _snap1(u: float, tol: float) -> float:
    if -tol < u < tol:
        return 0.0
    if -tol < 1.0 - u < tol:
        return 1.0
    return u


def _entries(verts, ws, tol: float, fade: float) -> tuple:
    """Nonzero ``(actuator, weight * fade)``, weights below ``tol`` dropped and the rest
    renormalised (as :meth:`Tessellation.weights` does)."""
    kept = [(i, w) for i, w in zip(verts, ws) if i >= 0 and w > 0.0]
    if all(w >= tol for _, w in kept):
        if fade == 1.0:
            return tuple(kept)
        total = 1.0
    else:
        kept = [(i, w) for i, w in kept if w >= tol]
        total = sum(w for _, w in kept)
    return tuple((i, w / total * fade) for i, w in kept)
