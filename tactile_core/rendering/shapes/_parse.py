"""Shapes from text (the command-line form) and from JSON objects (:meth:`Shape.to_dict`)."""

from __future__ import annotations

import re

from ..._shared import validate as _validate
from ._polyline import MAX_POINTS, Polyline, Square
from ._shape import Circle, Line, Shape

SHAPE_KINDS = ("line", "circle", "square", "polyline", "polygon")
_NUMBER = re.compile(r"[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?")
"""A decimal number as a user types it (no nan, inf, hex or underscores)."""


def parse_shape(text: str) -> Shape:
    """Parse the command-line form of a shape.

    Parameters
    ----------
    text : str
        ``line:X0,Y0,X1,Y1``, ``circle:CX,CY,R``, ``square:CX,CY,EDGE``, or (beyond the
        contract) ``polyline:X0,Y0,X1,Y1,...`` and ``polygon:...`` (closed).

    Returns
    -------
    Shape

    Raises
    ------
    ValueError
        Naming ``shape`` and what is wrong with the text.

    Examples
    --------
    >>> parse_shape("circle:2.5,3,2")
    Circle(center=(2.5, 3.0), radius=2.0)
    """
    if not isinstance(text, str) or ":" not in text:
        raise ValueError(
            f"shape must look like 'circle:2.5,3,2' ({', '.join(SHAPE_KINDS)}), "
            f"got {_validate.shown(text)}"
        )
    kind, _, args = text.partition(":")
    kind = kind.strip().lower()
    if kind not in SHAPE_KINDS:
        raise ValueError(
            f"shape kind must be one of {', '.join(SHAPE_KINDS)}, got {_validate.shown(kind)}"
        )
    parts = [a.strip() for a in args.split(",")] if args.strip() else []
    if len(parts) > 2 * MAX_POINTS:
        raise ValueError(f"shape {kind}: at most {2 * MAX_POINTS} numbers, got {len(parts)}")
    bad = next((a for a in parts if not _NUMBER.fullmatch(a)), None)
    if bad is not None:
        raise ValueError(
            f"shape {kind}: coordinates must be decimal numbers separated by commas, "
            f"got {_validate.shown(bad)}"
        )
    values = [float(a) for a in parts]
    need = {"line": 4, "circle": 3, "square": 3}
    if kind in need and len(values) != need[kind]:
        raise ValueError(f"shape {kind}: needs {need[kind]} numbers, got {len(values)}")
    if kind not in need and (len(values) < 4 or len(values) % 2):
        raise ValueError(f"shape {kind}: needs an even number (>= 4) of coordinates")
    try:
        if kind == "line":
            return Line(values[0:2], values[2:4])
        if kind == "circle":
            return Circle(values[0:2], values[2])
        if kind == "square":
            return Square(values[0:2], values[2])
        return Polyline(list(zip(values[0::2], values[1::2])), closed=kind == "polygon")
    except ValueError as exc:
        raise ValueError(f"shape {kind}: {exc}") from None


def shape_from_dict(data) -> Shape:
    """Build a shape from :meth:`Shape.to_dict` output; ``ValueError`` names a bad field."""
    if not isinstance(data, dict):
        raise ValueError(f"shape must be an object with a 'type', got {_validate.shown(data)}")
    kind = data.get("type")
    fields = {
        "line": ("p0", "p1"),
        "circle": ("center", "radius"),
        "square": ("center", "edge"),
        "polyline": ("points",),
    }
    if not isinstance(kind, str) or kind not in fields:
        raise ValueError(
            f"shape.type must be one of {', '.join(fields)}, got {_validate.shown(kind)}"
        )
    for name in fields[kind]:
        if name not in data:
            raise ValueError(f"shape.{name} is missing for a {kind}")
    try:
        if kind == "line":
            return Line(data["p0"], data["p1"])
        if kind == "circle":
            return Circle(data["center"], data["radius"])
        if kind == "square":
            return Square(data["center"], data["edge"])
        return Polyline(data["points"], closed=data.get("closed", False))
    except ValueError as exc:
        raise ValueError(f"shape.{exc}") from None
