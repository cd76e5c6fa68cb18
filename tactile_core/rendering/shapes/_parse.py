"""Shapes from text (the command-line form) and from JSON objects (:meth:`Shape.to_dict`)."""

from __future__ import annotations

from ..._shared import validate as _validate
from ._polyline import MAX_POINTS, Polyline, Square
from ._shape import Circle, Line, Shape
from ._timed import SPEC_OPTIONS, TimedPath

SHAPE_KINDS = ("line", "circle", "square", "polyline", "polygon", "timed")
SHAPE_FORMS = (
    "line:X0,Y0,X1,Y1",
    "circle:CX,CY,R",
    "square:CX,CY,EDGE",
    "polyline:X0,Y0,X1,Y1,...",
    "polygon:X0,Y0,X1,Y1,...",
    "timed:X0,Y0,T0,I0,X1,Y1,T1,I1,...[;OPTION]",
)
"""The command-line forms of :data:`SHAPE_KINDS`, for help texts and errors: coordinates in
grid units; a polygon closes; ``timed``: each point's time in seconds and intensity, then the
options of ``_timed.SPEC_OPTIONS`` (``;speed``, ``;fade-in``, ...)."""
_NUMBER = _validate.DECIMAL
"""A decimal number as a user types it (ASCII digits: no nan, inf, hex, underscores or
full-width digits)."""


def parse_shape(text: str) -> Shape:
    """Parse the command-line form of a shape.

    Parameters
    ----------
    text : str
        ``line:X0,Y0,X1,Y1``, ``circle:CX,CY,R``, ``square:CX,CY,EDGE``, or (beyond the
        contract) ``polyline:X0,Y0,X1,Y1,...``, ``polygon:...`` (closed) and
        ``timed:X0,Y0,T0,I0,X1,Y1,T1,I1,...`` (a :class:`TimedPath`: points, times in seconds
        and intensities, ``CONST_TDM``), optionally followed by ``;speed`` (``CONST_SPEED``) and
        ``;fade-in``, ``;fade-out`` or ``;fade-in-out``.

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
            f"shape must be one word such as circle:2.5,3,2, one of {' | '.join(SHAPE_FORMS)}; "
            f"got {_validate.shown(text)}"
        )
    kind, _, args = text.partition(":")
    kind = kind.strip().lower()
    if kind not in SHAPE_KINDS:
        raise ValueError(
            f"shape kind must be one of {', '.join(SHAPE_KINDS)} ({' | '.join(SHAPE_FORMS)}), "
            f"got {_validate.shown(kind)}"
        )
    if kind == "timed":
        return _parse_timed(args)
    values = _numbers(kind, args, 2 * MAX_POINTS, "coordinates")
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


def _numbers(kind: str, text: str, most: int, what: str) -> list[float]:
    """The comma-separated decimal numbers of a spec (none for blank ``text``), at most
    ``most``; ``ValueError`` naming the shape kind and the first that is not a number."""
    parts = [a.strip() for a in text.split(",")] if text.strip() else []
    if len(parts) > most:
        raise ValueError(f"shape {kind}: at most {most} numbers, got {len(parts)}")
    bad = next((a for a in parts if not _NUMBER.fullmatch(a)), None)
    if bad is not None:
        raise ValueError(
            f"shape {kind}: {what} must be decimal numbers separated by commas, "
            f"got {_validate.shown(bad)}"
        )
    return [float(a) for a in parts]


def _parse_timed(args: str) -> TimedPath:
    """The ``timed:`` form: quadruples ``x, y, time_s, intensity``, then ``;options``."""
    numbers, *words = [a.strip() for a in args.split(";")]
    options = {}
    for word in words:
        if word.lower() not in SPEC_OPTIONS:
            raise ValueError(
                f"shape timed: options are {', '.join(SPEC_OPTIONS)}, got {_validate.shown(word)}"
            )
        key, value = SPEC_OPTIONS[word.lower()]
        options[key] = value
    v = _numbers("timed", numbers, 4 * MAX_POINTS, "numbers")
    if len(v) < 8 or len(v) % 4:
        raise ValueError(
            "shape timed: needs x, y, time_s, intensity for each of at least 2 points "
            f"(a multiple of 4 numbers, >= 8), got {len(v)}"
        )
    try:
        return TimedPath(list(zip(v[0::4], v[1::4])), v[2::4], v[3::4], **options)
    except ValueError as exc:
        raise ValueError(f"shape timed: {exc}") from None


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
        "timed_path": ("points", "times_s"),
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
        if kind == "timed_path":
            options = {k: data[k] for k in ("intensities", "pattern", "fade") if k in data}
            return TimedPath(data["points"], data["times_s"], **options)
        return Polyline(data["points"], closed=data.get("closed", False))
    except ValueError as exc:
        raise ValueError(f"shape.{exc}") from None
