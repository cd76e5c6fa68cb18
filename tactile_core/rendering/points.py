"""Free points: positions another program sends, rendered each frame with a scene's method.

A :class:`FreePoints` table holds named points ``{id: (x, y, intensity, time of the update)}``.
Any thread may write it (the OSC server's, a script's); the streamer's output thread reads it
once per frame through the frame source that :meth:`FreePoints.live` returns, which is what a
:class:`~tactile_core.rendering.scene.Scene` takes as its ``source``::

    points = FreePoints()
    scene = Scene(method="AS", source=points)   # hand it to a streamer once
    points.set("hand", 2.5, 3.0)                 # then move the point from any thread

Threads: a writer builds a new dictionary and swaps it in under a lock that only writers take;
the output thread reads whichever dictionary is current (one reference, read atomically) and
never waits for a writer. Each point is an immutable tuple.

Per frame, at the frame's time ``now`` (the clock read when the frame is computed, just before
it is written):

- a point whose newest update is older than ``timeout_s`` (100 ms by default) is not rendered,
  so a sender that crashed or lost its network never leaves a motor on (:meth:`expire` also
  drops it from the table, for the counters);
- *newest* (default): each point is where its newest update put it; updates arriving faster
  than the frame rate are resampled by taking the newest, slower ones are held;
- *interpolated* (``interpolate=True``): the point moves from its previous update to its newest
  over the time between the two, starting when the newest arrived, so a 30 Hz sender gives
  smooth motion at 300 frames a second at the cost of one update interval of delay; an interval
  longer than the timeout or 1 s (a sender that paused) is not interpolated: the point jumps;
- each point is rendered by the scene's method (one that needs no shape: CT, AS, EN, PK, RO,
  GS, VRCH, BA, or a plug-in; MM and IM are refused as for :func:`~.rasterize.render_xy`) and
  corrected with its intensity as the master intensity: a lit tactor gets
  ``mu + gain * intensity * (1 - mu) * I**gamma``; intensity 0 lights nothing;
- several points on one tactor: the tactor gets the largest of their corrected values (max,
  ``docs/decisions.md``).

With the box filter, the values are averaged over the scene's sub-sample times within the frame
period just ended (a difference only for interpolated points).

From :data:`BATCH_FROM` points on, a frame renders all of them with a handful of numpy calls
(:meth:`PointFrames.at_many`: the method's batch form on a grid, :attr:`LayoutSampler.many
<tactile_core.rendering.methods._layout.LayoutSampler>` on a layout) instead of one Python loop
per point (:meth:`PointFrames.at_each`, about 3-10 µs a point): the same candidates and the
same operations, so the same values to rounding (``tests/test_live_points.py`` compares them).
64 points on a 255-actuator layout cost 113-220 µs a frame instead of 0.3-1.5 ms
(``docs/benchmarks.md``, Many free points). Plug-ins are rendered point by point.
"""

from __future__ import annotations

import math
import threading
import time
from itertools import chain
from typing import NamedTuple

import numpy as np

from .._shared import validate as _validate
from .correction import check_correction, correct1
from .geometry import SNAP_REL
from .methods import layout_sampler
from .rasterize import check_target, free_method

DEFAULT_TIMEOUT_S = 0.1
"""A point not refreshed within this long is released (the contract's 100 ms)."""
MAX_POINTS = 64
"""Most points at once: the cost of a frame stays bounded whatever a sender does."""
TIMEOUT_RANGE_S = (0.001, 60.0)
"""Timeouts a points table takes, in seconds."""
MAX_ID_CHARS = 64
BATCH_FROM = 16
"""Points from which a frame renders them all at once (below, one by one is cheaper)."""
_NO_PREVIOUS = (math.nan,) * 4


class Point(NamedTuple):
    """One point as its newest update left it, with the update before (for interpolation)."""

    x: float
    y: float
    intensity: float
    time_s: float
    previous: tuple | None = None
    """``(x, y, intensity, time_s)`` of the update before, or None (a new point)."""


