"""A pattern's frames on one array (:class:`PatternFrames`, the frame source a
:class:`~tactile_core.rendering.scene.Scene` plays).

**A frame.** At each sample time every path active then is rendered by the method on the
actuators of its position's placement (the whole array, or its group's actuators), its
intensity envelope included; the paths combine by the maximum per actuator. Every dot active
then adds its value on the actuator nearest to its motor's place: as bHaptics' own frames show
(docs/tact.md, "bHaptics' own frames"), each dot is first cut to whole hundredths
(``floor(100 v) / 100``, bHaptics' motor values 0..100) and the dots on one actuator add up,
capped at 1. The two combine by the maximum per actuator; then the correction (mu, gamma, gain)
applies and, with the box filter, the frame averages its sub-samples. Frame ``k`` covers
``[k / rate, (k + 1) / rate)`` seconds of the file; frames after the content end are empty.
"""

from __future__ import annotations

import bisect
import math

import numpy as np

from ..rendering.methods import layout_sampler
from ..rendering.rasterize import (
    check_renders,
    layout_entries,
    point_entries,  # fmt: skip
    render,
)
from ..rendering.shapes import FADES
from ._tabled import TabledFrames
from ._tact_coords import fade1

_MARGIN_S = 1e-9
"""Widens the search for effects that may be on at a time by more than the rounding of
``time - longest`` (the exact test ``start <= time <= end`` follows)."""
_HUNDREDTHS = 1e-9
"""Added before a dot's value is cut to hundredths, so that a value that is a whole number of
hundredths in exact arithmetic (0.7 x 0.4 = 0.28) is not cut one below by float rounding."""


def dot_value(level: float, fade: str, u: float) -> float:
    """A dot's value at ``u`` in [0, 1] of its span: ``level`` times its fade, cut to whole
    hundredths as bHaptics' motor values are."""
    return math.floor(level * fade1(fade, u) * 100.0 + _HUNDREDTHS) / 100.0


def _dot_columns(dots) -> tuple:
    """Sorted dots as arrays: starts, ends, actuators, levels, fades (indices of
    :data:`~tactile_core.rendering.shapes.FADES`) and closed ends."""
    return (
        np.array([d[0] for d in dots], dtype=np.float64),
        np.array([d[1] for d in dots], dtype=np.float64),
        np.array([d[2] for d in dots], dtype=np.intp),
        np.array([d[3] for d in dots], dtype=np.float64),
        np.array([FADES.index(d[4]) for d in dots], dtype=np.intp),
        np.array([d[5] for d in dots], dtype=bool),
    )


