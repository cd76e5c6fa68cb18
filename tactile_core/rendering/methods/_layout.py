"""The methods that work on any layout: EN, PK, RO, GS, VRCH, BA and TB, on actuators anywhere.

On a :class:`~tactile_core.rendering.layout.Layout` that is not a grid, a method renders
through a :class:`LayoutSampler`: ``frames(x, y, tol)`` for many points (dense ``(n, size)``),
``entries1(x, y, tol)`` for one (the live path: ``((actuator, value), ...)`` of the lit
actuators, computed from the actuators near the point only) and ``many(x, y, tol)`` for the
live path's many points at once (the same candidates as ``entries1`` and the same arithmetic,
in arrays: ``(point, actuator, value)`` triples). Distances are in layout units, the short way
round a wrap.

=======  ==================================================================================
``RO``   ``s(1 - d / r)`` for ``d < r`` (Syntacts' roll-off; ``curve`` smoothstep or linear)
``GS``   ``exp(-d^2 / (2 sigma^2))``, zero below 0.05
``VRCH`` 1 for ``d < r``
``PK``   the three nearest actuators, ``sqrt((1/d_i) / sum_j 1/d_j)``; on an actuator, it
         alone at 1; ties in distance go to the higher index (up/right on a grid, as there;
         ``blend`` needs a grid)
``BA``   barycentric weights over the layout's Delaunay cells, rectangles bilinear
         (:mod:`._tessellation`): AS's weights on a grid
``EN``   ``sqrt`` of BA's weights: Tactile Brush's energy model on BA's cells, as EN is on AS's
``TB``   Tactile Brush along a shape's trace: its virtual points on the sides of BA's cells,
         each rendered with EN's weights there, on at their onsets (:mod:`.brush`)
=======  ==================================================================================

A plug-in works on layouts when its module has ``sample_layout(layout, x, y, **params)``
(dense ``(n, size)``) and ``sample1_layout(layout, x, y, **params)`` (``((index, value),
...)``); the others are refused there, as the paper's four are.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from ..layout import Layout
from . import brush, gaussian, rolloff
from ._candidates import candidates
from ._tessellation import Tessellation

LAYOUT_METHODS = ("EN", "PK", "RO", "GS", "VRCH", "BA")
"""The built-in methods that render any point on any layout (free points too)."""

TRACED_LAYOUT_METHODS = ("TB",)
"""The built-in methods that render a shape's trace on any layout (they need the shape and
``t``, so no free points)."""


class LayoutSampler:
    """One method with its parameters, bound to one layout.

    Parameters
    ----------
    frames : callable
        ``frames(x, y, tol) -> (n, size)`` float64 for ``(n,)`` arrays.
    entries1 : callable
        ``entries1(x, y, tol) -> ((index, value), ...)`` with plain floats.
    many : callable or None
        ``many(x, y, tol) -> (point, index, value)`` for ``(n,)`` arrays: three ``(k,)``
        arrays, candidate ``j`` being actuator ``index[j]`` (-1: none) of point ``point[j]``
        with ``value[j]``; per point, what ``entries1`` gives it (the same operations on
        float64, so the same numbers) and candidates of value 0. None where there is no such
        form (plug-ins; BA with an actuator twice in one cell).
    traced : object, optional
        For a method that follows the shape's trace (TB): an object with
        ``frames(shape, t, tol)`` and ``entries1(shape, t, tol)``, which the renderer calls
        instead (``frames`` and ``entries1`` then refuse free points).
    """

    __slots__ = ("entries1", "frames", "many", "traced")

    def __init__(self, frames, entries1, many=None, traced=None):
        self.frames = frames
        self.entries1 = entries1
        self.many = many
        self.traced = traced

    def frames_of(self, shape, t: np.ndarray) -> np.ndarray:
        """Dense ``(n, size)`` intensities of ``shape`` at the checked parameters ``t``
        (``(n,)`` float64)."""
        if self.traced is not None:
            return self.traced.frames(shape, t, shape.snap_tol)
        x, y = shape.xy(t)
        return self.frames(x, y, shape.snap_tol)

    def entries_of(self, shape, t: float) -> tuple:
        """``((index, value), ...)`` of the actuators ``shape`` lights at ``t``."""
        if self.traced is not None:
            return self.traced.entries1(shape, t, shape.snap_tol)
        x, y = shape.point(t)
        return self.entries1(x, y, shape.snap_tol)


@functools.lru_cache(maxsize=64)
def tessellation(layout: Layout) -> Tessellation:
    """BA's cells of ``layout`` (built once per layout)."""
    return Tessellation(layout)


def _joined(found: list) -> tuple:
    """``(point, index, value)`` of several blocks of candidates, one after the other."""
    if len(found) == 1:
        return found[0]
    return tuple(np.concatenate(part) for part in zip(*found))


