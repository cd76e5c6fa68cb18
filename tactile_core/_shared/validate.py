"""Argument checks shared by the public functions.

Every check raises ``ValueError`` whose message starts with the parameter's name and shows the
offending value, as the contract requires (``"mu must be within [0, 1], got 1.5"``); a value's
text is cut to :data:`SHOWN_CHARS` characters so that a 100 KB value does not flood a message.

Numbers must be numbers: a string, a boolean or a list is refused, not converted (``"1_0"`` is
not 10). Bounds keep every number that reaches the renderer or the streamer in a range where the
arithmetic stays finite and exact to far below a tactor's pitch:

- coordinates and sizes: within :data:`MAX_COORD` grid units of the origin (10^6 units is 18 km
  on the palm array; a shape that large still renders its passage through the grid correctly),
  and so is every point a shape passes through (a square's corners, a circle's extremes:
  :func:`extent`);
- durations and pauses: at most :data:`MAX_DURATION_S` (an hour per trace);
- frame rates: at most :data:`MAX_RATE_HZ` (the streamer then caps at what the link carries).
"""

from __future__ import annotations

import math
import numbers
import re

import numpy as np

MAX_COORD = 1e6
"""Largest coordinate, radius or edge magnitude, in grid units."""
MAX_DURATION_S = 3600.0
"""Longest trace duration or pause, in seconds."""
MAX_RATE_HZ = 100_000.0
"""Highest frame rate accepted anywhere (rendering to a file; streams are capped by the link)."""
SHOWN_CHARS = 80


