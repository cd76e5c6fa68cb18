"""The tactor grid, the description of a physical array, and snapping float noise to cells.

Coordinates follow the paper (section 2.1) and the contract: tactors sit at the centres of unit
cells of an axis-aligned grid whose lower-left cell corner is the origin. Cell ``(col, row)``
spans ``[col, col + 1) x [row, row + 1)`` and its tactor is at ``(col + 0.5, row + 0.5)``; x grows
to the right and y upwards. Frames are indexed ``[row, col]`` with row 0 at the bottom.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._shared import validate as _validate
from ._grid import Grid
from .layout import Layout


@dataclass(frozen=True)
class ArraySpec:
    """A physical tactor array: where its actuators are, their spacing, intensity levels and
    channel wiring.

    Parameters
    ----------
    layout : Layout
        Where the actuators are: a :class:`Grid` (the paper's palm array by default) or
        actuators anywhere (:class:`~tactile_core.rendering.layout.Layout`, in pitches).
    pitch_mm : float
        Centre-to-centre actuator spacing in millimetres (18 mm on the paper's palm array):
        one layout unit.
    levels : int
        Number of intensity levels the drive electronics resolve, 2..256 (one byte per channel
        on the wire). Level 0 is off and ``levels - 1`` is full intensity.
    channels : tuple of int, optional
        ``channels[k]`` is the actuator index (on a grid the flat cell index
        ``row * cols + col``) that drive channel ``k`` feeds. It must be a permutation of
        ``range(layout.size)``. The default is the identity.

    Notes
    -----
    The paper's array (section 3.3) is 5 x 6 DC motors, about 18 mm apart, driven by PWM at
    roughly 300 Hz with 23 levels. The device link reuses this description.
    """

    layout: Layout = None
    pitch_mm: float = 18.0
    levels: int = 23
    channels: tuple[int, ...] | None = None

    def __post_init__(self):
        if self.layout is None:
            object.__setattr__(self, "layout", Grid())
        if not isinstance(self.layout, Layout):
            raise ValueError(
                f"layout must be a Grid or a Layout, got {_validate.shown(self.layout)}"
            )
        object.__setattr__(self, "pitch_mm", _validate.positive("pitch_mm", self.pitch_mm))
        object.__setattr__(self, "levels", _validate.integer("levels", self.levels, 2, 256))
        size = self.layout.size
        if self.channels is None:
            channels = tuple(range(size))
        else:
            try:
                channels = tuple(
                    _validate.integer(f"channels[{k}]", c, 0, size - 1)
                    for k, c in enumerate(self.channels)
                )
            except TypeError:
                raise ValueError(
                    f"channels must be a list of integers, got {_validate.shown(self.channels)}"
                ) from None
            if sorted(channels) != list(range(size)):
                raise ValueError(
                    f"channels must be a permutation of 0..{size - 1} (one channel per tactor), "
                    f"got {_validate.shown(list(channels))}"
                )
        object.__setattr__(self, "channels", channels)

    @property
    def size(self) -> int:
        """Number of actuators (and drive channels)."""
        return self.layout.size

    @property
    def channel_index(self) -> np.ndarray:
        """``(size,)`` int array: actuator index of each channel, for ``flat[channel_index]``."""
        return np.asarray(self.channels, dtype=np.intp)


PALM_ARRAY = ArraySpec()
"""The paper's palm array: 5 x 6 tactors, 18 mm pitch, 23 levels, channel = row * cols + col."""


SNAP_ULPS = 64
"""Coordinates within this many units in the last place of an integer count as that integer.

Float noise puts a point that should sit exactly on a cell edge or a tactor centre a few ulps
to one side (``0.3 / 0.1 - 0.5 == 2.4999999999999996``). Without snapping, area sampling would
give the neighbouring tactor an intensity of ~4e-16, which the threshold correction then lifts
to ``mu``: a tactor that should be off buzzes. The noise of ``f(t)`` scales with the numbers it
is computed from, so the tolerance is ``SNAP_ULPS`` ulps of the shape's largest coordinate
(at least 1): ~1.4e-14 grid units (~3e-13 mm) for shapes on the palm array, ~1.4e-8 for a circle
of radius 1e6 whose arc passes through it.
"""

SNAP_REL = SNAP_ULPS * np.finfo(np.float64).eps


def snap_tolerance(scale: float) -> float:
    """Snap tolerance for coordinates computed from numbers of magnitude up to ``scale``."""
    return SNAP_REL * max(abs(scale), 1.0)


def cell_split(x, tol):
    """Split coordinates into cell index and position within the cell, snapping float noise.

    Parameters
    ----------
    x : ndarray of float64
        Coordinates along one axis, in grid units.
    tol : float or ndarray
        Snap tolerance (see :func:`snap_tolerance`), broadcast against ``x``.

    Returns
    -------
    index : ndarray of float64
        ``floor(x)``, the index of the cell containing ``x`` (as float; may be outside the
        grid). A coordinate exactly on a cell edge belongs to the upper/right cell, as the paper
        breaks ties (section 2.2). Within ``tol`` of an integer, the integer.
    frac : ndarray of float64
        ``x - index`` in [0, 1); 0 within ``tol`` of an integer.
    """
    index = x + tol
    if type(index) is not np.ndarray:  # numbers
        index = np.floor(index)
        frac = x - index
        return index, np.where(frac < tol, 0.0, frac)
    np.floor(index, out=index)
    frac = x - index
    np.putmask(frac, frac < tol, 0.0)
    return index, frac


def cell_floor(x, tol):
    """Index of the cell containing ``x``, snapped: :func:`cell_split` without the fraction."""
    return np.floor(x + tol)


def clamp(x, lo, hi):
    """``min(max(x, lo), hi)`` elementwise: ``np.clip`` costs twice as much on small arrays."""
    return np.minimum(np.maximum(x, lo), hi)


def cell_split1(x: float, tol: float) -> tuple[int, float]:
    """Scalar :func:`cell_split` with plain Python numbers: ``(index, frac)``."""
    index = math.floor(x + tol)
    frac = x - index
    return index, (0.0 if frac < tol else frac)


class Pieces:
    """Which piece of ``[0, 1]`` each ``t`` lies in, for a few sorted breakpoints.

    :meth:`of` equals ``clip(searchsorted(points, t, side="right") - 1, 0, last)``: piece ``k``
    starts at ``points[k]`` (a point belongs to the piece it starts). For ``t`` within
    ``[0, 1]`` it reads two tables at ``floor(t * m)`` instead of searching: with ``m``
    buckets narrow enough that at most one breakpoint lies within half a bucket of each, a
    bucket's piece is its first one, plus one past the breakpoint (``searchsorted`` costs as
    much as the rest of a frame's geometry). Breakpoints closer than 1 / 4096 of the range
    (or none) fall back to ``searchsorted``.

    Parameters
    ----------
    points : array_like of float
        Ascending breakpoints (may extend beyond [0, 1]).
    last : int
        The highest piece index.
    """

    BUCKETS = (64, 256, 1024, 4096)

    def __init__(self, points, last: int):
        self.points = np.asarray(points, dtype=np.float64)
        self.last = int(last)
        self._tables = None
        for m in self.BUCKETS:
            b = np.arange(m + 1)
            first = np.searchsorted(self.points, (b - 0.5) / m, side="right")
            beyond = np.searchsorted(self.points, (b + 1.5) / m, side="right")
            if (beyond - first > 1).any():
                continue
            base = np.clip(first - 1, 0, self.last)
            step = np.clip(first, 0, self.last) > base
            inside = (beyond > first) & step
            tau = np.where(inside, self.points.take(np.minimum(first, len(self.points) - 1)),
                           np.inf)  # fmt: skip
            self._tables = (float(m), base.astype(np.intp), tau)
            break

    def of(self, t: np.ndarray) -> np.ndarray:
        """Piece index (intp) of each ``t`` (a float64 array within [0, 1])."""
        if self._tables is None:
            index = np.searchsorted(self.points, t, side="right")
            index -= 1
            np.maximum(index, 0, out=index)
            return np.minimum(index, self.last, out=index)
        m, base, tau = self._tables
        bucket = (t * m).astype(np.intp)
        index = base.take(bucket, mode="clip")
        index += tau.take(bucket, mode="clip") <= t
        return index
