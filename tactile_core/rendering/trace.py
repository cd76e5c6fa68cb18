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

import bisect
import math
import threading
import time
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from .._shared import validate as _validate
from .correction import check_correction, correct, correct1
from .geometry import Grid
from .layout import Layout
from .methods import get_method
from .methods._layout import layout_sampler
from .rasterize import check_shape, check_target, frame_shape, layout_entries, point_entries, render
from .shapes import Shape

DIRECTIONS = ("forward", "reverse")
FILTERS = ("point", "box")
MAX_SAMPLES = 20_000_000
"""Most samples one render_frames call computes."""


@dataclass(frozen=True)
class Trace:
    """A shape traced over time.

    Parameters
    ----------
    shape : Shape
        What is traced.
    duration_s : float
        Seconds from ``t = 0`` to ``t = 1``, > 0 and at most an hour (2 s in the paper).
    pause_s : float
        Seconds off between traces, 0 to an hour (0.5 s in the paper's Experiments 1 and 2; 0
        for the continuous retracing of Experiment 3).
    direction : {"forward", "reverse"}
        ``forward`` follows ``f(t)`` (counter-clockwise for circles and squares);
        ``reverse`` runs ``t`` from 1 to 0.
    repeat : bool
        Repeat forever (True) or trace once and stay off.
    emphasis : float
        Corner emphasis in [0, 0.9]: the point slows down near the shape's corners (paper
        section 4.3's suggestion); 0 (default) moves at constant speed in ``t``. See
        :func:`corner_warp`.
    hold_s : float or None
        Hold the trace at this many seconds into it (scrubbing in the tuner: the array plays
        that one instant for as long as it is held); None (default) runs the clock.
    """

    shape: Shape
    duration_s: float = 2.0
    pause_s: float = 0.5
    direction: str = "forward"
    repeat: bool = True
    emphasis: float = 0.0
    hold_s: float | None = None

    def __post_init__(self):
        check_shape(self.shape)
        object.__setattr__(self, "duration_s", _validate.duration("duration_s", self.duration_s))
        object.__setattr__(
            self, "pause_s", _validate.duration("pause_s", self.pause_s, allow_zero=True)
        )
        _validate.choice("direction", self.direction, DIRECTIONS)
        object.__setattr__(self, "repeat", _validate.boolean("repeat", self.repeat))
        object.__setattr__(
            self, "emphasis", _validate.in_range("emphasis", self.emphasis, 0.0, 0.9)
        )
        object.__setattr__(self, "hold_s", check_hold(self.hold_s))

    @cached_property
    def _warp(self):
        """``(u, t)`` tables of the corner warp, or None for uniform motion."""
        if self.emphasis == 0.0 or not self.shape.corners:
            return None
        u, t = corner_warp(self.shape.corners, self.emphasis, closed=self.shape.closed)
        return u, t, u.tolist(), t.tolist()

    @property
    def period_s(self) -> float:
        """Seconds from the start of one trace to the start of the next."""
        return self.duration_s + self.pause_s

    def parameter(self, time_s) -> tuple[np.ndarray, np.ndarray]:
        """Trace parameter at times.

        Parameters
        ----------
        time_s : array_like of float
            Seconds since the first trace started; finite.

        Returns
        -------
        t : ndarray of float64
            Trace parameter in [0, 1] (0 where off).
        on : ndarray of bool
            False during the pause, and (when ``repeat`` is False) before and after the trace.
        """
        time = np.asarray(time_s, dtype=np.float64)
        if not np.isfinite(time).all():
            raise ValueError("time_s must be finite")
        if self.hold_s is not None:
            time = np.full_like(time, self.hold_s)
        phase = np.mod(time, self.period_s) if self.repeat else time
        on = (phase >= 0.0) & (phase < self.duration_s)
        t = np.clip(phase / self.duration_s, 0.0, 1.0)
        if self._warp is not None:
            t = np.interp(t, self._warp[0], self._warp[1])
        if self.direction == "reverse":
            t = 1.0 - t
        return np.where(on, t, 0.0), on

    def parameter1(self, time_s: float) -> float | None:
        """Scalar :meth:`parameter`: ``t``, or None while off. ``time_s`` is not checked."""
        if self.hold_s is not None:
            time_s = self.hold_s
        phase = math.fmod(time_s, self.period_s) if self.repeat else time_s
        if phase < 0.0 and self.repeat:
            phase += self.period_s
        if not 0.0 <= phase < self.duration_s:
            return None
        t = min(phase / self.duration_s, 1.0)
        warp = self._warp
        if warp is not None:
            us, ts = warp[2], warp[3]
            i = min(bisect.bisect_right(us, t), len(us) - 1)
            u0, u1 = us[i - 1], us[i]
            t = ts[i - 1] + (ts[i] - ts[i - 1]) * ((t - u0) / (u1 - u0) if u1 > u0 else 0.0)
        return 1.0 - t if self.direction == "reverse" else t