DECIMAL = re.compile(r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")
"""A number as typed on a command line or in a shape or method spec: ASCII digits, an optional
sign, point and exponent (no ``1_0``, no full-width or other non-ASCII digits, no spaces around
it, no hex). Python's ``float()`` accepts all of those; the tool does not."""
WHOLE = re.compile(r"[+-]?[0-9]+")
"""A whole number as typed: ASCII digits and an optional sign."""


def decimal_text(name: str, text: str, *, whole: bool = False) -> float | int:
    """A number typed as text (:data:`DECIMAL`, or :data:`WHOLE` with ``whole``), or
    ``ValueError`` naming ``name`` and showing the text. ``nan`` and ``inf`` pass as floats, for
    the range checks to refuse by name."""
    if isinstance(text, str):
        if (WHOLE if whole else DECIMAL).fullmatch(text):
            return int(text) if whole else float(text)
        if not whole and text.lower().lstrip("+-") in ("nan", "inf", "infinity"):
            return float(text)
    kind = "a whole number such as 3" if whole else "a decimal number such as 0.5"
    raise ValueError(f"{name} must be {kind}, got {shown(text)}")


def shown(value) -> str:
    """``repr(value)``, cut to :data:`SHOWN_CHARS` characters for messages."""
    try:
        text = repr(value)
    except Exception:  # a value whose repr fails still gets a message
        text = f"<{type(value).__name__}>"
    if len(text) > SHOWN_CHARS:
        text = text[: SHOWN_CHARS - 15] + f"... ({len(text)} chars)"
    return text


def is_number(value) -> bool:
    """True for real numbers (Python or numpy), False for booleans, strings and the rest."""
    kind = type(value)
    if kind is float or kind is int:  # the common case, without the ABC checks (a bool is not)
        return True
    return not isinstance(value, (bool, np.bool_)) and isinstance(
        value, (numbers.Real, np.integer, np.floating)
    )


def real(name: str, value) -> float:
    """Return ``value`` as a finite float or raise ``ValueError`` naming ``name``."""
    if not is_number(value):
        raise ValueError(f"{name} must be a finite number, got {shown(value)}")
    try:
        value = float(value)
    except OverflowError:  # an integer too large for a float
        value = math.inf
    if not math.isfinite(value):
        raise ValueError(f"{name} must be a finite number, got {shown(value)}")
    return value


def in_range(name: str, value, lo: float, hi: float) -> float:
    """Return ``value`` as a float within ``[lo, hi]`` or raise ``ValueError`` naming ``name``."""
    value = real(name, value)
    if not lo <= value <= hi:
        raise ValueError(f"{name} must be within [{lo:g}, {hi:g}], got {shown(value)}")
    return value


def positive(name: str, value) -> float:
    """Return ``value`` as a finite float > 0 or raise ``ValueError`` naming ``name``."""
    value = real(name, value)
    if value <= 0:
        raise ValueError(f"{name} must be > 0, got {shown(value)}")
    return value


def non_negative(name: str, value) -> float:
    """Return ``value`` as a finite float >= 0 or raise ``ValueError`` naming ``name``."""
    value = real(name, value)
    if value < 0:
        raise ValueError(f"{name} must be >= 0, got {shown(value)}")
    return value


def coordinate(name: str, value) -> float:
    """A coordinate in grid units, within ``[-MAX_COORD, MAX_COORD]``."""
    return in_range(name, value, -MAX_COORD, MAX_COORD)


def size(name: str, value) -> float:
    """A radius or edge in grid units, within ``[0, MAX_COORD]``."""
    return in_range(name, value, 0.0, MAX_COORD)


def extent(name: str, shape: str, value: float, bounds) -> None:
    """Refuse a ``shape`` whose points, given ``name`` = ``value``, reach beyond
    :data:`MAX_COORD` on either axis (``bounds``: its extreme x and y values): a centre within
    the bound is not enough, every point the trace passes through must be."""
    far = max(bounds, key=abs)
    if abs(far) > MAX_COORD:
        raise ValueError(
            f"{name} {shown(value)} takes the {shape} to {far:.12g}: every point of a shape must "
            f"be within [{-MAX_COORD:g}, {MAX_COORD:g}] grid units on each axis"
        )


def duration(name: str, value, *, allow_zero: bool = False) -> float:
    """Seconds, > 0 (or >= 0 with ``allow_zero``) and at most :data:`MAX_DURATION_S`."""
    value = real(name, value)
    if value < 0 or (value == 0 and not allow_zero) or value > MAX_DURATION_S:
        low = ">= 0" if allow_zero else "> 0"
        raise ValueError(
            f"{name} must be {low} and at most {MAX_DURATION_S:g} s, got {shown(value)}"
        )
    return value


def rate(name: str, value, lo: float = 1.0, hi: float = MAX_RATE_HZ) -> float:
    """A frame rate in Hz within ``[lo, hi]``."""
    return in_range(name, value, lo, hi)


def integer(name: str, value, minimum: int, maximum: int | None = None) -> int:
    """Return ``value`` as an int within ``[minimum, maximum]`` or raise ``ValueError``."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (numbers.Integral, np.integer)):
        if isinstance(value, (float, np.floating)) and float(value).is_integer():
            value = int(value)
        else:
            raise ValueError(f"{name} must be an integer, got {shown(value)}")
    value = int(value)
    if value < minimum or (maximum is not None and value > maximum):
        upper = "" if maximum is None else f" and <= {maximum}"
        raise ValueError(f"{name} must be >= {minimum}{upper}, got {shown(value)}")
    return value


def point(name: str, value) -> tuple[float, float]:
    """Return a 2D point as two finite coordinates within :data:`MAX_COORD`, or raise
    ``ValueError``. A point is a pair (tuple, list or array of two numbers), not a string."""
    if isinstance(value, (str, bytes, dict)):
        raise ValueError(f"{name} must be a point (x, y), got {shown(value)}")
    try:
        x, y = value
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a point (x, y), got {shown(value)}") from None
    return coordinate(f"{name}[0]", x), coordinate(f"{name}[1]", y)


def boolean(name: str, value) -> bool:
    """A true boolean (``True``/``False``, numpy's too); anything else is refused."""
    if not isinstance(value, (bool, np.bool_)):
        raise ValueError(f"{name} must be true or false, got {shown(value)}")
    return bool(value)


def choice(name: str, value, options) -> str:
    """Return ``value`` if it is one of ``options`` or raise ``ValueError`` naming ``name``."""
    if not isinstance(value, str) or value not in options:
        raise ValueError(
            f"{name} must be one of {', '.join(map(repr, options))}, got {shown(value)}"
        )
    return value


def parameter_array(t) -> np.ndarray:
    """Return the trace parameter as a float64 array, checked to be finite and in [0, 1]."""
    if isinstance(t, (str, bytes)):
        raise ValueError(f"t must be numbers within [0, 1], got {shown(t)}")
    try:
        arr = np.asarray(t, dtype=np.float64)
    except (TypeError, ValueError, OverflowError):
        raise ValueError(f"t must be numbers within [0, 1], got {shown(t)}") from None
    bad = ~((arr >= 0.0) & (arr <= 1.0))  # NaN fails both comparisons
    if bad.any():
        index = np.flatnonzero(bad.ravel())[0]
        value = float(arr.ravel()[index])
        raise ValueError(f"t must be finite and within [0, 1], got {value!r} at index {index}")
    return arr


def intensity_array(name: str, values) -> np.ndarray:
    """Return intensities as a float64 array, checked to be finite and in [0, 1]."""
    if isinstance(values, (str, bytes)):
        raise ValueError(f"{name} must be numbers within [0, 1], got {shown(values)}")
    try:
        arr = np.asarray(values, dtype=np.float64)
    except (TypeError, ValueError, OverflowError):
        raise ValueError(f"{name} must be numbers within [0, 1], got {shown(values)}") from None
    bad = ~((arr >= 0.0) & (arr <= 1.0))
    if bad.any():
        index = np.flatnonzero(bad.ravel())[0]
        value = float(arr.ravel()[index])
        raise ValueError(f"{name} must be within [0, 1], got {value!r} at index {index}")
    return arr
