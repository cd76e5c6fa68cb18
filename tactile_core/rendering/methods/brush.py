"""Tactile Brush (TB): apparent tactile motion by timed onsets along the stroke, with virtual
actuators between the physical ones (Israr and Poupyrev, "Tactile Brush: Drawing on Skin with a
Tactile Grid Display", CHI 2011).

The model, as this method computes it:

1. **Virtual actuators.** The stroke's ends and the points where it crosses a line between
   neighbouring actuators (:mod:`._brush_points`: the grid lines through the tactor centres,
   or the sides of BA's cells on a layout), ``n`` of them in trace order.
2. **Energy split.** A virtual point at relative position ``beta`` between actuators 1 and 2
   is rendered with ``A1 = sqrt(1 - beta) A``, ``A2 = sqrt(beta) A`` (``A = 1``), so that
   ``A1^2 + A2^2 = A^2``: EN's weights at the point (the square roots of AS's areas on a grid,
   of BA's weights on a layout), which on a line between two actuators are exactly these. On a
   tactor it is that tactor alone; a stroke's end between lines gets EN's up to four.
3. **Timing.** Every point vibrates for ``d`` ms; consecutive onsets are
   ``SOA = 0.32 d + 47.3`` ms apart (the paper's apparent-motion fit); ``n`` points in a stroke
   of ``T`` ms: ``T = (n - 1) SOA + d``, so ``d = (T - 47.3 (n - 1)) / (1 + 0.32 (n - 1))``.
   Point ``i`` is on over ``[i SOA, i SOA + d]`` (both ends, within :data:`EDGE_MS`).
4. **Too short a stroke.** Consecutive vibrations overlap (apparent motion, not separate taps)
   while ``d >= SOA``, that is ``d >= D_OVERLAP = 47.3 / (1 - 0.32) = 69.56`` ms, which the
   equations give for ``T >= n D_OVERLAP``; below that (and for ``T <= 47.3 (n - 1)`` no
   ``d > 0`` exists at all) the brush plays the most points that still overlap,
   ``m = min(n, floor(T / D_OVERLAP))`` (at least 1: the start, for ``T``), spread evenly along
   the stroke by index with both ends kept (:func:`~._brush_points.kept`), and times those.
5. **Time.** ``t`` in [0, 1] is ``t T`` ms into the stroke. ``T`` is the trace's duration: the
   method declares :data:`DURATION_S` (the protocol's clock), and the trace clock binds its own
   duration (``Method.on_clock``); without one (``tc.render``, ``render_point``) it is 2 s, the
   default scene's.
6. **Overlap.** Up to four points are on at once (``SOA <= d < 3.125 SOA``); an actuator that
   two of them share gets the square root of the sum of their energies, at most 1.

Between consecutive onsets the set of active points does not change, so a stroke's brush is a
table, built once per shape and duration: per *window* of active points (first, last), the lit
actuators. A sample finds its window with two binary searches, batch and live alike.
"""

from __future__ import annotations

import bisect
import math
from typing import NamedTuple

import numpy as np

from . import energy
from ._brush_points import kept, layout_edges, virtual_points
from ._cells import CellTable, Indexed, stack_points

NAME = "TB"
TITLE = "Tactile Brush (timed onsets, virtual actuators)"
BILEVEL = False
NEEDS_SHAPE = True
MAX_TACTORS = 12
"""At most 4 points on at once (``d / SOA < 1 / 0.32``): two stroke ends with up to 4
actuators each and two crossings with up to 2."""
CORRECTION = "none"
"""The energy split is its own normalisation, as EN's is."""
DURATION_S = 2.0
"""The method's clock: seconds from ``t = 0`` to 1 when no trace binds its own (the default
scene's duration)."""

SOA_SLOPE = 0.32
SOA_OFFSET_MS = 47.3
"""``SOA = SOA_SLOPE d + SOA_OFFSET_MS`` (ms): the paper's fit for apparent tactile motion."""