class FreePoints:
    """A table of named points, written from any thread, rendered by the output thread.

    Parameters
    ----------
    timeout_s : float or None
        A point not refreshed within this long is released (0.1 s by default; 0.001 to 60).
        None: a point stays until released (a script's points; never for a network sender).
    interpolate : bool
        Move each point from its previous update to its newest (see the module's notes) instead
        of showing the newest at once.
    max_points : int
        Most points at once (1 to 1024); a new id beyond it raises ``ValueError``.
    clock : callable
        Seconds on the streamer's clock (``time.perf_counter`` by default).
    """

    def __init__(self, *, timeout_s: float | None = DEFAULT_TIMEOUT_S, interpolate: bool = False,
                 max_points: int = MAX_POINTS, clock=time.perf_counter):  # fmt: skip
        if timeout_s is not None:
            timeout_s = _validate.in_range("timeout_s", timeout_s, *TIMEOUT_RANGE_S)
        self.timeout_s = timeout_s
        self._limit = math.inf if timeout_s is None else timeout_s
        self.interpolate = _validate.boolean("interpolate", interpolate)
        self.max_points = _validate.integer("max_points", max_points, 1, 1024)
        self.clock = clock
        self._points: dict = {}
        self._write = threading.Lock()

    def __reduce__(self):
        raise TypeError(
            "free points are fed and rendered in one process: stream them from a thread of "
            "this process (open_stream(..., process=False)), not through the stream process"
        )

    @property
    def points(self) -> dict:
        """The current points, ``{id: Point}`` (a snapshot: never changes after it is read)."""
        return self._points

    def set(self, point_id, x, y, intensity=1.0, *, time_s: float | None = None) -> None:
        """Put point ``point_id`` (a string of 0 to 64 characters) at ``(x, y)`` in grid units
        (layout units on a layout) with ``intensity`` in [0, 1]; ``ValueError`` names a bad
        value. ``time_s``: when the update arrived (now by default)."""
        if not isinstance(point_id, str) or len(point_id) > MAX_ID_CHARS:
            raise ValueError(
                f"point id must be a string of at most {MAX_ID_CHARS} characters, got "
                f"{_validate.shown(point_id)}"
            )
        x = _validate.coordinate("x", x)
        y = _validate.coordinate("y", y)
        intensity = _validate.in_range("intensity", intensity, 0.0, 1.0)
        self.put(point_id, x, y, intensity, self.clock() if time_s is None else time_s)

    def put(self, point_id: str, x: float, y: float, intensity: float, now: float) -> None:
        """:meth:`set` for a caller that checked every value (the OSC server, per message)."""
        with self._write:
            points = self._points
            old = points.get(point_id)
            if old is None and len(points) >= self.max_points:
                raise ValueError(
                    f"point {_validate.shown(point_id)}: already {self.max_points} points "
                    "(release some first)"
                )
            fresh = old is not None and now - old.time_s <= self._limit
            before = (old.x, old.y, old.intensity, old.time_s) if fresh else None
            new = dict(points)
            new[point_id] = Point(x, y, intensity, now, before)
            self._points = new

    def release(self, point_id=None) -> int:
        """Release one point (None: all); how many were released. ``ValueError`` for an id
        that is not a string (a point id always is)."""
        if point_id is not None and not isinstance(point_id, str):
            raise ValueError(f"point id must be a string or None, got {_validate.shown(point_id)}")
        with self._write:
            points = self._points
            if point_id is None:
                self._points = {}
                return len(points)
            if point_id not in points:
                return 0
            new = dict(points)
            del new[point_id]
            self._points = new
            return 1

    def expire(self, now_s: float | None = None) -> int:
        """Drop the points not refreshed within the timeout; how many were dropped. (The
        frames already leave them out: this keeps the table and its counters honest.)"""
        now = self.clock() if now_s is None else now_s
        with self._write:
            points = self._points
            keep = {k: p for k, p in points.items() if now - p.time_s <= self._limit}
            if len(keep) != len(points):
                self._points = keep
            return len(points) - len(keep)

    def live(self, method, target, sampling, mu, gamma, gain=1.0) -> PointFrames:
        """The frame source of a :class:`~tactile_core.rendering.scene.Scene`: frames of the
        current points with ``method`` on ``target`` (a Grid or a Layout)."""
        return PointFrames(self, method, target, sampling, mu, gamma, gain)


