"""What the frame sources of a file share: a ``.tact`` position and a pattern are both played
one frame at a time, from a table once it is built and by a scalar path before.

A subclass sets, in its constructor, through :meth:`TabledFrames._setup`: the array (``grid``),
the sampling, the correction and ``n_frames``; and defines :meth:`~TabledFrames.raw1` (the
combined raw intensities of the lit actuators at one time, by scalar arithmetic),
:meth:`~TabledFrames.raw_at` (the same for many times, vectorised) and
:meth:`~TabledFrames.spans` (when each of its parts is on). :meth:`~TabledFrames.entries` then
serves frame ``k`` from the table :meth:`~TabledFrames.precompute` builds with
:meth:`~TabledFrames.render`, or computes it by :meth:`~TabledFrames.compute`; both give the same
values (tested for each subclass).
"""

from __future__ import annotations

import math
import threading
import time

import numpy as np

from .._shared import validate as _validate
from ..rendering.correction import check_correction, correct, correct1
from ..rendering.methods import get_method
from ..rendering.rasterize import check_target
from ..rendering.trace import MAX_SAMPLES, Sampling, entry_table

MAX_TABLE_FRAMES = 200_000
"""Most frames :meth:`TabledFrames.precompute` tabulates (11 minutes at 300 Hz); longer
patterns are computed frame by frame as they play."""


class TabledFrames:
    """Frames of a file's content on one array, served one at a time (the ``Scene.source``
    protocol: :meth:`entries`, :meth:`compute`, :meth:`frame`, :meth:`render`,
    :meth:`precompute`)."""

    FOREGROUND_CHUNK: int | None = None
    """Frames rendered together when :meth:`precompute` runs in the caller's thread (None: all
    at once)."""
    THREAD_NAME = "tactile-precompute"

    def _setup(self, method, target, sampling, mu, gamma, gain) -> None:
        """Check and keep what every frame needs; ``n_frames`` is the subclass's to set."""
        if not isinstance(sampling, Sampling):
            raise ValueError(f"sampling must be a Sampling, got {_validate.shown(sampling)}")
        self.method = get_method(method)
        self.grid = check_target(target)
        self.sampling = sampling
        self.mu, self.gamma = check_correction(mu, gamma)
        self.gain = _validate.in_range("gain", gain, 0.0, 1.0)
        self._offsets = sampling.offsets_s().tolist()
        self._table: list | None = None
        self.n_frames = 0

    # --- what a subclass defines -----------------------------------------------------------

    def raw1(self, when: float) -> dict:
        """Combined raw intensities at ``when`` seconds: ``{actuator: value}`` of the lit."""
        raise NotImplementedError

    def raw_at(self, when_s: np.ndarray) -> np.ndarray:
        """Combined raw intensities at the ascending times ``when_s``: ``(n, size)``."""
        raise NotImplementedError

    def spans(self) -> list:
        """``[(start_s, end_s), ...]`` of the parts: when each is on."""
        raise NotImplementedError

    # --- shared ----------------------------------------------------------------------------

    @property
    def precomputed(self) -> bool:
        """True once the table is in use."""
        return self._table is not None

    def busiest_frame(self) -> int:
        """The frame at which the most parts are on (the first such), 0 if none."""
        spans = self.spans()
        edges = sorted([(s, 1) for s, _ in spans] + [(e, -1) for _, e in spans])
        on, most, when = 0, 0, 0.0
        for t, step in edges:  # (an end sorts before a start at the same time)
            on += step
            if on > most:
                most, when = on, t
        return min(max(int(when * self.sampling.rate_hz), 0), max(self.n_frames - 1, 0))

    def busiest_frame_s(self) -> float:
        """Seconds the scalar path takes for :meth:`busiest_frame`: what playing costs a frame
        before the table is built (measured here, the best of two)."""
        k, best = self.busiest_frame(), math.inf
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
            threading.Thread(target=self._build, args=(64,), name=self.THREAD_NAME,
                             daemon=True).start()  # fmt: skip
            return
        self._build(self.FOREGROUND_CHUNK or self.n_frames)

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
        ...)``; empty after the content's end."""
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
            for i, v in self.raw1(start + offset).items():
                acc[i] = acc.get(i, 0.0) + correct1(v, mu, gamma, gain)
        scale = 1.0 / len(self._offsets)
        return tuple((i, v * scale) for i, v in acc.items())

    def frame(self, k: int) -> np.ndarray:
        """Frame ``k`` as a dense array: ``(rows, cols)`` on a grid, ``(size,)`` on a layout."""
        out = np.zeros(self.grid.size)
        for i, v in self.entries(k):
            out[i] = v
        return out.reshape(self.grid.frame_shape)

    def render(self, first: int, count: int, *, corrected: bool = True):
        """Frames ``first .. first + count - 1`` at once.

        Returns
        -------
        time_s : ndarray of float64, shape (count,)
            Start of each frame.
        frames : ndarray of float64, shape ``(count, rows, cols)`` (``(count, size)`` on a layout)
        """
        count = _validate.integer("count", count, 0)
        first = _validate.integer("first", first, 0)
        s = len(self._offsets)
        if count * s > MAX_SAMPLES:
            raise ValueError(f"count x subsamples must be at most {MAX_SAMPLES:.0e}, got "
                             f"{count} x {s}: render in chunks")  # fmt: skip
        size = self.grid.size
        start = (np.arange(count) + first) / self.sampling.rate_hz
        when = (start[:, None] + self.sampling.offsets_s()[None, :]).reshape(-1)
        raw = self.raw_at(when)
        if corrected:
            raw = correct(raw, self.mu, self.gamma, gain=self.gain)
        frames = raw.reshape(count, s, size).mean(axis=1)
        return start, frames.reshape((count, *self.grid.frame_shape))