D_OVERLAP_MS = SOA_OFFSET_MS / (1.0 - SOA_SLOPE)
"""69.56 ms: the vibration at which ``d = SOA``; longer ones overlap the next point's onset.
Strokes too short for ``d >= D_OVERLAP_MS`` play fewer points (:func:`timing`)."""

EDGE_MS = 1e-9
"""A point is on from ``EDGE_MS`` before its onset to ``EDGE_MS`` after its offset (so that a
time computed as ``t T`` lands on the right side of an onset it equals)."""


class Timing(NamedTuple):
    """The brush's timing of one stroke.

    Attributes
    ----------
    count : int
        Points played (``n``, or fewer when the stroke is too short for them).
    d_ms : float
        Vibration of each point, ms.
    soa_ms : float
        Onset to onset, ms (``0.32 d + 47.3``).
    """

    count: int
    d_ms: float
    soa_ms: float


def timing(n: int, duration_ms: float) -> Timing:
    """Tactile Brush's timing of ``n`` points in a stroke of ``duration_ms``.

    Parameters
    ----------
    n : int
        Virtual points of the stroke, >= 1.
    duration_ms : float
        The stroke's duration ``T`` in ms, > 0.

    Returns
    -------
    Timing
        ``d = (T - 47.3 (m - 1)) / (1 + 0.32 (m - 1))`` and ``SOA = 0.32 d + 47.3`` for the
        most points ``m <= n`` whose vibrations overlap (``d >= SOA``, i.e.
        ``m <= T / D_OVERLAP_MS``), at least one.

    Examples
    --------
    >>> timing(3, 1000.0)  # doctest: +ELLIPSIS
    Timing(count=3, d_ms=552.07..., soa_ms=223.96...)
    >>> timing(3, 200.0).count  # 3 x 69.56 ms > 200 ms: two points
    2
    """
    if n < 1 or not duration_ms > 0:
        raise ValueError(f"timing needs n >= 1 and duration_ms > 0, got {n} and {duration_ms}")

    def d_of(m: int) -> float:
        return (duration_ms - SOA_OFFSET_MS * (m - 1)) / (1.0 + SOA_SLOPE * (m - 1))

    # d(m) >= D_OVERLAP  <=>  T - 47.3 (m - 1) >= D (1 + 0.32 (m - 1))  <=>  m <= T / D, since
    # 47.3 + 0.32 D = D; the check on d itself settles a quotient that rounds across a whole.
    count = min(n, max(1, math.floor(duration_ms / D_OVERLAP_MS)))
    while count > 1 and d_of(count) < D_OVERLAP_MS * (1.0 - 1e-12):
        count -= 1
    while count < n and d_of(count + 1) >= D_OVERLAP_MS * (1.0 - 1e-12):
        count += 1
    d = d_of(count)
    return Timing(count, d, SOA_SLOPE * d + SOA_OFFSET_MS)