class PointFrames:
    """Frames of a :class:`FreePoints` table with one method and correction, for the streamer.

    :meth:`entries` renders the points as they are at the moment it is called (frame ``k`` is
    only counted); nothing is tabulated, so :meth:`precompute` does nothing.
    """

    precomputed = False

    def __init__(self, points: FreePoints, method, target, sampling, mu, gamma, gain=1.0):
        self.table = points
        self.method = free_method(method)
        self.target = check_target(target)
        self.mu, self.gamma = check_correction(mu, gamma)
        self.gain = _validate.in_range("gain", gain, 0.0, 1.0)
        self.sampling = sampling
        offsets = sampling.offsets_s().tolist()
        period = 1.0 / sampling.rate_hz
        self._lags = [period - o for o in offsets] if len(offsets) > 1 else [0.0]
        self._many = None
        if not self.target.is_grid:
            sampler = layout_sampler(self.method, self.target)
            entries1 = sampler.entries1
            self._entries1 = lambda x, y, tol: [(i, v) for i, v in entries1(x, y, tol) if v > 0]
            self._many = sampler.many
            self._size = self.target.size
        else:
            cols, rows, sample1 = self.target.cols, self.target.rows, self.method.sample1
            self._entries1 = lambda x, y, tol: [
                (r * cols + c, v)
                for c, r, v in sample1(None, x, y, None, tol)
                if v > 0.0 and 0 <= c < cols and 0 <= r < rows
            ]
            if not self.method.plugin and not self.method.needs_shape:
                self._many = _grid_many(self.method, cols, rows)
            self._size = cols * rows

    def precompute(self, background: bool = False) -> None:
        """Nothing to tabulate: free points change every frame."""

    def entries(self, k: int) -> tuple:
        """Lit tactors now: ``((flat index, corrected value), ...)``."""
        points = self.table.points
        if not points:
            return ()
        now = self.table.clock()
        if len(self._lags) == 1:
            return tuple(self.at(points, now).items())
        acc: dict[int, float] = {}
        for lag in self._lags:
            for i, v in self.at(points, now - lag).items():
                acc[i] = acc.get(i, 0.0) + v
        scale = 1.0 / len(self._lags)
        return tuple((i, v * scale) for i, v in acc.items())

    def at(self, points: dict, now: float) -> dict:
        """``{index: corrected value}`` of ``points`` at time ``now`` (max over points):
        :meth:`at_many` from :data:`BATCH_FROM` points on, else :meth:`at_each`."""
        if self._many is not None and len(points) >= BATCH_FROM:
            return self.at_many(points, now)
        return self.at_each(points, now)

    def at_each(self, points: dict, now: float) -> dict:
        """:meth:`at`, one point at a time with plain floats."""
        timeout = self.table._limit
        interpolate = self.table.interpolate
        mu, gamma, gain = self.mu, self.gamma, self.gain
        out: dict[int, float] = {}
        for p in points.values():
            age = now - p.time_s
            if age > timeout:
                continue
            x, y, a = p.x, p.y, p.intensity
            if interpolate and p.previous is not None and age >= 0.0:
                px, py, pa, pt = p.previous
                span = p.time_s - pt
                if 0.0 < span <= min(timeout, 1.0) and age < span:
                    f = age / span
                    x, y, a = px + (x - px) * f, py + (y - py) * f, pa + (a - pa) * f
            if a <= 0.0:
                continue
            tol = SNAP_REL * max(abs(x), abs(y), 1.0)
            for i, v in self._entries1(x, y, tol):
                value = correct1(v, mu, gamma, gain * a)
                if value > out.get(i, 0.0):
                    out[i] = value
        return out

    def at_many(self, points: dict, now: float) -> dict:
        """:meth:`at` for all the points at once, in arrays: what :meth:`at_each` computes,
        with the same operations (the method's batch form, ``LayoutSampler.many`` on a layout)."""
        n = len(points)
        interpolate = self.table.interpolate
        if interpolate:  # (numpy reads a flat iterator of floats 2-4 x faster than tuples)
            fields = chain.from_iterable(p[:4] + (p.previous or _NO_PREVIOUS)
                                         for p in points.values())  # fmt: skip
        else:
            fields = chain.from_iterable(p[:4] for p in points.values())
        table = np.fromiter(fields, np.float64, (8 if interpolate else 4) * n).reshape(n, -1)
        x, y, a, t = table[:, 0], table[:, 1], table[:, 2], table[:, 3]
        timeout = self.table._limit
        age = now - t
        if interpolate:
            px, py, pa, pt = table[:, 4], table[:, 5], table[:, 6], table[:, 7]
            span = t - pt  # NaN without a previous update: every test below is False
            moving = (age >= 0.0) & (span > 0.0) & (span <= min(timeout, 1.0)) & (age < span)
            if moving.any():
                with np.errstate(invalid="ignore", divide="ignore"):
                    f = age / span
                    x = np.where(moving, px + (x - px) * f, x)
                    y = np.where(moving, py + (y - py) * f, y)
                    a = np.where(moving, pa + (a - pa) * f, a)
        keep = (age <= timeout) & (a > 0.0)
        if not keep.all():
            x, y, a = x[keep], y[keep], a[keep]
        if not len(x):
            return {}
        tol = SNAP_REL * np.maximum(np.maximum(np.abs(x), np.abs(y)), 1.0)
        point, index, value = self._many(x, y, tol)
        lit = (value > 0.0) & (index >= 0)
        point, index, value = point[lit], index[lit], value[lit]
        mu = self.mu
        scale = (self.gain * a) * (1.0 - mu)  # correct1's gain * (1 - mu), per point
        value = np.minimum(mu + scale[point] * value**self.gamma, 1.0)
        out = np.zeros(self._size)
        np.maximum.at(out, index, value)
        lit = np.flatnonzero(out)
        return dict(zip(lit.tolist(), out[lit].tolist()))


