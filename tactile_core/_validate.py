"""Argument checks shared by the public functions.

Every check raises ``ValueError`` whose message starts with the parameter's name and shows the
offending value, as the contract requires (``"mu must be within [0, 1], got 1.5"``).
"""

from __future__ import annotations

import math
import numbers

import numpy as np


def real(name: str, value) -> float:
    """Return ``value`` as a finite float or raise ``ValueError`` naming ``name``."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (numbers.Real, np.generic)):
        try:
            value = float(value)
        except (TypeError, ValueError):
            raise ValueError(f"{name} must be a finite number, got {value!r}") from None
    value = float(value)
    if not math.isfinite(value):
        raise ValueError(f"{name} must be a finite number, got {value!r}")
    return value


def in_range(name: str, value, lo: float, hi: float) -> float:
    """Return ``value`` as a float within ``[lo, hi]`` or raise ``ValueError`` naming ``name``."""
    value = real(name, value)
    if not lo <= value <= hi:
        raise ValueError(f"{name} must be within [{lo:g}, {hi:g}], got {value!r}")
    return value


def positive(name: str, value) -> float:
    """Return ``value`` as a finite float > 0 or raise ``ValueError`` naming ``name``."""
    value = real(name, value)
    if value <= 0:
        raise ValueError(f"{name} must be > 0, got {value!r}")
    return value


def non_negative(name: str, value) -> float:
    """Return ``value`` as a finite float >= 0 or raise ``ValueError`` naming ``name``."""
    value = real(name, value)
    if value < 0:
        raise ValueError(f"{name} must be >= 0, got {value!r}")
    return value


def integer(name: str, value, minimum: int, maximum: int | None = None) -> int:
    """Return ``value`` as an int within ``[minimum, maximum]`` or raise ``ValueError``."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (numbers.Integral, np.integer)):
        if isinstance(value, (float, np.floating)) and float(value).is_integer():
            value = int(value)
        else:
            raise ValueError(f"{name} must be an integer, got {value!r}")
    value = int(value)
    if value < minimum or (maximum is not None and value > maximum):
        upper = "" if maximum is None else f" and <= {maximum}"
        raise ValueError(f"{name} must be >= {minimum}{upper}, got {value!r}")
    return value


def point(name: str, value) -> tuple[float, float]:
    """Return a 2D point as a tuple of two finite floats or raise ``ValueError``."""
    try:
        x, y = value
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a point (x, y), got {value!r}") from None
    return real(f"{name}[0]", x), real(f"{name}[1]", y)


def choice(name: str, value, options) -> str:
    """Return ``value`` if it is one of ``options`` or raise ``ValueError`` naming ``name``."""
    if not isinstance(value, str) or value not in options:
        raise ValueError(f"{name} must be one of {', '.join(map(repr, options))}, got {value!r}")
    return value


def parameter_array(t) -> np.ndarray:
    """Return the trace parameter as a float64 array, checked to be finite and in [0, 1]."""
    try:
        arr = np.asarray(t, dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError(f"t must be numbers within [0, 1], got {t!r}") from None
    bad = ~((arr >= 0.0) & (arr <= 1.0))  # NaN fails both comparisons
    if bad.any():
        index = np.flatnonzero(bad.ravel())[0]
        value = float(arr.ravel()[index])
        raise ValueError(f"t must be finite and within [0, 1], got {value!r} at index {index}")
    return arr


def intensity_array(name: str, values) -> np.ndarray:
    """Return intensities as a float64 array, checked to be finite and in [0, 1]."""
    try:
        arr = np.asarray(values, dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be numbers within [0, 1], got {values!r}") from None
    bad = ~((arr >= 0.0) & (arr <= 1.0))
    if bad.any():
        index = np.flatnonzero(bad.ravel())[0]
        value = float(arr.ravel()[index])
        raise ValueError(
            f"{name} must be intensities within [0, 1], got {value!r} at index {index}"
        )
    return arr
