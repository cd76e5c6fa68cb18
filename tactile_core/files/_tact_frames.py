"""An imported ``.tact`` file as a *pattern*: frames on this array, by the scene's method.

A :class:`TactPattern` is one device position of a file, kept in bHaptics' 0..1 coordinates;
it is mapped onto an array only when it is played (:meth:`TactPattern.live`, the frame source
a :class:`~tactile_core.rendering.scene.Scene` takes) or rendered (:meth:`TactPattern.frames`).

**The coordinate mapping.** bHaptics' ``(x, y)`` in 0..1, y downward, goes onto the extent of
the array's actuator centres ``[x0, x1] x [y0, y1]`` (:func:`layout_box`):
``X = x0 + x (x1 - x0)``, ``Y = y1 - y (y1 - y0)``. Corner motors land on corner actuators, so a
4 x 5 vest file plays motor for motor on a 4 x 5 vest profile; on the 5 x 6 palm array the
path stretches over the tactors' centres (0.5..4.5 x 0.5..5.5). An axis along which all
actuators line up (a belt's y) maps every coordinate to that line.

**A frame.** At each sample time every path active then is rendered by the method on this
array (its intensity envelope included), every dot active then lights the actuator nearest to
its motor's place (mapped as above) at its intensity, and the raw intensities are combined by
taking the **maximum per actuator**; then the correction (mu, gamma, gain) applies and, with the
box filter, the frame averages its sub-samples. Frame ``k`` covers ``[k / rate, (k + 1) / rate)``
seconds of the file; after the end of the last effect holding the position's content
(:attr:`TactPattern.duration_s`) frames are empty.
"""

from __future__ import annotations

import bisect
import math
import threading
import time
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from .._shared import validate as _validate
from ..rendering.correction import check_correction, correct, correct1
from ..rendering.curves import ActivationCurves, curves_from_frames
from ..rendering.methods import get_method, layout_sampler
from ..rendering.rasterize import (
    check_renders,
    check_target,
    layout_entries,
    point_entries,  # fmt: skip
    render,
)
from ..rendering.shapes import FADES, TimedPath
from ..rendering.trace import MAX_SAMPLES, Sampling, entry_table
from ._tact_coords import fade1, layout_box, unit_to_layout
from ._tact_read import TactError, TactFile

NOTHING_TO_PLAY = "no paths or dots to play (no enabled track holds any)"
"""Why a file without content is refused (:class:`TactPattern`, ``load_pattern`` with the
file's name before it)."""

MAX_TABLE_FRAMES = 200_000
"""Most frames :meth:`PatternFrames.precompute` tabulates (11 minutes at 300 Hz); longer
patterns are computed frame by frame as they play."""


