"""The trace clock: seconds to trace parameter, and frames at a rate with a temporal filter.

A :class:`Trace` runs the shape from ``t = 0`` to 1 in ``duration_s`` seconds, stays off for
``pause_s``, and repeats (paper 3.4.2: 2 s traces with a 0.5 s pause). Streaming samples it at
``rate_hz``: frame ``k`` is on the array during ``[k / rate, (k + 1) / rate)``. What value the
frame carries is the temporal filter (:class:`Sampling`):

``point``
    The corrected intensity at the middle of the frame interval. Sampling the middle rather
    than the start makes the hold add no systematic lag (onset errors within +-half a frame).
``box``
    The average of the corrected intensity over the frame interval, estimated with ``S``
    sub-samples at the centres of ``S`` equal parts. It preserves each tactor's delivered
    energy (the time integral of its drive), so a fast tactor hand-over is not lost between two
    frames; on the bi-level methods the frame of a hand-over carries both tactors at partial
    intensity. ``S = 1`` is the point filter.

The filter averages corrected intensities (what drives the motors), not raw ones: the
correction is non-linear, and averaging after it is what keeps the energy.
"""

from __future__ import annotations

import math
import threading
import time
from dataclasses import dataclass

import numpy as np

from .._shared import validate as _validate
from ._trace_clock import DIRECTIONS, Trace, check_hold, corner_warp  # noqa: F401
from .correction import check_correction, correct, correct1
from .geometry import Grid
from .methods import get_method, layout_sampler
from .rasterize import check_target, layout_entries, point_entries, render

FILTERS = ("point", "box")
MAX_SAMPLES = 20_000_000
"""Most samples one render_frames call computes."""


@dataclass(frozen=True)
class Sampling:
    """How a trace becomes frames: the update rate and the temporal filter.

    Parameters
    ----------
    rate_hz : float
        Frames per second, > 0 and at most 10^7 (a reference sampling every 0.1 us).
    filter : {"point", "box"}
        See the module notes; ``"point"`` (the paper's pipeline) by default.
    subsamples : int
        ``S``, sub-samples per frame for the box filter (1..1024); ignored by ``point``.
    """

    rate_hz: float = 300.0
    filter: str = "point"
    subsamples: int = 4

    def __post_init__(self):
        object.__setattr__(self, "rate_hz", _validate.positive("rate_hz", self.rate_hz))
        if self.rate_hz > 1e7:
            raise ValueError(f"rate_hz must be at most 1e7, got {_validate.shown(self.rate_hz)}")
        _validate.choice("filter", self.filter, FILTERS)
        object.__setattr__(
            self, "subsamples", _validate.integer("subsamples", self.subsamples, 1, 1024)
        )

    @property
    def n_sub(self) -> int:
        """Sub-samples actually taken per frame (1 for the point filter)."""
        return 1 if self.filter == "point" else self.subsamples

    @property
    def frame_s(self) -> float:
        """Frame interval in seconds."""
        return 1.0 / self.rate_hz

    def offsets_s(self) -> np.ndarray:
        """``(S,)`` sample times within a frame interval, in seconds from its start."""
        s = self.n_sub
        return (np.arange(s) + 0.5) / (s * self.rate_hz)

    @property
    def label(self) -> str:
        """Short name such as ``"point"`` or ``"box S=4"``."""
        return "point" if self.n_sub == 1 else f"box S={self.n_sub}"


DEFAULT_SAMPLING = Sampling()
DEFAULT_GRID = Grid()