def _grid_many(method, cols: int, rows: int):
    """``many(x, y, tol) -> (point, index, value)`` from a built-in grid method's batch form
    (:mod:`.methods._cells`), as :attr:`~.methods._layout.LayoutSampler.many` gives them: flat
    indices ``row * cols + col`` (-1 off the grid). None for a method without that form; one
    whose candidates add up (IM's, which needs a shape and never renders points) raises."""
    sample_cells = method.sample_cells
    if sample_cells is None:
        return None

    def many(x, y, tol):
        found = sample_cells(None, np.stack([x, y]), None, tol)
        if not hasattr(found, "selectors"):
            found = found.cells()  # a Block or Indexed: its candidates as Cells
        if found.add:
            raise ValueError(f"method {method.name}: candidates that add up have no batch form")
        col_index, row_index = found.selectors()
        c, r = found.cols[col_index], found.rows[row_index]  # (k, n)
        v = np.broadcast_to(found.values, c.shape).reshape(c.shape)
        on = (c >= 0) & (c < cols) & (r >= 0) & (r < rows)
        index = np.where(on, r * cols + c, -1).astype(np.intp)
        point = np.broadcast_to(np.arange(c.shape[1]), c.shape)
        return point.reshape(-1), index.reshape(-1), v.reshape(-1)

    return many