@dataclass(frozen=True, eq=False)
class TactPattern:
    """One device position of a ``.tact`` file, to play on any array.

    Parameters
    ----------
    file : TactFile
        The checked file (:func:`~tactile_core.files.tact.read_tact`).
    position : str, optional
        The device position to play (``"VestFront"``...); by default the first that holds
        paths or dots. The others are listed in :attr:`skipped`.

    Raises
    ------
    TactError
        When no position of the file holds paths or dots (an empty file: nothing to play), or
        ``position`` holds none.
    """

    file: TactFile
    position: str | None = None

    def __post_init__(self):
        positions = self.file.positions
        if not positions:
            raise TactError(NOTHING_TO_PLAY)
        if self.position is None:
            object.__setattr__(self, "position", positions[0])
        elif self.position not in positions:
            held = ", ".join(positions) or "none"
            raise TactError(
                f"position {_validate.shown(self.position)} holds no paths or dots in this file "
                f"(positions with content: {held})"
            )

    @property
    def name(self) -> str:
        """The project's name."""
        return self.file.name

    @property
    def key(self) -> tuple:
        """What makes two patterns the same content (the file's and the position): a copy of
        the scene in the stream's process goes on playing, not from its start."""
        return (self.file, self.position)

    @property
    def duration_s(self) -> float:
        """When the last effect holding this position's paths or dots ends, in seconds: what
        the position lasts played alone (frames after it are empty). The file's other
        positions do not count: the front of a file whose back plays after it ends with its
        own effects (``TactFile.duration_s`` is the whole file's)."""
        return self.file.ends_s.get(self.position, self.file.duration_s)

    @property
    def notes(self) -> tuple:
        """What of this position does not play as the file asks, in words (empty if nothing):
        dot effects with ``dotConnected: true`` play as separate dots (docs/tact.md)."""
        connected = [(field, n) for where, field, n in self.file.connected
                     if where == self.position]  # fmt: skip
        if not connected:
            return ()
        (field, _), dots = connected[0], sum(n for _, n in connected)
        which = (f"{field}.dotConnected is true: its" if len(connected) == 1 else
                 f"{field} and {len(connected) - 1} more dot effects have dotConnected true: "
                 "their")  # fmt: skip
        return (f"{which} {dots} dots play as separate dots, not as a path through them "
                "(not supported)",)  # fmt: skip

    @property
    def skipped(self) -> tuple:
        """The file's other positions with content, which this pattern does not play."""
        return tuple(p for p in self.file.positions if p != self.position)

    def paths(self, target) -> tuple:
        """The position's paths on ``target`` (a Grid or Layout): :class:`TimedPath` shapes in
        layout units, their times in seconds from the file's start."""
        return _paths(self, check_target(target))

    def dots(self, target) -> tuple:
        """The position's dots on ``target``: ``(start_s, end_s, actuator, intensity, fade)``,
        each motor on the actuator nearest to its place."""
        return _dots(self, check_target(target))

    def live(self, method, target, sampling, mu, gamma, gain=1.0) -> PatternFrames:
        """The frame source a :class:`~tactile_core.rendering.scene.Scene` plays (see
        :class:`PatternFrames`): the same object for the same arguments (the latest few are
        kept), so a table tabulated before a stream starts is the one it plays from."""
        try:  # (keyed by the Method, however it was named)
            return _live(self, get_method(method), target, sampling, mu, gamma, gain)
        except TypeError:  # (an argument that cannot be a key: a fresh one, checked there)
            return PatternFrames(self, method, target, sampling, mu, gamma, gain)

    def frames(self, method, target, *, rate_hz: float = 300.0, sampling: Sampling | None = None,
               mu: float = 0.0, gamma: float = 1.0, gain: float = 1.0,
               corrected: bool = True) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
        """All frames of the pattern, as they are streamed.

        Parameters
        ----------
        method : str
            The rendering method (on a layout that is not a grid, one that works there).
        target : Grid or Layout
            The array.
        rate_hz : float, keyword-only
            Frames per second (used when ``sampling`` is None, with point sampling).
        sampling : Sampling, optional
            Rate and temporal filter, as the stream's.
        mu, gamma, gain : float, keyword-only
            The correction; the defaults leave intensities as rendered.
        corrected : bool
            False: the combined raw intensities (filtered, uncorrected).

        Returns
        -------
        time_s : ndarray of float64, shape (n,)
            Start of each frame, ``n = ceil(duration_s * rate)``.
        frames : ndarray of float64, shape ``(n, rows, cols)`` (``(n, size)`` on a layout)
            Intensities in [0, 1].
        """
        sampling = Sampling(rate_hz, "point") if sampling is None else sampling
        live = self.live(method, target, sampling, mu, gamma, gain)
        return live.render(0, live.n_frames, corrected=corrected)

    @property
    def effects(self) -> int:
        """How many paths and dots the position holds (what drawing its curves costs)."""
        file = self.file
        return sum(p.position == self.position for p in file.paths) + sum(
            d.position == self.position for d in file.dots
        )

    def curves(self, method, target, *, mu: float, gamma: float, samples: int = 400,
               motor=None, compensate=None) -> ActivationCurves:  # fmt: skip
        """The pattern's activation curves with ``method`` on ``target``: each actuator it
        lights, raw and corrected, over the pattern's duration (``samples`` point samples,
        the frames' own combination of paths and dots).

        Parameters
        ----------
        method : str
        target : Grid or Layout
        mu, gamma : float, keyword-only
            The correction of the ``corrected`` curves.
        samples : int, keyword-only
            Samples over the duration, >= 3.
        motor : MotorResponse, optional
            Also the curves through the motors (``felt``).
        compensate : MotorResponse, optional
            Also the motor-aware drive for these motors (``drive``; ``felt`` is of it).

        Returns
        -------
        ActivationCurves
            ``time_s``: when each sample was taken (the middle of each of ``samples`` frames
            over :attr:`duration_s`, as the stream's point sampling takes them).
        """
        samples = _validate.integer("samples", samples, 3)
        if self.duration_s <= 0.0:
            raise ValueError("the pattern has no duration to plot")
        sampling = Sampling(samples / self.duration_s, "point")
        start_s, frames = self.frames(method, target, sampling=sampling, corrected=False)
        return curves_from_frames(frames, start_s + sampling.offsets_s()[0], mu=mu,
                                  gamma=gamma, grid=check_target(target), motor=motor,
                                  compensate=compensate)  # fmt: skip


