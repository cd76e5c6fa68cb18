"""A pattern's frames on one array: its effects laid out as *parts*, found by time, combined.

Each effect becomes parts when it is played on an array: a shape is one *stroke* drawn by its
method over each play; each dot is a *dot* part; an imported ``.tact`` effect gives a stroke per
path and a dot part per dot, its 0..1 coordinates mapped onto the extent of the effect's group
(:func:`~tactile_core.files.tact.unit_to_layout`). A part knows its effect's span, the length of
one play, and its own window within a play. An index of the parts by time (:class:`_Spans`)
hands each frame only the parts that can be on then: a frame computes what is lit, never the
whole pattern.

At a sample time each part that is on gives raw intensities (a stroke: its method's, times its
shape's own envelope; a dot: its intensity times its fade), times its effect's envelope,
restricted to its group; the pattern's rule combines them (the maximum per actuator, or the sum
clipped to 1); then the correction applies, and the box filter averages sub-samples.
"""

from __future__ import annotations

import bisect
import math

import numpy as np

from ..rendering.rasterize import check_renders, render
from ..rendering.shapes import FADES
from ._pattern_parts import compile_parts
from ._tabled import TabledFrames
from ._tact_coords import fade1

BLOCK_SAMPLES = 256
"""Samples rendered together (a block of a table or of :meth:`PatternFrames.render`)."""
BLOCK_DOTS = 2048
"""Dots compared with a block of samples at once (bounds the arrays to 256 x 2048)."""


class _Spans:
    """The parts' spans ``[start, end)`` in buckets of one width, as sorted arrays: the parts
    that may be on at a time, or within an interval, without looking at the others.

    The width is a quarter of the mean span (at least 1 ms), so the buckets hold about five
    entries per part, however long the pattern or its longest effect."""

    def __init__(self, starts: np.ndarray, ends: np.ndarray):
        n = len(starts)
        self.width = max(float((ends - starts).sum()) / (4 * n), 1e-3) if n else 1.0
        first = np.floor(starts / self.width).astype(np.int64)
        last = np.maximum(np.ceil(ends / self.width).astype(np.int64) - 1, first)
        counts = last - first + 1
        part = np.repeat(np.arange(n), counts)
        step = np.arange(int(counts.sum())) - np.repeat(np.cumsum(counts) - counts, counts)
        bucket = np.repeat(first, counts) + step
        order = np.lexsort((part, bucket))
        self.parts = part[order]
        keys, begins = np.unique(bucket[order], return_index=True)
        self.keys = keys.tolist()
        self.offsets = [*begins.tolist(), len(self.parts)]
        self._lists: dict[int, list] = {}

    def at(self, when: float) -> list:
        """Indices of the parts that may be on at ``when`` s, ascending."""
        b = math.floor(when / self.width)
        hit = self._lists.get(b)
        if hit is None:
            k = bisect.bisect_left(self.keys, b)
            found = k < len(self.keys) and self.keys[k] == b
            hit = self.parts[self.offsets[k] : self.offsets[k + 1]].tolist() if found else []
            if len(self._lists) > 4096:
                self._lists.clear()
            self._lists[b] = hit
        return hit

    def between(self, t0: float, t1: float) -> np.ndarray:
        """Indices of the parts that may be on within ``[t0, t1]``, ascending, unique."""
        lo = bisect.bisect_left(self.keys, math.floor(t0 / self.width))
        hi = bisect.bisect_right(self.keys, math.floor(t1 / self.width))
        return np.unique(self.parts[self.offsets[lo] : self.offsets[hi]])


def _phases(part, when: np.ndarray):
    """``(samples, phase_s)``: which of the ascending ``when`` fall in ``part``'s window, and
    how far into a play each is (the scalar path's arithmetic, element by element)."""
    offset = when - part.start
    idx = np.flatnonzero((offset >= 0.0) & (when < part.end))
    off = offset[idx]
    r = np.minimum(np.floor(off / part.period), part.repeat - 1)
    phase = np.minimum(np.maximum(off - r * part.period, 0.0), part.period)
    keep = (phase >= part.a) & (phase < part.stop)
    return idx[keep], phase[keep]


def gains(effect, phase: np.ndarray) -> np.ndarray:
    """The envelope's gains at ``phase`` (seconds into a play), as :meth:`Effect.gain1`."""
    env = effect.envelope
    if not env:
        return np.ones(len(phase))
    times = np.array([t for t, _ in env])
    values = np.array([g for _, g in env])
    j = np.clip(np.searchsorted(times, phase, "left") - 1, 0, max(len(env) - 2, 0))
    if len(env) == 1:
        return np.full(len(phase), values[0])
    t0, g0, t1, g1 = times[j], values[j], times[j + 1], values[j + 1]
    out = g0 + (g1 - g0) * (phase - t0) / (t1 - t0)
    out = np.where(phase <= times[0], values[0], out)
    return np.where(phase > times[-1], values[-1], out)