def render_frames(
    trace: Trace,
    method,
    *,
    sampling: Sampling = DEFAULT_SAMPLING,
    mu: float = 0.0,
    gamma: float = 1.0,
    grid: Grid = DEFAULT_GRID,
    n_frames: int | None = None,
    first_frame: int = 0,
    corrected: bool = True,
    gain: float = 1.0,
    phase_s: float = 0.0,
) -> tuple[np.ndarray, np.ndarray]:
    """Frames of a trace as they would be streamed.

    Parameters
    ----------
    trace : Trace
    method : str or Method
        Any registered method (the paper's CT, MM, AS, IM, the peers EN, PK, RO, GS, VRCH,
        BA, a plug-in), with its parameters (``"RO:r=1.5"``).
    sampling : Sampling, keyword-only
        Rate and temporal filter.
    mu, gamma : float, keyword-only
        Correction parameters; the defaults (0, 1) leave intensities unchanged.
    grid : Grid or Layout, keyword-only
        On a layout that is not a grid, frames are ``(n_frames, size)``.
    n_frames : int, optional
        Number of frames; default: enough to cover one period,
        ``ceil(period_s * rate_hz)``.
    first_frame : int
        Index of the first frame (frame ``k`` starts at ``k / rate_hz`` seconds).
    corrected : bool
        Filter corrected intensities (True, what is streamed) or raw ones (False).
    gain : float, keyword-only
        Master intensity in [0, 1], part of the correction (see
        :func:`~tactile_core.rendering.correction.correct`).
    phase_s : float, keyword-only
        Where the frame clock stands when the trace starts: frame ``k`` starts at
        ``k / rate_hz + phase_s`` seconds of the trace's clock (0: aligned to a frame).

    Returns
    -------
    time_s : ndarray of float64, shape (n_frames,)
        Start time of each frame.
    frames : ndarray of float64, shape (n_frames, rows, cols)
        Filtered intensities in [0, 1].
    """
    m = get_method(method).on_clock(trace.duration_s)  # TB times its onsets by the trace
    grid = check_target(grid)
    mu, gamma = check_correction(mu, gamma)
    if not isinstance(sampling, Sampling):
        raise ValueError(f"sampling must be a Sampling, got {_validate.shown(sampling)}")
    if n_frames is None:
        n_frames = max(1, math.ceil(trace.period_s * sampling.rate_hz - 1e-9))
    n_frames = _validate.integer("n_frames", n_frames, 0)
    first_frame = _validate.integer("first_frame", first_frame, 0)
    s = sampling.n_sub
    if n_frames * s > MAX_SAMPLES:
        raise ValueError(
            f"n_frames x subsamples must be at most {MAX_SAMPLES:.0e} (about 4 GB of frames), "
            f"got {n_frames} x {s}: render in chunks with first_frame"
        )
    phase_s = _validate.real("phase_s", phase_s)
    start = (np.arange(n_frames) + first_frame) / sampling.rate_hz + phase_s
    times = (start[:, None] + sampling.offsets_s()[None, :]).reshape(-1)
    t, on = trace.parameter(times)
    shape = grid.frame_shape
    samples = np.zeros((times.size, *shape))
    samples[on] = render(trace.shape, m, t[on], grid=grid)
    if corrected and (mu != 0.0 or gamma != 1.0 or gain != 1.0):
        samples = correct(samples, mu, gamma, gain=gain)
    frames = samples.reshape((n_frames, s, *shape)).mean(axis=1)
    return start, frames


def frames_per_cycle(period_s: float, rate_hz: float, max_frames: int = 200_000) -> int | None:
    """Frames after which a repeating trace's frames repeat exactly, or None.

    The smallest ``n = p * period_s * rate_hz`` (``p`` whole periods) that is an integer to
    within 1e-9, if it is at most ``max_frames``. E.g. 2.5 s at 300 Hz: 750; at 25 Hz: 125.
    """
    per_period = period_s * rate_hz
    for p in range(1, 65):
        n = p * per_period
        if round(n) > max_frames:
            return None
        if round(n) >= 1 and abs(n - round(n)) <= 1e-9 * max(n, 1.0):
            return round(n)
    return None


def entry_table(flat: np.ndarray) -> list:
    """Frames ``(count, size)`` as the live path serves them: per frame a tuple of
    ``(index, value)`` of its nonzero entries (a precomputed table's rows)."""
    rows, cols = np.nonzero(flat)
    values = flat[rows, cols].tolist()
    bounds = np.searchsorted(rows, np.arange(len(flat) + 1)).tolist()
    cols = cols.tolist()
    return [
        tuple(zip(cols[bounds[k] : bounds[k + 1]], values[bounds[k] : bounds[k + 1]]))
        for k in range(len(flat))
    ]


