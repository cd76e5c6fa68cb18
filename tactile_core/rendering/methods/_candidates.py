"""The live path's candidate actuators of a layout: for each small square of the plane, the
actuators that can matter to a point in it (those within a reach, or those that may be among the
k nearest), so that a point on a layout that is not a grid costs a handful of distances."""

from __future__ import annotations

import functools
import math

import numpy as np

from ..layout import Layout


@functools.lru_cache(maxsize=256)
def candidates(layout: Layout, reach: float | None = None, k: int = 0) -> _Candidates:
    """The live path's candidate actuators of ``layout`` per small square of the plane (built
    once per layout and reach): those within ``reach`` (``k = 0``), or those that may be among
    the ``k`` nearest (``reach`` None)."""
    return _Candidates(layout, reach, k)


class _Candidates:
    """For each square bucket of side ``h`` around the actuators, the actuators that can matter
    to a point in it, so that the live path computes a handful of distances.

    A point ``p`` in a bucket with centre ``c`` and half-diagonal ``b`` is within ``reach`` of
    actuator ``a`` only if ``d(a, c) < reach + b``; and the ``k`` nearest actuators of ``p`` are
    within ``D_k(p) <= D_k(c) + b`` of it (``D_k`` moves no faster than the point), hence within
    ``D_k(c) + 2 b`` of ``c``. Points beyond the table (far outside the array) are checked
    against every actuator. Distances run the short way round a wrap, computed as the batch
    path computes them (the same rounding).
    """

    MAX_BUCKETS = 40_000

    def __init__(self, layout: Layout, reach: float | None, k: int):
        self.layout = layout
        self.wrap = layout.wrap
        xy = layout.xy
        n = len(xy)
        self.all = tuple((i, float(x), float(y)) for i, (x, y) in enumerate(xy.tolist()))
        if n > 1:
            d = layout.distances(xy[:, 0], xy[:, 1])
            np.fill_diagonal(d, np.inf)
            spacing = float(np.median(d.min(axis=1)))
        else:
            spacing = 1.0
        margin = reach if reach is not None else 1.0
        x0, x1, y0, y1 = layout.bounds(margin)
        h = max(spacing / 2.0, 1e-3)
        while math.ceil((x1 - x0) / h) * math.ceil((y1 - y0) / h) > self.MAX_BUCKETS:
            h *= 2.0
        self.h, self.x0, self.y0 = h, x0, y0
        self.table_x1, self.table_y1 = x1, y1
        ni, nj = math.ceil((x1 - x0) / h), math.ceil((y1 - y0) / h)
        b = h * math.sqrt(0.5)
        cx = x0 + (np.arange(ni) + 0.5) * h
        cy = y0 + (np.arange(nj) + 0.5) * h
        gx, gy = np.meshgrid(cx, cy, indexing="ij")
        dist = layout.distances(gx.ravel(), gy.ravel())  # (buckets, n)
        if reach is None:
            kth = np.partition(dist, min(k, n) - 1, axis=1)[:, min(k, n) - 1]
            limit = kth + 2.0 * b
        else:
            limit = np.full(len(dist), reach + b)
        near = dist <= limit[:, None] * (1 + 1e-12) + 1e-12
        self.table = {}
        for flat in range(len(dist)):
            members = np.flatnonzero(near[flat])
            self.table[divmod(flat, nj)] = tuple(self.all[i] for i in members.tolist())

    @functools.cached_property
    def _arrays(self) -> tuple:
        """The table as arrays for :meth:`many`: ``(buckets, m)`` candidate indices (highest
        first, -1 padding), every actuator (highest first), and the positions with a NaN at
        index -1 (a padding slot is at no distance)."""
        ni = math.ceil((self.table_x1 - self.x0) / self.h)
        nj = math.ceil((self.table_y1 - self.y0) / self.h)
        width = max(len(members) for members in self.table.values())
        index = np.full((ni * nj, width), -1, dtype=np.intp)
        for (i, j), members in self.table.items():
            row = sorted((m[0] for m in members), reverse=True)
            index[i * nj + j, : len(row)] = row
        every = np.arange(len(self.all))[::-1].copy()
        px = np.array([a[1] for a in self.all] + [math.nan])
        py = np.array([a[2] for a in self.all] + [math.nan])
        return ni, nj, index, every, px, py

    def many(self, x: np.ndarray, y: np.ndarray) -> list:
        """:meth:`near` and :meth:`distance` for points ``(x, y)`` (``(n,)`` arrays) at once.

        Returns
        -------
        list of (point, index, d)
            One or two blocks (the points in the table's squares; those beyond it, whose
            candidates are every actuator): ``point`` ``(p,)`` the points' positions in ``x``,
            ``index`` ``(p, m)`` their candidates, highest index first, -1 padding a row, and
            ``d`` ``(p, m)`` the distances, computed as :meth:`distance` computes them (the
            same operations), NaN in padding slots.
        """
        ni, nj, table, every, px, py = self._arrays
        kx, ky = x, y
        wrap = self.wrap
        if wrap is not None:
            if wrap.axis == "x":
                kx = np.mod(x, wrap.circumference)
            else:
                ky = np.mod(y, wrap.circumference)
        i = np.floor((kx - self.x0) / self.h)
        j = np.floor((ky - self.y0) / self.h)
        inside = (i >= 0) & (i < ni) & (j >= 0) & (j < nj)
        point = np.arange(len(x))
        if inside.all():
            blocks = [(point, table[(i * nj + j).astype(np.intp)])]
        else:  # beyond the table: every actuator is a candidate
            out = ~inside
            key = (i[inside] * nj + j[inside]).astype(np.intp)
            beyond = np.broadcast_to(every, (int(out.sum()), len(every)))
            blocks = [(point[inside], table[key]), (point[out], beyond)]
        found = []
        for rows, index in blocks:
            dx = x[rows, None] - px[index]
            dy = y[rows, None] - py[index]
            if wrap is not None:
                c = wrap.circumference
                if wrap.axis == "x":
                    dx -= c * np.round(dx / c)
                else:
                    dy -= c * np.round(dy / c)
            found.append((rows, index, np.sqrt(dx * dx + dy * dy)))
        return found

    def near(self, x: float, y: float) -> tuple:
        """``((index, ax, ay), ...)``: the candidates for the point ``(x, y)``."""
        wrap = self.wrap
        kx, ky = x, y
        if wrap is not None:
            c = wrap.circumference
            if wrap.axis == "x":
                kx = x % c
            else:
                ky = y % c
        key = (math.floor((kx - self.x0) / self.h), math.floor((ky - self.y0) / self.h))
        return self.table.get(key, self.all)

    def distance(self, x: float, y: float, ax: float, ay: float) -> float:
        """The distance from ``(x, y)`` to an actuator at ``(ax, ay)``, the short way round."""
        dx, dy = x - ax, y - ay
        wrap = self.wrap
        if wrap is not None:
            c = wrap.circumference
            if wrap.axis == "x":
                dx -= c * round(dx / c)
            else:
                dy -= c * round(dy / c)
        return math.sqrt(dx * dx + dy * dy)