class PatternFrames(TabledFrames):
    """A pattern's frames on one array, served one at a time (the ``Scene.source`` protocol,
    as :class:`~tactile_core.files.tact.PatternFrames` of an imported ``.tact`` file).

    :meth:`entries` serves frame ``k`` from a table once :meth:`precompute` has built it
    (:meth:`render`, vectorised) and otherwise computes it by the scalar path, on the parts
    that are on; both give the same values (tested).

    Parameters
    ----------
    pattern : Pattern
    method : str or Method
        The scene's method: the effects' that name none render with it.
    target : Grid or Layout
    sampling : Sampling
    mu, gamma, gain : float
        The correction.
    """

    def __init__(self, pattern, method, target, sampling, mu, gamma, gain=1.0):
        self._setup(method, target, sampling, mu, gamma, gain)
        self.pattern = pattern
        if any(e.method is None and e.kind != "dots" for e in pattern.effects):
            check_renders(self.method, self.grid)
        self._parts = compile_parts(pattern, self.method, self.grid)
        self._sum = pattern.combine == "sum"
        self.n_frames = max(0, math.ceil(pattern.duration_s * sampling.rate_hz - 1e-9))
        starts = np.array([p.lo for p in self._parts], dtype=np.float64)
        ends = np.array([p.hi for p in self._parts], dtype=np.float64)
        self._spans = _Spans(starts, ends)
        self._dots = [k for k, p in enumerate(self._parts) if p.shape is None]
        self._first_dot = self._dots[0] if self._dots else len(self._parts)
        self._columns = _dot_columns([self._parts[k] for k in self._dots])
        self._waveforms = any(e.waveform is not None for e in pattern.effects)

    FOREGROUND_CHUNK = BLOCK_SAMPLES
    THREAD_NAME = "tactile-pattern-precompute"

    def spans(self) -> list:
        """When each part is on: ``[(start_s, end_s), ...]``."""
        return [(p.lo, p.hi) for p in self._parts]

    def _found(self, part, when: float):
        """What ``part`` lights at ``when`` seconds: ``[(actuator, raw value), ...]``, or None
        when it is not on then."""
        offset = when - part.start
        if offset < 0.0 or when >= part.end:
            return None
        r = min(math.floor(offset / part.period), part.repeat - 1)
        phase = min(max(offset - r * part.period, 0.0), part.period)
        if not part.a <= phase < part.stop:
            return None
        g = part.effect.gain1(phase)
        if g <= 0.0:
            return None
        u = min(max((phase - part.a) / (part.b - part.a), 0.0), 1.0)
        if part.shape is not None:
            mask = part.mask
            return [(i, v * g) for i, v in part.entries(part.shape, u)
                    if mask is None or i in mask]  # fmt: skip
        return [(part.actuator, part.level * fade1(FADES[part.fade], u) * g)]

    def raw1(self, when: float) -> dict:
        """Combined raw intensities at ``when`` seconds: ``{actuator: value}`` of the lit."""
        lit: dict[int, float] = {}
        add = self._sum
        for n in self._spans.at(when):
            found = self._found(self._parts[n], when)
            for i, v in found or ():
                if add:
                    lit[i] = lit.get(i, 0.0) + v
                elif v > lit.get(i, 0.0):
                    lit[i] = v
        if add:
            return {i: min(v, 1.0) for i, v in lit.items() if v > 0.0}
        return {i: v for i, v in lit.items() if v > 0.0}

    @property
    def waveforms(self) -> bool:
        """True if some effect asks for a waveform of its own (:meth:`voices`)."""
        return self._waveforms

    def voices(self, k: int) -> tuple | None:
        """The waveforms frame ``k`` asks for, one per actuator (a
        :class:`~tactile_core.device.waveform.Waveform`, or None: the device's own), or None
        when it asks for none. An actuator plays the waveform of the effect that gives it its
        largest raw intensity within the frame (the first such effect on a tie); an effect
        without a waveform gives the device's."""
        if not self._waveforms or not 0 <= k < self.n_frames:
            return None
        start = k / self.sampling.rate_hz
        best: dict[int, tuple] = {}
        for offset in self._offsets:
            when = start + offset
            for n in self._spans.at(when):
                part = self._parts[n]
                for i, v in self._found(part, when) or ():
                    if v > 0.0 and v > best.get(i, (0.0,))[0]:
                        best[i] = (v, part.effect.waveform)
        if all(w is None for _, w in best.values()):
            return None
        chosen = [None] * self.grid.size
        for i, (_, waveform) in best.items():
            chosen[i] = waveform
        return tuple(chosen)

    def raw_at(self, when_s: np.ndarray) -> np.ndarray:
        """Combined raw intensities at the ascending times ``when_s`` (seconds from the
        pattern's start), before the correction: ``(len(when_s), size)`` float64."""
        when = np.asarray(when_s, dtype=np.float64).reshape(-1)
        raw = np.zeros((when.size, self.grid.size))
        for lo in range(0, when.size, BLOCK_SAMPLES):
            self._render_block(when[lo : lo + BLOCK_SAMPLES], raw[lo : lo + BLOCK_SAMPLES])
        if self._sum:
            np.minimum(raw, 1.0, out=raw)
        return raw

    def _render_block(self, when: np.ndarray, raw: np.ndarray) -> None:
        """Combine the parts on at the ascending times ``when`` into ``raw`` (a view)."""
        if not when.size:
            return
        found = self._spans.between(float(when[0]), float(when[-1]))
        cut = int(np.searchsorted(found, self._first_dot))
        for n in found[:cut].tolist():
            part = self._parts[n]
            idx, phase = _phases(part, when)
            if not idx.size:
                continue
            u = np.minimum(np.maximum((phase - part.a) / (part.b - part.a), 0.0), 1.0)
            lit = render(part.shape, part.method, u, grid=self.grid).reshape(-1, raw.shape[1])
            lit *= gains(part.effect, phase)[:, None]
            if part.mask_vec is not None:
                lit *= part.mask_vec
            if self._sum:
                raw[idx] += lit
            else:
                raw[idx] = np.maximum(raw[idx], lit)
        dots = found[cut:] - self._first_dot
        for lo in range(0, dots.size, BLOCK_DOTS):
            self._render_dots(when, raw, dots[lo : lo + BLOCK_DOTS])

    def _render_dots(self, when: np.ndarray, raw: np.ndarray, which: np.ndarray) -> None:
        """The dot parts ``which`` (indices into the dot columns) on ``when``, into ``raw``."""
        c = {name: column[which] for name, column in self._columns.items()}
        offset = when[:, None] - c["start"][None, :]
        on = (offset >= 0.0) & (when[:, None] < c["end"][None, :])
        r = np.minimum(np.floor(offset / c["period"]), c["repeat"] - 1)
        phase = np.minimum(np.maximum(offset - r * c["period"], 0.0), c["period"])
        on &= (phase >= c["a"]) & (phase < c["stop"])
        rows, cols = np.nonzero(on)
        if not rows.size:
            return
        phase = phase[rows, cols]
        a, b = c["a"][cols], c["b"][cols]
        u = np.minimum(np.maximum((phase - a) / (b - a), 0.0), 1.0)
        fade = c["fade"][cols]
        factor = np.where(fade == 1, u, 1.0)
        factor = np.where(fade == 2, 1.0 - u, factor)
        factor = np.where(fade == 3, 1.0 - np.abs(2.0 * u - 1.0), factor)
        g = np.ones(rows.size)
        enveloped = c["enveloped"][cols]
        if enveloped.any():
            for k in np.unique(which[cols[enveloped]]).tolist():
                sel = which[cols] == k
                g[sel] = gains(self._parts[self._dots[k]].effect, phase[sel])
        values = c["level"][cols] * factor * g
        target = (rows, c["actuator"][cols])
        if self._sum:
            np.add.at(raw, target, values)
        else:
            np.maximum.at(raw, target, values)


def _dot_columns(parts) -> dict:
    """The dot parts as arrays, one per field."""
    return {
        "start": np.array([p.start for p in parts], dtype=np.float64),
        "end": np.array([p.end for p in parts], dtype=np.float64),
        "period": np.array([p.period for p in parts], dtype=np.float64),
        "repeat": np.array([p.repeat for p in parts], dtype=np.float64),
        "a": np.array([p.a for p in parts], dtype=np.float64),
        "b": np.array([p.b for p in parts], dtype=np.float64),
        "stop": np.array([p.stop for p in parts], dtype=np.float64),
        "actuator": np.array([p.actuator for p in parts], dtype=np.intp),
        "level": np.array([p.level for p in parts], dtype=np.float64),
        "fade": np.array([p.fade for p in parts], dtype=np.intp),
        "enveloped": np.array([bool(p.effect.envelope) for p in parts], dtype=bool),
    }