def _distances(layout: Layout, x, y) -> np.ndarray:
    """``(n, size)`` distances, computed as the live path computes them (same rounding)."""
    dx, dy = layout.deltas(x, y)
    return np.sqrt(dx * dx + dy * dy)


# -- the methods ------------------------------------------------------------------------------


def _radial(layout, reach, weight, weight1, strict=True):
    table = candidates(layout, float(reach))
    near, distance = table.near, table.distance

    def frames(x, y, tol):
        d = _distances(layout, x, y)
        inside = d < reach if strict else d <= reach
        return np.where(inside, weight(np.where(inside, d, 0.0)), 0.0)

    def entries1(x, y, tol):
        out = []
        for i, ax, ay in near(x, y):
            d = distance(x, y, ax, ay)
            if d < reach or (not strict and d == reach):
                v = weight1(d)
                if v > 0.0:
                    out.append((i, v))
        return tuple(out)

    def many(x, y, tol):
        found = []
        for rows, index, d in table.many(x, y):
            inside = d < reach if strict else d <= reach
            point, slot = np.nonzero(inside)
            found.append((rows[point], index[point, slot], weight(d[point, slot])))
        return _joined(found)

    return LayoutSampler(frames, entries1, many)


def _ro(layout, r=1.0, curve="smoothstep"):
    s = rolloff.CURVES[curve]
    inv = 1.0 / r
    return _radial(layout, r, lambda d: s(1.0 - d * inv), lambda d: s(1.0 - d * inv))


def _vrch(layout, r=1.0):
    return _radial(layout, r, lambda d: np.ones_like(d), lambda d: 1.0)


def _gs(layout, sigma=0.5):
    k = -1.0 / (2.0 * sigma * sigma)
    cut = gaussian.CUTOFF
    reach = gaussian.radius(sigma) * (1 + 1e-9)

    def weight(d):
        w = np.exp(d * d * k)
        return np.where(w >= cut, w, 0.0)

    def weight1(d):
        w = math.exp(d * d * k)
        return w if w >= cut else 0.0

    return _radial(layout, reach, weight, weight1, strict=False)


def _pk(layout, blend=0.0):
    if blend != 0.0:
        raise ValueError(
            f"method PK:blend={blend:g} needs a grid (its bands run along the grid's centre "
            f"lines); on this layout ({layout.describe()}) use PK without blend"
        )
    k = min(3, layout.size)
    table = candidates(layout, None, k)
    near, distance = table.near, table.distance

    def frames(x, y, tol):
        d = _distances(layout, x, y)
        n = len(d)
        # nearest first, ties to the higher index (up/right on a grid, as PK breaks them there)
        order = (layout.size - 1) - np.argsort(d[:, ::-1], axis=1, kind="stable")[:, :k]
        rows = np.arange(n)[:, None]
        dk = d[rows, order]
        tol = np.broadcast_to(np.asarray(tol, dtype=np.float64), (n,))
        on = dk[:, 0] <= tol
        inv = 1.0 / np.where(dk > 0.0, dk, 1.0)
        w = np.sqrt(inv / inv.sum(axis=1, keepdims=True))
        w[on] = 0.0
        w[on, 0] = 1.0
        out = np.zeros_like(d)
        out[rows, order] = w
        return out

    def entries1(x, y, tol):
        # nearest first, ties to the higher index, as the batch path ranks them
        ranked = sorted((distance(x, y, ax, ay), -i) for i, ax, ay in near(x, y))[:k]
        if ranked[0][0] <= tol:
            return ((-ranked[0][1], 1.0),)
        inv = [1.0 / d for d, _ in ranked]
        total = sum(inv)
        return tuple((-i, math.sqrt(v / total)) for v, (_, i) in zip(inv, ranked))

    def many(x, y, tol):
        return _joined([nearest(rows, index, d, tol[rows]) for rows, index, d in table.many(x, y)])

    def nearest(rows, index, d, tol):
        order = np.argsort(d, axis=1, kind="stable")[:, :k]  # highest index first: ties there
        at = np.arange(len(d))[:, None]
        index, d = index[at, order], d[at, order]
        on = d[:, 0] <= tol
        with np.errstate(divide="ignore", invalid="ignore"):  # on an actuator: set below
            inv = 1.0 / d
            total = inv[:, 0].copy()  # summed in order, as sum() does
            for j in range(1, k):
                total += inv[:, j]
            w = np.sqrt(inv / total[:, None])
        w[on] = 0.0
        w[on, 0] = 1.0
        return np.repeat(rows, k), index.reshape(-1), w.reshape(-1)

    return LayoutSampler(frames, entries1, many)