class Schedule:
    """One stroke's brush on one target at one duration.

    Parameters
    ----------
    points : Points
        The stroke's virtual points (:func:`~._brush_points.virtual_points`).
    shares : callable
        ``shares(x, y) -> ((key, amplitude), ...)``: the actuators that render a virtual point
        at ``(x, y)`` (a ``(col, row)`` cell on a grid, an index on a layout).
    duration_ms : float
        ``T``.
    size : int or None
        None on a grid; a layout's size (its spare slot for unused entries).

    Attributes
    ----------
    timing : Timing
    t, x, y : ndarray of float64, shape (m,)
        The points played.
    onsets_ms, offsets_ms : ndarray of float64, shape (m,)
    lit : list of tuple
        Per window ``1 + first * stride + (last - first)`` (0: none on), ``((key, value), ...)``.
    """

    def __init__(self, points, shares, duration_ms: float, size: int | None = None):
        self.duration_ms = float(duration_ms)
        self.timing = timing(len(points.t), self.duration_ms)
        chosen = kept(len(points.t), self.timing.count)
        self.t, self.x, self.y = (np.asarray(v)[chosen] for v in points)
        self.shares = [shares(float(x), float(y)) for x, y in zip(self.x, self.y)]
        m, d, soa = self.timing
        self.onsets_ms = np.arange(m) * soa
        self.offsets_ms = self.onsets_ms + d
        self._lo = self.onsets_ms - EDGE_MS
        self._hi = self.offsets_ms + EDGE_MS
        self._lo1, self._hi1 = self._lo.tolist(), self._hi.tolist()
        reach = np.searchsorted(self._lo, self._hi, side="right") - np.arange(m)
        self.stride = int(reach.max())  # most points on at once (4 at most)
        self.lit = [()]
        for first in range(m):
            for width in range(self.stride):
                last = first + width
                self.lit.append(_combined(self.shares[first : last + 1]) if last < m else ())
        self._tables(size)

    def _tables(self, size) -> None:
        """The batch tables (picks and values, ``(slots, windows)``) and the live entries."""
        slots = max(1, max(len(w) for w in self.lit))
        picks = np.empty((len(self.lit), slots), dtype=np.intp)
        values = np.zeros((len(self.lit), slots))
        if size is None:
            keys = sorted({key for window in self.lit for key, _ in window})
            where = {key: i for i, key in enumerate(keys)}
            self.cells = CellTable([c for c, _ in keys] + [-1.0], [r for _, r in keys] + [-1.0])
            picks[:] = len(keys)  # unused: the cell off every grid
            self.entries1 = [tuple((c, r, v) for (c, r), v in w) for w in self.lit]
        else:
            where = {i: i for i in range(size)}
            picks[:] = size  # unused: the spare slot
            self.entries1 = [tuple(w) for w in self.lit]
        for k, window in enumerate(self.lit):
            for j, (key, value) in enumerate(window):
                picks[k, j] = where[key]
                values[k, j] = value
        self.picks = np.ascontiguousarray(picks.T)
        self.values = np.ascontiguousarray(values.T)

    def windows(self, t: np.ndarray) -> np.ndarray:
        """Window of each ``t`` (``(n,)`` float64): which points are on at ``t T`` ms."""
        tau = t * self.duration_ms
        last = np.searchsorted(self._lo, tau, side="right") - 1
        first = np.searchsorted(self._hi, tau, side="left")
        width = last - first
        return np.where(width >= 0, 1 + first * self.stride + width, 0)

    def window1(self, t: float) -> int:
        """Scalar :meth:`windows`, with the same comparisons."""
        tau = t * self.duration_ms
        last = bisect.bisect_right(self._lo1, tau) - 1
        first = bisect.bisect_left(self._hi1, tau)
        return 1 + first * self.stride + (last - first) if last >= first else 0


def _combined(shares: list) -> tuple:
    """The lit actuators of points on at once: each actuator's amplitude, or, shared, the square
    root of the sum of the energies, at most 1."""
    energy_of: dict = {}
    for point in shares:
        for key, value in point:
            energy_of.setdefault(key, []).append(value)
    return tuple(
        (key, v[0] if len(v) == 1 else math.sqrt(min(math.fsum(a * a for a in v), 1.0)))
        for key, v in energy_of.items()
    )


def _cache(shape) -> dict:
    """The brush tables kept with a shape's strokes (as MM's and IM's are)."""
    strokes = shape.strokes
    try:
        return strokes.tb_cache
    except AttributeError:
        strokes.tb_cache = {}
        return strokes.tb_cache


def _kept(cache: dict, key, build):
    hit = cache.get(key)
    if hit is None:
        if len(cache) >= 32:
            cache.clear()
        hit = cache[key] = build()
    return hit


