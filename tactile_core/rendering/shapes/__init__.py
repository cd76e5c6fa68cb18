"""Shapes traced by the moving point: parametric curves ``f(t)`` for ``t`` in [0, 1].

The contract fixes the parameterisations:

=====================  ===============================================================
``Line(p0, p1)``       ``p0 + (p1 - p0) t``
``Circle(c, r)``       ``(cx + r cos 2 pi t, cy + r sin 2 pi t)``: counter-clockwise from
                       the rightmost point
``Square(c, edge)``    counter-clockwise from the midpoint of its right edge, ``t``
                       proportional to arc length
``Polyline(points)``   through the points in order, ``t`` proportional to arc length;
                       ``closed=True`` returns to the first point
``TimedPath(points,    through the points at their times (``CONST_TDM``) or at one speed
times_s, ...)``        (``CONST_SPEED``), ``t`` the fraction of the duration; beyond the
                       contract, with an intensity envelope (bHaptics' path mode)
=====================  ===============================================================

Besides ``f(t)``, every shape describes itself as *strokes* for the midpoint methods (MM, IM):
pieces along which one axis is the major axis (paper section 2.3). A line is one stroke; a
polyline is one stroke per maximal straight run (consecutive segments that continue in the same
direction are merged, so the right edge of a square, which the trace enters twice, is one
stroke); a circle is four 90-degree arcs, the top and bottom arcs x-major (``|dy/dx| <= 1``,
including the 45-degree points) and the left and right arcs y-major.

Inside: ``_shape`` holds the base class, :class:`Line` and :class:`Circle`; ``_polyline``
:class:`Polyline` and :class:`Square`; ``_strokes`` the stroke machinery; ``_parse`` the text
and JSON forms (:func:`parse_shape`, :func:`shape_from_dict`); ``_timed`` :class:`TimedPath`.
"""

# ``_name as _name``: helpers of the module this package was, still importable from here.
from ._parse import SHAPE_FORMS, SHAPE_KINDS, parse_shape, shape_from_dict
from ._polyline import MAX_POINTS, Polyline, Square
from ._shape import Circle, Line, Shape
from ._strokes import TWO_PI, ArcStrokes, LineStrokes, Run, Strokes
from ._timed import FADES, PATTERNS, TimedPath, path_from_samples

__all__ = [
    "FADES",
    "MAX_POINTS",
    "PATTERNS",
    "SHAPE_FORMS",
    "SHAPE_KINDS",
    "TWO_PI",
    "ArcStrokes",
    "Circle",
    "Line",
    "LineStrokes",
    "Polyline",
    "Run",
    "Shape",
    "Square",
    "Strokes",
    "TimedPath",
    "parse_shape",
    "path_from_samples",
    "shape_from_dict",
]