def _ba(layout):
    cells = tessellation(layout)
    size = layout.size

    def frames(x, y, tol):
        index, weight = cells.weights(x, y, tol)
        out = np.zeros((len(index), size + 1))  # slot ``size``: unused (-1)
        rows = np.arange(len(index))[:, None]
        slots = np.where(index >= 0, index, size)
        if cells.repeats:  # an actuator twice in one cell: add
            np.add.at(out, (rows, slots), weight)
        else:  # one slot per actuator (unused slots all write 0 to the spare)
            out[rows, slots] = weight
        return out[:, :size]

    def many(x, y, tol):
        index, w = cells.weights(x, y, tol)
        return np.repeat(np.arange(len(x)), index.shape[1]), index.reshape(-1), w.reshape(-1)

    if not cells.repeats:
        return LayoutSampler(frames, cells.weights1, many)

    def entries1(x, y, tol):  # an actuator twice in one cell (a wrap of one or two turns)
        lit: dict = {}
        for i, w in cells.weights1(x, y, tol):
            lit[i] = lit.get(i, 0.0) + w
        return tuple(lit.items())

    return LayoutSampler(frames, entries1)


def _en(layout):
    ba = _ba(layout)

    def frames(x, y, tol):
        return np.sqrt(ba.frames(x, y, tol))

    def entries1(x, y, tol):
        return tuple((i, math.sqrt(w)) for i, w in ba.entries1(x, y, tol))

    def many(x, y, tol):
        point, index, w = ba.many(x, y, tol)
        return point, index, np.sqrt(w)

    return LayoutSampler(frames, entries1, None if ba.many is None else many)


def _tb(layout, duration_s=brush.DURATION_S):
    on_layout = brush.OnLayout(layout, tessellation(layout), _en(layout).entries1, duration_s)

    def refuse(*args):
        raise ValueError("method TB needs a shape: it times its actuators along the stroke")

    return LayoutSampler(refuse, refuse, traced=on_layout)


BUILT_IN = {"RO": _ro, "GS": _gs, "VRCH": _vrch, "PK": _pk, "BA": _ba, "EN": _en, "TB": _tb}


def _plugin(module, layout, params):
    fn, fn1 = module.sample_layout, module.sample1_layout

    def frames(x, y, tol):
        out = np.asarray(fn(layout, x, y, **params), dtype=np.float64)
        if out.shape != (len(x), layout.size):
            raise ValueError(
                f"sample_layout returned shape {out.shape}, expected {(len(x), layout.size)}"
            )
        if not np.isfinite(out).all() or out.min(initial=0.0) < 0 or out.max(initial=0.0) > 1:
            raise ValueError("sample_layout returned values outside [0, 1]")
        return out

    def entries1(x, y, tol):
        out = tuple((int(i), float(v)) for i, v in fn1(layout, x, y, **params))
        for i, v in out:
            if not (0 <= i < layout.size and 0.0 <= v <= 1.0):
                raise ValueError(
                    f"sample1_layout returned ({i}, {v}): not an actuator and a value in [0, 1]"
                )
        return out

    return LayoutSampler(frames, entries1)


_SAMPLERS: dict = {}


def layout_sampler(method, layout: Layout) -> LayoutSampler:
    """The :class:`LayoutSampler` of ``method`` (a bound :class:`~.Method`) on ``layout``.

    Raises
    ------
    ValueError
        When the method is defined on grids only (the paper's four, plug-ins without
        ``sample_layout``), saying why and which methods apply.
    """
    key = (method.name, method.params, method.module, layout, method.clock_s)
    hit = _SAMPLERS.get(key)
    if hit is not None:
        return hit
    params = dict(method.params)
    if method.clocked:
        params["duration_s"] = method.duration_s
    build = BUILT_IN.get(method.name) if not method.plugin else None
    if build is not None:
        hit = build(layout, **params)
    elif (
        method.plugin
        and hasattr(method.module, "sample_layout")
        and hasattr(method.module, "sample1_layout")
    ):
        hit = _plugin(method.module, layout, params)
    else:
        raise ValueError(refusal(method.name, layout))
    if len(_SAMPLERS) > 256:
        _SAMPLERS.clear()
    _SAMPLERS[key] = hit
    return hit


def refusal(name: str, layout: Layout) -> str:
    """Why ``name`` cannot render on ``layout``, and what can."""
    why = (
        "it is defined on a grid of tactors (the paper's sections 2.2-2.5 pick cells, columns "
        "and rows)"
        if name in ("CT", "MM", "AS", "IM")
        else "it is defined on a grid of tactors"
    )
    return (
        f"method {name} cannot render on this layout ({layout.describe()}): {why}; on "
        f"actuators anywhere use {', '.join(LAYOUT_METHODS + TRACED_LAYOUT_METHODS)} (BA is "
        f"AS's weights generalised)"
    )