def check_hold(hold_s) -> float | None:
    """``hold_s`` as a float (finite, 0 to an hour) or None; else ``ValueError`` naming it."""
    if hold_s is None:
        return None
    return _validate.in_range("hold_s", hold_s, 0.0, 3600.0)


def corner_warp(
    corners, emphasis: float, *, width: float = 0.05, closed: bool = True, n: int = 4097
):
    """Time-warp of a trace that dwells near corners.

    The point's speed along ``t`` is ``1 / w(t)`` with the time density
    ``w(t) = 1 + k * sum_j bump(t - c_j)``, ``k = emphasis / (1 - emphasis)`` and ``bump`` a
    raised cosine of half-width ``width`` (in ``t``) around each corner ``c_j``: with
    ``emphasis = 0.5`` the point spends twice as long per unit of path at a corner as elsewhere.
    The trace takes the same total time.

    Parameters
    ----------
    corners : sequence of float
        Corner parameters in [0, 1].
    emphasis : float
        In [0, 0.9].
    width : float
        Half-width of the slow-down around each corner, in ``t``.
    closed : bool
        Bumps wrap around t = 0/1 (closed shapes).
    n : int
        Table size.

    Returns
    -------
    u, t : ndarray of float64, shape (n,)
        Fraction of the trace's time ``u`` and the parameter ``t`` reached then (both from 0 to
        1, increasing): ``t = interp(u, u_table, t_table)``.
    """
    t = np.linspace(0.0, 1.0, n)
    k = emphasis / (1.0 - emphasis)
    density = np.ones(n)
    for c in corners:
        d = t - c
        if closed:
            d = (d + 0.5) % 1.0 - 0.5
        inside = np.abs(d) < width
        density[inside] += k * 0.5 * (1.0 + np.cos(np.pi * d[inside] / width))
    u = np.concatenate([[0.0], np.cumsum((density[1:] + density[:-1]) * 0.5 * np.diff(t))])
    u /= u[-1]
    return u, t


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
    method : {"CT", "MM", "AS", "IM"}
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
    m = get_method(method)
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
    shape = frame_shape(grid)
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
    method : {"CT", "MM", "AS", "IM"}
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
        self.method = get_method(method)
        self.sampling = sampling
        self.mu, self.gamma = check_correction(mu, gamma)
        self.gain = _validate.in_range("gain", gain, 0.0, 1.0)
        self.grid = check_target(grid)
        self._layout = (
            layout_sampler(self.method, self.grid) if isinstance(self.grid, Layout) else None
        )
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
        start = k / self.sampling.rate_hz
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
        trace, shape, entries1 = self.trace, self.trace.shape, self._layout.entries1
        if len(self._offsets) == 1:  # point sampling: no sums across sub-samples
            t = trace.parameter1(start + self._offsets[0])
            if t is None:
                return ()
            mu, gamma, gain = self.mu, self.gamma, self.gain
            return tuple(
                (i, correct1(v, mu, gamma, gain)) for i, v in layout_entries(shape, entries1, t)
            )
        acc: dict[int, float] = {}
        for offset in self._offsets:
            t = trace.parameter1(start + offset)
            if t is None:
                continue
            for i, v in layout_entries(shape, entries1, t):
                acc[i] = acc.get(i, 0.0) + correct1(v, self.mu, self.gamma, self.gain)
        scale = self._scale
        return tuple((i, v * scale) for i, v in acc.items())

    def frame(self, k: int) -> np.ndarray:
        """Frame ``k`` as a dense array (for display and tests): ``(rows, cols)`` on a grid,
        ``(size,)`` on a layout."""
        out = np.zeros(self.grid.size)
        for i, v in self.entries(k):
            out[i] = v
        return out.reshape(frame_shape(self.grid))