@lru_cache(maxsize=4)
def _live(pattern, method, target, sampling, mu, gamma, gain) -> PatternFrames:
    return PatternFrames(pattern, method, target, sampling, mu, gamma, gain)


@lru_cache(maxsize=16)
def _paths(pattern: TactPattern, target) -> tuple:
    box = layout_box(target)
    out = []
    for path in pattern.file.paths:
        if path.position == pattern.position:
            points = [unit_to_layout(x, y, box) for x, y in path.points]
            out.append(TimedPath(points, path.times_s, path.intensities, path.pattern, path.fade))
    return tuple(out)


@lru_cache(maxsize=16)
def _dots(pattern: TactPattern, target) -> tuple:
    box = layout_box(target)
    layout = target
    motors = pattern.file.layouts.get(pattern.position, {})
    out = []
    for dot in pattern.file.dots:
        if dot.position == pattern.position:
            x, y = unit_to_layout(*motors[dot.index], box)
            out.append((dot.start_s, dot.end_s, layout.nearest(x, y), dot.intensity, dot.fade))
    return tuple(out)


_MARGIN_S = 1e-9
"""Widens the search for effects that may be on at a time by more than the rounding of
``time - longest`` (the exact test ``start <= time < end`` follows)."""


def _dot_columns(dots) -> tuple:
    """Sorted dots as arrays: starts, ends, actuators, levels and fades (indices of
    :data:`~tactile_core.rendering.shapes.FADES`)."""
    return (
        np.array([d[0] for d in dots], dtype=np.float64),
        np.array([d[1] for d in dots], dtype=np.float64),
        np.array([d[2] for d in dots], dtype=np.intp),
        np.array([d[3] for d in dots], dtype=np.float64),
        np.array([FADES.index(d[4]) for d in dots], dtype=np.intp),
    )