class LiveFrames:
    """Frames of one scene served one at a time, touching only the lit tactors.

    Validates everything once. :meth:`entries` serves frame ``k`` from a table of one cycle
    of frames when :meth:`precompute` has built it (one vectorised :func:`render_frames`
    call, ~1 ms), and otherwise computes it with scalar arithmetic on the lit tactors (a few
    microseconds; a batch :func:`render_frames` call for one frame costs ~40 us of numpy
    overhead). Both give the same values (tested). Building the table in a background thread
    with ``precompute(background=True)`` lets a new scene go on the wire at once.

    Parameters
    ----------
    trace : Trace
    method : str or Method
        Any registered method (the paper's CT, MM, AS, IM, the peers EN, PK, RO, GS, VRCH,
        BA, a plug-in), with its parameters (``"RO:r=1.5"``).
    sampling : Sampling
    mu, gamma : float
    grid : Grid or Layout
        On a layout that is not a grid the entries' indices are actuator indices.
    gain : float
        Master intensity in [0, 1], part of the correction.
    """

    def __init__(self, trace, method, sampling, mu, gamma, grid, gain=1.0):
        if not isinstance(trace, Trace):
            raise ValueError(f"trace must be a Trace, got {_validate.shown(trace)}")
        if not isinstance(sampling, Sampling):
            raise ValueError(f"sampling must be a Sampling, got {_validate.shown(sampling)}")
        self.trace = trace
        self.method = get_method(method).on_clock(trace.duration_s)  # TB's clock: the trace
        self.sampling = sampling
        self.mu, self.gamma = check_correction(mu, gamma)
        self.gain = _validate.in_range("gain", gain, 0.0, 1.0)
        self.grid = check_target(grid)
        self._layout = None if self.grid.is_grid else layout_sampler(self.method, self.grid)
        self.cycle = frames_per_cycle(trace.period_s, sampling.rate_hz) if trace.repeat else None
        self._offsets = sampling.offsets_s().tolist()
        self._scale = 1.0 / len(self._offsets)
        self._sample1 = self.method.sample1
        self._identity = self.mu == 0.0 and self.gamma == 1.0 and self.gain == 1.0
        self._table: list | None = None

    @property
    def precomputed(self) -> bool:
        """True once the cycle table is in use."""
        return self._table is not None

    def precompute(self, background: bool = False) -> None:
        """Build the table of one cycle of frames (no-op if the frames never repeat exactly).

        With ``background=True`` the table is built in a daemon thread and takes over when
        ready; until then frames come from the scalar path.
        """
        if self.cycle is None or self._table is not None:
            return
        if background:
            threading.Thread(
                target=self._build, args=(64,), name="tactile-precompute", daemon=True
            ).start()
            return
        self._build(self.cycle)

    def _build(self, chunk: int) -> None:
        """Tabulate the cycle ``chunk`` frames at a time, yielding the GIL between chunks so
        that a concurrent output thread is never held up by one long numpy call."""
        table = []
        for first in range(0, self.cycle, chunk):
            count = min(chunk, self.cycle - first)
            _, frames = render_frames(
                self.trace,
                self.method,
                sampling=self.sampling,
                mu=self.mu,
                gamma=self.gamma,
                grid=self.grid,
                n_frames=count,
                first_frame=first,
                gain=self.gain,
            )
            table.extend(entry_table(frames.reshape(count, self.grid.size)))
            if chunk < self.cycle:
                time.sleep(0)
        self._table = table

    def entries(self, k: int) -> tuple:
        """Lit tactors of frame ``k`` (``k >= 0``): a tuple of ``(flat index, intensity)``."""
        table = self._table
        if table is not None:
            return table[k % self.cycle]
        return self.compute(k)

    def compute(self, k: int) -> tuple:
        """Frame ``k`` by the scalar path, whether or not a table exists."""
        return self.entries_at(k / self.sampling.rate_hz)

    def entries_at(self, start_s: float) -> tuple:
        """Lit tactors of the frame that starts ``start_s`` seconds into the trace clock, by the
        scalar path: frame ``k`` is ``entries_at(k / rate_hz)``. What a view of a streamed
        instant (a streamer's ``last_frame``) shows, computed as the stream computed it."""
        start = start_s
        trace, shape, sample1 = self.trace, self.trace.shape, self._sample1
        if self._layout is not None:
            return self._compute_layout(start)
        cols, rows = self.grid.cols, self.grid.rows
        if len(self._offsets) == 1:
            t = trace.parameter1(start + self._offsets[0])
            if t is None:
                return ()
            lit = point_entries(shape, sample1, t, cols, rows)
            if self._identity:
                return lit
            return tuple((i, correct1(v, self.mu, self.gamma, self.gain)) for i, v in lit)
        acc: dict[int, float] = {}
        for offset in self._offsets:
            t = trace.parameter1(start + offset)
            if t is None:
                continue
            for i, v in point_entries(shape, sample1, t, cols, rows):
                acc[i] = acc.get(i, 0.0) + correct1(v, self.mu, self.gamma, self.gain)
        scale = self._scale
        return tuple((i, v * scale) for i, v in acc.items())

    def _compute_layout(self, start: float) -> tuple:
        """:meth:`compute` on a layout that is not a grid."""
        trace, shape, sampler = self.trace, self.trace.shape, self._layout
        if len(self._offsets) == 1:  # point sampling: no sums across sub-samples
            t = trace.parameter1(start + self._offsets[0])
            if t is None:
                return ()
            mu, gamma, gain = self.mu, self.gamma, self.gain
            return tuple(
                (i, correct1(v, mu, gamma, gain)) for i, v in layout_entries(shape, sampler, t)
            )
        acc: dict[int, float] = {}
        for offset in self._offsets:
            t = trace.parameter1(start + offset)
            if t is None:
                continue
            for i, v in layout_entries(shape, sampler, t):
                acc[i] = acc.get(i, 0.0) + correct1(v, self.mu, self.gamma, self.gain)
        scale = self._scale
        return tuple((i, v * scale) for i, v in acc.items())

    def frame(self, k: int) -> np.ndarray:
        """Frame ``k`` as a dense array (for display and tests): ``(rows, cols)`` on a grid,
        ``(size,)`` on a layout."""
        out = np.zeros(self.grid.size)
        for i, v in self.entries(k):
            out[i] = v
        return out.reshape(self.grid.frame_shape)
