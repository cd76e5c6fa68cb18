"""Jumps: how abruptly a method switches a tactor as the point moves.

A smooth method changes every tactor's intensity continuously with the point; a bi-level one
(CT, MM) switches tactors from 0 to 1; PK switches a tactor at each centre line of the square of
tactor centres. :func:`largest_jump` measures the largest change of any tactor's intensity
between two points ``step`` pitches apart along a set of paths (:data:`JUMP_PATHS`), found by
refining the largest changes of a coarse sampling: a discontinuity keeps its size as the step
shrinks, a continuous change vanishes with it. After the correction, every method that lights
a tactor from 0 jumps by at least ``mu`` there (the paper's threshold is a jump by design).
"""

from __future__ import annotations

import numpy as np

from .._shared import validate as _validate
from .correction import correct
from .geometry import Grid
from .methods import get_method
from .rasterize import render
from .shapes import Circle, Line

JUMP_PATHS = (
    Line((0.5, 1.84), (4.5, 4.16)),  # the paper's Experiment 1 line
    Circle((2.5, 3.0), 2.0),  # its circle
    Line((0.55, 3.1), (4.45, 3.1)),  # across the centre lines, between tactor rows
    Line((2.2, 0.55), (2.2, 5.45)),  # up, between tactor columns
    Line((0.6, 1.6), (4.4, 5.4)),  # through cell corners: the squares' centres
    Line((0.7, 5.2), (4.3, 0.9)),  # a falling diagonal
)
"""Paths the jumps are measured along (grid units, inside the palm array's hull)."""


def _frames(shape, method, t, mu, gamma, grid):
    return correct(render(shape, method, t, grid=grid), mu, gamma).reshape(len(t), grid.size)


def largest_jump(method, mu: float = 0.0, gamma: float = 1.0, *, paths=JUMP_PATHS,
                 grid: Grid | None = None, step: float = 1e-5,
                 per_pitch: int = 400, refine: int = 24) -> float:  # fmt: skip
    """The largest change of one tactor's intensity between points ``step`` pitches apart.

    Parameters
    ----------
    method : str
        Any registered method or spec.
    mu, gamma : float
        Correction applied first (the defaults leave the raw intensities).
    paths : sequence of Shape
        Where to look (:data:`JUMP_PATHS` by default).
    grid : Grid, optional
        The palm array's 5 x 6 by default.
    step : float
        Final distance between the two points, in pitches.
    per_pitch : int
        Coarse samples per pitch of path length.
    refine : int
        How many of the largest coarse changes per path are refined.

    Returns
    -------
    float
        The largest change, in intensity units (1 = off to full).
    """
    grid = grid or Grid()
    m = get_method(method)
    step = _validate.in_range("step", step, 1e-9, 0.1)
    worst = 0.0
    for shape in paths:
        length = float(np.hypot(*np.diff(shape.outline(), axis=0).T).sum())
        n = max(16, int(length * per_pitch))
        t = np.linspace(0.0, 1.0, n + 1)
        frames = _frames(shape, m, t, mu, gamma, grid)
        change = np.abs(np.diff(frames, axis=0)).max(axis=1)
        lo = t[:-1][np.argsort(change)[-refine:]]
        hi = lo + 1.0 / n
        dt = step / length
        # Bisect each interval towards its larger half until it is one step long.
        while True:
            width = hi[0] - lo[0]
            if width <= dt:
                break
            mid = (lo + hi) / 2
            ends = _frames(shape, m, np.concatenate([lo, mid, hi]), mu, gamma, grid)
            a, b, c = np.split(ends, 3)
            left = np.abs(b - a).max(axis=1) >= np.abs(c - b).max(axis=1)
            lo, hi = np.where(left, lo, mid), np.where(left, mid, hi)
        ends = _frames(shape, m, np.concatenate([lo, hi]), mu, gamma, grid)
        a, c = np.split(ends, 2)
        worst = max(worst, float(np.abs(c - a).max()))
    return worst