class PatternFrames:
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
        if not isinstance(sampling, Sampling):
            raise ValueError(f"sampling must be a Sampling, got {_validate.shown(sampling)}")
        self.pattern = pattern
        self.method = get_method(method)
        self.grid = check_target(target)
        check_renders(self.method, self.grid)
        self.sampling = sampling
        self.mu, self.gamma = check_correction(mu, gamma)
        self.gain = _validate.in_range("gain", gain, 0.0, 1.0)
        self.n_frames = max(0, math.ceil(pattern.duration_s * sampling.rate_hz - 1e-9))
        paths = sorted(pattern.paths(self.grid), key=lambda p: p.times_s[0])
        self._paths = [(p.times_s[0], p.times_s[-1], p) for p in paths]
        self._starts = [s for s, _, _ in self._paths]
        self._longest = max((e - s for s, e, _ in self._paths), default=0.0)
        self._dots = sorted(pattern.dots(self.grid), key=lambda d: d[0])
        self._dot_starts = [d[0] for d in self._dots]
        self._dot_longest = max((e - s for s, e, *_ in self._dots), default=0.0)
        self._dot_columns = _dot_columns(self._dots)
        # per path: a method timed by its trace (TB) plays each over the path's own duration
        self._path_entries = {id(p): self._entries_for(self.method.on_clock(e - s))
                              for s, e, p in self._paths}  # fmt: skip
        self._offsets = sampling.offsets_s().tolist()
        self._table: list | None = None

    def _entries_for(self, method):
        """``entries(shape, t)``: the raw ``((index, value), ...)`` of ``method`` on the target."""
        if not self.grid.is_grid:
            sampler = layout_sampler(method, self.grid)
            return lambda shape, t: layout_entries(shape, sampler, t)
        sample1, cols, rows = method.sample1, self.grid.cols, self.grid.rows
        return lambda shape, t: point_entries(shape, sample1, t, cols, rows)

    @property
    def precomputed(self) -> bool:
        """True once the table is in use."""
        return self._table is not None

    def busiest_frame(self) -> int:
        """The frame at which the most paths and dots are on (the first such), 0 if none."""
        spans = [(s, e) for s, e, _ in self._paths] + [(d[0], d[1]) for d in self._dots]
        edges = sorted([(s, 1) for s, _ in spans] + [(e, -1) for _, e in spans])
        on, most, when = 0, 0, 0.0
        for t, step in edges:  # (an end sorts before a start at the same time)
            on += step
            if on > most:
                most, when = on, t
        return min(int(when * self.sampling.rate_hz), max(self.n_frames - 1, 0))

    def busiest_frame_s(self) -> float:
        """Seconds the scalar path takes for :meth:`busiest_frame`: what playing costs a frame
        before the table is built (measured here, the best of two)."""
        k = self.busiest_frame()
        best = math.inf
        for _ in range(2):
            start = time.perf_counter()
            self.compute(k)
            best = min(best, time.perf_counter() - start)
        return best

    def precompute(self, background: bool = False) -> None:
        """Tabulate every frame (no-op beyond :data:`MAX_TABLE_FRAMES`); with
        ``background=True`` in a daemon thread, frames coming from the scalar path meanwhile."""
        if self._table is not None or self.n_frames > MAX_TABLE_FRAMES:
            return
        if background:
            threading.Thread(target=self._build, args=(64,), name="tactile-tact-precompute",
                             daemon=True).start()  # fmt: skip
            return
        self._build(self.n_frames)

    def _build(self, chunk: int) -> None:
        table = []
        for first in range(0, self.n_frames, max(chunk, 1)):
            count = min(chunk, self.n_frames - first)
            _, frames = self.render(first, count)
            table.extend(entry_table(frames.reshape(count, self.grid.size)))
            if chunk < self.n_frames:
                time.sleep(0)  # let a concurrent output thread run between chunks
        self._table = table

    def entries(self, k: int) -> tuple:
        """Lit actuators of frame ``k`` (from the scene's start): ``((index, corrected value),
        ...)``; empty after the pattern's end."""
        if not 0 <= k < self.n_frames:
            return ()
        table = self._table
        return table[k] if table is not None else self.compute(k)

    def compute(self, k: int) -> tuple:
        """Frame ``k`` by the scalar path, whether or not a table exists."""
        start = k / self.sampling.rate_hz
        mu, gamma, gain = self.mu, self.gamma, self.gain
        acc: dict[int, float] = {}
        for offset in self._offsets:
            for i, v in self._raw(start + offset).items():
                acc[i] = acc.get(i, 0.0) + correct1(v, mu, gamma, gain)
        scale = 1.0 / len(self._offsets)
        return tuple((i, v * scale) for i, v in acc.items())

    def _raw(self, when: float) -> dict:
        """Combined raw intensities at ``when`` seconds: the maximum per actuator."""
        lit: dict[int, float] = {}
        first = bisect.bisect_left(self._starts, when - self._longest)
        last = bisect.bisect_right(self._starts, when)
        for s, e, shape in self._paths[first:last]:
            if s <= when < e:
                entries = self._path_entries[id(shape)]
                for i, v in entries(shape, min(max((when - s) / (e - s), 0.0), 1.0)):
                    if v > lit.get(i, 0.0):
                        lit[i] = v
        # only the dots that can be on: started by now, and not before the longest could end
        first = bisect.bisect_left(self._dot_starts, when - self._dot_longest - _MARGIN_S)
        last = bisect.bisect_right(self._dot_starts, when)
        for s, e, i, level, fade in self._dots[first:last]:
            if s <= when < e:
                v = level * fade1(fade, (when - s) / (e - s))
                if v > lit.get(i, 0.0):
                    lit[i] = v
        return lit

    def _render_dots(self, when: np.ndarray, raw: np.ndarray) -> None:
        """Combine the dots on at the ascending times ``when`` into ``raw`` (``(len(when),
        size)``, the maximum per actuator), all at once: each dot is on over a run of the
        times, found by searching, and only the dots that can be on within them are looked
        at (a file may hold 200,000). The values are :func:`fade1`'s, operation for
        operation."""
        starts, ends, actuators, levels, fades = self._dot_columns
        a = np.searchsorted(starts, when[0] - self._dot_longest - _MARGIN_S, "left")
        b = np.searchsorted(starts, when[-1], "right")
        if a >= b:
            return
        s, e = starts[a:b], ends[a:b]
        lo = np.searchsorted(when, s, "left")  # the first time at or after the start
        counts = np.maximum(np.searchsorted(when, e, "left") - lo, 0)  # ... and before the end
        total = int(counts.sum())
        if not total:
            return
        dot = np.repeat(np.arange(b - a), counts)
        at = np.repeat(lo - (np.cumsum(counts) - counts), counts) + np.arange(total)
        u = (when[at] - s[dot]) / (e[dot] - s[dot])
        fade = fades[a:b][dot]
        factor = np.where(fade == 1, u, 1.0)
        factor = np.where(fade == 2, 1.0 - u, factor)
        factor = np.where(fade == 3, 1.0 - np.abs(2.0 * u - 1.0), factor)
        np.maximum.at(raw, (at, actuators[a:b][dot]), levels[a:b][dot] * factor)

    def frame(self, k: int) -> np.ndarray:
        """Frame ``k`` as a dense array: ``(rows, cols)`` on a grid, ``(size,)`` on a layout."""
        out = np.zeros(self.grid.size)
        for i, v in self.entries(k):
            out[i] = v
        return out.reshape(self.grid.frame_shape)

    def render(self, first: int, count: int, *, corrected: bool = True):
        """Frames ``first .. first + count - 1`` at once: ``(time_s, frames)`` as
        :meth:`TactPattern.frames` returns them."""
        count = _validate.integer("count", count, 0)
        first = _validate.integer("first", first, 0)
        s = len(self._offsets)
        if count * s > MAX_SAMPLES:
            raise ValueError(f"count x subsamples must be at most {MAX_SAMPLES:.0e}, got "
                             f"{count} x {s}: render in chunks")  # fmt: skip
        rate, size = self.sampling.rate_hz, self.grid.size
        start = (np.arange(count) + first) / rate
        when = (start[:, None] + self.sampling.offsets_s()[None, :]).reshape(-1)
        raw = np.zeros((when.size, size))
        if when.size:
            first_path = bisect.bisect_left(self._starts, when[0] - self._longest - _MARGIN_S)
            last_path = bisect.bisect_right(self._starts, when[-1])
            for s0, e0, shape in self._paths[first_path:last_path]:
                on = (when >= s0) & (when < e0)
                if on.any():
                    t = np.clip((when[on] - s0) / (e0 - s0), 0.0, 1.0)
                    method = self.method.on_clock(e0 - s0)  # (TB: the path's own duration)
                    lit = render(shape, method, t, grid=self.grid).reshape(-1, size)
                    raw[on] = np.maximum(raw[on], lit)
            self._render_dots(when, raw)
        if corrected:
            raw = correct(raw, self.mu, self.gamma, gain=self.gain)
        frames = raw.reshape(count, s, size).mean(axis=1)
        return start, frames.reshape((count, *self.grid.frame_shape))