class PatternFrames(TabledFrames):
    """A pattern's frames on one array, served one at a time (the ``Scene.source`` protocol).

    :meth:`entries` serves frame ``k`` from a table when :meth:`precompute` has built it (the
    vectorised :meth:`render`) and otherwise computes it with scalar arithmetic on the lit
    actuators; both give the same values (tested).

    Parameters
    ----------
    pattern : TactPattern
    method : str or Method
    target : Grid or Layout
    sampling : Sampling
    mu, gamma, gain : float
        The correction.
    """

    def __init__(self, pattern, method, target, sampling, mu, gamma, gain=1.0):
        self._setup(method, target, sampling, mu, gamma, gain)
        self.pattern = pattern
        placed = pattern.placed(self.grid)
        self._places = [place for place, _, _ in placed]
        for place in self._places:
            check_renders(self.method, place.target)
        self.n_frames = max(0, math.ceil(pattern.duration_on(self.grid) * sampling.rate_hz - 1e-9))
        paths = sorted(((p.times_s[0], p.times_s[-1], p, k) for k, (_, shapes, _) in
                        enumerate(placed) for p in shapes), key=lambda e: e[0])  # fmt: skip
        self._paths = paths
        self._starts = [s for s, *_ in paths]
        self._longest = max((e - s for s, e, *_ in paths), default=0.0)
        self._dots = sorted((d for _, _, dots in placed for d in dots), key=lambda d: d[0])
        self._dot_starts = [d[0] for d in self._dots]
        self._dot_longest = max((e - s for s, e, *_ in self._dots), default=0.0)
        self._dot_columns = _dot_columns(self._dots)
        # per path: a method timed by its trace (TB) plays each over the path's own duration
        self._path_entries = {id(p): self._entries_for(self.method.on_clock(e - s), k)
                              for s, e, p, k in paths}  # fmt: skip

    THREAD_NAME = "tactile-tact-precompute"

    def spans(self) -> list:
        """When each path and dot is on: ``[(start_s, end_s), ...]``."""
        return [(s, e) for s, e, *_ in self._paths] + [(d[0], d[1]) for d in self._dots]

    def _entries_for(self, method, k: int):
        """``entries(shape, t)``: the raw ``((index, value), ...)`` of ``method`` on placement
        ``k``, indices of the whole array."""
        place = self._places[k]
        sub = place.target
        if not sub.is_grid:
            sampler = layout_sampler(method, sub)
            found = lambda shape, t: layout_entries(shape, sampler, t)  # noqa: E731
        else:
            sample1, cols, rows = method.sample1, sub.cols, sub.rows
            found = lambda shape, t: point_entries(shape, sample1, t, cols, rows)  # noqa: E731
        if place.index is None:
            return found
        index = place.index.tolist()
        return lambda shape, t: tuple((index[i], v) for i, v in found(shape, t))

    def raw1(self, when: float) -> dict:
        """Combined raw intensities at ``when`` seconds: the paths' maximum per actuator and
        the dots' capped sum, the larger of the two."""
        lit: dict[int, float] = {}
        first = bisect.bisect_left(self._starts, when - self._longest)
        last = bisect.bisect_right(self._starts, when)
        for s, e, shape, _ in self._paths[first:last]:
            if s <= when < e:
                entries = self._path_entries[id(shape)]
                for i, v in entries(shape, min(max((when - s) / (e - s), 0.0), 1.0)):
                    if v > lit.get(i, 0.0):
                        lit[i] = v
        # only the dots that can be on: started by now, and not before the longest could end
        first = bisect.bisect_left(self._dot_starts, when - self._dot_longest - _MARGIN_S)
        last = bisect.bisect_right(self._dot_starts, when)
        added: dict[int, float] = {}
        for s, e, i, level, fade, closed in self._dots[first:last]:
            if s <= when < e or (closed and when == e):
                added[i] = added.get(i, 0.0) + dot_value(level, fade, (when - s) / (e - s))
        for i, v in added.items():
            v = min(v, 1.0)
            if v > lit.get(i, 0.0):
                lit[i] = v
        return {i: v for i, v in lit.items() if v > 0.0}

    def _render_dots(self, when: np.ndarray) -> np.ndarray:
        """The dots' capped sum at the ascending times ``when``, ``(len(when), size)``, all at
        once: each dot is on over a run of the times, found by searching, and only the dots
        that can be on within them are looked at (a file may hold 200,000). The values are
        :func:`dot_value`'s, operation for operation."""
        out = np.zeros((when.size, self.grid.size))
        starts, ends, actuators, levels, fades, closed = self._dot_columns
        a = np.searchsorted(starts, when[0] - self._dot_longest - _MARGIN_S, "left")
        b = np.searchsorted(starts, when[-1], "right")
        if a >= b:
            return out
        s, e = starts[a:b], ends[a:b]
        lo = np.searchsorted(when, s, "left")  # the first time at or after the start
        hi = np.where(closed[a:b], np.searchsorted(when, e, "right"), np.searchsorted(when, e))
        counts = np.maximum(hi - lo, 0)  # ... and before the end (at it, for a closed end)
        total = int(counts.sum())
        if not total:
            return out
        dot = np.repeat(np.arange(b - a), counts)
        at = np.repeat(lo - (np.cumsum(counts) - counts), counts) + np.arange(total)
        u = (when[at] - s[dot]) / (e[dot] - s[dot])
        fade = fades[a:b][dot]
        factor = np.where(fade == 1, u, 1.0)
        factor = np.where(fade == 2, 1.0 - u, factor)
        factor = np.where(fade == 3, 1.0 - np.abs(2.0 * u - 1.0), factor)
        values = np.floor(levels[a:b][dot] * factor * 100.0 + _HUNDREDTHS) / 100.0
        np.add.at(out, (at, actuators[a:b][dot]), values)
        return np.minimum(out, 1.0)

    def raw_at(self, when) -> np.ndarray:
        """Combined raw intensities (uncorrected) at the ascending times ``when`` (seconds from
        the file's start): ``(len(when), size)``. The frames sample these; bHaptics' compiled
        frames are their values at ``k * intervalMillis``."""
        when = np.asarray(when, dtype=np.float64).reshape(-1)
        size = self.grid.size
        raw = np.zeros((when.size, size))
        if not when.size:
            return raw
        first_path = bisect.bisect_left(self._starts, when[0] - self._longest - _MARGIN_S)
        last_path = bisect.bisect_right(self._starts, when[-1])
        for s0, e0, shape, k in self._paths[first_path:last_path]:
            on = (when >= s0) & (when < e0)
            if on.any():
                place = self._places[k]
                t = np.clip((when[on] - s0) / (e0 - s0), 0.0, 1.0)
                method = self.method.on_clock(e0 - s0)  # (TB: the path's own duration)
                lit = render(shape, method, t, grid=place.target).reshape(-1, place.target.size)
                if place.index is not None:
                    full = np.zeros((len(lit), size))
                    full[:, place.index] = lit
                    lit = full
                raw[on] = np.maximum(raw[on], lit)
        return np.maximum(raw, self._render_dots(when))
