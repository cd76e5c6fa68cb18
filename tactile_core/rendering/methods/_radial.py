"""Shared machinery of the distance-weighted methods (RO, GS): every tactor within a radius of
the point gets a weight that depends only on its distance ``d`` (in pitches) from the point.

Only the tactors that can lie within the radius are visited: the point sits in the square of
tactor centres ``[c + 0.5, c + 1.5) x [r + 0.5, r + 1.5)`` (``c = floor(x - 0.5)``), so a tactor
``k`` columns away is at least ``max(0, -k, k - 1)`` pitches away along x; columns (rows) whose
bound reaches the radius are skipped. With the default radii that leaves a 2 x 2 block (RO) or a
4 x 4 block (GS) of candidates, and at most 4 (RO) or 6 (GS) of them nonzero.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from ..geometry import cell_split, cell_split1


def offsets(radius: float, strict: bool) -> tuple[int, ...]:
    """Column (row) offsets from ``floor(x - 0.5)`` that may hold a tactor within ``radius``."""
    reach = math.ceil(radius) + 1
    out = []
    for k in range(-reach, reach + 2):
        nearest = max(0, -k, k - 1)
        if nearest < radius or (not strict and nearest == radius):
            out.append(k)
    return tuple(out)


def sample(x, y, tol, radius: float, strict: bool, weight):
    """Vectorised sampler: ``[(cols, rows, values), ...]`` over the candidate tactors.

    ``weight(d)`` maps distances (an array) to intensities; tactors at ``d >= radius``
    (``d > radius`` when not ``strict``) get 0.
    """
    c, fx = cell_split(x - 0.5, tol)
    r, fy = cell_split(y - 0.5, tol)
    ks = offsets(radius, strict)
    out = []
    for dc in ks:
        dx = fx - dc
        for dr in ks:
            dy = fy - dr
            d = np.hypot(dx, dy)
            inside = d < radius if strict else d <= radius
            value = np.where(inside, weight(np.where(inside, d, 0.0)), 0.0)
            out.append((c + dc, r + dr, value))
    return out


def sample1(x, y, tol, radius: float, strict: bool, weight1):
    """Scalar sampler: ``(col, row, value)`` of the tactors with a nonzero weight."""
    c, fx = cell_split1(x - 0.5, tol)
    r, fy = cell_split1(y - 0.5, tol)
    ks = offsets(radius, strict)
    out = []
    for dc in ks:
        dx = fx - dc
        for dr in ks:
            d = math.hypot(dx, fy - dr)
            if d < radius or (not strict and d == radius):
                value = weight1(d)
                if value > 0.0:
                    out.append((c + dc, r + dr, value))
    return tuple(out)


@functools.lru_cache(maxsize=64)
def max_within(radius: float, strict: bool) -> int:
    """Most lattice points within ``radius`` of any point (the most tactors one frame lights).

    Searched over the points of a 64 x 64 grid of one cell of tactor centres, its edges and
    corners included (the counts change only on circles through lattice points, and the
    maxima sit at the grid's symmetric points: the centre, edge midpoints and corners).
    """
    ks = offsets(radius, strict)
    best = 0
    for i in range(65):
        fx = i / 64
        for j in range(65):
            fy = j / 64
            n = 0
            for dc in ks:
                for dr in ks:
                    d = math.hypot(fx - dc, fy - dr)
                    n += d < radius or (not strict and d == radius)
            best = max(best, n)
    return best
