"""The base class of the traced shapes, and the two given by a formula: Line and Circle."""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ..._shared import validate as _validate
from ..geometry import snap_tolerance
from ._strokes import TWO_PI, ArcStrokes, LineStrokes, Strokes


class Shape:
    """Base class of the traced shapes: a parametric curve ``f(t)``, ``t`` in [0, 1]."""

    closed: bool = False
    has_envelope: bool = False
    """True for a shape whose :meth:`intensity` is not 1 everywhere (a time-keyed path): the
    renderer then multiplies the raw intensities by it."""

    def intensity(self, t) -> np.ndarray:
        """The intensity envelope at ``t`` (float or array in [0, 1]): 1 for the shapes of
        the contract; a time-keyed path interpolates its points' intensities."""
        return np.ones(np.shape(t))

    def intensity1(self, t: float) -> float:
        """Scalar :meth:`intensity` with plain floats, for the live path."""
        return 1.0

    def f(self, t) -> np.ndarray:
        """Points of the trace.

        Parameters
        ----------
        t : float or array_like
            Trace parameter(s), each finite and within [0, 1].

        Returns
        -------
        ndarray of float64, shape ``t.shape + (2,)``
            ``(x, y)`` in grid units (1 unit = one tactor pitch).
        """
        t = _validate.parameter_array(t)
        x, y = self.xy(t)
        return np.stack([x, y], axis=-1)

    def xy(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Vectorised ``f`` on an already checked float64 array: returns ``(x, y)``."""
        raise NotImplementedError

    def xy_rows(self, t: np.ndarray) -> np.ndarray:
        """:meth:`xy` as one ``(2, n)`` array (x in row 0, y in row 1), for a checked 1-D
        float64 ``t``: the same numbers, in fewer numpy calls where a shape can."""
        return np.stack(self.xy(t))

    def point(self, t: float) -> tuple[float, float]:
        """Scalar ``f`` with plain floats, for the live path. ``t`` is not checked."""
        raise NotImplementedError

    @property
    def strokes(self) -> Strokes:
        """The shape's strokes for the midpoint methods."""
        raise NotImplementedError

    @property
    def scale(self) -> float:
        """Largest coordinate magnitude the shape's points are computed from."""
        raise NotImplementedError

    @property
    def corners(self) -> tuple:
        """Trace parameters of the shape's corners, for corner emphasis (none by default)."""
        return ()

    @cached_property
    def snap_tol(self) -> float:
        """Snap tolerance for this shape's points (see ``geometry.SNAP_ULPS``)."""
        return snap_tolerance(self.scale)

    @property
    def spec(self) -> str:
        """The command-line form, e.g. ``"circle:2.5,3,2"``."""
        raise NotImplementedError

    def to_dict(self) -> dict:
        """A JSON-ready description; :func:`shape_from_dict` reverses it."""
        raise NotImplementedError

    def outline(self, n: int = 256) -> np.ndarray:
        """``(n, 2)`` points along the shape for drawing (vertices included for polylines)."""
        return self.f(np.linspace(0.0, 1.0, n))


def _column(point) -> np.ndarray:
    """A point as a read-only ``(2, 1)`` column, to broadcast against ``(2, n)`` rows."""
    column = np.array(point, dtype=np.float64).reshape(2, 1)
    column.flags.writeable = False
    return column


def _fmt(*values: float) -> str:
    return ",".join(f"{v:.12g}" for v in values)


@dataclass(frozen=True)
class Line(Shape):
    """Line segment from ``p0`` to ``p1``: ``f(t) = p0 + (p1 - p0) t``.

    Parameters
    ----------
    p0, p1 : (float, float)
        Endpoints in grid units. They may coincide (a zero-length line lights the cell of the
        point under every method).

    Notes
    -----
    ``f`` is evaluated as ``(1 - t) p0 + t p1``, which is exact at both ends and makes a
    reversed line at ``1 - t`` produce bit-identical points.

    Examples
    --------
    >>> Line((0.5, 1.0), (4.5, 3.0)).f(0.5)
    array([2.5, 2. ])
    """

    p0: tuple[float, float]
    p1: tuple[float, float]

    def __post_init__(self):
        object.__setattr__(self, "p0", _validate.point("p0", self.p0))
        object.__setattr__(self, "p1", _validate.point("p1", self.p1))

    def xy(self, t):
        (x0, y0), (x1, y1) = self.p0, self.p1
        s = 1.0 - t
        return s * x0 + t * x1, s * y0 + t * y1

    def xy_rows(self, t):
        p0, p1 = self._columns
        out = (1.0 - t) * p0
        out += t * p1
        return out

    @cached_property
    def _columns(self) -> tuple[np.ndarray, np.ndarray]:
        return _column(self.p0), _column(self.p1)

    def point(self, t):
        (x0, y0), (x1, y1) = self.p0, self.p1
        s = 1.0 - t
        return (s * x0 + t * x1, s * y0 + t * y1)

    @cached_property
    def strokes(self):
        return LineStrokes([self.p0 + self.p1], [0.0, 1.0], [0], self.snap_tol)

    @property
    def scale(self):
        return max(map(abs, self.p0 + self.p1))

    @property
    def length(self) -> float:
        """Length in grid units."""
        return math.dist(self.p0, self.p1)

    def reversed(self) -> Line:
        """The same segment traced from ``p1`` to ``p0``."""
        return Line(self.p1, self.p0)

    @property
    def spec(self):
        return "line:" + _fmt(*self.p0, *self.p1)

    def to_dict(self):
        return {"type": "line", "p0": list(self.p0), "p1": list(self.p1)}

    def outline(self, n=2):
        return np.array([self.p0, self.p1])


@dataclass(frozen=True)
class Circle(Shape):
    """Circle traced counter-clockwise from its rightmost point.

    ``f(t) = (cx + r cos 2 pi t, cy + r sin 2 pi t)``.

    Parameters
    ----------
    center : (float, float)
        Centre in grid units.
    radius : float
        Radius in grid units, >= 0 (0 is a point).
    """

    center: tuple[float, float]
    radius: float

    closed = True

    def __post_init__(self):
        object.__setattr__(self, "center", _validate.point("center", self.center))
        object.__setattr__(self, "radius", _validate.size("radius", self.radius))
        (cx, cy), r = self.center, self.radius
        _validate.extent("radius", "circle", r, (cx - r, cx + r, cy - r, cy + r))

    def xy(self, t):
        cx, cy = self.center
        angle = TWO_PI * t
        return cx + self.radius * np.cos(angle), cy + self.radius * np.sin(angle)

    def xy_rows(self, t):
        angle = TWO_PI * t
        out = np.empty((2, len(angle)))
        np.cos(angle, out=out[0])
        np.sin(angle, out=out[1])
        out *= self.radius
        out += self._center_column
        return out

    @cached_property
    def _center_column(self) -> np.ndarray:
        return _column(self.center)

    def point(self, t):
        cx, cy = self.center
        angle = TWO_PI * t
        return (cx + self.radius * math.cos(angle), cy + self.radius * math.sin(angle))

    @cached_property
    def strokes(self):
        cx, cy = self.center
        return ArcStrokes(cx, cy, self.radius, self.point, self.snap_tol)

    @property
    def scale(self):
        return max(map(abs, self.center)) + self.radius

    @property
    def length(self) -> float:
        """Circumference in grid units."""
        return TWO_PI * self.radius

    @property
    def corners(self):
        """A circle has none; the diagonal points (t = 1/8, 3/8, 5/8, 7/8, where a square of
        the same centre has its corners) are used, so that corner emphasis warps circles and
        squares in the same way and only their geometry differs."""
        return (0.125, 0.375, 0.625, 0.875)

    @property
    def spec(self):
        return "circle:" + _fmt(*self.center, self.radius)

    def to_dict(self):
        return {"type": "circle", "center": list(self.center), "radius": self.radius}
