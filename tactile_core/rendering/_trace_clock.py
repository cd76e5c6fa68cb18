"""The trace clock itself: a :class:`Trace` turns seconds into the shape's parameter ``t``
(duration, pause, direction, repeat, corner emphasis, a held instant). Re-exported by
:mod:`.trace`, with the frames built on it."""

from __future__ import annotations

import bisect
import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from .._shared import validate as _validate
from ._targets import check_shape
from .shapes import Shape

DIRECTIONS = ("forward", "reverse")


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
