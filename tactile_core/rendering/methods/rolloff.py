"""Roll-off method (RO): Syntacts' spatializer, for comparison with the paper's methods.

Syntacts (Pezent et al., "Syntacts: Open-Source Software and Hardware for Audio-Controlled
Haptics", IEEE Transactions on Haptics 14(1), 2021) spatialises a virtual source over an array by
giving each channel the volume ``curve(1 - clamp(d / r, 0, 1))`` for its distance ``d`` from
the source (``tact::Spatializer::update``). Its spatializer's defaults are the *linear* curve and
``r = 0.25`` in its normalised coordinates (``createGrid`` puts the channels of a grid at
``col / (cols - 1)``, ``row / (rows - 1)``, so on the 5-column palm array 0.25 is one pitch
across and 1.25 pitches up); the smoothstep ``s(x) = x^2 (3 - 2x)`` is one of the optional
``tact::Curves`` it can be given instead.

Here ``curve`` is a spec parameter, ``RO:curve=linear`` or ``RO:curve=smoothstep``; the
contract's ``RO`` is the smoothstep one (``s(1 - d / r)`` for ``d < r``: 1 on the tactor,
falling to 0 with zero slope at both ends), so that stays the default, and ``RO:curve=linear``
is Syntacts' own default. Distances are in pitches; ``r = 1`` by default, so a point on a tactor
lights it alone and a point at a cell corner lights the four around it at ``s(1 - 0.707) =
0.21`` each (linear: 0.29). Intensities do not sum to 1 (nor their squares): Syntacts leaves the
balance to the user, and plays the volumes as computed (``CORRECTION = "none"``). Works on any
coordinate, with or without a shape.
"""

from __future__ import annotations

import functools

import numpy as np

from ..geometry import clamp
from . import _radial
from ._cells import Block, stack_points

NAME = "RO"
TITLE = "roll-off (Syntacts)"
BILEVEL = False
NEEDS_SHAPE = False
PARAMS = {"r": (1.0, 0.1, 10.0, "roll-off radius in pitches: tactors farther away are off")}
CHOICES = {"curve": (("smoothstep", "linear"), "roll-off curve (Syntacts' default is linear)")}
CORRECTION = "none"


def MAX_TACTORS(r=1.0):
    """Most tactors lit at once for radius ``r`` (4 at ``r = 1``)."""
    return _radial.max_within(float(r), True)


def smoothstep(x):
    """``x^2 (3 - 2x)`` on [0, 1]: 0 and 1 at the ends, zero slope at both."""
    if type(x) is not np.ndarray:
        return x * x * (3.0 - 2.0 * x)
    out = x * x
    out *= 3.0 - 2.0 * x
    return out


def linear(x):
    """``x`` itself: Syntacts' default roll-off curve."""
    return x


CURVES = {"smoothstep": smoothstep, "linear": linear}


def _smoothstep_over(x: np.ndarray) -> np.ndarray:
    """:func:`smoothstep` of an array, computed over ``x`` (same operations, same numbers)."""
    out = np.square(x)
    np.multiply(x, -2.0, out=x)
    x += 3.0  # 3 - 2x, as rounded once
    out *= x
    return out


_CURVES_OVER = {"smoothstep": _smoothstep_over, "linear": linear}


def sample(shape, x, y, t, tol, r=1.0, curve="smoothstep"):
    """Tactors within ``r`` of the points ``(x, y)`` and their roll-off gains.

    Parameters
    ----------
    shape, t
        Unused: RO depends on the point only.
    x, y : ndarray of float64, shape (n,)
        Points in grid units.
    tol : float or ndarray
        Snap tolerance of the cell lookup.
    r : float
        Roll-off radius in pitches.
    curve : {"smoothstep", "linear"}
        The roll-off curve ``s``.

    Returns
    -------
    list of (cols, rows, values)
        One entry per candidate tactor (see :mod:`tactile_core.rendering.methods._radial`), values
        ``s(1 - d / r)`` in [0, 1], 0 at ``d >= r``.
    """
    return sample_cells(shape, stack_points(x, y), t, tol, r, curve).entries()


def sample_cells(shape, xy, t, tol, r=1.0, curve="smoothstep"):
    """:func:`sample` in the renderer's batch form (:class:`~._cells.Block`): distances
    ``sqrt(dx^2 + dy^2)``; a tactor within :data:`~._radial.MARGIN` (relative) of ``r`` is
    decided as ``hypot(dx, dy) < r`` decides."""
    inv = 1.0 / r
    split = _radial.block(xy, tol, r, True)
    u = np.sqrt(_radial.squared_distances(split.squares()))
    if inv != 1.0:
        u *= inv
    np.subtract(1.0, u, out=u)  # 1 - d / r: within MARGIN of 0 at the edge
    edge = np.abs(u)
    found = np.flatnonzero(edge < _radial.MARGIN) if edge.min() < _radial.MARGIN else None
    del edge
    np.maximum(u, 0.0, out=u)  # 0 beyond r (within the margin: decided below)
    values = _CURVES_OVER[curve](u)
    if found is not None:
        _radial.settle(values, found, split, r, True, _exact_weight(r, curve), _weight1(r, curve))
    return Block(split.origin, values, split.width, split.width)


@functools.lru_cache(maxsize=64)
def _exact_weight(r: float, curve: str):
    """The batch path's weight of exact distances (arrays), built once per parameter set."""
    inv = 1.0 / r
    s = CURVES[curve]
    return lambda d: s(clamp(1.0 - d * inv, 0.0, 1.0))


def sample1(shape, x, y, t, tol, r=1.0, curve="smoothstep"):
    """Scalar :func:`sample`: ``(col, row, value)`` of the lit tactors."""
    return _radial.sample1(x, y, tol, r, True, _weight1(r, curve))


def sample1_exact(shape, x, y, t, tol, r=1.0, curve="smoothstep"):
    """:func:`sample1`, or None where a tactor lies within rounding of ``r`` (the renderer then
    takes the array path)."""
    return _radial.sample1(x, y, tol, r, True, _weight1(r, curve), guard=True)


@functools.lru_cache(maxsize=64)
def _weight1(r: float, curve: str):
    """The scalar weight of a distance, built once per parameter set (not on every frame)."""
    inv = 1.0 / r
    s = CURVES[curve]
    return lambda d: s(1.0 - d * inv)