def grid_schedule(shape, duration_s: float = DURATION_S) -> Schedule:
    """The shape's :class:`Schedule` on a grid (any grid: cells off it are dropped later)."""
    cache = _cache(shape)
    hit = cache.get(("grid", duration_s))
    if hit is not None:
        return hit
    points = _kept(cache, ("grid points",), lambda: virtual_points(shape))
    tol = shape.snap_tol

    def shares(x, y):
        return tuple(((c, r), v) for c, r, v in energy.sample1(None, x, y, None, tol) if v > 0.0)

    return _kept(cache, ("grid", duration_s),
                 lambda: Schedule(points, shares, 1000.0 * duration_s))  # fmt: skip


def sample(shape, x, y, t, tol, duration_s=DURATION_S):
    """Tactors lit at the trace parameters ``t``.

    Parameters
    ----------
    shape : Shape
        The stroke (its virtual points).
    x, y : ndarray of float64, shape (n,)
        Unused: the brush depends on the time along the stroke, ``t`` times its duration.
    t : ndarray of float64, shape (n,)
        Trace parameters in [0, 1].
    tol : float
        Unused (the shape's own snap tolerance places the virtual points).
    duration_s : float
        The stroke's duration ``T`` in seconds (bound by the trace clock).

    Returns
    -------
    list of (cols, rows, values)
        :data:`MAX_TACTORS` entries at most; unused ones name a cell off every grid.
    """
    return sample_cells(shape, stack_points(x, y), t, tol, duration_s).entries()


def sample_cells(shape, xy, t, tol, duration_s=DURATION_S):
    """:func:`sample` in the renderer's batch form (:class:`~._cells.Indexed`)."""
    schedule = grid_schedule(shape, duration_s)
    window = schedule.windows(np.asarray(t, dtype=np.float64))
    return Indexed(
        schedule.picks.take(window, axis=1), schedule.cells, schedule.values.take(window, axis=1)
    )


def sample1(shape, x, y, t, tol, duration_s=DURATION_S):
    """Scalar :func:`sample`: ``((col, row, value), ...)`` of the lit tactors."""
    schedule = grid_schedule(shape, duration_s)
    return schedule.entries1[schedule.window1(t)]


class OnLayout:
    """TB on a layout that is not a grid: the shape-aware half of its layout sampler.

    Parameters
    ----------
    layout : Layout
    tessellation : Tessellation
        BA's cells of the layout (their sides carry the virtual points).
    shares : callable
        ``shares(x, y, tol) -> ((index, amplitude), ...)``: EN's live path on the layout.
    duration_s : float
        ``T`` in seconds.
    """

    def __init__(self, layout, tessellation, shares, duration_s: float = DURATION_S):
        self.layout = layout
        self.edges = layout_edges(tessellation)
        self._shares = shares
        self.duration_ms = 1000.0 * duration_s

    def schedule(self, shape) -> Schedule:
        """The shape's :class:`Schedule` on this layout."""
        cache = _cache(shape)
        hit = cache.get(self)
        if hit is not None:
            return hit
        wrap, tol = self.layout.wrap, shape.snap_tol
        points = _kept(cache, ("layout points", self.layout),
                       lambda: virtual_points(shape, self.edges, wrap))  # fmt: skip

        def shares(x, y):
            return tuple((i, v) for i, v in self._shares(x, y, tol) if v > 0.0)

        return _kept(cache, self, lambda: Schedule(points, shares, self.duration_ms,
                                                   self.layout.size))  # fmt: skip

    def frames(self, shape, t: np.ndarray, tol) -> np.ndarray:
        """Dense ``(n, size)`` intensities at the trace parameters ``t``."""
        schedule = self.schedule(shape)
        window = schedule.windows(t)
        size = self.layout.size
        out = np.zeros((len(t), size + 1))
        rows = np.arange(len(t))
        for picks, values in zip(schedule.picks, schedule.values):
            out[rows, picks.take(window)] = values.take(window)  # distinct within a window
        return out[:, :size]

    def entries1(self, shape, t: float, tol) -> tuple:
        """``((index, value), ...)`` of the lit actuators at ``t``."""
        schedule = self.schedule(shape)
        return schedule.entries1[schedule.window1(t)]
